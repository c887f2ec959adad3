// One plugin host for every unit test of a test program (loading the plugins once), and the
// small helpers the unit tests build their plugins and points with. Tests take them all with
// `using namespace fp::test;`.
#pragma once

#include <fixpoint/host/core/host.hpp>
#include <fixpoint/host/core/runtime.hpp>

#include <gtest/gtest.h>

#include <functional>
#include <memory>
#include <string>

namespace fp::test {

inline const fp::host::Host& host() {
    static const fp::host::Host h;
    return h;
}

/// The plugin of interface `I` (fp::Colourer, fp::Metric, fp::Transform, ...) that `yaml` builds.
/// A yaml that builds nothing fails the test there, naming the yaml, rather than later as a null
/// pointer.
template <class I>
std::shared_ptr<const I> make(const std::string& yaml) {
    auto p = host().make<I>(yaml);
    EXPECT_TRUE(p) << yaml;
    return p;
}

/// `p` after `steps` steps of the transform `t`.
inline fp::Vec2 apply(const fp::Transform& t, fp::Vec2 p, int steps = 1) {
    for (int i = 0; i < steps; ++i) t.apply(fp::Points<double>{&p.x, &p.y, 1}, nullptr);
    return p;
}

/// `got` within `tol` of `want` in each coordinate; a failure prints both points.
inline void expect_point(fp::Vec2 got, fp::Vec2 want, double tol) {
    EXPECT_NEAR(got.x, want.x, tol) << "got (" << got.x << ", " << got.y << "), want (" << want.x << ", "
                                    << want.y << ")";
    EXPECT_NEAR(got.y, want.y, tol) << "got (" << got.x << ", " << got.y << "), want (" << want.x << ", "
                                    << want.y << ")";
}

/// What a renderer gives: its image and its counts.
struct Render {
    fp::Image img;
    fp::RenderStats stats;
};

/// The renderer `yaml` (one YAML object) rendered on `threads` threads.
inline Render render(const std::string& yaml, unsigned threads = 2) {
    auto r = host().make<fp::Renderer>(yaml);
    fp::host::Runtime rt(threads, nullptr);
    Render out;
    out.img = r->render(rt, out.stats);
    return out;
}

/// Whether the transform `yaml` builds (its plugin may be left out of a build).
inline bool has_plugin(const std::string& yaml) {
    try {
        host().make_object(fp::Kind::Transform, yaml, "<string>");
        return true;
    } catch (const fp::InputError&) {
        return false;
    }
}

/// The message of the fp::InputError that `f` throws, or "(no error)".
inline std::string error_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const fp::InputError& e) {
        return e.what();
    }
    return "(no error)";
}

/// The message of the fp::InputError that the `kind` object `yaml` raises, without its
/// "<string>:LINE:COL: " place (one object in one line: the place says nothing); "(no error)" where
/// it builds.
inline std::string error_of(fp::Kind kind, const std::string& yaml) {
    try {
        host().make_object(kind, yaml, "<string>");
    } catch (const fp::InputError& e) {
        const std::string m = e.what();
        const auto at = m.find(": ");
        return m.rfind("<string>:", 0) == 0 && at != std::string::npos ? m.substr(at + 2) : m;
    }
    return "(no error)";
}

/// Paper 04's p4m example (Fig. 8), with the misprint P32 = [0.422963, 0] fixed to 0.429163 (the
/// p4m condition P32.x = P23.y; as in configs/orbit-trap/fig8a.yaml).
inline const std::string p4m_fig8 =
    "{type: wallpaper, group: p4m, P03: [0, -0.234602], P04: [0, -0.231376], P13: [0, -0.931333], "
    "P14: [0, -0.982975], P23: [0, 0.429163], P24: [0, 0.363704], P30: [-0.234602, 0], P31: [-0.931333, 0], "
    "P32: [0.429163, 0], P40: [-0.231376, 0], P41: [-0.982975, 0], P42: [0.363704, 0]}";

} // namespace fp::test
