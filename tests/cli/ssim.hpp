// Structural similarity of two pictures, for the tests that compare fixpoint's renders with
// flam3-render's (tests/flam3/parity.py computes the same).
#pragma once

#include <fixpoint/host/core/image_io.hpp>

#include <cmath>
#include <cstddef>
#include <vector>

namespace fp::test {

/// Grey levels of an image.
inline std::vector<double> grey(const fp::Image& im) {
    std::vector<double> g(std::size_t(im.width) * std::size_t(im.height));
    for (std::size_t i = 0; i < g.size(); ++i) {
        const float* p = &im.pixels[i * std::size_t(im.channels)];
        g[i] = 0.299 * p[0] + 0.587 * p[1] + 0.114 * p[2];
    }
    return g;
}

/// Wang et al.'s structural similarity (2004) of two grey images of w x h in [0, 1]: the mean
/// over the windows of an 11-tap Gaussian of sigma 1.5 (the whole windows only), K1 0.01, K2 0.03
/// (tests/flam3/parity.py computes the same).
inline double ssim(const std::vector<double>& a, const std::vector<double>& b, int w, int h) {
    double k[11], sum = 0;
    for (int i = 0; i < 11; ++i) sum += k[i] = std::exp(-double((i - 5) * (i - 5)) / (2 * 1.5 * 1.5));
    for (double& v : k) v /= sum;
    const int ow = w - 10, oh = h - 10;
    // The blurred image of f(a, b), separably: rows, then columns.
    auto blur = [&](auto f) {
        std::vector<double> rows(std::size_t(ow) * std::size_t(h)), out(std::size_t(ow) * std::size_t(oh));
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < ow; ++x) {
                double t = 0;
                for (int j = 0; j < 11; ++j) {
                    const std::size_t i = std::size_t(y) * std::size_t(w) + std::size_t(x + j);
                    t += k[j] * f(a[i], b[i]);
                }
                rows[std::size_t(y) * std::size_t(ow) + std::size_t(x)] = t;
            }
        for (int y = 0; y < oh; ++y)
            for (int x = 0; x < ow; ++x) {
                double t = 0;
                for (int j = 0; j < 11; ++j)
                    t += k[j] * rows[std::size_t(y + j) * std::size_t(ow) + std::size_t(x)];
                out[std::size_t(y) * std::size_t(ow) + std::size_t(x)] = t;
            }
        return out;
    };
    const auto ma = blur([](double u, double) { return u; }), mb = blur([](double, double v) { return v; });
    const auto aa = blur([](double u, double) { return u * u; }),
               bb = blur([](double, double v) { return v * v; });
    const auto ab = blur([](double u, double v) { return u * v; });
    const double c1 = 0.01 * 0.01, c2 = 0.03 * 0.03;
    double total = 0;
    for (std::size_t i = 0; i < ma.size(); ++i) {
        const double mx = ma[i], my = mb[i];
        total += (2 * mx * my + c1) * (2 * (ab[i] - mx * my) + c2) /
                 ((mx * mx + my * my + c1) * (aa[i] - mx * mx + bb[i] - my * my + c2));
    }
    return total / double(ma.size());
}

} // namespace fp::test
