// Fitting a chaos game's view to its orbits, first estimate (chaos-game/fit.cpp refines it by the
// render's own chains): a short pre-run (paper 03: Gumowski-Mira orbits
// range widely with mu, so a fixed window either crops them or wastes the image).
//
// The pre-run plays the same game as the renderer — the same maps, weights, inversion rules,
// iteration scheme and start points — in double, on at most 256 chains of a few thousand
// steps, from RNG streams of its own (so the render's streams are untouched), and takes the
// 0.1% and 99.9% quantiles of the points after `skip` in x and y (a rare escaping point does
// not blow the view up), adds a 5% margin and widens the shorter side so that pixels are
// square. It is a pure function of the recipe: a fitted render is as reproducible as any other.
// Batched like the render: one contains call per map and one step call per map and step.
#pragma once

#include <fixpoint/fixpoint.hpp>

#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

namespace fp_render {

struct FitSetup {
    const std::vector<std::shared_ptr<const fp::Transform>>* maps;
    std::vector<double> weights;
    bool rules = true;
    const fp::IterationScheme* iteration = nullptr;
    std::optional<fp::Vec2> start;
    fp::Box start_box; ///< where random start points are drawn
    std::uint64_t seed = 1, skip = 20, chains = 4096, points = 1000000;
    int width = 512, height = 512;
};

/// The view of a width x height image that shows the box b whole: a 5% margin on each side,
/// the shorter side widened so that pixels are square (a box of no size: one of 1e-3 of its
/// larger side, or about 1e-12 of its distance from the origin).
inline fp::Box framed(fp::Box b, int width, int height) {
    double w = b.xmax - b.xmin, h = b.ymax - b.ymin;
    const double size = std::max({w, h, 1e-12 * (1 + std::fabs(b.xmin) + std::fabs(b.ymin))});
    w = std::max(w, 1e-3 * size), h = std::max(h, 1e-3 * size);
    const double cx = 0.5 * (b.xmin + b.xmax), cy = 0.5 * (b.ymin + b.ymax);
    w *= 1.1, h *= 1.1; // 5% margin on each side
    const double aspect = double(width) / double(height);
    if (w / h < aspect)
        w = h * aspect;
    else
        h = w / aspect;
    return {cx - w / 2, cx + w / 2, cy - h / 2, cy + h / 2};
}

/// The fitted view; throws fp::ParamError("fit_view", ...) when the pre-run draws nothing.
inline fp::Box fit_view(const FitSetup& s) {
    const auto& maps = *s.maps;
    const std::size_t k = maps.size();
    const std::size_t C = std::size_t(std::min<std::uint64_t>(s.chains, 256));
    const std::uint64_t steps = s.skip + std::clamp<std::uint64_t>(s.points / C, 200, 4000);
    std::vector<double> x(C), y(C), gx(C), gy(C);
    std::vector<std::uint32_t> prev(C, std::uint32_t(k)), chosen(C), idx(C);
    std::vector<std::uint64_t> age(C, 0);
    std::vector<unsigned char> inside(k * C, 0), hit(C);
    std::vector<fp::Rng> rng;
    for (std::size_t i = 0; i < C; ++i) rng.push_back(fp::chain_stream(s.seed ^ 0xF17F17F17F17ull, i));
    auto restart = [&](std::size_t i) {
        age[i] = 0;
        prev[i] = std::uint32_t(k);
        if (s.start) {
            x[i] = s.start->x, y[i] = s.start->y;
            return;
        }
        for (int tries = 0; tries < 32; ++tries) { // a point outside every set, if one is found
            x[i] = s.start_box.xmin + (s.start_box.xmax - s.start_box.xmin) * fp::uniform_double(rng[i]);
            y[i] = s.start_box.ymin + (s.start_box.ymax - s.start_box.ymin) * fp::uniform_double(rng[i]);
            bool in = false;
            for (const auto& m : maps) {
                if (!s.rules || !m->has_region()) continue;
                unsigned char h = 0;
                m->contains(fp::Points<const double>{&x[i], &y[i], 1}, &h);
                in = in || h;
            }
            if (!in) return;
        }
    };
    for (std::size_t i = 0; i < C; ++i) restart(i);
    std::vector<double> xs, ys;
    xs.reserve(C * (steps - s.skip)), ys.reserve(C * (steps - s.skip));
    for (std::uint64_t n = 0; n < steps; ++n) {
        if (s.rules)
            for (std::size_t j = 0; j < k; ++j)
                if (maps[j]->has_region())
                    maps[j]->contains(fp::Points<const double>{x.data(), y.data(), C}, &inside[j * C]);
        for (std::size_t i = 0; i < C; ++i) {
            double total = 0;
            for (std::size_t j = 0; j < k; ++j)
                if (!s.rules || (j != prev[i] && !inside[j * C + i])) total += s.weights[j];
            chosen[i] = std::uint32_t(k);
            if (total <= 0) continue;
            double u = fp::uniform_double(rng[i]) * total;
            for (std::size_t j = 0; j < k; ++j) {
                if (s.rules && (j == prev[i] || inside[j * C + i])) continue;
                chosen[i] = std::uint32_t(j);
                if ((u -= s.weights[j]) < 0) break;
            }
        }
        for (std::size_t j = 0; j < k; ++j) {
            std::size_t m = 0;
            for (std::size_t i = 0; i < C; ++i)
                if (chosen[i] == j) idx[m] = std::uint32_t(i), gx[m] = x[i], gy[m] = y[i], ++m;
            if (!m) continue;
            s.iteration->step(*maps[j], fp::Points<double>{gx.data(), gy.data(), m}, nullptr, n);
            for (std::size_t t = 0; t < m; ++t) x[idx[t]] = gx[t], y[idx[t]] = gy[t];
        }
        for (std::size_t i = 0; i < C; ++i) {
            if (chosen[i] == k || !std::isfinite(x[i]) || !std::isfinite(y[i])) {
                restart(i);
                continue;
            }
            prev[i] = chosen[i];
            if (++age[i] > s.skip) xs.push_back(x[i]), ys.push_back(y[i]);
        }
    }
    if (xs.empty()) throw fp::ParamError("fit_view", "the pre-run that fits the view drew no points");
    auto quantile = [](std::vector<double>& v, double q) {
        const auto at = v.begin() + std::ptrdiff_t(q * double(v.size() - 1));
        std::nth_element(v.begin(), at, v.end());
        return *at;
    };
    return framed({quantile(xs, 0.001), quantile(xs, 0.999), quantile(ys, 0.001), quantile(ys, 0.999)},
                  s.width, s.height);
}

} // namespace fp_render
