// The finishing stage (fixpoint/finish.hpp): flam3's density estimation and spatial filter,
// in a fixed order of float sums so that the bytes do not depend on the workers or the strips.
//
// Order of the sums. The estimate scatters each bin into the bins around it; a bin's value is
// the sum of its sources' contributions in the sources' row-major order, whichever band of rows
// a worker fills and whichever strip holds them (a worker fills its own band, visiting every
// source that reaches it in that order). The filter is separable: a pass along the rows, then
// one down the columns, each output the sum of its taps in order.
#include <fixpoint/colourer.hpp>
#include <fixpoint/errors.hpp>
#include <fixpoint/filter.hpp>
#include <fixpoint/finish.hpp>
#include <fixpoint/params.hpp>
#include <fixpoint/render.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace fp {

namespace {

constexpr int C = 5;              // channels: a, a r, a g, a b, coverage
constexpr int de_threshold = 100; // flam3's DE_THRESH (filters.h)

// flam3's gaussian, the density kernels' shape (filters.c: flam3_gaussian_filter at 1.5 d).
double de_gaussian(double x) { return std::exp(-2.0 * x * x) * std::sqrt(2.0 / 3.14159265358979323846); }

// Runs f(i) for i in [0, n): on ctx's workers, polling for a cancel, or serially.
template <class F>
void each(RenderContext* ctx, std::size_t n, F f) {
    if (!ctx || ctx->workers() <= 1) {
        for (std::size_t i = 0; i < n; ++i) {
            if (ctx && ctx->cancelled()) throw Cancelled();
            f(i);
        }
        return;
    }
    ctx->parallel_for(n, [&](std::size_t i, unsigned) {
        if (ctx->cancelled()) throw Cancelled();
        f(i);
    });
}

// One axis of the filter: output o reads bins [first[o], first[o] + count[o]) with weights
// w[o * taps + t] (t counted from first[o]); at an edge the taps inside are renormalised.
// Outputs [inner0, inner1) are inside: all their taps in the bins, unrenormalised (`common`),
// and output o's first bin is o * N - off.
struct Axis {
    std::size_t taps = 0;
    std::vector<int> first, count;
    std::vector<float> w;
    int inner0 = 0, inner1 = 0;
    std::vector<float> common;
};

Axis make_axis(const std::vector<double>& taps, int N, int o0, int on, int bins) {
    Axis a;
    const int fw = int(taps.size()), off = (fw - N) / 2;
    a.taps = std::size_t(fw);
    a.first.resize(std::size_t(on));
    a.count.resize(std::size_t(on));
    a.w.assign(std::size_t(on) * a.taps, 0.0f);
    for (int o = 0; o < on; ++o) {
        const int start = (o0 + o) * N - off;
        const int t0 = std::max(0, -start), t1 = std::min(fw, bins - start);
        double sum = 0;
        for (int t = t0; t < t1; ++t) sum += taps[std::size_t(t)];
        const bool edge = t0 > 0 || t1 < fw;
        a.first[std::size_t(o)] = start + t0;
        a.count[std::size_t(o)] = std::max(0, t1 - t0);
        for (int t = t0; t < t1; ++t)
            a.w[std::size_t(o) * a.taps + std::size_t(t - t0)] =
                float(edge && sum > 0 ? taps[std::size_t(t)] / sum : taps[std::size_t(t)]);
    }
    // (The inside is one run: an output is at an edge only near the ends.)
    a.inner0 = on, a.inner1 = on;
    for (int o = 0; o < on; ++o)
        if (a.count[std::size_t(o)] == fw) {
            if (a.inner0 == on) a.inner0 = o;
            a.inner1 = o + 1;
        }
    for (int t = 0; t < fw; ++t) a.common.push_back(float(taps[std::size_t(t)]));
    return a;
}

} // namespace

std::vector<double> spatial_taps(const Filter* filter, int N) {
    if (!filter) return std::vector<double>(std::size_t(N), 1.0 / double(N));
    const double s = filter->support(), fw = 2.0 * s * double(N) * filter->radius();
    int width = int(fw) + 1;
    if ((width ^ N) & 1) ++width; // the same parity as N: the window centred on the pixel's bins
    const double adjust = fw > 0 ? s * double(width) / fw : 1.0;
    std::vector<double> taps(static_cast<std::size_t>(width));
    double sum = 0;
    for (int i = 0; i < width; ++i) {
        taps[std::size_t(i)] = filter->value(((2.0 * i + 1.0) / double(width) - 1.0) * adjust);
        sum += taps[std::size_t(i)];
    }
    if (!(sum > 0) || !std::isfinite(sum))
        throw ParamError("filter", "the filter has no weight at radius " + std::to_string(filter->radius()) +
                                       ": make the radius larger");
    for (double& t : taps) t /= sum;
    return taps;
}

DensityKernels DensityKernels::make(const FinishSpec& spec) {
    DensityKernels de;
    const int N = spec.supersample;
    de.curve = spec.estimator_curve;
    de.window = N / 2;
    de.window_scale = N % 2 == 0 ? std::pow(double(N) / (double(N) + 1.0), 2.0) : 1.0;
    if (!spec.estimates()) return de;
    if (spec.estimator_minimum > spec.estimator_radius)
        throw ParamError("estimator_minimum", "the estimator's minimum must not exceed estimator_radius");
    const double curve = spec.estimator_curve;
    // (flam3: "the '+1' comes from the assumed distance to the first pixel".)
    const double cmax = spec.estimator_radius * N + 1, cmin = spec.estimator_minimum * N + 1;
    const double nd = std::pow(cmax / cmin, 1.0 / curve);
    if (nd > 1e7)
        throw ParamError("estimator_curve", "the estimator needs too many kernels (" + std::to_string(nd) +
                                                "): raise estimator_minimum or estimator_curve");
    const int n = int(std::ceil(nd));
    constexpr int keep = 100;
    int count;
    if (n > keep) {
        count = int(std::ceil(de_threshold + std::pow(double(n - de_threshold), curve))) + 1;
        de.max_filtered_counts = int(std::pow(double(count - de_threshold), 1.0 / curve)) + de_threshold;
    } else {
        count = n;
        de.max_filtered_counts = count;
    }
    const int half = (int(2 * std::ceil(cmax) - 1) - 1) / 2;
    for (int k = 0; k < count; ++k) {
        double h = k < keep ? cmax / std::pow(double(k) + 1, curve)
                            : cmax / std::pow(std::pow(double(k - keep), 1.0 / curve) + keep + 1, curve);
        const bool last = h <= cmin;
        if (last) h = cmin;
        double sum = 0;
        for (int y = -half; y <= half; ++y)
            for (int x = -half; x <= half; ++x) {
                const double d = std::sqrt(double(x * x + y * y)) / h;
                if (d <= 1.0) sum += de_gaussian(1.5 * d);
            }
        Kernel K;
        K.width = h;
        K.reach = int(std::ceil(h)) - 1;
        const int side = 2 * K.reach + 1;
        K.coefs.assign(std::size_t(side) * std::size_t(side), 0.0f);
        for (int y = -K.reach; y <= K.reach; ++y)
            for (int x = -K.reach; x <= K.reach; ++x) {
                const double d = std::sqrt(double(x * x + y * y)) / h;
                if (d <= 1.0)
                    K.coefs[std::size_t((y + K.reach) * side + (x + K.reach))] =
                        float(de_gaussian(1.5 * d) / sum);
            }
        de.kernels.push_back(std::move(K));
        if (last) break;
    }
    return de;
}

std::size_t DensityKernels::index(double c) const {
    const std::size_t last = kernels.size() - 1;
    std::size_t k;
    if (c > max_filtered_counts)
        k = last;
    else if (c <= de_threshold)
        k = std::size_t(std::max(0.0, std::ceil(c) - 1));
    else
        k = std::size_t(de_threshold) + std::size_t(std::floor(std::pow(c - de_threshold, curve)));
    return std::min(k, last);
}

double DensityKernels::count_scale(const FinishSpec& spec, const HistogramSummary& whole) {
    if (!(spec.estimator_quality > 0) || whole.hits == 0) return 1.0;
    const double N = spec.supersample;
    const double pixels = double(whole.width) * double(whole.height) / (N * N);
    return spec.estimator_quality * pixels / double(whole.hits);
}

int FinishSpec::halo() const {
    const int N = supersample;
    const int filter_reach = (int(spatial_taps(filter.get(), N).size()) - N) / 2;
    if (!estimates()) return filter_reach;
    const DensityKernels de = DensityKernels::make(*this);
    return filter_reach + de.kernels.front().reach + de.window;
}

std::uint64_t FinishSpec::bytes(int width, int rows) const {
    const std::uint64_t N = std::uint64_t(supersample), W = std::uint64_t(width) * N;
    const std::uint64_t bins = W * (std::uint64_t(rows) * N + 2 * std::uint64_t(halo()));
    // The bins' channels, the estimate's, the row pass's (the image's width), the pixels'.
    const std::uint64_t estimate = estimates() ? bins : 0;
    return (bins + estimate) * C * sizeof(float) +
           std::uint64_t(width) * (bins / std::max<std::uint64_t>(W, 1)) * C * sizeof(float) +
           std::uint64_t(width) * std::uint64_t(rows) * C * sizeof(float);
}

FinishSpec FinishSpec::read(const ParamBag& p) {
    FinishSpec s;
    s.supersample = int(p.integer("supersample"));
    if (p.has("filter")) s.filter = p.object<Filter>("filter");
    s.estimator_radius = p.real("estimator_radius");
    s.estimator_minimum = p.real("estimator_minimum");
    s.estimator_curve = p.real("estimator_curve");
    s.estimator_quality = p.real("estimator_quality");
    (void)spatial_taps(s.filter.get(), s.supersample); // (its error now, not after the chains)
    (void)DensityKernels::make(s);
    return s;
}

namespace {

// What every band of a finish shares: the filter's taps, the density kernels.
struct Plan {
    std::vector<double> taps;
    DensityKernels de;
    double count_scale = 1; // DensityKernels::count_scale
};

// finish() of the image rows [o0, o0 + on): on ctx's workers within the strip, or serially.
void finish_rows(const FinishSpec& spec, const Plan& plan, const Colourer& colourer, const Histogram& part,
                 int p0, const HistogramSummary& whole, int width, int o0, int on, Rgb background, float* rgb,
                 RenderContext* ctx) {
    const int N = spec.supersample;
    const std::size_t Ws = std::size_t(width) * std::size_t(N);
    const int Hs = whole.height, p1 = p0 + part.height;
    const std::vector<double>& taps = plan.taps;
    const int off = (int(taps.size()) - N) / 2;
    // The estimate's rows the filter reads, [q0, q1), and the bins they read, [s0, s1).
    const DensityKernels& de = plan.de;
    const int reach = spec.estimates() ? de.kernels.front().reach : 0;
    const int q0 = std::max(0, o0 * N - off), q1 = std::min(Hs, (o0 + on) * N + off);
    const int s0 = std::max(p0, q0 - reach), s1 = std::min(p1, q1 + reach);
    if ((q0 - reach > 0 && s0 > q0 - reach) || (q1 + reach < Hs && s1 < q1 + reach))
        throw InternalError("finish: the strip's histogram lacks rows its pixels read");
    const std::size_t rows_in = std::size_t(std::max(0, s1 - s0)), rows_q = std::size_t(q1 - q0);
    const double scale = double(N) * double(N);

    // The channels in planes (a, a r, a g, a b, coverage), each rows x Ws, so that the estimate's
    // scatter and the filter's sums run along contiguous rows (the compiler's vectors).
    // Bin row y's channels into o[0..C) (Ws floats each), through `four` (4 Ws floats).
    const auto linear_row = [&](int y, float* const* o, float* four) {
        const std::size_t i_row = std::size_t(y - p0) * Ws;
        colourer.linear(part, p0, whole, scale, i_row, i_row + Ws, four);
        for (std::size_t x = 0; x < Ws; ++x) {
            const bool hit = part.hits_at(i_row + x) != 0;
            const float a = hit ? four[4 * x] : 0.0f;
            o[0][x] = a, o[1][x] = a * four[4 * x + 1], o[2][x] = a * four[4 * x + 2];
            o[3][x] = a * four[4 * x + 3], o[4][x] = hit ? 1.0f : 0.0f;
        }
    };
    // The filter along one row: its channels at in + ch * in_plane (Ws bins) into out + ch *
    // out_plane (the image's width).
    const Axis ax = make_axis(taps, N, 0, width, int(Ws));
    const std::size_t W = std::size_t(width), plane_row = rows_q * W;
    // Inside, the taps are the same for every output: tap by tap over the row, which the
    // compiler vectorises (each output's sum still in tap order: the same floats).
    const auto row_pass = [&](const float* in, std::size_t in_plane, float* out, std::size_t out_plane) {
        const std::size_t x0 = std::size_t(ax.inner0), x1 = std::size_t(ax.inner1), n = x1 - x0;
        const std::size_t step = std::size_t(N);
        for (int ch = 0; ch < C; ++ch) {
            const float* i = in + std::size_t(ch) * in_plane;
            float* o = out + std::size_t(ch) * out_plane;
            for (std::size_t x = 0; x < W; ++x) {
                if (x == x0 && n > 0) x = x1; // (the inside below)
                if (x >= W) break;
                const float* w = ax.w.data() + x * ax.taps;
                const float* b = i + std::size_t(ax.first[x]);
                float acc = 0;
                for (int t = 0; t < ax.count[x]; ++t) acc += w[t] * b[t];
                o[x] = acc;
            }
            if (n == 0) continue;
            float* __restrict oi = o + x0;
            std::fill(oi, oi + n, 0.0f);
            for (std::size_t t = 0; t < ax.taps; ++t) {
                const float wt = ax.common[t];
                const float* __restrict b = i + std::size_t(ax.first[x0]) + t;
                for (std::size_t k = 0; k < n; ++k) oi[k] += wt * b[k * step];
            }
        }
    };
    std::vector<float> rowpass(plane_row * C);
    if (!spec.estimates()) {
        // Without the estimate each bin row is filtered as soon as it is made, from a buffer of
        // one row that stays in cache: the same sums in the same order as through whole planes,
        // without writing and reading them (rows [q0, q1) = [s0, s1) here).
        each(ctx, rows_q, [&](std::size_t r) {
            std::vector<float> four(4 * Ws), row(std::size_t(C) * Ws);
            float* o[C];
            for (int ch = 0; ch < C; ++ch) o[ch] = row.data() + std::size_t(ch) * Ws;
            linear_row(q0 + int(r), o, four.data());
            row_pass(row.data(), Ws, rowpass.data() + r * W, plane_row);
        });
    } else {
        // Linear: rows [s0, s1).
        const std::size_t plane_in = rows_in * Ws;
        std::vector<float> lin(plane_in * C);
        each(ctx, rows_in, [&](std::size_t r) {
            std::vector<float> four(4 * Ws);
            float* o[C];
            for (int ch = 0; ch < C; ++ch) o[ch] = lin.data() + std::size_t(ch) * plane_in + r * Ws;
            linear_row(s0 + int(r), o, four.data());
        });

        // Estimate: the rows [q0, q1), from the sources [s0, s1), in bands of rows.
        const std::size_t plane_q = rows_q * Ws;
        std::vector<float> est(plane_q * C, 0.0f);
        const std::size_t band = 32, bands = (rows_q + band - 1) / band;
        each(ctx, bands, [&](std::size_t b) {
            const int b0 = q0 + int(b * band), b1 = std::min(q1, b0 + int(band));
            for (int y = std::max(s0, b0 - reach); y < std::min(s1, b1 + reach); ++y) {
                const std::size_t row = std::size_t(y - p0) * Ws;
                for (std::size_t x = 0; x < Ws; ++x) {
                    if (part.hits_at(row + x) == 0) continue;
                    // The count over the window around the bin (the histogram's own rows).
                    double c = 0;
                    const int w = de.window;
                    for (int yy = std::max(p0, y - w); yy <= std::min(p1 - 1, y + w); ++yy)
                        for (std::size_t xx = x >= std::size_t(w) ? x - std::size_t(w) : 0;
                             xx <= std::min(Ws - 1, x + std::size_t(w)); ++xx)
                            c += double(part.hits_at(std::size_t(yy - p0) * Ws + xx));
                    c *= de.window_scale * plan.count_scale;
                    const DensityKernels::Kernel& K = de.kernels[de.index(c)];
                    const int r = K.reach, side = 2 * r + 1;
                    if (y + r < b0 || y - r >= b1) continue;
                    const std::size_t at = std::size_t(y - s0) * Ws + x;
                    float v[C];
                    for (int ch = 0; ch < C; ++ch) v[ch] = lin[std::size_t(ch) * plane_in + at];
                    const std::size_t dx0 = std::min<std::size_t>(x, std::size_t(r));
                    const std::size_t dx1 = std::min<std::size_t>(Ws - 1 - x, std::size_t(r));
                    const std::size_t n = dx0 + dx1 + 1;
                    for (int dy = std::max(-r, b0 - y); dy <= std::min(r, b1 - 1 - y); ++dy) {
                        const float* k = K.coefs.data() + std::size_t((dy + r) * side + r) - dx0;
                        const std::size_t o0 = std::size_t(y + dy - q0) * Ws + x - dx0;
                        for (int ch = 0; ch < C; ++ch) {
                            float* __restrict o = est.data() + std::size_t(ch) * plane_q + o0;
                            const float vc = v[ch];
                            for (std::size_t i = 0; i < n; ++i) o[i] += k[i] * vc;
                        }
                    }
                }
            }
        });
        lin.clear();
        lin.shrink_to_fit();
        // The filter along the rows: rows [q0, q1) at the image's width.
        each(ctx, rows_q, [&](std::size_t r) {
            row_pass(est.data() + r * Ws, plane_q, rowpass.data() + r * W, plane_row);
        });
    }
    // Down the columns, then the pixels.
    const Axis ay = make_axis(taps, N, o0, on, Hs);
    each(ctx, std::size_t(on), [&](std::size_t o) {
        std::vector<float> col(W * C, 0.0f), px(W * C);
        const float* w = ay.w.data() + o * ay.taps;
        for (int ch = 0; ch < C; ++ch) {
            float* __restrict acc = col.data() + std::size_t(ch) * W;
            for (int t = 0; t < ay.count[o]; ++t) {
                const float* in =
                    rowpass.data() + std::size_t(ch) * plane_row + std::size_t(ay.first[o] + t - q0) * W;
                const float wt = w[t];
                for (std::size_t x = 0; x < W; ++x) acc[x] += wt * in[x];
            }
        }
        for (std::size_t x = 0; x < W; ++x) {
            float* p = px.data() + x * C;
            const float a = col[x], inv = a > 0 ? 1.0f / a : 0.0f;
            p[0] = a > 0 ? a : 0.0f;
            p[1] = a > 0 ? col[W + x] * inv : 0.0f;
            p[2] = a > 0 ? col[2 * W + x] * inv : 0.0f;
            p[3] = a > 0 ? col[3 * W + x] * inv : 0.0f;
            p[4] = std::clamp(col[4 * W + x], 0.0f, 1.0f);
        }
        colourer.display(px.data(), W, background, rgb + o * W * 3);
    });
}

} // namespace

void finish(const FinishSpec& spec, const Colourer& colourer, const Histogram& part, int p0,
            const HistogramSummary& whole, int width, int o0, int on, Rgb background, float* rgb,
            RenderContext* ctx) {
    if (part.width != width * spec.supersample)
        throw InternalError("finish: the histogram is not the image's width times N");
    const Plan plan{spatial_taps(spec.filter.get(), spec.supersample), DensityKernels::make(spec),
                    DensityKernels::count_scale(spec, whole)};
    // In bands of image rows, one a worker, each finished from its own rows of the histogram
    // and their halo (as a strip: the same bytes), in buffers a fraction of the image's, so
    // that they stay in cache and their pages are few.
    constexpr int band = 64;
    const int bands = (on + band - 1) / band;
    if (bands <= 1 || !ctx || ctx->workers() <= 1) {
        for (int b = 0; b < bands; ++b) {
            const int b0 = o0 + b * band;
            finish_rows(spec, plan, colourer, part, p0, whole, width, b0, std::min(band, o0 + on - b0),
                        background, rgb + std::size_t(b0 - o0) * std::size_t(width) * 3,
                        bands <= 1 ? ctx : nullptr);
            if (ctx && ctx->cancelled()) throw Cancelled();
        }
        return;
    }
    each(ctx, std::size_t(bands), [&](std::size_t b) {
        const int b0 = o0 + int(b) * band;
        finish_rows(spec, plan, colourer, part, p0, whole, width, b0, std::min(band, o0 + on - b0),
                    background, rgb + std::size_t(b0 - o0) * std::size_t(width) * 3, nullptr);
    });
}

} // namespace fp
