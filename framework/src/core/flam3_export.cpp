// A chaos-game config as a flam3 genome (host/core/flam3_import.hpp; docs/flam3.md): the inverse
// of flam3_import.cpp for what the format holds, so that import, export and import again give
// the same config. Read from the resolved recipe (every default filled in, canonical numbers),
// with the user's file for the places of errors. What a genome cannot hold is a warning (a
// map's own colour, a colourer other than flame), or an error at its place where the genome
// would be another picture (another renderer or scheme, a map that is not flam3's).
#include <fixpoint/host/core/config.hpp>
#include <fixpoint/host/core/flam3_import.hpp>
#include <fixpoint/host/core/pipeline.hpp>

#include <fixpoint/errors.hpp>
#include <fixpoint/flam3_table.hpp>
#include <fixpoint/palette.hpp>
#include <fixpoint/text.hpp>

#include <tinyxml2.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

namespace fp::host {

namespace {

using fp_flam3::param_info;
using fp_flam3::var_info;

double real(const CNode& n) { return std::stod(n.scalar); }

/// The recipe's text of `key` in map m, or `def` where the recipe leaves it out.
std::string text(const CNode& m, const char* key, const char* def) {
    const CNode* n = m.find(key);
    return n && n->is_scalar() ? n->scalar : def;
}

/// A list of numbers as flam3 writes them: separated by spaces.
std::string joined(const CNode& seq) {
    std::string s;
    for (const auto& i : seq.items) s += (s.empty() ? "" : " ") + i.scalar;
    return s;
}

int var_named(const std::string& n) {
    for (std::uint32_t v = 0; v < fp_flam3::var_count; ++v)
        if (n == var_info[v].name) return int(v);
    return -1;
}
int var_of_plugin(const std::string& t) {
    for (std::uint32_t v = 0; v < fp_flam3::var_count; ++v)
        if (t == var_info[v].plugin) return int(v);
    return -1;
}
int param_named(const std::string& n) {
    for (std::uint32_t p = 0; p < fp_flam3::param_count; ++p)
        if (n == param_info[p].name) return int(p);
    return -1;
}

[[noreturn]] void fail(const Mark& m, const std::string& msg) { throw InputError(m.str() + ": " + msg); }

/// Map `m` of the recipe (j of k; `place` in the user's file) as xform element x.
void write_xform(tinyxml2::XMLElement* x, const CNode& m, const Mark& place, const std::string& what,
                 std::size_t j, std::size_t k, bool final, std::vector<std::string>& warn) {
    const std::string type = m.find("type")->scalar;
    std::vector<double> weights(fp_flam3::var_count, 0.0);
    std::vector<std::pair<int, std::string>> params;
    if (type == "affine") {
        // x' = a x + b y + e, y' = c x + d y + f; flam3's coefs are c00 c01 c10 c11 c20 c21 with
        // t = (c00 x + c10 y + c20, c01 x + c11 y + c21).
        std::vector<std::string> c(6, "0");
        if (const CNode* co = m.find("coefficients")) {
            for (std::size_t i = 0; i < 6; ++i) c[i] = co->items[i].scalar;
        } else {
            const CNode* mx = m.find("matrix");
            const CNode* of = m.find("offset");
            for (std::size_t i = 0; i < 4; ++i) c[i] = mx->items[i].scalar;
            for (std::size_t i = 0; i < 2; ++i) c[4 + i] = of ? of->items[i].scalar : "0";
        }
        x->SetAttribute("coefs",
                        (c[0] + " " + c[2] + " " + c[1] + " " + c[3] + " " + c[4] + " " + c[5]).c_str());
        weights[0] = 1;
    } else if (type == "xform" || var_of_plugin(type) >= 0) {
        if (type != "xform") weights[std::size_t(var_of_plugin(type))] = 1; // (its weight key overrides)
        for (const auto& [key, v] : m.keys) {
            if (key == "coefs" || key == "post") {
                x->SetAttribute(key.c_str(), joined(v).c_str());
            } else if (const int w = var_named(key); w >= 0) {
                weights[std::size_t(w)] = real(v);
            } else if (const int p = param_named(key); p >= 0) {
                params.emplace_back(p, v.scalar);
            }
        }
    } else {
        fail(place, what + ": a genome holds xforms, flam3's variations and affine maps, not " + quote(type));
    }
    for (std::uint32_t v = 0; v < fp_flam3::var_count; ++v)
        if (weights[v] != 0) x->SetAttribute(var_info[v].name, number_text(weights[v]).c_str());
    // The parameters of the variations it uses (the recipe has every one's default).
    for (const auto& [p, text] : params)
        if (weights[param_info[p].var] != 0) x->SetAttribute(param_info[p].name, text.c_str());
    if (!final) x->SetAttribute("weight", m.find("weight") ? m.find("weight")->scalar.c_str() : "1");
    // (Without `color` the chaos game spreads the maps over the palette: map j at j / (k - 1).)
    const CNode* color = m.find("color");
    x->SetAttribute("color", color ? color->scalar.c_str()
                                   : number_text(k > 1 && !final ? double(j) / double(k - 1) : 0).c_str());
    if (const CNode* s = m.find("color_speed")) x->SetAttribute("color_speed", s->scalar.c_str());
    if (const CNode* o = m.find("opacity"); o && real(*o) < 1) x->SetAttribute("opacity", o->scalar.c_str());
    if (const CNode* c = m.find("chaos")) x->SetAttribute("chaos", joined(*c).c_str());
    if (m.find("colour"))
        warn.push_back(what + ".colour is not carried over (a genome colours by its palette, `color`)");
}

/// The colourer's palette as 256 <color> elements (or palette="N" for flam3's own).
void write_palette(tinyxml2::XMLElement* flame, const CNode* col, std::vector<std::string>& warn) {
    const CNode* name = col ? col->find("palette") : nullptr;
    const CNode* stops = col ? col->find("palette_stops") : nullptr;
    if (name && name->scalar.rfind("flam3:", 0) == 0 &&
        name->scalar.find_first_not_of("0123456789", 6) == std::string::npos) {
        flame->SetAttribute("palette", name->scalar.substr(6).c_str());
        return;
    }
    Palette p;
    if (name) {
        p = palette_named(name->scalar, "palette");
    } else if (stops) {
        std::vector<double> v;
        for (const auto& i : stops->items) v.push_back(real(i));
        p = palette_of_stops(v, "palette_stops");
        // 256 stops at i / 256 (the importer's, flam3's entries) are the entries themselves.
        bool entries = v.size() == 4 * std::size_t(Palette::size);
        for (std::size_t i = 0; entries && i < std::size_t(Palette::size); ++i)
            entries = v[4 * i] == double(i) / Palette::size;
        for (std::size_t i = 0; entries && i < std::size_t(Palette::size); ++i)
            p.colours[i] = Rgb{float(v[4 * i + 1]), float(v[4 * i + 2]), float(v[4 * i + 3])};
    } else {
        warn.push_back("the colourer has no palette: the genome's is white");
        p.colours.fill(Rgb{1, 1, 1});
    }
    for (int i = 0; i < Palette::size; ++i) {
        const Rgb c = p.colours[std::size_t(i)];
        // flam3's channels are 0..255, decimals allowed: to 4 places, so that a palette read from
        // a genome's bytes (or flam3-genome's decimals) comes back as those.
        auto ch = [](float f) { return number_text(std::round(double(f) * 255.0 * 1e4) / 1e4); };
        auto* e = flame->InsertNewChildElement("color");
        e->SetAttribute("index", i);
        e->SetAttribute("rgb", (ch(c.r) + " " + ch(c.g) + " " + ch(c.b)).c_str());
    }
}

} // namespace

Flam3Export export_flam3(const Registry& reg, const std::string& config,
                         const std::vector<std::string>& sets) {
    const Pipeline pl = load_pipeline(reg, config, sets);
    const CNode user = load_config(config, false);
    const CNode tree = parse_yaml(pl.recipe, config + " (its recipe)");
    Flam3Export out;
    auto& warn = out.warnings;
    const CNode* ur = user.find("renderer");
    const CNode* r = tree.find("renderer");
    if (pl.renderer_type != "chaos-game")
        fail(ur->find("type") ? ur->find("type")->mark : ur->mark,
             "a genome is a chaos game of flam3's: not the renderer " + quote(pl.renderer_type));
    auto at = [&](const char* key) { return ur->find(key) ? ur->find(key)->mark : ur->mark; };
    if (const CNode* it = r->find("iteration"); it && it->find("type")->scalar != "picard")
        fail(at("iteration"),
             "flam3 iterates its maps (Picard): not the scheme " + quote(it->find("type")->scalar));
    if (text(*r, "fit_view", "false") == "true")
        warn.push_back("fit_view: the genome takes the config's view as written");

    tinyxml2::XMLDocument doc;
    auto* flame = doc.NewElement("flame");
    doc.InsertEndChild(flame);
    flame->SetAttribute("name", std::filesystem::path(config).stem().string().c_str());
    flame->SetAttribute("version", "fixpoint");
    const double W = std::stod(text(*r, "width", "100")), H = std::stod(text(*r, "height", "100"));
    const CNode& v = *r->find("view");
    const double x0 = real(v.items[0]), x1 = real(v.items[1]), y0 = real(v.items[2]), y1 = real(v.items[3]);
    const double scale = W / (x1 - x0);
    if (std::fabs((y1 - y0) * scale - H) > 1e-9 * H)
        warn.push_back("the view's pixels are not square: flam3's are (its scale is the width's)");
    if (text(*r, "y_axis", "up") != "down")
        warn.push_back("y_axis up: flam3's rows run down its y axis, so its picture is this one upside down");
    flame->SetAttribute("size", (number_text(W) + " " + number_text(H)).c_str());
    flame->SetAttribute("center", (number_text((x0 + x1) / 2) + " " + number_text((y0 + y1) / 2)).c_str());
    flame->SetAttribute("scale", number_text(scale).c_str());
    flame->SetAttribute("rotate", text(*r, "rotate", "0").c_str());
    flame->SetAttribute("quality", number_text(std::stod(text(*r, "points", "1")) / (W * H)).c_str());
    flame->SetAttribute("supersample", text(*r, "supersample", "1").c_str());
    if (const CNode* f = r->find("filter")) {
        flame->SetAttribute("filter", f->find("radius")->scalar.c_str());
        flame->SetAttribute("filter_shape", f->find("type")->scalar.c_str());
    } else {
        flame->SetAttribute("filter", "0");
    }
    const double est = std::stod(text(*r, "estimator_radius", "0"));
    flame->SetAttribute("estimator_radius", number_text(est).c_str());
    if (est > 0) {
        flame->SetAttribute("estimator_minimum", text(*r, "estimator_minimum", "0").c_str());
        flame->SetAttribute("estimator_curve", text(*r, "estimator_curve", "0.4").c_str());
        if (std::stod(text(*r, "estimator_quality", "0")) > 0)
            warn.push_back("estimator_quality: flam3 chooses its kernels from the hits as they are (its "
                           "picture is this one's where its quality is estimator_quality)");
    }
    if (const CNode* b = r->find("background")) flame->SetAttribute("background", joined(*b).c_str());

    const CNode* col = r->find("colourer");
    if (col->find("type")->scalar != "flame") {
        warn.push_back("colourer " + col->find("type")->scalar + ": a genome is shaded by flam3's tone");
        col = nullptr;
    } else {
        for (const char* k : {"gamma", "brightness", "contrast", "vibrancy", "highlight_power",
                              "gamma_threshold", "palette_mode"})
            if (col->find(k)) flame->SetAttribute(k, col->find(k)->scalar.c_str());
        if (text(*col, "density", "log") != "flam3")
            warn.push_back("density log: a genome's tone is flam3's (density flam3), its brightness flam3's");
        if (text(*col, "mode", "mean") != "mean")
            warn.push_back("mode " + text(*col, "mode", "mean") + ": flam3's pixels show the mean colour");
    }
    write_palette(flame, col, warn);

    const CNode& maps = *r->find("maps");
    const CNode* umaps = ur->find("maps");
    const std::size_t k = maps.items.size();
    for (std::size_t j = 0; j < k; ++j) {
        const Mark& place = umaps && j < umaps->items.size() ? umaps->items[j].mark : ur->mark;
        auto* x = doc.NewElement("xform");
        write_xform(x, maps.items[j], place, "maps[" + std::to_string(j) + "]", j, k, false, warn);
        flame->InsertEndChild(x);
    }
    if (const CNode* fin = r->find("final"); fin && !fin->items.empty()) {
        const CNode* ufin = ur->find("final");
        auto* x = doc.NewElement("finalxform");
        write_xform(x, fin->items[0], ufin && !ufin->items.empty() ? ufin->items[0].mark : ur->mark,
                    "final[0]", 0, 1, true, warn);
        flame->InsertEndChild(x);
        if (fin->items.size() > 1)
            warn.push_back("flam3 has one final xform: final[1] and after are not carried over");
    }
    tinyxml2::XMLPrinter printer;
    doc.Print(&printer);
    out.xml = printer.CStr();
    return out;
}

} // namespace fp::host
