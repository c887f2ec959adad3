// wallpaper: the maps with wallpaper symmetry of paper 04 (after Carter, Eagles, Grimes, Hahn and
// Reiter 1998), f: R^2 -> R^2 reduced "mod 2 pi", for all 17 groups:
//
//   p1 ... p4g (square lattice 2 pi Z^2), eq. (1):
//       f(x, y) = [1, cos x, cos 2x, sin x, sin 2x] P [1, cos y, cos 2y, sin y, sin 2y]^T,
//       P a 5 x 5 matrix of 2-vectors P_ij (i: the x factor, j: the y factor);
//   p3, p6 (k = 3, 6), eq. (7); p3m1, p31m (k = 3), p6m (k = 6), eq. (8):
//       f(p) = sum_j g_k(p, v_j, G_vj) + h_k(p, v_j, H_vj) (+ the sigma terms of eq. (8)),
//       g_k(p, v, G) = sum_i R_k^i(G) cos(R_k^i(v) . p), h_k likewise with H and sin,
//       v0 = (1, -1/sqrt 3), v1 = (0, -2/sqrt 3), v2 = v0 + v1, sigma (-x, y) for p3m1 and
//       (x, -y) for p31m and p6m (eq. (9)).
//
// Coefficients, in the paper's notation: the whole `P` (25 pairs, row by row) and / or single
// entries `P03: [0, -0.234602]` (an entry given on its own replaces that entry of P; entries not
// given are 0), or for the hexagonal groups `G: [G_v0, G_v1, G_v2]`, `H: [...]` and / or
// `G_v0: [...]`, ... Or `seed: n`: coefficients uniform in [-1, 1) drawn from fp::chain_stream(n,
// 0) (the 50 numbers of P row by row, x before y; or G_v0 .. G_v2, H_v0 .. H_v2), then projected
// onto the group's conditions. For p6 and p6m the G terms cancel (R6^3 = -I pairs cos terms of
// opposite vectors), so only H matters there.
//
// The groups' conditions (wallpaper_groups.hpp derives them, Appendix A being damaged in our
// text): given coefficients that break them are refused, with the first broken relation, e.g.
//   P32 = [0.422963, 0] breaks p4m's P32.x = P23.y (0.429163)
// within a relative tolerance of 1e-6 (the paper prints 6 digits); accepted ones are then
// projected, so that the map is exactly symmetric in floating point. (Refusing rather than
// silently constraining: a misprint in a config should be seen, not fixed behind one's back.)
//
// Reduction ("mod 2 pi" of eqs. (1), (7), (8)), parameter `reduction`:
//   fmod     C's fmod: v - 2 pi trunc(v / 2 pi), in (-2 pi, 2 pi), odd (the default: the paper's
//            traps reach |coordinates| up to 6.3, at negative coordinates too, and an odd
//            reduction keeps the mirror and rotation symmetries through the origin)
//   centred  into [-pi, pi): v - 2 pi round(v / 2 pi) (odd except at +-pi)
//   floor    into [0, 2 pi): GLSL's mod (breaks the symmetries through 0: traps at negative
//            coordinates are never reached)
//   none     no reduction
//   hexagonal (p3, p3m1, p31m, p6, p6m only) modulo the hexagonal lattice of periods L =
//            2 pi Z (1, 0) + 2 pi Z (1/2, sqrt 3 / 2) into its Voronoi cell of 0, a hexagon
//            (inradius pi, circumradius 2 pi / sqrt 3 = 3.63): p minus the nearest point of L
//            (fixpoint/lattice.hpp derives it). Not the paper's; designed here.
// The square lattice's reduction commutes with the square groups' point groups; for the
// hexagonal groups it does not commute with the rotations by 60 / 120 degrees (the paper
// reduces on the square lattice all the same; use `none` to see eq. (7) itself). `hexagonal`
// does: the cell is invariant under R6 and both mirrors and f is L-periodic, so the reduced
// orbit of R p is R times the reduced orbit of p (up to rounding, and except where a point of the
// orbit falls on a cell's boundary). The square groups' f is not L-periodic: `hexagonal` is
// refused for them ("hexagonal is for the hexagonal groups (p3, p3m1, p31m, p6, p6m),
// whose lattice of periods is hexagonal; p4m's is the square lattice 2 pi Z^2 (use fmod,
// centred, floor or none)").
//
// Speed: wallpaper_kernel.hpp (vectorised float and double loops, own sin / cos, zero terms of
// sparse groups skipped by a form chosen once here). Per point no call, branch or allocation.
#include <fixpoint/fixpoint.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "wallpaper_kernel.hpp"

// The map's loops once per instruction set: Map::run_body inlined into a function of each
// Highway target, where the compiler vectorises the per-point code with that target's
// instructions; dispatched at run time (the same bits on each: no FMA, own sin and cos).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "wallpaper.cpp"
#include <hwy/foreach_target.h> // IWYU pragma: keep

#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace fp_wallpaper::HWY_NAMESPACE {
void run_f(const Map& m, float* x, float* y, fp::Mask mask, std::size_t n) { m.run_body(x, y, mask, n); }
void run_d(const Map& m, double* x, double* y, fp::Mask mask, std::size_t n) { m.run_body(x, y, mask, n); }
} // namespace fp_wallpaper::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace fp_wallpaper {
HWY_EXPORT(run_f);
HWY_EXPORT(run_d);
void dispatch_f(const Map& m, float* x, float* y, fp::Mask mask, std::size_t n) {
    HWY_DYNAMIC_DISPATCH(run_f)(m, x, y, mask, n);
}
void dispatch_d(const Map& m, double* x, double* y, fp::Mask mask, std::size_t n) {
    HWY_DYNAMIC_DISPATCH(run_d)(m, x, y, mask, n);
}
} // namespace fp_wallpaper

namespace {

namespace wp = fp_wallpaper;

const char* const entry_names[25] = {"P00", "P01", "P02", "P03", "P04", "P10", "P11", "P12", "P13",
                                     "P14", "P20", "P21", "P22", "P23", "P24", "P30", "P31", "P32",
                                     "P33", "P34", "P40", "P41", "P42", "P43", "P44"};
const char* const g_names[3] = {"G_v0", "G_v1", "G_v2"};
const char* const h_names[3] = {"H_v0", "H_v1", "H_v2"};

wp::Reduction reduction_of(const fp::ParamBag& p) {
    const std::string& group = p.string("group");
    const wp::Reduction r = fp::kernels::reduction_named(p.string("reduction"));
    if (r == wp::Reduction::hexagonal && !wp::is_hexagonal(group))
        throw fp::ParamError("reduction", "hexagonal is for the hexagonal groups (p3, p3m1, p31m, "
                                          "p6, p6m), whose lattice of periods is hexagonal; " +
                                              group +
                                              "'s is the square lattice 2 pi Z^2 (use fmod, centred, floor "
                                              "or none)");
    return r;
}

/// The coefficient matrix Q (P, or eqs. (7) / (8) expanded) from the parameters.
wp::Matrix coefficients(const fp::ParamBag& p, const std::string& group) {
    const bool hex = wp::is_hexagonal(group);
    bool given_square = p.has("P"), given_hex = p.has("G") || p.has("H");
    for (const char* e : entry_names) given_square |= p.has(e);
    for (int j = 0; j < 3; ++j) given_hex |= p.has(g_names[j]) || p.has(h_names[j]);
    const bool given = hex ? given_hex : given_square;

    // Coefficients of the other family of groups: name the first one given.
    if (hex && given_square) {
        const char* name = p.has("P") ? "P" : "P00";
        for (const char* e : entry_names)
            if (!p.has("P") && p.has(e)) {
                name = e;
                break;
            }
        throw fp::ParamError(name, std::string(name) + " is for the square-lattice groups (p1 ... p4g); " +
                                       group + " takes G and H (or G_v0 ... H_v2)");
    }
    if (!hex && given_hex) {
        std::string name = p.has("G") ? "G" : p.has("H") ? "H" : "";
        for (int j = 0; j < 3 && name.empty(); ++j)
            name = p.has(g_names[j]) ? g_names[j] : p.has(h_names[j]) ? h_names[j] : "";
        throw fp::ParamError(name, name + " is for the hexagonal groups (p3, p3m1, p31m, p6, p6m); " + group +
                                       " takes P (or P00 ... P44)");
    }
    if (p.has("seed") && given)
        throw fp::ParamError("seed",
                             "give either a seed (random coefficients) or the coefficients, not both");
    if (!p.has("seed") && !given)
        throw fp::ParamError(hex ? "give the coefficients (G and H, or G_v0 ... H_v2) or a seed"
                                 : "give the coefficients (P, or P00 ... P44) or a seed");

    if (hex) {
        std::array<fp::Vec2, 3> G{}, H{};
        if (p.has("seed")) {
            fp::Rng r = fp::chain_stream(std::uint64_t(p.integer("seed")), 0);
            for (auto* v : {&G, &H})
                for (fp::Vec2& e : *v) {
                    e.x = 2 * fp::uniform_double(r) - 1;
                    e.y = 2 * fp::uniform_double(r) - 1;
                }
        }
        for (auto [name, v] : {std::pair{"G", &G}, std::pair{"H", &H}}) {
            if (!p.has(name)) continue;
            const std::vector<fp::Vec2>& rows = p.vec2s(name);
            if (rows.size() != 3)
                throw fp::ParamError(name, std::string(name) + " must be [" + name + "_v0, " + name +
                                               "_v1, " + name + "_v2] (3 pairs [x, y]), got " +
                                               std::to_string(rows.size()) + " pairs");
            for (int j = 0; j < 3; ++j) (*v)[j] = rows[j];
        }
        for (int j = 0; j < 3; ++j) {
            if (p.has(g_names[j])) G[j] = p.vec2(g_names[j]);
            if (p.has(h_names[j])) H[j] = p.vec2(h_names[j]);
        }
        const int k = group == "p6" || group == "p6m" ? 6 : 3;
        const bool mirror = group == "p3m1" || group == "p31m" || group == "p6m";
        return wp::hex_coefficients(k, mirror, group == "p3m1", G, H);
    }

    wp::Matrix P{};
    if (p.has("seed")) {
        fp::Rng r = fp::chain_stream(std::uint64_t(p.integer("seed")), 0);
        for (int s = 0; s < 50; ++s) wp::at(P, s) = 2 * fp::uniform_double(r) - 1;
        return wp::project(group, P);
    }
    if (p.has("P")) {
        const std::vector<fp::Vec2>& all = p.vec2s("P");
        if (all.size() != 25)
            throw fp::ParamError("P", "P must be the 5 x 5 matrix of pairs [x, y], row by row (25 pairs, "
                                      "P00 ... P04, P10, ...), got " +
                                          std::to_string(all.size()) + " pairs");
        for (int e = 0; e < 25; ++e) P[e / 5][e % 5] = all[e];
    }
    for (int e = 0; e < 25; ++e)
        if (p.has(entry_names[e])) P[e / 5][e % 5] = p.vec2(entry_names[e]);
    int blamed = 0;
    const std::string broken = wp::broken_relation(group, P, blamed);
    if (!broken.empty()) throw fp::ParamError(p.has(entry_names[blamed]) ? entry_names[blamed] : "P", broken);
    return wp::project(group, P);
}

class Wallpaper final : public fp::Transform {
public:
    explicit Wallpaper(const fp::ParamBag& p)
        : map_(coefficients(p, p.string("group")), wp::is_hexagonal(p.string("group")), reduction_of(p)),
          hexagonal_(wp::is_hexagonal(p.string("group"))) {
        map_.set_runners(&fp_wallpaper::dispatch_f, &fp_wallpaper::dispatch_d);
    }

    void apply(fp::Points<float> p, fp::Mask mask) const override { map_.apply(p, mask); }
    void apply(fp::Points<double> p, fp::Mask mask) const override { map_.apply(p, mask); }

    /// The paper's area [-2 pi, 2 pi]^2 and a little more.
    fp::Box sample_domain() const override { return {-7, 7, -7, 7}; }

    /// The input's periods (the output's reduction does not matter): 2 pi Z^2 for the square
    /// groups (cm and cmm forget (pi, pi) too: 2 pi Z^2 is a sublattice of theirs with the same
    /// smallest rectangle), and 2 pi Z (1, 0) + 2 pi Z (1/2, sqrt(3)/2) for the hexagonal ones
    /// (X = v0 . p and Y = v1 . p change by multiples of 2 pi), whose smallest rectangle is
    /// 2 pi x 2 pi sqrt(3).
    std::optional<fp::PeriodLattice> periods() const override {
        const double a = 2 * std::numbers::pi;
        if (hexagonal_)
            return fp::PeriodLattice{
                {a, 0}, {a / 2, a * std::numbers::sqrt3 / 2}, a, a * std::numbers::sqrt3};
        return fp::PeriodLattice{{a, 0}, {0, a}, a, a};
    }

private:
    wp::Map map_;
    bool hexagonal_ = false;
};

#define FP_WALLPAPER_ENTRY(n)                                                                                \
    fp::param::vec2(n, "one entry of P (eq. (1)); replaces that entry of P; entries not given are 0").opt()
#define FP_WALLPAPER_HEX(n, what)                                                                            \
    fp::param::vec2(n, what " of eqs. (7) / (8) for one of v0, v1, v2; replaces that row of " what).opt()

constexpr fp::ParamSpec params[] = {
    fp::param::string("group",
                      "the wallpaper group: p1 ... p4g use eq. (1) and P; p3, p3m1, p31m, p6, p6m use "
                      "eqs. (7) / (8) and G, H")
        .one_of(wp::group_names),
    fp::param::vec2s("P",
                     "the 5 x 5 matrix P of eq. (1): 25 pairs [x, y], row by row (P00 ... P04, P10, ...); "
                     "must satisfy the group's conditions (relative tolerance 1e-6)")
        .opt(),
    FP_WALLPAPER_ENTRY("P00"),
    FP_WALLPAPER_ENTRY("P01"),
    FP_WALLPAPER_ENTRY("P02"),
    FP_WALLPAPER_ENTRY("P03"),
    FP_WALLPAPER_ENTRY("P04"),
    FP_WALLPAPER_ENTRY("P10"),
    FP_WALLPAPER_ENTRY("P11"),
    FP_WALLPAPER_ENTRY("P12"),
    FP_WALLPAPER_ENTRY("P13"),
    FP_WALLPAPER_ENTRY("P14"),
    FP_WALLPAPER_ENTRY("P20"),
    FP_WALLPAPER_ENTRY("P21"),
    FP_WALLPAPER_ENTRY("P22"),
    FP_WALLPAPER_ENTRY("P23"),
    FP_WALLPAPER_ENTRY("P24"),
    FP_WALLPAPER_ENTRY("P30"),
    FP_WALLPAPER_ENTRY("P31"),
    FP_WALLPAPER_ENTRY("P32"),
    FP_WALLPAPER_ENTRY("P33"),
    FP_WALLPAPER_ENTRY("P34"),
    FP_WALLPAPER_ENTRY("P40"),
    FP_WALLPAPER_ENTRY("P41"),
    FP_WALLPAPER_ENTRY("P42"),
    FP_WALLPAPER_ENTRY("P43"),
    FP_WALLPAPER_ENTRY("P44"),
    fp::param::vec2s("G", "[G_v0, G_v1, G_v2] of eqs. (7) / (8): the cos coefficients (hexagonal groups)")
        .opt(),
    fp::param::vec2s("H", "[H_v0, H_v1, H_v2] of eqs. (7) / (8): the sin coefficients (hexagonal groups)")
        .opt(),
    FP_WALLPAPER_HEX("G_v0", "G"),
    FP_WALLPAPER_HEX("G_v1", "G"),
    FP_WALLPAPER_HEX("G_v2", "G"),
    FP_WALLPAPER_HEX("H_v0", "H"),
    FP_WALLPAPER_HEX("H_v1", "H"),
    FP_WALLPAPER_HEX("H_v2", "H"),
    fp::param::integer("seed",
                       "instead of coefficients: draw them uniform in [-1, 1) from this seed and project "
                       "them onto the group's conditions")
        .min(0)
        .opt(),
    fp::param::string("reduction",
                      "'mod 2 pi' of the output: fmod (C's fmod, in (-2 pi, 2 pi), odd: keeps the symmetries "
                      "through 0), centred ([-pi, pi)), floor ([0, 2 pi), GLSL's mod: breaks the symmetries "
                      "through 0), none, or hexagonal (p3 ... p6m only: modulo their hexagonal lattice of "
                      "periods into the hexagon about 0, which keeps the 3- and 6-fold rotations exact)")
        .one_of("fmod|centred|floor|none|hexagonal")
        .def("fmod"),
};

} // namespace

FIXPOINT_PLUGIN(fp::describe<Wallpaper>(fp::Kind::Transform, "wallpaper",
                                        "maps with wallpaper symmetry, all 17 groups (paper 04 eqs. (1)-(9))",
                                        params)
                    .with_example("{group: p4m, seed: 1}"))
#endif // HWY_ONCE
