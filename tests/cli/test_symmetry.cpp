// `fixpoint symmetry`: first on synthetic pictures whose symmetry follows by hand, then on paper
// 04's claims, from renders of configs/orbit-trap/ at 161 x 161 pixels (the configs' area
// [-2 pi, 2 pi]^2 then puts the period 2 pi exactly 80 pixels apart), 8 samples per pixel.
//
// The paper's claims and what the renders show:
//   - Sec. 4: only Figs. 5(a), 5(c), 5(g) keep p3m1, the other panels cm; Fig. 5(e) keeps cm only.
//     Measured so. (Fig. 5(c)'s traps, Fig. 1b, are centred at (0, 0.02), not at the origin: its
//     3-fold rotation is not exact either way, and still scores 0.97.)
//   - Fig. 10: "magnify the area near the origin further and we get the same images repeatedly".
//     The origin is a fixed point of the step S (Picard or the S-iteration) and the traps leave
//     a disc about it free, so a pixel p whose first point S(p) escapes the traps has the colour
//     of S(p) (its orbit is that of S(p), one step later), and near 0, S(p) ~ J p with J the
//     Jacobian at 0. The claim made measurable: a render of the area A / |J| against a render of A,
//     under p -> J p, agrees almost everywhere; under a wrong scale or turn it does not. J from
//     `fixpoint eval` (finite differences): -3.71 I (10a: a half-turn with the magnification, so
//     +3.71 I fails, p3m1 having no 2-fold rotation), -18.8 I (10b), a spiral similarity of
//     ratio 8.64 (10c: complex alpha, p4 map). For 10a it holds only well inside the trap-free
//     disc (radius 0.53) and where the map's quadratic terms are small: at [-0.03, 0.03]^2, not
//     at the config's [-1, 1]^2 (measured 0.13: the config's comment overstates it).
//   - Every config whose traps share the map's group keeps that group: the table below. It does
//     not hold for the lattice translations under the S-iteration with beta != 1 (Figs. 8a, 8c,
//     8d, 9a-9d): u_0 = (1 - beta) p_0 + beta f(p_0) is computed from the start point p_0, which
//     is not reduced, so p_0 and p_0 + 2 pi start different orbits; the point groups (D4, C4)
//     are kept. Nor for the mirror of Figs. 7(b), 7(c): Rickman balls with gamma 0.7 and 0.5 around
//     (0, +-3.5) overlap, and the first trap that holds a point catches it (Algorithm 3), so the
//     mirror (x, -y), which swaps the traps, is broken where they overlap (the render with the
//     traps' order reversed is exactly the mirror image; see MirrorBrokenByTrapOrder).
#include "cli.hpp"

#include <fixpoint/host/core/image_io.hpp>
#include <fixpoint/host/tools/symmetry.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <map>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

using namespace fp::test;

namespace {

constexpr double pi = std::numbers::pi;

std::string config(const std::string& name) {
    return fp::test::source_dir() + "/configs/orbit-trap/" + name + ".yaml";
}

std::vector<std::string> small(std::vector<std::string> args) {
    for (const char* s : {"renderer.width=161", "renderer.height=161"}) args.insert(args.end(), {"--set", s});
    args.insert(args.end(), {"--threads", "2", "-q"});
    return args;
}

/// A 161 x 161 picture of a scalar field v over [-2 pi, 2 pi]^2 (pixel 0 at -2 pi, as the
/// default frame of an image without a recipe), coloured smoothly, written without a recipe.
std::string synthetic(const std::string& name, const std::function<double(double, double)>& v) {
    fp::Image img;
    img.width = img.height = 161;
    img.channels = 3;
    img.pixels.resize(161 * 161 * 3);
    for (int j = 0; j < 161; ++j)
        for (int i = 0; i < 161; ++i) {
            const double x = -2 * pi + 4 * pi * i / 160, y = 2 * pi - 4 * pi * j / 160;
            const double t = v(x, y);
            float* px = &img.pixels[(std::size_t(j) * 161 + i) * 3];
            px[0] = float(0.5 + 0.5 * std::tanh(t));
            px[1] = float(0.5 + 0.5 * std::sin(2 * t));
            px[2] = float(0.5 + 0.5 * std::cos(3 * t));
        }
    const std::string path = fp::test::scratch_dir("symmetry-" + name) + "/" + name + ".png";
    fp::host::write_image(img, path, 8, "");
    return path;
}

struct Measured {
    int rc = -1;
    std::map<std::string, double> score; ///< by operation id; NaN: n/a
    std::string largest, lattice, point_group, out, err;
};

/// The reports of `fixpoint symmetry ... --json` (one object, or a list of them), read by
/// scanning (the JSON is flat and its strings hold no escapes).
std::vector<Measured> reports(const std::string& out, int rc, const std::string& err) {
    const auto field = [&](const std::string& key, std::size_t from) {
        const auto k = out.find("\"" + key + "\": ", from);
        if (k == std::string::npos) return std::string();
        const auto b = k + key.size() + 4;
        if (out[b] == '"') return out.substr(b + 1, out.find('"', b + 1) - b - 1);
        return out.substr(b, out.find_first_of(",}]", b) - b);
    };
    std::vector<Measured> ms;
    for (std::size_t at = out.find("{\"image\": "); at != std::string::npos;) {
        const std::size_t next = out.find("{\"image\": ", at + 1);
        const std::string text = out.substr(at, next == std::string::npos ? std::string::npos : next - at);
        Measured m;
        m.rc = rc, m.out = text, m.err = err;
        for (std::size_t p = text.find("{\"id\": "); p != std::string::npos;
             p = text.find("{\"id\": ", p + 1)) {
            const std::string id = field("id", at + p), s = field("score", at + p);
            m.score[id] = s == "null" ? NAN : std::stod(s);
        }
        m.largest = field("largest", at);
        m.lattice = field("largest_lattice", at);
        m.point_group = field("point_group", at);
        ms.push_back(m);
        at = next;
    }
    if (ms.empty()) {
        Measured m;
        m.rc = rc, m.out = out, m.err = err;
        ms.push_back(m);
    }
    return ms;
}

Measured measure(const std::vector<std::string>& args) {
    std::vector<std::string> a = {"symmetry"};
    a.insert(a.end(), args.begin(), args.end());
    a.push_back("--json");
    const auto r = run_cli(a);
    return reports(r.out, r.rc, r.err).front();
}

const std::vector<std::string> all_configs = {
    "fig5a", "fig5a-hexagonal", "fig5b", "fig5c", "fig5d", "fig5e", "fig5f",  "fig5g",  "fig6a", "fig6b",
    "fig6c", "fig6d",           "fig6e", "fig6f", "fig7a", "fig7b", "fig7c",  "fig7d",  "fig8a", "fig8b",
    "fig8c", "fig8d",           "fig9a", "fig9b", "fig9c", "fig9d", "fig10a", "fig10b", "fig10c"};

/// Configs of configs/orbit-trap/ measured in one run (the plugins load once), by name.
std::map<std::string, Measured> measure_configs(const std::vector<std::string>& names) {
    std::vector<std::string> args = {"symmetry"};
    for (const auto& c : names) args.push_back(config(c));
    args.push_back("--json");
    const auto r = run_cli(small(args));
    EXPECT_EQ(r.rc, 0) << r.err;
    const auto ms = reports(r.out, r.rc, r.err);
    EXPECT_EQ(ms.size(), names.size()) << r.out << r.err;
    std::map<std::string, Measured> out;
    for (std::size_t k = 0; k < ms.size() && k < names.size(); ++k) out[names[k]] = ms[k];
    return out;
}

constexpr double kept = 0.85;  // the command's default threshold
constexpr double broken = 0.6; // what "well below" means here

void expect_kept(const Measured& m, const std::vector<std::string>& ids, const std::string& what) {
    for (const auto& id : ids) {
        ASSERT_TRUE(m.score.count(id)) << what << ": no score for " << id << "\n" << m.out << m.err;
        EXPECT_GE(m.score.at(id), kept) << what << ": " << id;
    }
}
void expect_broken(const Measured& m, const std::vector<std::string>& ids, const std::string& what) {
    for (const auto& id : ids) {
        ASSERT_TRUE(m.score.count(id)) << what << ": no score for " << id << "\n" << m.out << m.err;
        EXPECT_LT(m.score.at(id), broken) << what << ": " << id;
    }
}

const std::vector<std::string> hex_rot = {"r3", "r6"};

} // namespace

// ---------------------------------------------------------------- frames, by hand

// `area` (orbit-trap): pixel 0 at xmin, pixel W - 1 at xmax, row 0 at ymax. `view` (chaos-game):
// W cells, pixel i at the centre of cell i.
TEST(Symmetry, PixelFramesPlacePixelsAsTheRenderersDo) {
    fp::host::PixelFrame area;
    area.width = 5, area.height = 3, area.region = {-2, 2, -1, 1}, area.endpoints = true;
    EXPECT_DOUBLE_EQ(area.to_plane(0, 0).x, -2);
    EXPECT_DOUBLE_EQ(area.to_plane(4, 0).x, 2);
    EXPECT_DOUBLE_EQ(area.to_plane(0, 0).y, 1);
    EXPECT_DOUBLE_EQ(area.to_plane(0, 2).y, -1);
    fp::host::PixelFrame view = area;
    view.endpoints = false;
    EXPECT_DOUBLE_EQ(view.to_plane(0, 0).x, -1.6); // cells 0.8 wide
    EXPECT_DOUBLE_EQ(view.to_plane(4, 2).y, -2.0 / 3);
    for (const auto* f : {&area, &view}) {
        const fp::Vec2 q = f->to_pixel(f->to_plane(3.25, 1.5));
        EXPECT_NEAR(q.x, 3.25, 1e-12);
        EXPECT_NEAR(q.y, 1.5, 1e-12);
    }
    // An image without a recipe: [-2 pi, 2 pi] across, square pixels.
    const auto d = fp::host::default_frame(161, 81);
    EXPECT_DOUBLE_EQ(d.region.xmax, 2 * pi);
    EXPECT_DOUBLE_EQ(d.region.ymax, pi);
}

// ---------------------------------------------------------------- synthetic, by hand

// cos x + cos y: period 2 pi in x and y, unchanged by the quarter turn (-y, x) and the mirrors in
// the axes and diagonals: p4m. Not by (x + pi, y + pi) (both cosines change sign), so not a
// finer lattice; no 3- or 6-fold rotation.
TEST(Symmetry, SquareP4mPattern) {
    const auto m = measure({synthetic("p4m", [](double x, double y) { return std::cos(x) + std::cos(y); })});
    ASSERT_EQ(m.rc, 0) << m.err;
    expect_kept(m, {"t(2pi,0)", "t(0,2pi)", "r2", "r4", "m(x,-y)", "m(-x,y)", "m(y,x)"}, "p4m");
    for (const char* id : {"t(2pi,0)", "r4", "m(y,x)"}) EXPECT_GE(m.score.at(id), 0.99) << id;
    expect_broken(m, {"t(pi,pi)", "t(pi,pi*sqrt3)", "r3", "r6", "g(x+pi,-y)", "g(-x,y+pi)", "g(x+pi,pi-y)"},
                  "p4m");
    EXPECT_EQ(m.largest, "p4m");
    EXPECT_EQ(m.lattice, "square");
    EXPECT_EQ(m.point_group, "D4");
}

// cos(x + 2y) + 0.7 cos(2x - y) + 0.4 sin x sin 2y: every term even under p -> -p, periodic in
// 2 pi Z^2; the mirrors change x + 2y into x - 2y, the quarter turn swaps the first two terms'
// coefficients: p2 only.
TEST(Symmetry, OnlyTheHalfTurn) {
    const auto m = measure({synthetic("p2", [](double x, double y) {
        return std::cos(x + 2 * y) + 0.7 * std::cos(2 * x - y) + 0.4 * std::sin(x) * std::sin(2 * y);
    })});
    ASSERT_EQ(m.rc, 0) << m.err;
    expect_kept(m, {"t(2pi,0)", "t(0,2pi)", "r2"}, "p2");
    expect_broken(m, {"r4", "r3", "m(x,-y)", "m(-x,y)", "m(y,x)", "t(pi,pi)", "g(x+pi,-y)", "g(-x,y+pi)"},
                  "p2");
    EXPECT_EQ(m.largest, "p2");
    EXPECT_EQ(m.point_group, "C2");
}

// cos x + 0.8 sin y + 0.5 cos x cos 2y: even in x only: the mirror in the y axis and the lattice.
TEST(Symmetry, OnlyAMirror) {
    const auto m = measure({synthetic("pm", [](double x, double y) {
        return std::cos(x) + 0.8 * std::sin(y) + 0.5 * std::cos(x) * std::cos(2 * y);
    })});
    ASSERT_EQ(m.rc, 0) << m.err;
    expect_kept(m, {"t(2pi,0)", "t(0,2pi)", "m(-x,y)"}, "pm");
    expect_broken(m, {"r2", "r4", "m(x,-y)", "m(y,x)", "t(pi,pi)", "g(x+pi,-y)", "g(-x,y+pi)"}, "pm");
    EXPECT_EQ(m.largest, "pm");
    EXPECT_EQ(m.point_group, "D1");
}

// sum_i sin(R3^i w . p), w = (0, -2/sqrt 3) (paper 04's v1): the three wave vectors have the
// hexagonal lattice 2 pi (1, 0), 2 pi (1/2, sqrt 3/2) as periods and are permuted by the 3-fold
// rotation and by (-x, y); (x, -y) and the half turn negate them, which sin does not forgive:
// p3m1, exactly (no reduction here, so r3 scores ~1, unlike the maps' 96 %).
TEST(Symmetry, HexagonalP3m1Pattern) {
    const auto m = measure({synthetic("p3m1", [](double x, double y) {
        const double wy = -2 / std::sqrt(3.0);
        double s = 0;
        for (int i = 0; i < 3; ++i) {
            const double c = std::cos(2 * pi * i / 3), sn = std::sin(2 * pi * i / 3);
            s += std::sin(-sn * wy * x + c * wy * y);
        }
        return 1.5 * s;
    })});
    ASSERT_EQ(m.rc, 0) << m.err;
    expect_kept(m, {"t(2pi,0)", "t(pi,pi*sqrt3)", "r3", "m(-x,y)"}, "p3m1");
    EXPECT_GE(m.score.at("r3"), 0.97);
    expect_broken(m, {"t(0,2pi)", "r2", "r4", "r6", "m(x,-y)"}, "p3m1");
    EXPECT_EQ(m.largest, "p3m1");
    EXPECT_EQ(m.lattice, "hexagonal");
    EXPECT_EQ(m.point_group, "D3");
}

TEST(Symmetry, GroupExitCodesAndText) {
    const std::string img =
        synthetic("p4m-group", [](double x, double y) { return std::cos(x) + std::cos(y); });
    const auto yes = run_cli({"symmetry", img, "--group", "p4m"});
    EXPECT_EQ(yes.rc, 0) << yes.err;
    EXPECT_NE(yes.out.find("p4m: kept\n"), std::string::npos) << yes.out;
    EXPECT_NE(yes.out.find("has no recipe"), std::string::npos) << yes.out;
    // --group scores only the group's operations (every orientation of that name).
    EXPECT_EQ(yes.out.find("r3 "), std::string::npos) << yes.out;
    const auto no = run_cli({"symmetry", img, "--group", "p6m"});
    EXPECT_EQ(no.rc, 1) << no.err;
    EXPECT_NE(no.out.find("p6m: not kept\n"), std::string::npos) << no.out;
    EXPECT_EQ(run_cli({"symmetry", img, "--group", "D4"}).rc, 0);
    // The table names the largest group.
    const auto all = run_cli({"symmetry", img});
    EXPECT_EQ(all.rc, 0);
    EXPECT_NE(all.out.find("largest wallpaper group: p4m (square lattice)\n"), std::string::npos) << all.out;
}

TEST(Symmetry, BadInputIsOneLineExitTwo) {
    const std::string img = synthetic("bad", [](double x, double y) { return std::cos(x) + std::cos(y); });
    struct Bad {
        std::vector<std::string> args;
        std::string err;
    };
    const std::vector<Bad> bad = {
        {{"symmetry", img, "--group", "p4mm"},
         "--group: unknown group 'p4mm' (did you mean 'p4m'?): a wallpaper group p1, p2, pm, pg, cm, pmm, "
         "cmm, pmg, "
         "pgg, p4, p4m, p4g, p3, p3m1, p31m, p6, p6m or a point group C1, C2, C3, C4, C6, D1, D2, D3, D4, "
         "D6\n"},
        {{"symmetry", img, "--op", "[1, 0, 0]"},
         "--op '[1, 0, 0]': expected [a, b, c, d] or [a, b, c, d, tx, ty] (finite numbers: p -> [a b; c d] p "
         "+ t in "
         "the plane)\n"},
        {{"symmetry", img, "--area", "[1, 0, 0, 1]"},
         "--area '[1, 0, 0, 1]': expected [xmin, xmax, ymin, ymax], four finite numbers with xmin < xmax and "
         "ymin < "
         "ymax\n"},
        {{"symmetry", img, "--set", "renderer.width=9"}, "--set: only with a config (.yaml), not an image\n"},
        {{"symmetry", img + ".missing.png"}, ""},
    };
    for (const auto& b : bad) {
        const auto r = run_cli(b.args);
        EXPECT_EQ(r.rc, 2) << b.args[2];
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
        if (!b.err.empty()) {
            EXPECT_EQ(r.err, b.err);
        }
        EXPECT_EQ(r.out, "");
    }
    // A config's error points at its line and column, and nothing is rendered.
    const std::string dir = fp::test::scratch_dir("symmetry-bad-config");
    fp::test::write_file(dir + "/bad.yaml",
                         fp::test::replace_once(fp::test::read_file(config("fig5a")), "max_iterations: 100",
                                                "max_iterations: -3"));
    const auto r = run_cli({"symmetry", dir + "/bad.yaml"});
    EXPECT_EQ(r.rc, 2);
    EXPECT_NE(r.err.find("bad.yaml:"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("renderer.max_iterations"), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

// An image's recipe places it in the plane: the same render read back gives the config's scores.
TEST(Symmetry, ReadsTheRegionFromTheRecipe) {
    const std::string dir = fp::test::scratch_dir("symmetry-recipe");
    auto args = small({"render", config("fig5e"), "-o", dir + "/fig5e.png"});
    ASSERT_EQ(run_cli(args).rc, 0);
    const auto from_png = measure({dir + "/fig5e.png"});
    const auto from_yaml = measure(small({config("fig5e")}));
    ASSERT_EQ(from_png.rc, 0) << from_png.err;
    EXPECT_EQ(from_png.largest, "cm");
    // The PNG is the render quantised to 8 bits: the same scores within a hair.
    for (const auto& [id, s] : from_yaml.score) EXPECT_NEAR(from_png.score.at(id), s, 0.01) << id;
    // A contact sheet (another size than its recipe's) is refused unless the region is given.
    fp::Image sheet;
    sheet.width = 300, sheet.height = 161;
    sheet.pixels.assign(300 * 161 * 3, 0.5f);
    fp::host::write_image(sheet, dir + "/sheet.png", 8, fp::host::read_recipe(dir + "/fig5e.png"));
    const auto r = run_cli({"symmetry", dir + "/sheet.png"});
    EXPECT_EQ(r.rc, 2);
    EXPECT_NE(r.err.find("the image is 300x161 but its recipe renders 161x161"), std::string::npos) << r.err;
    EXPECT_EQ(run_cli({"symmetry", dir + "/sheet.png", "--area", "[-1, 1, -1, 1]"}).rc, 0);
}

// ---------------------------------------------------------------- paper 04

// Sec. 4: "only Figure 5a,c,g have the same symmetry type as f, namely the p3m1 symmetry. All the
// other images have ... the cm symmetry." The hexagonal maps are reduced mod 2 pi on the square
// lattice, so their 3-fold rotation holds for about 96-97 % of the pixels (wallpaper_groups.hpp):
// kept at the threshold 0.85, far above the broken ones.
TEST(SymmetryPaper04, OnlyFig5acgKeepP3m1) {
    const auto fig5 = measure_configs({"fig5a", "fig5b", "fig5c", "fig5d", "fig5e", "fig5f", "fig5g"});
    for (const char* f : {"fig5a", "fig5b", "fig5c", "fig5d", "fig5e", "fig5f", "fig5g"}) {
        const bool p3m1 = f == std::string("fig5a") || f == std::string("fig5c") || f == std::string("fig5g");
        ASSERT_TRUE(fig5.count(f));
        const auto& m = fig5.at(f);
        expect_kept(m, {"t(2pi,0)", "t(pi,pi*sqrt3)", "m(-x,y)"}, f);
        if (p3m1) {
            expect_kept(m, {"r3"}, f);
            EXPECT_EQ(m.largest, "p3m1") << f;
        } else {
            // Below the threshold. Fig. 5f's r3 scores 0.66: its round trap at the origin (Fig. 3c)
            // colours much of the picture alike under the rotation; the others score below 0.4.
            EXPECT_LT(m.score.at("r3"), 0.7) << f;
            EXPECT_EQ(m.largest, "cm") << f;
        }
        EXPECT_EQ(m.lattice, "hexagonal") << f;
    }
    // --group p3m1: exit 0 when every image keeps it, 1 when one does not.
    EXPECT_EQ(
        run_cli(small({"symmetry", config("fig5a"), config("fig5c"), config("fig5g"), "--group", "p3m1"})).rc,
        0);
    EXPECT_EQ(run_cli(small({"symmetry", config("fig5b"), "--group", "p3m1"})).rc, 1);
}

// The hexagonal reduction (issue 16 item 5) against the paper's fmod on the square lattice:
// with it the 3-fold rotation holds for every sample (the map's tests), so the picture's score
// rises from about 0.97 to the exact symmetries' 0.99-1.
TEST(SymmetryPaper04, HexagonalReductionKeepsTheRotationExactly) {
    const auto m = measure_configs({"fig5a", "fig5a-hexagonal"});
    ASSERT_TRUE(m.count("fig5a") && m.count("fig5a-hexagonal"));
    const double square = m.at("fig5a").score.at("r3"), hex = m.at("fig5a-hexagonal").score.at("r3");
    EXPECT_LT(square, 0.985);
    EXPECT_GE(hex, 0.995);
    EXPECT_EQ(m.at("fig5a-hexagonal").largest, "p3m1");
    EXPECT_EQ(m.at("fig5a-hexagonal").point_group, "D3");
}

// Fig. 5(e): only cm is left (the mirror (-x, y) of the map, which the traps of Fig. 3b share,
// and the hexagonal lattice, a centred rectangular one for that mirror).
TEST(SymmetryPaper04, Fig5eKeepsOnlyCm) {
    const auto m = measure(small({config("fig5e")}));
    ASSERT_EQ(m.rc, 0) << m.err;
    expect_kept(m, {"t(2pi,0)", "t(pi,pi*sqrt3)", "m(-x,y)"}, "fig5e");
    expect_broken(m,
                  {"t(0,2pi)", "t(pi,pi)", "r2", "r3", "r4", "r6", "m(x,-y)", "m(y,x)", "g(x+pi,-y)",
                   "g(-x,y+pi)", "g(x+pi,pi-y)"},
                  "fig5e");
    EXPECT_EQ(m.largest, "cm");
    EXPECT_EQ(m.point_group, "D1");
    // Every other group needs one of the broken operations; cm alone is kept.
    const auto g = run_cli(small({"symmetry", config("fig5e"), "--group", "cm"}));
    EXPECT_EQ(g.rc, 0) << g.out << g.err;
}

// Every config of configs/orbit-trap/: the group it keeps (the largest wallpaper group, or none
// where a lattice translation is broken or cannot be seen) and its point group about the origin.
TEST(SymmetryPaper04, EveryOrbitTrapConfig) {
    struct Row {
        const char* config;
        const char* largest; // "" for none
        const char* point_group;
        const char* why;
    };
    const std::vector<Row> table = {
        {"fig5a", "p3m1", "D3", "p3m1 map, one circle about the origin"},
        {"fig5a-hexagonal", "p3m1", "D3", "the same on the hexagonal lattice"},
        {"fig5b", "cm", "D1", "traps of Fig. 3a: no 3-fold rotation"},
        {"fig5c", "p3m1", "D3", "traps of Fig. 1b share p3m1 (to 0.02)"},
        {"fig5d", "cm", "D1", "traps of Fig. 1c"},
        {"fig5e", "cm", "D1", "traps of Fig. 3b"},
        {"fig5f", "cm", "D1", "traps of Fig. 3c"},
        {"fig5g", "p3m1", "D3", "traps of Fig. 1d share p3m1"},
        {"fig6a", "cmm", "D2", "cmm map, traps of Fig. 3a in l1"},
        {"fig6b", "cmm", "D2", "l1.5"},
        {"fig6c", "cmm", "D2", "l2"},
        {"fig6d", "cmm", "D2", "l2.5"},
        {"fig6e", "cmm", "D2", "l3"},
        {"fig6f", "cmm", "D2", "Chebyshev"},
        {"fig7a", "cmm", "D2", "Rickman 0.9: the balls barely overlap (mirror 0.90)"},
        {"fig7b", "cm", "D1", "Rickman 0.7: overlapping balls, the first catches: mirror (x, -y) broken"},
        {"fig7c", "cm", "D1", "Rickman 0.5: likewise"},
        {"fig7d", "cmm", "D2", "Rickman 0.1: both balls hold nearly every point, d differs little"},
        {"fig8a", "", "D4", "S-iteration, beta 1.1: the start point is not reduced, the lattice is lost"},
        {"fig8b", "p4m", "D4", "beta 1: u_0 = f(p_0) does not see p_0, the lattice is kept"},
        {"fig8c", "", "D4", "beta 1.3"},
        {"fig8d", "", "D4", "beta -1.1"},
        {"fig9a", "", "C4", "p4 map, complex alpha, beta 0.5"},
        {"fig9b", "", "C4", "beta 0.5"},
        {"fig9c", "", "C4", "beta 0.5"},
        {"fig9d", "", "C4", "beta 0.5"},
        {"fig10a", "", "D3", "[-1, 1]^2: no lattice translation inside"},
        {"fig10b", "", "D4", "[-1, 1]^2"},
        {"fig10c", "", "C4", "[-1, 1]^2"},
    };
    // The table and the list cover every config there is.
    std::vector<std::string> on_disk;
    for (const auto& e : std::filesystem::directory_iterator(fp::test::source_dir() + "/configs/orbit-trap"))
        if (e.path().extension() == ".yaml") on_disk.push_back(e.path().stem().string());
    std::sort(on_disk.begin(), on_disk.end());
    std::vector<std::string> listed = all_configs;
    std::sort(listed.begin(), listed.end());
    EXPECT_EQ(on_disk, listed);
    ASSERT_EQ(table.size(), all_configs.size());
    for (std::size_t k = 0; k < table.size(); ++k) EXPECT_EQ(table[k].config, all_configs[k]);
    const auto all = measure_configs(all_configs);
    for (const auto& row : table) {
        ASSERT_TRUE(all.count(row.config)) << row.config;
        const auto& m = all.at(row.config);
        EXPECT_EQ(m.largest, *row.largest ? std::string(row.largest) : "null")
            << row.config << ": " << row.why;
        EXPECT_EQ(m.point_group, row.point_group) << row.config << ": " << row.why;
    }
}

// Figs. 7(b) and 7(c) lose the mirror (x, -y) to the order of the traps, not to the metric: with
// the two traps listed the other way round the render is exactly the mirror image of the original.
TEST(SymmetryPaper04, MirrorBrokenByTrapOrder) {
    const std::string dir = fp::test::scratch_dir("symmetry-trap-order");
    ASSERT_EQ(run_cli(small({"render", config("fig7b"), "-o", dir + "/a.png"})).rc, 0);
    ASSERT_EQ(
        run_cli(
            small({"render", config("fig7b"), "-o", dir + "/b.png", "--set",
                   "renderer.traps={type: circles, metric: {type: rickman, gamma: 0.7}, centres: [[0, -3.5], "
                   "[0, 3.5]], radii: [3.5, 3.5]}"}))
            .rc,
        0);
    const auto m = measure({dir + "/b.png", "--against", dir + "/a.png", "--group", "C1", "--op",
                            "[1, 0, 0, -1]", "--op", "[1, 0, 0, 1]"});
    ASSERT_EQ(m.rc, 0) << m.err;
    EXPECT_GE(m.score.at("op1"), 0.99);   // reversed order = the mirror image
    EXPECT_LT(m.score.at("op2"), broken); // and not the same picture
}

namespace {

/// The Jacobian at the origin of one step of a config's mapping and iteration, by `fixpoint
/// eval` on (h, 0) and (0, h): [a b; c d] row major.
std::array<double, 4> jacobian(const std::string& mapping, const std::string& scheme) {
    const double h = 1e-7;
    const auto r = run_cli({"eval", mapping, "--scheme", scheme}, "0 0\n1e-7 0\n0 1e-7\n");
    EXPECT_EQ(r.rc, 0) << r.err;
    std::istringstream in(r.out);
    double x0, y0, x1, y1, x2, y2;
    in >> x0 >> y0 >> x1 >> y1 >> x2 >> y2;
    return {(x1 - x0) / h, (x2 - x0) / h, (y1 - y0) / h, (y2 - y0) / h};
}

std::string op_text(const std::array<double, 4>& J, double scale = 1) {
    char buf[200];
    std::snprintf(buf, sizeof buf, "[%.9g, %.9g, %.9g, %.9g]", scale * J[0], scale * J[1], scale * J[2],
                  scale * J[3]);
    return buf;
}

/// Render `cfg` over [-a, a]^2 and over [-a / ratio, a / ratio]^2 and score the zoom against the
/// wider render under each of `ops`.
Measured zoom_against(const std::string& cfg, double a, double ratio, const std::vector<std::string>& ops) {
    const std::string dir = fp::test::scratch_dir("symmetry-zoom-" + cfg);
    const auto area = [](double s) {
        char buf[160];
        std::snprintf(buf, sizeof buf, "renderer.area=[%.12g, %.12g, %.12g, %.12g]", -s, s, -s, s);
        return std::string(buf);
    };
    EXPECT_EQ(run_cli(small({"render", config(cfg), "-o", dir + "/wide.png", "--set", area(a)})).rc, 0);
    EXPECT_EQ(run_cli(small({"render", config(cfg), "-o", dir + "/zoom.png", "--set", area(a / ratio)})).rc,
              0);
    std::vector<std::string> args = {dir + "/zoom.png", "--against", dir + "/wide.png", "--group", "C1"};
    for (const auto& o : ops) args.insert(args.end(), {"--op", o});
    return measure(args);
}

const std::string p3m1_map =
    "{type: wallpaper, group: p3m1, G: [[0.343244, 0.711418], [-0.671499, -0.289951], "
    "[-0.959405, -0.868905]], H: [[-0.224996, 0.0844803], [-0.0571376, 0.0250126], "
    "[0.0250892, 0.553883]]}";
const std::string p4m_map =
    "{type: wallpaper, group: p4m, P03: [0, -0.234602], P04: [0, -0.231376], P13: [0, "
    "-0.931333], P14: [0, -0.982975], P23: [0, 0.429163], P24: [0, 0.363704], P30: "
    "[-0.234602, 0], P31: [-0.931333, 0], P32: [0.429163, 0], P40: [-0.231376, 0], P41: "
    "[-0.982975, 0], P42: [0.363704, 0]}";
const std::string p4_map =
    "{type: wallpaper, group: p4, P03: [0.215989, -0.150289], P04: [0.0748772, 0.670663], "
    "P13: [0.741719, 0.543639], P14: [0.709028, -0.822211], P23: [0.708072, -0.814562], P24: "
    "[0.100835, 0.40511], P30: [-0.150289, -0.215989], P31: [0.543639, -0.741719], P32: "
    "[-0.814562, -0.708072], P40: [0.670663, -0.0748772], P41: [-0.822211, -0.709028], P42: "
    "[0.40511, -0.100835]}";

} // namespace

// Fig. 10: near the origin the pattern repeats itself under p -> J p (see the top of the file).
TEST(SymmetryPaper04, Fig10SelfSimilarNearTheOrigin) {
    // 10a (Fig. 5c zoomed): J = -3.71 I, a magnification with a half turn.
    const auto Ja = jacobian(p3m1_map, "{type: picard}");
    EXPECT_NEAR(Ja[0], -3.7107, 1e-3);
    EXPECT_NEAR(Ja[3], -3.7107, 1e-3);
    EXPECT_NEAR(Ja[1], 0, 1e-6);
    const double la = std::fabs(Ja[0]);
    {
        // Well inside the trap-free disc: the same picture, turned; not without the turn
        // (p3m1 has no half turn), not at another scale.
        const auto m = zoom_against("fig10a", 0.03, la, {op_text(Ja), op_text(Ja, -1), op_text(Ja, 1.2)});
        ASSERT_EQ(m.rc, 0) << m.err;
        EXPECT_GE(m.score.at("op1"), 0.95);
        EXPECT_LT(m.score.at("op2"), broken);
        EXPECT_LT(m.score.at("op3"), broken);
        // At the config's own [-1, 1]^2 the first step of many pixels lands in a trap: not yet.
        const auto far = zoom_against("fig10a", 1, la, {op_text(Ja)});
        EXPECT_LT(far.score.at("op1"), broken);
    }
    // 10b (Fig. 8c zoomed): the S-iteration alpha = -1.5, beta = 1.3 on the p4m map: J = -18.8 I.
    const auto Jb =
        jacobian(p4m_map, "{type: s-iteration, numbers: {type: complex}, alpha: [-1.5, 0], beta: [1.3, 0]}");
    EXPECT_NEAR(Jb[0], -18.783, 1e-2);
    {
        const auto m = zoom_against("fig10b", 1, std::fabs(Jb[0]), {op_text(Jb), op_text(Jb, 1.2)});
        ASSERT_EQ(m.rc, 0) << m.err;
        EXPECT_GE(m.score.at("op1"), 0.95);
        EXPECT_LT(m.score.at("op2"), broken);
    }
    // 10c (Fig. 9a zoomed): complex alpha on the p4 map: a spiral similarity of ratio 8.64.
    const auto Jc =
        jacobian(p4_map, "{type: s-iteration, numbers: {type: complex}, alpha: [1.1, 0.5], beta: [0.5, 0]}");
    EXPECT_NEAR(Jc[0], Jc[3], 1e-4); // a rotation and scaling: [a -b; b a]
    EXPECT_NEAR(Jc[1], -Jc[2], 1e-4);
    const double lc = std::hypot(Jc[0], Jc[2]);
    EXPECT_NEAR(lc, 8.64, 0.01);
    {
        // The mirror-image spiral (J transposed) is not a symmetry.
        const std::array<double, 4> JcT = {Jc[0], Jc[2], Jc[1], Jc[3]};
        const auto m = zoom_against("fig10c", 1, lc, {op_text(Jc), op_text(JcT)});
        ASSERT_EQ(m.rc, 0) << m.err;
        EXPECT_GE(m.score.at("op1"), 0.95);
        EXPECT_LT(m.score.at("op2"), broken);
    }
}
