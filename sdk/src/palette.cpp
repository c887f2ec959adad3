// Palettes (fixpoint/palette.hpp): the built-in gradients, gradients of stops, and flam3's
// palette file, read with tinyxml2 (Debian's libtinyxml2-dev) where flam3-palette installs it.
// No palette of flam3's is copied here: the built-ins are fixpoint's own.
#include <fixpoint/errors.hpp>
#include <fixpoint/palette.hpp>
#include <fixpoint/text.hpp>

#include <tinyxml2.h>

#include <cctype>
#include <cstdlib>
#include <map>
#include <mutex>
#include <utility>

namespace fp {

namespace {

/// fixpoint's gradients: name and stops {t, r, g, b}.
struct Builtin {
    const char* name;
    std::vector<double> stops;
};

const std::vector<Builtin>& builtins() {
    static const std::vector<Builtin> b = {
        {"grey", {0, 0, 0, 0, 1, 1, 1, 1}},
        {"fire", {0, 0, 0, 0, 0.35, 0.6, 0.05, 0, 0.7, 1, 0.55, 0, 1, 1, 1, 0.8}},
        {"ice", {0, 0.02, 0.02, 0.1, 0.5, 0.1, 0.45, 0.8, 1, 0.9, 1, 1}},
        {"sea", {0, 0, 0.05, 0.15, 0.5, 0, 0.5, 0.55, 1, 0.85, 1, 0.8}},
        {"sunset", {0, 0.1, 0.02, 0.25, 0.4, 0.75, 0.15, 0.35, 0.75, 1, 0.55, 0.2, 1, 1, 0.9, 0.6}},
        {"spectrum", {0, 1, 0,       0, 1.0 / 6, 1, 1,       0, 2.0 / 6, 0, 1, 0, 0.5, 0,
                      1, 1, 4.0 / 6, 0, 0,       1, 5.0 / 6, 1, 0,       1, 1, 1, 0,   0}},
    };
    return b;
}

int hex_digit(char c) {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
}

/// A palette's `data`: 256 entries of 8 hex digits "00RRGGBB", whitespace between them.
bool parse_data(const char* data, Palette& out) {
    int n = 0, digits = 0;
    unsigned v = 0;
    for (const char* c = data; *c; ++c) {
        if (std::isspace(static_cast<unsigned char>(*c))) continue;
        const int d = hex_digit(*c);
        if (d < 0) return false;
        v = v << 4 | unsigned(d);
        if (++digits < 8) continue;
        if (n >= Palette::size) return false;
        out.colours[std::size_t(n++)] =
            Rgb{float((v >> 16) & 0xff) / 255.0f, float((v >> 8) & 0xff) / 255.0f, float(v & 0xff) / 255.0f};
        digits = 0, v = 0;
    }
    return n == Palette::size && digits == 0;
}

std::string did_you_mean(const std::string& word, const std::vector<std::string>& names) {
    const auto near = suggest(word, names);
    return near.empty() ? "" : " (did you mean '" + near[0] + "'?)";
}

} // namespace

const char* palette_builtins() { return "grey|fire|ice|sea|sunset|spectrum"; }

Palette palette_of_stops(const std::vector<double>& stops, const std::string& param) {
    if (stops.size() < 4 || stops.size() % 4 != 0)
        throw ParamError(param, "expected stops of four numbers each (t, r, g, b), got " +
                                    std::to_string(stops.size()) + " numbers");
    for (std::size_t i = 0; i < stops.size(); i += 4) {
        for (std::size_t j = 0; j < 4; ++j)
            if (!(stops[i + j] >= 0 && stops[i + j] <= 1))
                throw ParamError(param, "stop " + std::to_string(i / 4) + ": every number must be in [0, 1]");
        if (i > 0 && !(stops[i] > stops[i - 4]))
            throw ParamError(param, "stop " + std::to_string(i / 4) + ": the positions must increase");
    }
    Palette p;
    const std::size_t k = stops.size() / 4;
    for (int e = 0; e < Palette::size; ++e) {
        const double t = (e + 0.5) / Palette::size;
        std::size_t s = 0;
        while (s + 1 < k && stops[4 * (s + 1)] <= t) ++s;
        const double* a = &stops[4 * s];
        if (t <= a[0] || s + 1 == k) {
            p.colours[std::size_t(e)] = Rgb{float(a[1]), float(a[2]), float(a[3])};
            continue;
        }
        const double* b = &stops[4 * (s + 1)];
        const double f = (t - a[0]) / (b[0] - a[0]);
        p.colours[std::size_t(e)] = Rgb{float(a[1] + (b[1] - a[1]) * f), float(a[2] + (b[2] - a[2]) * f),
                                        float(a[3] + (b[3] - a[3]) * f)};
    }
    return p;
}

std::string flam3_palette_file() {
    if (const char* e = std::getenv("FIXPOINT_FLAM3_PALETTES"); e && *e) return e;
    return "/usr/share/flam3/flam3-palettes.xml";
}

Palette read_flam3_palette(const std::string& path, const std::string& which, const std::string& param) {
    // Read once per file and palette: a colourer is built for every draft and preview.
    static std::mutex m;
    static std::map<std::pair<std::string, std::string>, Palette> cache;
    std::lock_guard<std::mutex> lock(m);
    if (const auto it = cache.find({path, which}); it != cache.end()) return it->second;
    tinyxml2::XMLDocument doc;
    const tinyxml2::XMLError rc = doc.LoadFile(path.c_str());
    if (rc == tinyxml2::XML_ERROR_FILE_NOT_FOUND || rc == tinyxml2::XML_ERROR_FILE_COULD_NOT_BE_OPENED)
        throw ParamError(param, "flam3's palettes are read from " + quote(path, 200) +
                                    ", which is not there: install Debian's flam3-palette (or set "
                                    "FIXPOINT_FLAM3_PALETTES to the file)");
    const tinyxml2::XMLElement* root =
        rc == tinyxml2::XML_SUCCESS ? doc.FirstChildElement("palettes") : nullptr;
    if (!root) throw ParamError(param, quote(path, 200) + " is not a flam3 palette file (no <palettes>)");
    std::vector<std::string> names;
    const bool by_number = !which.empty() && which.find_first_not_of("0123456789") == std::string::npos;
    for (const auto* e = root->FirstChildElement("palette"); e; e = e->NextSiblingElement("palette")) {
        const char* number = e->Attribute("number");
        const char* name = e->Attribute("name");
        if (name) names.emplace_back(name);
        const bool match = by_number ? number && which == number : name && which == name;
        if (!match) continue;
        Palette p;
        const char* data = e->Attribute("data");
        if (!data || !parse_data(data, p))
            throw ParamError(param, "palette " + quote(which) + " of " + quote(path, 200) +
                                        ": its data is not 256 colours of 8 hex digits");
        cache.emplace(std::pair{path, which}, p);
        return p;
    }
    throw ParamError(param, quote(path, 200) + " holds no palette " + (by_number ? "number " : "named ") +
                                quote(which) + (by_number ? "" : did_you_mean(which, names)));
}

Palette palette_named(const std::string& name, const std::string& param) {
    if (name.rfind("flam3:", 0) == 0) return read_flam3_palette(flam3_palette_file(), name.substr(6), param);
    std::vector<std::string> names;
    for (const auto& b : builtins()) {
        if (name == b.name) return palette_of_stops(b.stops, param);
        names.emplace_back(b.name);
    }
    throw ParamError(param, "unknown palette " + quote(name) + did_you_mean(name, names) +
                                "; the built-ins are " + std::string(palette_builtins()) +
                                ", and flam3's are flam3:N or flam3:NAME");
}

bool palette_of(const ParamBag& p, Palette& out) {
    // (Read whether or not a palette is given: the host refuses a declared parameter never read.)
    const bool linear = p.string("palette_mode") == "linear";
    const bool named = p.has("palette"), stops = p.has("palette_stops");
    if (named && stops)
        throw ParamError("palette_stops",
                         "give a palette by name (palette) or by its stops (palette_stops), not both");
    if (!named && !stops) return false;
    out = named ? palette_named(p.string("palette"), "palette")
                : palette_of_stops(p.reals("palette_stops"), "palette_stops");
    out.linear = linear;
    return true;
}

} // namespace fp
