// --where conditions of `fixpoint addresses` (host/where.hpp).
#include <fixpoint/errors.hpp>
#include <fixpoint/host/core/config.hpp>
#include <fixpoint/host/tools/where.hpp>
#include <fixpoint/text.hpp>

#include <cmath>
#include <cstdlib>
#include <string_view>

namespace fp::host {

namespace {

bool in_box(Vec2 p, const Box& b) { return p.x >= b.xmin && p.x <= b.xmax && p.y >= b.ymin && p.y <= b.ymax; }

/// "[x0, x1, y0, y1]" (YAML) as a box with x0 <= x1, y0 <= y1; false when it is not one.
bool parse_box(std::string_view text, Box& b) {
    CNode n;
    try {
        n = parse_yaml(std::string(text), "--where");
    } catch (const InputError&) {
        return false;
    }
    if (!n.is_seq() || n.items.size() != 4) return false;
    double v[4];
    for (std::size_t i = 0; i < 4; ++i) {
        const CNode& c = n.items[i];
        char* end = nullptr;
        v[i] = c.is_scalar() && !c.scalar.empty() ? std::strtod(c.scalar.c_str(), &end) : NAN;
        if (!end || *end || !std::isfinite(v[i])) return false;
    }
    b = {v[0], v[1], v[2], v[3]};
    return b.xmin <= b.xmax && b.ymin <= b.ymax;
}

} // namespace

bool PolygonTest::operator()(const std::vector<Vec2>& vs) const {
    if (vs.empty()) return false;
    switch (kind) {
    case Kind::centre_in: {
        Vec2 c{0, 0};
        for (const Vec2& v : vs) c.x += v.x, c.y += v.y;
        return in_box({c.x / double(vs.size()), c.y / double(vs.size())}, box);
    }
    case Kind::inside:
        for (const Vec2& v : vs)
            if (!in_box(v, box)) return false;
        return true;
    case Kind::meets:
        for (const Vec2& v : vs)
            if (in_box(v, box)) return true;
        return false;
    }
    return false;
}

PolygonTest parse_where(const std::string& text) {
    std::string_view s = text;
    while (!s.empty() && s.front() == ' ') s.remove_prefix(1);
    PolygonTest t;
    std::string_view rest;
    if (s.starts_with("centre in "))
        t.kind = PolygonTest::Kind::centre_in, rest = s.substr(10);
    else if (s.starts_with("inside "))
        t.kind = PolygonTest::Kind::inside, rest = s.substr(7);
    else if (s.starts_with("meets "))
        t.kind = PolygonTest::Kind::meets, rest = s.substr(6);
    else
        throw InputError("--where " + quote(text) +
                         ": expected 'centre in [x0, x1, y0, y1]', 'inside [...]' or 'meets [...]'");
    if (!parse_box(rest, t.box))
        throw InputError(
            "--where " + quote(text) +
            ": expected a box [x0, x1, y0, y1] of four finite numbers with x0 <= x1 and y0 <= y1");
    return t;
}

std::vector<Vec2> address_line_vertices(const std::string& line) {
    std::vector<Vec2> vs;
    for (std::size_t open = line.find('('); open != std::string::npos; open = line.find('(', open + 1)) {
        const char* p = line.c_str() + open + 1;
        char* end = nullptr;
        const double x = std::strtod(p, &end);
        if (end == p || *end != ',') continue;
        p = end + 1;
        const double y = std::strtod(p, &end);
        if (end == p || *end != ')') continue;
        vs.push_back({x, y});
    }
    return vs;
}

} // namespace fp::host
