// flam3 genomes as configs (host/tools/flam3_import.hpp; docs/flam3.md has the mapping).
//
// Read with tinyxml2 (Debian's libtinyxml2-dev), which gives each element's and attribute's
// line; the column of an attribute is found on its line by its name. Every value is checked
// here, at its place in the XML, before any config is written: a number that is not finite, a
// size out of range, an unknown attribute or variation. What fixpoint cannot carry over yet
// (motion, temporal samples) is a warning, never a silent drop.
#include <fixpoint/host/core/flam3_import.hpp>

#include <fixpoint/errors.hpp>
#include <fixpoint/text.hpp>

#include <fixpoint/flam3_table.hpp>
#include <fixpoint/palette.hpp>

#include <tinyxml2.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace fp::host {

namespace {

using fp_flam3::param_info;
using fp_flam3::var_info;

std::string num(double v) {
    char b[40];
    if (v == std::floor(v) && std::fabs(v) < 1e15) {
        std::snprintf(b, sizeof b, "%.0f", v);
        return b;
    }
    std::snprintf(b, sizeof b, "%.17g", v);
    // The shortest text that reads back the same double.
    for (int p = 1; p <= 17; ++p) {
        char c[40];
        std::snprintf(c, sizeof c, "%.*g", p, v);
        if (std::strtod(c, nullptr) == v) return c;
    }
    return b;
}

class Reader {
public:
    Reader(std::string path, std::string text) : path_(std::move(path)), text_(std::move(text)) {
        std::size_t at = 0;
        lines_.push_back(0);
        while ((at = text_.find('\n', at)) != std::string::npos) lines_.push_back(++at);
    }

    [[noreturn]] void fail(int line, int col, const std::string& msg) const {
        throw InputError(path_ + ":" + std::to_string(line) + ":" + std::to_string(col) + ": " + msg);
    }
    /// The column of attribute `name` on its line (1 when not found there).
    int column(const tinyxml2::XMLAttribute* a) const {
        const int line = a->GetLineNum();
        if (line < 1 || std::size_t(line) > lines_.size()) return 1;
        const std::size_t b = lines_[std::size_t(line - 1)];
        const std::size_t e = std::size_t(line) < lines_.size() ? lines_[std::size_t(line)] : text_.size();
        const std::string l = text_.substr(b, e - b), n = a->Name();
        for (std::size_t at = l.find(n); at != std::string::npos; at = l.find(n, at + 1)) {
            const bool start = at == 0 || std::isspace(static_cast<unsigned char>(l[at - 1]));
            std::size_t k = at + n.size();
            while (k < l.size() && std::isspace(static_cast<unsigned char>(l[k]))) ++k;
            if (start && k < l.size() && l[k] == '=') return int(at) + 1;
        }
        return 1;
    }
    [[noreturn]] void fail(const tinyxml2::XMLAttribute* a, const std::string& msg) const {
        fail(a->GetLineNum(), column(a), std::string(a->Name()) + ": " + msg);
    }
    [[noreturn]] void fail(const tinyxml2::XMLElement* e, const std::string& msg) const {
        fail(e->GetLineNum(), 1, msg);
    }

    /// The attribute's numbers (at least `min`, at most `max` of them), each finite.
    std::vector<double> numbers(const tinyxml2::XMLAttribute* a, std::size_t min, std::size_t max) const {
        std::vector<double> v;
        std::istringstream in(a->Value());
        std::string w;
        while (in >> w) {
            char* end = nullptr;
            const double x = std::strtod(w.c_str(), &end);
            if (end == w.c_str() || *end) fail(a, quote(w, 40) + " is not a number");
            if (!std::isfinite(x)) fail(a, quote(w, 40) + " is not a finite number");
            v.push_back(x);
        }
        if (v.size() < min || v.size() > max)
            fail(a,
                 "expected " +
                     (min == max ? std::to_string(min) : std::to_string(min) + " to " + std::to_string(max)) +
                     " numbers, got " + std::to_string(v.size()));
        return v;
    }
    double number(const tinyxml2::XMLAttribute* a) const { return numbers(a, 1, 1)[0]; }
    double number(const tinyxml2::XMLAttribute* a, double lo, double hi) const {
        const double x = number(a);
        if (!(x >= lo && x <= hi)) fail(a, num(x) + " is out of range [" + num(lo) + ", " + num(hi) + "]");
        return x;
    }

private:
    std::string path_, text_;
    std::vector<std::size_t> lines_;
};

/// The index of variation `name` (flam3's attribute name), or -1.
int variation(const std::string& name) {
    for (std::uint32_t v = 0; v < fp_flam3::var_count; ++v)
        if (name == var_info[v].name) return int(v);
    return -1;
}
int parameter(const std::string& name) {
    std::string n = name;
    if (n.rfind("oscope_", 0) == 0) n = "oscilloscope_" + n.substr(7); // flam3 reads both spellings
    for (std::uint32_t p = 0; p < fp_flam3::param_count; ++p)
        if (n == param_info[p].name) return int(p);
    return -1;
}

/// An xform (or the final xform) as a YAML flow mapping but for its closing brace; its weight
/// and its xaos row (flam3's chaos: empty where not given) beside.
std::string xform(const Reader& r, const tinyxml2::XMLElement* e, bool final, std::vector<std::string>& warn,
                  double& weight, std::vector<double>& chaos, const std::string& what) {
    std::string s = "{type: xform";
    // (Variations and parameters in the table's order, whatever the file's: a canonical config,
    // which export writes back the same.)
    std::map<int, std::string> vars, prm;
    weight = 1;
    double color = 0, speed = 0.5, opacity = 1;
    chaos.clear();
    bool any = false;
    std::vector<double> old_vars;
    for (const auto* a = e->FirstAttribute(); a; a = a->Next()) {
        const std::string n = a->Name();
        if (n == "weight") {
            weight = r.number(a, 0, 1e300);
        } else if (n == "color") {
            const auto c = r.numbers(a, 1, 2); // (flam3 2's "color" had two; the first is the index)
            color = c[0];
            if (!(color >= 0 && color <= 1)) r.fail(a, num(color) + " is out of range [0, 1]");
        } else if (n == "color_speed") {
            speed = r.number(a, 0, 1);
        } else if (n == "symmetry") {
            speed = (1 - r.number(a, -1, 1)) / 2; // flam3's older name: color_speed = (1 - symmetry) / 2
        } else if (n == "coefs" || n == "post") {
            const auto c = r.numbers(a, 6, 6);
            s += ", " + n + ": [";
            for (std::size_t i = 0; i < 6; ++i) s += (i ? ", " : "") + num(c[i]);
            s += "]";
        } else if (n == "opacity" || n == "plotmode") {
            // (flam3's plotmode "off" is opacity 0.)
            const double o =
                n == "plotmode" ? (std::string(a->Value()) == "off" ? 0.0 : 1.0) : r.number(a, 0, 1);
            opacity = std::min(opacity, o); // (a final's: the chance it applies, as in flam3)
        } else if (n == "chaos") {
            const auto c = r.numbers(a, 0, 1u << 16);
            for (double x : c)
                if (!(x >= 0)) r.fail(a, "xaos weights must be numbers >= 0");
            if (final) {
                if (std::any_of(c.begin(), c.end(), [](double x) { return x != 1; }))
                    warn.push_back(what + ": chaos has no meaning for the final xform (flam3 ignores it)");
            } else {
                chaos = c;
            }
        } else if (n == "animate" || n == "name" || n == "motion_frequency" || n == "motion_function") {
            // animation only: a still render does not read it
        } else if (n == "var1") {
            const double v = r.number(a, 0, fp_flam3::var_count - 1);
            old_vars.assign(fp_flam3::var_count, 0);
            old_vars[std::size_t(v)] = 1;
        } else if (n == "var") {
            old_vars = r.numbers(a, 1, fp_flam3::var_count);
        } else if (const int v = variation(n); v >= 0) {
            const double w = r.number(a);
            if (w != 0) vars[v] = std::string(", ") + var_info[v].name + ": " + num(w), any = true;
        } else if (const int p = parameter(n); p >= 0) {
            prm[p] = std::string(", ") + param_info[p].name + ": " + num(r.number(a));
        } else {
            std::vector<std::string> names;
            for (const auto& v : var_info) names.emplace_back(v.name);
            for (const auto& p : param_info) names.emplace_back(p.name);
            const auto near = suggest(n, names);
            r.fail(a, "unknown variation or xform attribute" +
                          (near.empty() ? std::string() : " (did you mean '" + near[0] + "'?)"));
        }
    }
    for (std::size_t v = 0; v < old_vars.size(); ++v)
        if (old_vars[v] != 0)
            vars[int(v)] = std::string(", ") + var_info[v].name + ": " + num(old_vars[v]), any = true;
    if (!any) vars[0] = ", linear: 1"; // flam3's default xform is linear
    for (const auto& [v, text] : vars) s += text;
    for (const auto& [p, text] : prm) s += text;
    if (!final) s += ", weight: " + num(weight);
    s += ", color: " + num(color) + ", color_speed: " + num(speed);
    if (opacity < 1) s += ", opacity: " + num(opacity);
    for (const auto* c = e->FirstChildElement(); c; c = c->NextSiblingElement())
        if (std::string(c->Name()) == "motion") {
            warn.push_back(what + ": its motion elements are not carried over (a still render)");
            break;
        }
    return s;
}

/// flam3's hsv2rgb(rgb2hsv(v) + (dh, 0, 0)) (palettes.c), in place: v in [0, 1], h in [0, 6).
void rotate_hue(double* v, double dh) {
    const double mx = std::max({v[0], v[1], v[2]}), mn = std::min({v[0], v[1], v[2]}), del = mx - mn;
    const double s = mx != 0 ? del / mx : 0.0;
    double h = 0;
    if (s != 0) {
        const double rc = (mx - v[0]) / del, gc = (mx - v[1]) / del, bc = (mx - v[2]) / del;
        if (v[0] == mx)
            h = bc - gc;
        else if (v[1] == mx)
            h = 2 + rc - bc;
        else
            h = 4 + gc - rc;
        if (h < 0) h += 6;
    }
    h += dh;
    while (h >= 6) h -= 6;
    while (h < 0) h += 6;
    const int j = int(std::floor(h));
    const double f = h - j, p = mx * (1 - s), q = mx * (1 - s * f), t = mx * (1 - s * (1 - f));
    const double table[6][3] = {{mx, t, p}, {q, mx, p}, {p, mx, t}, {p, q, mx}, {t, p, mx}, {mx, p, q}};
    std::copy_n(table[j < 6 ? j : 0], 3, v);
}

/// flam3_add_symmetry's xforms for `<symmetry kind="N">` (flam3.c): for N < 0 a mirror x -> -x,
/// then for |N| the rotations by 2 pi k / |N|, k = 1 .. |N| - 1; each linear, of weight 1 and
/// color_speed 0, with flam3's colours, their coefficients rounded to 6 decimals as flam3 does.
std::vector<std::string> symmetry_xforms(int sym) {
    std::vector<std::string> out;
    auto add = [&](double a, double b, double color) {
        out.push_back("{type: xform, coefs: [" + num(a) + ", " + num(b) + ", " + num(-b == 0 ? 0.0 : -b) +
                      ", " + num(a) + ", 0, 0], linear: 1, weight: 1, color: " + num(color) +
                      ", color_speed: 0}");
    };
    if (sym < 0) {
        out.push_back(
            "{type: xform, coefs: [-1, 0, 0, 1, 0, 0], linear: 1, weight: 1, color: 1, color_speed: 0}");
        sym = -sym;
    }
    const double step = 2 * 3.14159265358979323846 / sym;
    auto round6 = [](double x) { return std::round(x * 1e6) / 1e6; };
    for (int k = 1; k < sym; ++k)
        add(round6(std::cos(k * step)), round6(std::sin(k * step)), sym < 3 ? 0.0 : (k - 1.0) / (sym - 2.0));
    return out;
}

std::string palette_of(const Reader& r, const tinyxml2::XMLElement* flame, std::vector<std::string>& warn) {
    std::vector<double> rgb(256 * 3, 0.0);
    bool got = false;
    for (const auto* c = flame->FirstChildElement("color"); c; c = c->NextSiblingElement("color")) {
        const auto* ia = c->FindAttribute("index");
        const auto* ca = c->FindAttribute("rgb");
        if (!ia || !ca) r.fail(c, "color: expected index=\"I\" and rgb=\"R G B\"");
        const double i = r.number(ia, 0, 255);
        if (i != std::floor(i)) r.fail(ia, num(i) + " is not a whole number");
        const auto v = r.numbers(ca, 3, 3);
        for (int k = 0; k < 3; ++k) {
            if (!(v[std::size_t(k)] >= 0 && v[std::size_t(k)] <= 255))
                r.fail(ca, "a channel out of range [0, 255]");
            rgb[std::size_t(i) * 3 + std::size_t(k)] = v[std::size_t(k)] / 255.0;
        }
        got = true;
    }
    if (const auto* p = flame->FirstChildElement("palette")) {
        const char* text = p->GetText();
        std::string hex;
        for (const char* t = text ? text : ""; *t; ++t)
            if (!std::isspace(static_cast<unsigned char>(*t))) hex += *t;
        if (hex.size() != 256 * 6)
            r.fail(p, "palette: expected 256 colours of 6 hex digits, got " + std::to_string(hex.size()) +
                          " digits");
        for (std::size_t i = 0; i < 256 * 3; ++i) {
            char* end = nullptr;
            const std::string b = hex.substr(2 * i, 2);
            const long v = std::strtol(b.c_str(), &end, 16);
            if (*end) r.fail(p, "palette: " + quote(b) + " is not a hex byte");
            rgb[i] = double(v) / 255.0;
        }
        got = true;
    }
    const auto* pi = flame->FindAttribute("palette");
    if (!got && pi) {
        const std::string name = "flam3:" + num(r.number(pi, 0, 1e6));
        const auto* hue = flame->FindAttribute("hue");
        const double h = hue ? std::fmod(r.number(hue), 1.0) : 0.0; // (flam3's parser: fmod(hue, 1))
        if (h == 0) return "palette: " + name;
        // flam3_get_palette: each entry's hue turned by 6 h in flam3's HSV (h in [0, 6)).
        fp::Palette p;
        try {
            p = fp::palette_named(name, "palette");
        } catch (const fp::ParamError& e) {
            r.fail(pi, e.what());
        }
        for (std::size_t i = 0; i < 256; ++i) {
            const fp::Rgb c = p.colours[i];
            // (flam3's entries are bytes / 255; ours are those bytes as floats.)
            double v[3] = {std::round(double(c.r) * 255) / 255, std::round(double(c.g) * 255) / 255,
                           std::round(double(c.b) * 255) / 255};
            rotate_hue(v, 6 * h);
            std::copy_n(v, 3, &rgb[3 * i]);
        }
        got = true;
    }
    if (!got) {
        warn.push_back("the genome has no palette: white");
        std::fill(rgb.begin(), rgb.end(), 1.0);
    }
    // 256 stops at i / 256: flam3's step lookup takes entry floor(256 t), as ours does
    // (fixpoint/palette.hpp); its linear one interpolates between entries at i / 256 too.
    std::string s = "palette_stops: [";
    for (int i = 0; i < 256; ++i)
        s += (i ? ", " : "") + num(i / 256.0) + ", " + num(rgb[std::size_t(i) * 3]) + ", " +
             num(rgb[std::size_t(i) * 3 + 1]) + ", " + num(rgb[std::size_t(i) * 3 + 2]);
    return s + "]";
}

} // namespace

bool is_flam3_file(const std::string& path) {
    const std::string e = std::filesystem::path(path).extension().string();
    return e == ".flam3" || e == ".flame" || e == ".flam";
}

Flam3Import import_flam3(const std::string& path, const Flam3Select& which, const std::string& output) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path + ": cannot open file");
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (text.size() > (64u << 20)) throw InputError(path + ": file too large (more than 64 MiB)");
    const Reader r(path, text);
    tinyxml2::XMLDocument doc;
    if (doc.Parse(text.data(), text.size()) != tinyxml2::XML_SUCCESS)
        r.fail(doc.ErrorLineNum() > 0 ? doc.ErrorLineNum() : 1, 1,
               std::string("malformed XML: ") + (doc.ErrorName() ? doc.ErrorName() : "error"));
    const tinyxml2::XMLElement* root = doc.RootElement();
    if (!root) r.fail(1, 1, "no flame in the file");
    std::vector<const tinyxml2::XMLElement*> flames;
    if (std::string(root->Name()) == "flame")
        flames.push_back(root);
    else
        for (const auto* f = root->FirstChildElement("flame"); f; f = f->NextSiblingElement("flame"))
            flames.push_back(f);
    if (flames.empty()) r.fail(root, "no <flame> element (a flam3 genome file holds <flame>s)");
    Flam3Import out;
    out.count = int(flames.size());
    int k = 0;
    if (!which.name.empty()) {
        k = -1;
        for (std::size_t i = 0; i < flames.size(); ++i)
            if (const char* n = flames[i]->Attribute("name"); n && which.name == n) k = int(i);
        if (k < 0) throw InputError(path + ": no flame named " + quote(which.name));
    } else if (which.index >= 0) {
        if (which.index >= int(flames.size()))
            throw InputError(path + ": --index " + std::to_string(which.index) + ": the file holds " +
                             std::to_string(flames.size()) + " flames (0 to " +
                             std::to_string(flames.size() - 1) + ")");
        k = which.index;
    } else if (flames.size() > 1) {
        out.warnings.push_back(path + " holds " + std::to_string(flames.size()) +
                               " flames: the first is taken (fixpoint import --index K or --name N)");
    }
    out.index = k;
    const tinyxml2::XMLElement* f = flames[std::size_t(k)];
    auto& warn = out.warnings;

    double W = 100, H = 100, cx = 0, cy = 0, ppu = 50, rotate = 0, zoom = 0, quality = 1, ss = 1;
    double filter = 0.5, est = 9, est_min = 0, est_curve = 0.4;
    double gamma = 4, brightness = 4, contrast = 1, vibrancy = 1, highlight = -1, gthresh = 0.01;
    std::string filter_shape = "gaussian", palette_mode = "step";
    std::vector<double> bg = {0, 0, 0};
    for (const auto* a = f->FirstAttribute(); a; a = a->Next()) {
        const std::string n = a->Name();
        if (n == "size") {
            const auto s = r.numbers(a, 2, 2);
            for (double v : s)
                if (!(v >= 1 && v <= 65536 && v == std::floor(v)))
                    r.fail(a, "width and height must be whole numbers from 1 to 65536");
            W = s[0], H = s[1];
        } else if (n == "center") {
            const auto c = r.numbers(a, 2, 2);
            cx = c[0], cy = c[1];
        } else if (n == "scale") {
            ppu = r.number(a, 1e-300, 1e300);
        } else if (n == "rotate") {
            rotate = r.number(a);
        } else if (n == "zoom") {
            zoom = r.number(a, -30, 30);
        } else if (n == "quality") {
            quality = r.number(a, 1e-9, 1e9);
        } else if (n == "supersample" || n == "oversample") {
            ss = r.number(a, 1, 16);
        } else if (n == "filter") {
            filter = r.number(a, 0, 64);
        } else if (n == "filter_shape") {
            filter_shape = a->Value();
        } else if (n == "estimator_radius") {
            est = r.number(a, 0, 64);
        } else if (n == "estimator_minimum") {
            est_min = r.number(a, 0, 64);
        } else if (n == "estimator_curve") {
            est_curve = r.number(a, 1e-9, 4);
        } else if (n == "gamma") {
            gamma = r.number(a, 1e-9, 1e9);
        } else if (n == "brightness") {
            brightness = r.number(a, 1e-9, 1e9);
        } else if (n == "vibrancy") {
            vibrancy = r.number(a, 0, 1);
        } else if (n == "highlight_power") {
            highlight = r.number(a, -1, 16);
        } else if (n == "gamma_threshold") {
            gthresh = r.number(a, 0, 1);
        } else if (n == "background") {
            bg = r.numbers(a, 3, 3);
            for (double v : bg)
                if (!(v >= 0 && v <= 1)) r.fail(a, "a channel out of range [0, 1]");
        } else if (n == "palette_mode") {
            palette_mode = a->Value();
            if (palette_mode != "step" && palette_mode != "linear") r.fail(a, "expected step or linear");
        } else if (n == "contrast") {
            contrast = r.number(a, 1e-9, 1e9);
        }
        // hue and palette are read with the palette; the rest is metadata or animation (name,
        // version, time, interpolation, the temporal samples of a motion blur, which a genome
        // without motion does not show): a still render does not read it.
    }
    if (filter_shape != "gaussian" && filter_shape != "box" && filter_shape != "mitchell" &&
        filter_shape.rfind("lanczos", 0) != 0) {
        warn.push_back("filter_shape " + quote(filter_shape) + " is not one of fixpoint's: gaussian is used");
        filter_shape = "gaussian";
    }
    if (filter_shape.rfind("lanczos", 0) == 0) filter_shape = "lanczos";
    std::string palette = palette_of(r, f, warn);

    // The view: flam3's camera, centre and pixels per unit (times 2^zoom), its y axis down.
    const double scale = ppu * std::pow(2.0, zoom);
    const double hw = W / scale / 2, hh = H / scale / 2;
    const double points = std::max(1.0, std::round(quality * std::pow(4.0, zoom) * W * H));
    if (points > 1e15) r.fail(f, "quality times the image's pixels is more than 1e15 points");

    // The maps in flam3's order of its xforms (those of a symmetry where its element stands), each
    // with its xaos row, whose entries are by that order; weight-0 xforms are left out after.
    struct Map {
        std::string text, comment;
        std::vector<double> chaos;
        bool kept = true;
    };
    std::vector<Map> xf;
    std::vector<std::string> finals;
    int n = 0;
    for (const auto* x = f->FirstChildElement(); x; x = x->NextSiblingElement()) {
        const std::string nm = x->Name();
        if (nm == "symmetry") {
            // flam3's parser adds its xforms on reading it (also where flam3-genome wrote them out
            // beside it: flam3-render then has them twice, and so do we).
            const auto* kind = x->FindAttribute("kind");
            if (!kind) r.fail(x, "symmetry: expected kind=\"N\"");
            const double sym = r.number(kind, -1000, 1000);
            if (sym != std::floor(sym)) r.fail(kind, num(sym) + " is not a whole number");
            if (sym == 0) warn.push_back("symmetry kind 0: flam3 picks a random symmetry; none is added");
            for (const auto& m : symmetry_xforms(int(sym)))
                xf.push_back({m.substr(0, m.size() - 1),
                              "symmetry " + num(sym) + " (line " + std::to_string(x->GetLineNum()) + ")",
                              {},
                              true});
            continue;
        }
        if (nm != "xform" && nm != "finalxform") continue;
        const std::string what =
            nm + " " + std::to_string(n++) + " (line " + std::to_string(x->GetLineNum()) + ")";
        double w = 1;
        std::vector<double> chaos;
        const std::string m = xform(r, x, nm == "finalxform", warn, w, chaos, what);
        if (nm == "finalxform")
            finals.push_back("    - " + m + "}  # " + what);
        else
            xf.push_back({m, what, chaos, w > 0});
    }
    // Each kept map's xaos row over the kept maps (1 past its end, as flam3 reads it).
    std::vector<std::size_t> kept;
    for (std::size_t i = 0; i < xf.size(); ++i)
        if (xf[i].kept) kept.push_back(i);
    if (kept.empty()) r.fail(f, "the flame has no xform of positive weight");
    std::vector<std::string> maps;
    for (const auto& m : xf) {
        if (!m.kept) {
            maps.push_back("    # " + m.comment + ": weight 0, never chosen (flam3 skips it too)");
            continue;
        }
        std::vector<double> row;
        for (std::size_t i : kept) row.push_back(i < m.chaos.size() ? m.chaos[i] : 1.0);
        while (!row.empty() && row.back() == 1) row.pop_back();
        std::string c;
        for (std::size_t i = 0; i < row.size(); ++i) c += (i ? ", " : ", chaos: [") + num(row[i]);
        if (!row.empty()) c += "]";
        if (!row.empty() && std::all_of(row.begin(), row.end(), [](double v) { return v == 0; }) &&
            row.size() == kept.size())
            r.fail(f, m.comment + ": its chaos is 0 for every xform: none may follow it");
        maps.push_back("    - " + m.text + c + "}  # " + m.comment);
    }

    std::ostringstream y;
    const char* name = f->Attribute("name");
    y << "# Imported from " << std::filesystem::path(path).filename().string() << ", flame " << k
      << (name ? std::string(" (") + name + ")" : std::string()) << " of " << flames.size()
      << ", by fixpoint import (docs/flam3.md).\n";
    y << "# flam3's camera: size " << num(W) << " " << num(H) << ", center " << num(cx) << " " << num(cy)
      << ", scale " << num(ppu) << ", zoom " << num(zoom) << ", rotate " << num(rotate) << ".\n";
    for (const auto& w : warn) y << "# not carried over: " << w << "\n";
    y << "renderer:\n  type: chaos-game\n";
    y << "  width: " << num(W) << "\n  height: " << num(H) << "\n";
    y << "  view: [" << num(cx - hw) << ", " << num(cx + hw) << ", " << num(cy - hh) << ", " << num(cy + hh)
      << "]  # center and scale\n";
    y << "  y_axis: down  # flam3's image rows run down the y axis\n";
    if (rotate != 0) y << "  rotate: " << num(rotate) << "\n";
    y << "  points: " << num(points) << "  # quality " << num(quality) << " per pixel\n";
    y << "  inversion_rules: off\n";
    // flam3's starts and bad points: a random point of [-1, 1]^2, and a chain whose point is not
    // finite goes on from such a point at once (flam3_iterate, apply_xform).
    // flam3 starts one chain a sub-batch of 10 000 samples and plots it after 15 steps (its
    // fuse; 100 with earlyclip); fixpoint's 4096 chains each plot points / 4096, a tenth of that
    // at quality 400 on 100^2, and their first points, not yet on the attractor, were a haze
    // over the sparse regions of weakly contracting genomes (genome-033: SSIM 0.900 against
    // flam3's own 0.971 at 20 skipped steps, 0.977 at 60 or 100): skip 100.
    y << "  start_box: [-1, 1, -1, 1]\n  skip: 100\n  restart_skip: 0\n  escape: 1e10  # flam3's badvalue\n";
    if (ss > 1) y << "  supersample: " << num(std::round(ss)) << "\n";
    if (filter > 0) y << "  filter: {type: " << filter_shape << ", radius: " << num(filter) << "}\n";
    if (est > 0) {
        y << "  estimator_radius: " << num(est) << "\n  estimator_minimum: " << num(std::min(est_min, est))
          << "\n  estimator_curve: " << num(est_curve) << "\n";
    }
    y << "  background: [" << num(bg[0]) << ", " << num(bg[1]) << ", " << num(bg[2]) << "]\n";
    y << "  colourer: {type: flame, density: flam3, brightness: " << num(brightness)
      << ", contrast: " << num(contrast) << ",\n    gamma: " << num(gamma) << ", vibrancy: " << num(vibrancy)
      << ", highlight_power: " << num(highlight) << ", gamma_threshold: " << num(gthresh)
      << ", palette_mode: " << palette_mode << ",\n    " << palette << "}\n";
    y << "  maps:\n";
    for (const auto& m : maps) y << m << "\n";
    if (!finals.empty()) {
        y << "  final:\n";
        for (const auto& m : finals) y << m << "\n";
    }
    if (!output.empty()) y << "output:\n  path: " << output << "\n";
    out.yaml = y.str();
    return out;
}

} // namespace fp::host
