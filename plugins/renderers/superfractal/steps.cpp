// The steps of the V-variable algorithm (superfractal.cpp's header: the shares, bad values,
// colour, determinism): the start buffers, each step's new buffers from the old ones, the repair
// of bad values, and the child's plot into one integer histogram.
#include "superfractal/choices.hpp"
#include "superfractal/renderer.hpp"

#include <fixpoint/fixpoint.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace fp_superfractal {

void Superfractal::fill_start(Generation& g, size_t b, size_t begin, size_t end, uint64_t stream) const {
    fp::Rng rng = fp::chain_stream(seed_, stream);
    const size_t base = b * size_t(points_);
    for (size_t i = begin; i < end; ++i) {
        const double u = fp::uniform_double(rng), w = fp::uniform_double(rng);
        g.x[base + i] = sxmin_ + (sxmax_ - sxmin_) * u;
        g.y[base + i] = symin_ + (symax_ - symin_) * w;
    }
    // flam3's random start of the palette index, from the same stream after the points (which
    // are then those of a render without a palette).
    if (palette_)
        for (size_t i = begin; i < end; ++i) g.ci[base + i] = fp::uniform_float(rng);
    if (steal_) {
        std::fill(g.u.begin() + std::ptrdiff_t(base + begin), g.u.begin() + std::ptrdiff_t(base + end), 0.5);
        std::fill(g.v.begin() + std::ptrdiff_t(base + begin), g.v.begin() + std::ptrdiff_t(base + end), 0.5);
    }
    if (rgb_) {
        std::fill(g.r.begin() + std::ptrdiff_t(base + begin), g.r.begin() + std::ptrdiff_t(base + end),
                  initial_colour_.r);
        std::fill(g.g.begin() + std::ptrdiff_t(base + begin), g.g.begin() + std::ptrdiff_t(base + end),
                  initial_colour_.g);
        std::fill(g.b.begin() + std::ptrdiff_t(base + begin), g.b.begin() + std::ptrdiff_t(base + end),
                  initial_colour_.b);
    }
}

// New buffer b, points [begin, end): for each share j of IFS `ifs` overlapping the range, the
// source points j + m t of buffer src[j], in batches of batch_points that stay in L1: gather,
// one Transform::apply call, the colours and one Colourer::update call, the finiteness count.
// Returns the number of non-finite points made.
uint64_t Superfractal::step_chunk(const Generation& cur, Generation& next, size_t b, size_t begin, size_t end,
                                  uint32_t ifs, const uint32_t* src) const {
    const std::vector<uint32_t>& maps = ifs_[ifs];
    const size_t n = size_t(points_), m = maps.size();
    const size_t q = n / m, rem = n % m;
    const size_t base = b * n;
    uint32_t map_index[batch_points];
    uint64_t bad = 0;
    for (size_t j = 0; j < m; ++j) {
        const size_t off = j * q + std::min(j, rem), nj = q + (j < rem ? 1 : 0);
        const size_t lo = std::max(begin, off), hi = std::min(end, off + nj);
        if (lo >= hi) continue;
        const size_t sbase = size_t(src[j]) * n;
        std::fill(map_index, map_index + batch_points, maps[j]);
        for (size_t b0 = lo; b0 < hi; b0 += batch_points) {
            const size_t b1 = std::min(hi, b0 + batch_points), len = b1 - b0;
            double* __restrict x = next.x.data() + base + b0;
            double* __restrict y = next.y.data() + base + b0;
            const double* __restrict cx = cur.x.data();
            const double* __restrict cy = cur.y.data();
            const size_t s0 = sbase + j + m * (b0 - off); // source of point b0 + i: s0 + m i
            for (size_t i = 0; i < len; ++i) {
                const size_t s = s0 + m * i;
                x[i] = cx[s];
                y[i] = cy[s];
            }
            maps_[maps[j]]->apply(fp::Points<double>{x, y, len}, nullptr);
            if (steal_) {
                // The colour IFS in lockstep: the same map number, the same source point.
                const std::array<double, 6>& cm = colour_maps_[maps[j]];
                double* __restrict u = next.u.data() + base + b0;
                double* __restrict v = next.v.data() + base + b0;
                const double* __restrict cu = cur.u.data();
                const double* __restrict cv = cur.v.data();
                for (size_t i = 0; i < len; ++i) {
                    const size_t s = s0 + m * i;
                    const double u0 = cu[s], v0 = cv[s];
                    u[i] = cm[0] * u0 + cm[1] * v0 + cm[4];
                    v[i] = cm[2] * u0 + cm[3] * v0 + cm[5];
                }
            }
            if (rgb_) {
                float* __restrict r = next.r.data() + base + b0;
                float* __restrict g = next.g.data() + base + b0;
                float* __restrict bl = next.b.data() + base + b0;
                for (size_t i = 0; i < len; ++i) {
                    const size_t s = s0 + m * i;
                    r[i] = cur.r[s];
                    g[i] = cur.g[s];
                    bl[i] = cur.b[s];
                }
                fp::ColourState cs{r, g, bl, len};
                if (palette_) {
                    float* __restrict ci = next.ci.data() + base + b0;
                    for (size_t i = 0; i < len; ++i) ci[i] = cur.ci[s0 + m * i];
                    cs.index = ci;
                    cs.map_index = map_index_.data();
                    cs.map_speed = map_speed_.data();
                }
                colourer_->update(map_index, cs, colours_.data(), nullptr);
            }
            for (size_t i = 0; i < len; ++i) bad += (std::isfinite(x[i]) && std::isfinite(y[i])) ? 0u : 1u;
        }
    }
    return bad;
}

// Replace the non-finite points of buffer b by the previous finite point (the first finite
// one for those before it); redraw the whole buffer from the start box when none is finite.
// Returns the points redrawn.
uint64_t Superfractal::repair(Generation& g, size_t b, uint64_t stream) const {
    const size_t n = size_t(points_), base = b * n;
    auto finite = [&](size_t i) { return std::isfinite(g.x[base + i]) && std::isfinite(g.y[base + i]); };
    size_t first = 0;
    while (first < n && !finite(first)) ++first;
    if (first == n) {
        fill_start(g, b, 0, n, stream);
        return n;
    }
    auto copy = [&](size_t to, size_t from) {
        g.x[base + to] = g.x[base + from];
        g.y[base + to] = g.y[base + from];
        if (steal_) {
            g.u[base + to] = g.u[base + from];
            g.v[base + to] = g.v[base + from];
        }
        if (rgb_) {
            g.r[base + to] = g.r[base + from];
            g.g[base + to] = g.g[base + from];
            g.b[base + to] = g.b[base + from];
        }
        if (palette_) g.ci[base + to] = g.ci[base + from];
    };
    for (size_t i = 0; i < first; ++i) copy(i, first);
    for (size_t i = first + 1; i < n; ++i)
        if (!finite(i)) copy(i, i - 1);
    return 0;
}

fp::Image Superfractal::render(fp::RenderContext& ctx, fp::RenderStats& stats) const {
    stats = fp::RenderStats{};
    const size_t n = size_t(points_), nb = size_t(buffers_);
    const size_t chunks = (n + chunk_points - 1) / chunk_points;
    const size_t tasks = nb * chunks;

    Generation gen[2];
    for (auto& g : gen) {
        g.x.resize(nb * n);
        g.y.resize(nb * n);
        if (rgb_) {
            g.r.resize(nb * n);
            g.g.resize(nb * n);
            g.b.resize(nb * n);
        }
        if (steal_) {
            g.u.resize(nb * n);
            g.v.resize(nb * n);
        }
        if (palette_) g.ci.resize(nb * n);
    }

    // Over several ranks (MPI), rank r computes tasks r, r + N, ... of every generation, the
    // rest of it left +0 (all bits zero), and every rank gets the whole generation back by a
    // bitwise or (RenderContext::combine) before the next step reads it. Each task's points
    // depend on the recipe alone, so the generations are the same bytes on any rank count.
    const size_t rank = ctx.rank(), ranks = std::max(1u, ctx.ranks());
    const size_t mine = tasks > rank ? (tasks - rank + ranks - 1) / ranks : 0;
    const auto clear = [&](Generation& g) {
        if (ranks == 1) return;
        for (auto* a : {&g.x, &g.y, &g.u, &g.v}) std::fill(a->begin(), a->end(), 0.0);
        for (auto* a : {&g.r, &g.g, &g.b, &g.ci}) std::fill(a->begin(), a->end(), 0.0f);
    };
    const auto share = [&](Generation& g) {
        if (ranks == 1) return;
        for (auto* a : {&g.x, &g.y, &g.u, &g.v})
            ctx.combine(a->data(), a->size() * sizeof(double), sizeof(uint64_t), fp::fold::bit_or<uint64_t>,
                        true);
        for (auto* a : {&g.r, &g.g, &g.b, &g.ci})
            ctx.combine(a->data(), a->size() * sizeof(float), sizeof(uint32_t), fp::fold::bit_or<uint32_t>,
                        true);
    };
    static_assert(sizeof(double) == sizeof(uint64_t) && sizeof(float) == sizeof(uint32_t));

    // Start sets: random points of the start box.
    clear(gen[0]);
    ctx.parallel_for(mine, [&](size_t i, unsigned) {
        if (ctx.cancelled()) throw fp::Cancelled();
        const size_t t = rank + i * ranks;
        const size_t b = t / chunks, c = t % chunks;
        const size_t begin = c * chunk_points, end = std::min(n, begin + chunk_points);
        fill_start(gen[0], b, begin, end, 1 + t);
        ctx.progress(end - begin);
    });
    share(gen[0]);

    fp::Rng choices = fp::chain_stream(seed_, 0);
    std::vector<uint32_t> ifs_choice(nb), src(nb * max_maps_);
    std::vector<uint64_t> bad(tasks);
    std::vector<uint64_t> redrawn(nb);
    for (uint64_t s = 0; s < steps_; ++s) {
        if (ctx.cancelled()) throw fp::Cancelled();
        const Generation& cur = gen[s % 2];
        Generation& next = gen[(s + 1) % 2];
        for (size_t b = 0; b < nb; ++b) {
            ifs_choice[b] = draw(choices, ifs_cum_, ifs_fallback_);
            for (size_t j = 0; j < ifs_[ifs_choice[b]].size(); ++j)
                src[b * max_maps_ + j] = draw(choices, buffer_cum_, buffer_fallback_);
        }
        clear(next);
        std::fill(bad.begin(), bad.end(), 0);
        ctx.parallel_for(mine, [&](size_t i, unsigned) {
            if (ctx.cancelled()) throw fp::Cancelled();
            const size_t t = rank + i * ranks;
            const size_t b = t / chunks, c = t % chunks;
            const size_t begin = c * chunk_points, end = std::min(n, begin + chunk_points);
            bad[t] = step_chunk(cur, next, b, begin, end, ifs_choice[b], src.data() + b * max_maps_);
            ctx.progress(end - begin);
        });
        share(next);
        if (ranks > 1) ctx.combine(bad.data(), bad.size() * 8, 8, fp::fold::sum<uint64_t>, true);
        uint64_t bad_step = 0;
        for (uint64_t x : bad) bad_step += x;
        if (bad_step == 0) continue;
        stats.bad_values += bad_step;
        std::fill(redrawn.begin(), redrawn.end(), 0);
        ctx.parallel_for(nb, [&](size_t b, unsigned) {
            if (ctx.cancelled()) throw fp::Cancelled();
            uint64_t any = 0;
            for (size_t c = 0; c < chunks; ++c) any += bad[b * chunks + c];
            if (any) redrawn[b] = repair(next, b, 1 + tasks + s * nb + b);
        });
        for (uint64_t x : redrawn) stats.restarts += x;
    }
    if (ctx.cancelled()) throw fp::Cancelled();
    // (Every rank holds the last generation; rank 0 plots it, a small part of the work.)
    if (rank != 0) return fp::Image{};

    // The child: buffer `child` of the last generation, into one integer histogram.
    const Generation& last = gen[steps_ % 2];
    // A colourer that reads hit counts alone gets them alone (fp::Histogram::hits): a quarter
    // of the memory, and of the work of filling, summarising and shading the bins.
    const bool hits_only = colourer_->reads_hits_only();
    // (With the finishing stage, supersample times the image: fixpoint/finish.hpp.)
    const int N = finish_.supersample, W = frame_.width * N, H = frame_.height * N;
    fp::Histogram hist;
    if (hits_only) {
        hist.width = W;
        hist.height = H;
        hist.hits.assign(size_t(W) * size_t(H), 0);
    } else {
        hist.resize(W, H);
    }
    const double scx = double(W) / (frame_.region.xmax - frame_.region.xmin),
                 scy = double(H) / (frame_.region.ymax - frame_.region.ymin);
    const size_t base = size_t(child_) * n;
    const auto quant = fp::quantise_colour;
    uint64_t drawn = 0;
    for (size_t i = 0; i < n; ++i) {
        if (i % (size_t(1) << 20) == 0 && ctx.cancelled()) throw fp::Cancelled();
        const double x = last.x[base + i], y = last.y[base + i];
        if (!(x >= frame_.region.xmin && x < frame_.region.xmax && y > frame_.region.ymin &&
              y <= frame_.region.ymax))
            continue;
        const auto ix = std::min(uint32_t((x - frame_.region.xmin) * scx), uint32_t(W - 1));
        const auto iy = std::min(uint32_t((frame_.region.ymax - y) * scy), uint32_t(H - 1));
        const size_t at = size_t(iy) * size_t(W) + ix;
        ++drawn;
        if (hits_only) {
            ++hist.hits[at];
            continue;
        }
        fp::HistBin& bin = hist.bins[at];
        ++bin.hits;
        if (steal_) {
            const fp::Rgb c = picture_.at(last.u[base + i], last.v[base + i]);
            bin.r += quant(c.r);
            bin.g += quant(c.g);
            bin.b += quant(c.b);
        } else if (colour_) {
            bin.r += quant(last.r[base + i]);
            bin.g += quant(last.g[base + i]);
            bin.b += quant(last.b[base + i]);
        }
    }
    stats.samples = n;
    stats.drawn = drawn;
    stats.unit = "points";

    fp::Image img;
    img.width = frame_.width;
    img.height = frame_.height;
    img.channels = 3;
    img.pixels.assign(size_t(frame_.width) * size_t(frame_.height) * 3, 0.0f);
    if (finish_.active())
        fp::finish(finish_, *colourer_, hist, 0, fp::HistogramSummary::of(hist, &ctx), frame_.width, 0,
                   frame_.height, frame_.background, img.pixels.data(), &ctx);
    else
        colourer_->resolve_parallel(hist, frame_.background, img.pixels.data(), ctx);
    return img;
}

} // namespace fp_superfractal
