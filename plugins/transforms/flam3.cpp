// flam3: the fractal-flame maps of flam3 3.1.1 as transform plugins, from one table
// (fixpoint/flam3_table.hpp), in one library (FIXPOINT_PLUGIN_FAMILY):
//   xform       flam3's xform: the affine pre-transform `coefs`, a weighted sum of variations
//               (each variation's weight a parameter named after it, flam3's attributes), the
//               post-transform `post`; its colour (`color`, `color_speed`) and its weight are
//               the chaos game's, as for any map;
//   linear ...  each of flam3's 99 variations alone (plugin names in kebab-case: gaussian-blur,
//               radial-blur, super-shape, pre-blur, wedge-julia, wedge-sph), with its own
//               parameters and its weight (named after it, default 1), and optional `coefs`
//               and `post`: an xform of that one variation, usable in any slot a transform
//               fits (an inversion config's map, an iteration scheme's T).
// The arithmetic is flam3's apply_xform (variations.c), in double whatever the chain's
// precision, on the SIMD layer (flam3/eval.cpp: every variation vectorised, no libm call).
//
// Random numbers. 21 variations draw them (julia, noise, julian, juliascope, blur,
// gaussian_blur, radial_blur, pie, arch, square, rays, blade, twintrian, super_shape, flower,
// conic, parabola, boarders, cpow, wedge_julia, pre_blur; table.hpp's counts). They take them
// from the batch's keys (fp::Points::key: the chaos game draws one per chain and step from
// the chain's own stream), so a render is the same bytes on any thread count; flam3 draws
// from one ISAAC stream per thread, so its renders of such genomes are not reproducible.
// Without keys (the conformance suite, fit_view) a point's randoms come from its bits.
#include "flam3/xform_data.hpp"
#include <fixpoint/flam3_table.hpp>

#include <fixpoint/fixpoint.hpp>
#include <fixpoint/rng.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace {

using namespace fp_flam3;

constexpr std::uint32_t max_randoms = [] {
    std::uint32_t n = 0;
    for (const VarInfo& v : var_info) n += v.randoms;
    return n;
}();

/// flam3's affine form [c00, c01, c10, c11, c20, c21] (x' = c00 x + c10 y + c20) from a
/// parameter; false when absent.
bool read_affine(const fp::ParamBag& p, const char* name, double out[6]) {
    if (!p.has(name)) return false;
    const std::vector<double>& k = p.reals(name);
    for (int i = 0; i < 6; ++i) out[i] = k[i];
    return true;
}

class Flam3Map : public fp::Transform {
public:
    void apply(fp::Points<float> p, fp::Mask mask) const override { run(p, mask); }
    void apply(fp::Points<double> p, fp::Mask mask) const override { run(p, mask); }
    bool uses_random() const override { return x_.randoms > 0; }
    fp::Box sample_domain() const override { return {-1.5, 1.5, -1.5, 1.5}; }

protected:
    /// The common parameters (coefs, post), the variation parameters, then derive().
    void read_common(const fp::ParamBag& p) {
        read_affine(p, "coefs", x_.coef);
        x_.has_post = read_affine(p, "post", x_.post);
        if (x_.has_post) {
            const double id[6] = {1, 0, 0, 1, 0, 0};
            x_.has_post = !std::equal(x_.post, x_.post + 6, id);
        }
        for (std::uint32_t i = 0; i < param_count; ++i)
            x_.prm[i] = p.has(param_info[i].name) ? p.real(param_info[i].name) : param_info[i].def;
        derive(x_);
    }
    XformData x_;

private:
    template <class T>
    void run(fp::Points<T> p, fp::Mask mask) const {
        constexpr std::size_t cn = fp::chunk_size;
        alignas(64) double bx[cn], by[cn];
        alignas(64) double rnd[max_randoms ? max_randoms * cn : 1];
        for (std::size_t b = 0; b < p.n; b += cn) {
            const std::size_t m = std::min(cn, p.n - b);
            for (std::size_t i = 0; i < m; ++i) bx[i] = double(p.x[b + i]), by[i] = double(p.y[b + i]);
            for (std::size_t i = 0; i < m && x_.randoms; ++i) {
                // (A point's own key from its float bits, so that float and double agree.)
                const std::uint64_t key = p.key ? p.key[b + i] : fp::point_key(float(bx[i]), float(by[i]));
                for (std::uint32_t j = 0; j < x_.randoms; ++j)
                    rnd[j * cn + i] = fp::map_uniform(key, p.salt, j);
            }
            eval_chunk(x_, bx, by, m, rnd);
            for (std::size_t i = 0; i < m; ++i)
                if (!mask || mask[b + i]) p.x[b + i] = T(bx[i]), p.y[b + i] = T(by[i]);
        }
    }
};

/// flam3's xform: any of the variations, each by its weight.
class Xform final : public Flam3Map {
public:
    explicit Xform(const fp::ParamBag& p) {
        for (std::uint32_t v = 0; v < var_count; ++v)
            if (p.has(var_info[v].name)) {
                const double w = p.real(var_info[v].name);
                if (w != 0) add_variation(x_, v, w);
            }
        read_common(p);
    }
};

/// One variation alone.
class Variation final : public Flam3Map {
public:
    Variation(std::uint32_t v, const fp::ParamBag& p) {
        add_variation(x_, v, p.real(var_info[v].name));
        read_common(p);
    }
};

template <std::uint32_t V>
fp::Object* create_variation(const fp::ParamBag& p) {
    return new Variation(V, p);
}

constexpr fp::ParamSpec coefs_param =
    fp::param::reals("coefs", "flam3's pre-transform [c00, c01, c10, c11, c20, c21]: t = (c00 x + c10 y + "
                              "c20, c01 x + c11 y + c21), applied before the variations")
        .len(6)
        .def("[1, 0, 0, 1, 0, 0]");
constexpr fp::ParamSpec post_param =
    fp::param::reals("post", "flam3's post-transform, in the order of coefs, applied to the variations' sum")
        .len(6)
        .opt();

/// A variation's own parameters under flam3's names.
constexpr fp::ParamSpec param_spec(const ParamInfo& i) {
    return fp::param::real(i.name, i.desc).def(i.def_text);
}

/// Variation V's parameters: its weight, coefs, post, then its own.
template <std::uint32_t V>
inline constexpr auto variation_params = [] {
    std::array<fp::ParamSpec, 3 + params_of(V)> a{};
    a[0] =
        fp::param::real(var_info[V].name, "the variation's weight (flam3's attribute of its name)").def("1");
    a[1] = coefs_param;
    a[2] = post_param;
    std::size_t n = 3;
    for (const ParamInfo& i : param_info)
        if (i.var == V) a[n++] = param_spec(i);
    return a;
}();

/// The xform's parameters: coefs, post, every variation's weight (optional), every parameter.
inline constexpr auto xform_params = [] {
    std::array<fp::ParamSpec, 2 + var_count + param_count> a{};
    a[0] = coefs_param;
    a[1] = post_param;
    std::size_t n = 2;
    for (const VarInfo& v : var_info) a[n++] = fp::param::real(v.name, v.summary).opt();
    for (const ParamInfo& i : param_info) a[n++] = param_spec(i);
    return a;
}();

/// A parameter set whose defaults are degenerate (a zero divisor, a point at infinity) gets an
/// example of the common use, for `describe` and the conformance suite.
constexpr const char* example_of(std::uint32_t v) {
    switch (v) {
    case v_waves: return "{coefs: [1, 0, 0, 1, 0.3, 0.4]}";
    case v_mobius: return "{mobius_re_a: 1, mobius_im_b: 0.3, mobius_re_c: 0.2, mobius_re_d: 1}";
    case v_perspective: return "{perspective_angle: 0.3, perspective_dist: 2}";
    case v_modulus: return "{modulus_x: 0.7, modulus_y: 0.4}";
    case v_fan2: return "{fan2_x: 0.6, fan2_y: 0.3}";
    case v_rings2: return "{rings2_val: 0.5}";
    case v_flower: return "{flower_petals: 5, flower_holes: 0.2}";
    case v_wedge_julia:
        return "{wedge_julia_power: 3, wedge_julia_dist: 1, wedge_julia_count: 2, wedge_julia_angle: 0.4}";
    default: return "{}";
    }
}

template <std::uint32_t V>
constexpr fp::PluginDescriptor variation_descriptor() {
    fp::PluginDescriptor d;
    d.name = var_info[V].plugin;
    d.kind = fp::Kind::Transform;
    d.summary = var_info[V].summary;
    d.params = variation_params<V>.data();
    d.n_params = std::uint32_t(variation_params<V>.size());
    d.create = &create_variation<V>;
    d.example = example_of(V);
    return d;
}

constexpr fp::PluginDescriptor xform_descriptor() {
    fp::PluginDescriptor d;
    d.name = "xform";
    d.kind = fp::Kind::Transform;
    d.summary = "flam3's xform: the affine coefs, a weighted sum of flam3's variations (each weight "
                "named after its variation), the post affine";
    d.params = xform_params.data();
    d.n_params = std::uint32_t(xform_params.size());
    d.create = &fp::create_plugin<Xform>;
    d.example = "{coefs: [0.5, 0.2, -0.2, 0.5, 0.1, 0], julia: 0.6, swirl: 0.4}";
    return d;
}

template <std::size_t... I>
constexpr auto family_of(std::index_sequence<I...>) {
    return std::array<fp::PluginDescriptor, 1 + sizeof...(I)>{xform_descriptor(),
                                                              variation_descriptor<std::uint32_t(I)>()...};
}

constexpr auto family = family_of(std::make_index_sequence<var_count>{});

} // namespace

FIXPOINT_PLUGIN_FAMILY(family)
