// fixpoint's flam3 variations against libflam3 itself (Debian's libflam3-dev, linked by this
// test only, never by the product): for each of flam3's 99 variations, an xform of that
// variation with non-trivial parameters, pre- and post-transform is built twice, from the same
// attributes: by flam3_parse_xml2 and flam3's own apply_xform, and by fixpoint's `xform`
// plugin. On a grid of points the deterministic variations agree to 1e-12 relative (flam3's
// libm against the SDK's own polynomials); the 21 random ones are compared in distribution
// (mean and spread of x and y over many draws at a few points, within 5 standard errors).
#include "host.hpp"

#include <fixpoint/flam3_table.hpp>

#include <fixpoint/host/core/host.hpp>
#include <fixpoint/rng.hpp>

#include <gtest/gtest.h>

extern "C" {
#include <flam3.h>
// Exported by libflam3, declared in its private headers.
int apply_xform(flam3_genome* cp, int fn, double* p, double* q, randctx* rc);
int prepare_precalc_flags(flam3_genome* cp);
void xform_precalc(flam3_genome* cp, int xi);
}

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

using namespace fp::test;

namespace {

/// Parameters off their defaults (flam3's defaults are often degenerate: a zero divisor), in
/// flam3's attribute syntax; the same text becomes the YAML mapping.
std::vector<std::pair<std::string, std::string>> attributes(std::uint32_t v) {
    std::vector<std::pair<std::string, std::string>> a;
    std::uint32_t k = 0;
    for (const auto& p : fp_flam3::param_info)
        if (p.var == v) {
            // A value of each parameter's own scale: small offsets from the default, varied by
            // position, keep powers, counts and divisors meaningful.
            double x = p.def + 0.3 + 0.17 * k++;
            const std::string n = p.name;
            if (n.find("power") != std::string::npos || n.find("sides") != std::string::npos ||
                n.find("count") != std::string::npos || n == "pie_slices" || n == "flower_petals")
                x = std::round(p.def + 2 + k); // integral, as flam3's use (julian's power)
            a.emplace_back(n, std::to_string(x));
        }
    return a;
}

struct Pair {
    flam3_genome* g = nullptr;
    std::shared_ptr<const fp::Transform> t;
    ~Pair() {
        if (g) {
            clear_cp(g, 0);
            free(g);
        }
    }
};

const char* coefs = "0.71 -0.23 0.31 0.84 0.13 -0.07";
const char* post = "0.93 0.11 -0.09 1.02 0.05 0.02";

void build(std::uint32_t v, Pair& out) {
    const auto& info = fp_flam3::var_info[v];
    const double w = 0.83;
    std::string xml =
        "<flame size=\"64 64\" center=\"0 0\" scale=\"20\"><xform weight=\"1\" color=\"0\" coefs=\"";
    xml += std::string(coefs) + "\" post=\"" + post + "\" " + info.name + "=\"" + std::to_string(w) + "\"";
    std::string yaml = "{type: xform, coefs: [" + std::string(coefs) + "], post: [" + post + "], " +
                       info.name + ": " + std::to_string(w);
    for (const auto& [n, x] : attributes(v)) {
        xml += " " + n + "=\"" + x + "\"";
        yaml += ", " + n + ": " + x;
    }
    xml += "/><color index=\"0\" rgb=\"255 255 255\"/></flame>";
    yaml += "}";
    // YAML lists need commas.
    std::string y2;
    bool in_list = false;
    for (std::size_t i = 0; i < yaml.size(); ++i) {
        if (yaml[i] == '[') in_list = true;
        if (yaml[i] == ']') in_list = false;
        y2 += in_list && yaml[i] == ' ' ? std::string(", ") : std::string(1, yaml[i]);
    }
    int n = 0;
    std::vector<char> buf(xml.begin(), xml.end());
    buf.push_back(0);
    char fn[] = "test";
    out.g = flam3_parse_xml2(buf.data(), fn, flam3_defaults_on, &n);
    ASSERT_TRUE(out.g) << xml;
    ASSERT_EQ(n, 1);
    ASSERT_EQ(prepare_precalc_flags(out.g), 0);
    xform_precalc(out.g, 0);
    out.t = make<fp::Transform>(y2);
}

double rel(double a, double b) {
    return std::fabs(a - b) / std::max(1.0, std::max(std::fabs(a), std::fabs(b)));
}

class Variation : public testing::TestWithParam<std::uint32_t> {};

TEST_P(Variation, AgreesWithLibflam3) {
    const std::uint32_t v = GetParam();
    Pair pr;
    build(v, pr);
    if (HasFatalFailure()) return;
    randctx rc;
    for (int i = 0; i < RANDSIZ; ++i) rc.randrsl[i] = ub4(i * 2654435761u + 1);
    irandinit(&rc, 1);
    if (fp_flam3::var_info[v].randoms == 0) {
        // A grid over [-1.9, 1.9]^2, off the axes (where atan2's branch cut and x = 0 tests sit).
        int bad = 0, compared = 0;
        std::string first;
        for (int iy = 0; iy < 23; ++iy)
            for (int ix = 0; ix < 23; ++ix) {
                const double x = -1.9 + 3.8 * (ix + 0.37) / 23, y = -1.9 + 3.8 * (iy + 0.61) / 23;
                double p[4] = {x, y, 0, 0}, q[4] = {0, 0, 0, 0};
                const int badv = apply_xform(pr.g, 0, p, q, &rc);
                double gx = x, gy = y;
                pr.t->apply(fp::Points<double>{&gx, &gy, 1}, nullptr);
                if (badv || !std::isfinite(gx) || !std::isfinite(gy))
                    continue; // flam3 then draws a random point
                ++compared;
                if (rel(q[0], gx) > 1e-12 || rel(q[1], gy) > 1e-12) {
                    if (!bad)
                        first = "at (" + std::to_string(x) + ", " + std::to_string(y) + "): flam3 (" +
                                std::to_string(q[0]) + ", " + std::to_string(q[1]) + "), fixpoint (" +
                                std::to_string(gx) + ", " + std::to_string(gy) + ")";
                    ++bad;
                }
            }
        // Discontinuous variations (floor, fmod, a comparison) may land on the other side of a
        // jump where the two computations round differently: at most 1 grid point in 100.
        EXPECT_LE(bad, compared / 100) << fp_flam3::var_info[v].name << ": " << bad << " of " << compared
                                       << " points differ; first " << first;
        EXPECT_GE(compared, 400) << fp_flam3::var_info[v].name;
        return;
    }
    // Random: the laws of many draws at a few points, each draw from its own key.
    constexpr int draws = 20000;
    for (const auto& [x, y] : std::vector<std::pair<double, double>>{{0.3, 0.7}, {-0.8, 0.2}, {1.1, -0.9}}) {
        std::vector<double> f[2], g[2];
        for (int i = 0; i < draws; ++i) {
            double p[4] = {x, y, 0, 0}, q[4] = {0, 0, 0, 0};
            if (!apply_xform(pr.g, 0, p, q, &rc))
                for (int c = 0; c < 2; ++c) f[c].push_back(q[c]);
            double gx = x, gy = y;
            const std::uint64_t key = fp::map_key(7, std::uint64_t(i), 3);
            pr.t->apply(fp::Points<double>{&gx, &gy, 1, &key, 0}, nullptr);
            if (std::isfinite(gx) && std::isfinite(gy) && std::fabs(gx) < 1e10 && std::fabs(gy) < 1e10)
                g[0].push_back(gx), g[1].push_back(gy);
        }
        ASSERT_GT(f[0].size(), std::size_t(draws / 2)) << fp_flam3::var_info[v].name;
        ASSERT_GT(g[0].size(), std::size_t(draws / 2)) << fp_flam3::var_info[v].name;
        for (int c = 0; c < 2; ++c) {
            // The two-sample Kolmogorov-Smirnov distance: the largest gap between the empirical
            // distribution functions (fine for discrete laws, julia's two roots, and heavy tails
            // alike). With 20 000 draws each, 0.03 is passed by equal laws but for odds of 1e-6.
            std::sort(f[c].begin(), f[c].end());
            std::sort(g[c].begin(), g[c].end());
            double dmax = 0;
            std::size_t a = 0, b = 0;
            while (a < f[c].size() && b < g[c].size()) {
                // (Atoms of a discrete law, julia's roots, sit 1e-16 apart in the two
                // computations: values within 1e-9 count as one.)
                const double t = std::min(f[c][a], g[c][b]) + 1e-9 * (1 + std::fabs(f[c][a]));
                while (a < f[c].size() && f[c][a] <= t) ++a;
                while (b < g[c].size() && g[c][b] <= t) ++b;
                dmax = std::max(dmax, std::fabs(double(a) / f[c].size() - double(b) / g[c].size()));
            }
            EXPECT_LE(dmax, 0.03) << fp_flam3::var_info[v].name << ": the laws of "
                                  << "xy"[c] << " at (" << x << ", " << y
                                  << ") differ (Kolmogorov-Smirnov distance " << dmax << ")";
        }
    }
}

std::string name_of(const testing::TestParamInfo<std::uint32_t>& i) {
    return fp_flam3::var_info[i.param].name;
}

INSTANTIATE_TEST_SUITE_P(Flam3, Variation,
                         testing::Range(std::uint32_t(0), std::uint32_t(fp_flam3::var_count)), name_of);

} // namespace
