// The colourers' halves of the finishing stage (fixpoint/finish.hpp): each bin's density
// before gamma (Colourer::linear), and the pixel from the filtered channels after the filter
// (Colourer::display). Split where flam3 splits its tone: the log of the density before the
// filter and the density estimation, the gamma after, so that a filtered or estimated image of
// a dense region is the unfinished one's, and a sparse region's estimate glows as flam3's does.
#pragma once

#include <fixpoint/fixpoint.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

namespace fp_colourers {

/// a = log2(1 + s h) / log2(1 + s max h), paper 02's eq. (28) before its power 1 / gamma, with
/// the hits read as s h (s = N^2 for an N-times supersampled histogram: an image pixel's hits),
/// so that a supersampled render's densities are those of its image's pixels.
class LinearDensity {
public:
    LinearDensity(std::uint64_t max_hits, double scale)
        : scale_(scale), inv_(max_hits > 0 ? 1.0 / std::log2(1.0 + scale * double(max_hits)) : 0.0) {}
    float operator()(std::uint64_t h) const { return float(std::log2(1.0 + scale_ * double(h)) * inv_); }

private:
    double scale_, inv_;
};

/// flam3's density of a bin (flam3 3.1.1, rect.c: k1 log(1 + c k2) / PREFILTER_WHITE, c = 255
/// per hit), in units where 1 is white: a = k1 ln(1 + k2 h), k1 = contrast brightness 268 / 256,
/// k2 = rho / contrast with rho = whole.density, the points per point drawn and per unit of
/// the view's area that one hit of a bin is (flam3's 1 / (area sample_density) with its
/// oversample). So a pixel's density is the plane's measure, whatever the points, size and
/// supersampling: a longer render converges to the same picture, as in flam3. Without a
/// density from the renderer (0), rho is that of the hits over the histogram as a unit square.
class Flam3Density {
public:
    Flam3Density(const fp::HistogramSummary& whole, double brightness, double contrast)
        : k1_(contrast * brightness * 268.0 / 256.0), k2_(rho(whole) / contrast) {}
    float operator()(std::uint64_t h) const { return float(k1_ * std::log1p(k2_ * double(h))); }

private:
    static double rho(const fp::HistogramSummary& w) {
        if (w.density > 0) return w.density;
        return w.hits > 0 ? double(w.width) * double(w.height) / double(w.hits) : 0.0;
    }
    double k1_, k2_;
};

/// Colourer::linear for a colourer whose bin colour is colour(i, hits) (3 floats) and whose
/// density is density(hits) (a float).
template <class Density, class Colour>
void density_bins(const fp::Histogram& h, std::size_t i0, std::size_t i1, float* out, const Density& density,
                  Colour colour) {
    for (std::size_t i = i0; i < i1; ++i) {
        float* o = out + 4 * (i - i0);
        const std::uint64_t hits = h.hits_at(i);
        if (hits == 0) {
            o[0] = o[1] = o[2] = o[3] = 0;
            continue;
        }
        o[0] = density(hits);
        const fp::Rgb c = colour(i, hits);
        o[1] = c.r, o[2] = c.g, o[3] = c.b;
    }
}

/// density_bins with the density log (LinearDensity) or flat (1 wherever hit).
template <class Colour>
void linear_bins(const fp::Histogram& h, const fp::HistogramSummary& whole, double scale, bool log,
                 std::size_t i0, std::size_t i1, float* out, Colour colour) {
    const LinearDensity density(whole.max_hits, scale);
    density_bins(
        h, i0, i1, out, [&](std::uint64_t hits) { return log ? density(hits) : 1.0f; }, colour);
}

/// The mean colour of bin i (its colour sums over its hits), or with `last` its last colour.
inline fp::Rgb bin_colour(const fp::Histogram& h, std::size_t i, std::uint64_t hits, bool last) {
    const double k = 1.0 / double(fp::colour_scale);
    if (last) {
        const fp::LastColour& c = h.last[i];
        return {float(c.r * k), float(c.g * k), float(c.b * k)};
    }
    const fp::HistBin& b = h.bins[i];
    const double m = k / double(hits);
    return {float(double(b.r) * m), float(double(b.g) * m), float(double(b.b) * m)};
}

/// Colourer::display of the shaded colourers: pixel = clamp(colour * k(a) + (1 - coverage) *
/// background, 0, 1), k(a) = brightness * a^(1 / gamma) with log density, brightness * a with
/// flat; unfiltered (coverage 0 or 1) that is resolve()'s pixel.
inline void display_shaded(const float* in, std::size_t n, fp::Rgb bg, float* rgb, bool log, double gamma,
                           double brightness) {
    const double inv_gamma = 1.0 / gamma;
    for (std::size_t i = 0; i < n; ++i) {
        const float* p = in + 5 * i;
        const double a = p[0], open = 1.0 - double(p[4]);
        const double k = a > 0 ? brightness * (log ? std::pow(a, inv_gamma) : a) : 0.0;
        rgb[3 * i] = float(std::clamp(double(p[1]) * k + open * double(bg.r), 0.0, 1.0));
        rgb[3 * i + 1] = float(std::clamp(double(p[2]) * k + open * double(bg.g), 0.0, 1.0));
        rgb[3 * i + 2] = float(std::clamp(double(p[3]) * k + open * double(bg.b), 0.0, 1.0));
    }
}

} // namespace fp_colourers

namespace fp_colourers {

/// flam3's tone after the filter (flam3 3.1.1: rect.c's final loop, flam3_calc_alpha and
/// flam3_calc_newrgb in palettes.c), in units where 1 is white (flam3 counts 0..255 and
/// compares with 255 after a factor 256: the same but for that 256/255):
///   alpha = a^g with g = 1 / gamma, or below gamma_threshold t the blend
///           (1 - a/t) a t^g / t + (a/t) a^g (linear near 0, so that sparse pixels are not
///           lifted by the power's infinite slope);
///   ls    = brightness vibrancy alpha / a, the factor on the premultiplied colour c = a colour;
///   where ls c saturates a channel (above 1): highlight_power h >= 0 scales the colour to its
///           largest channel and multiplies its saturation by ((1 / max c) / ls)^h (towards
///           white); h < 0 blends the clipped colour ls c (h <= -1) with the scaled one;
///   pixel = that + (1 - vibrancy) brightness c^g per channel, + (1 - coverage) background.
/// With vibrancy 1, highlight_power -1 and gamma_threshold 0 it is display_shaded's log case.
struct Flam3Tone {
    double gamma = 2.2, brightness = 1, vibrancy = 1, highlight_power = -1, gamma_threshold = 0;
    /// flam3's background: over (1 - alpha), alpha clamped to [0, 1], rather than over the
    /// uncovered share.
    bool alpha_background = false;
    /// flam3's 8 bits: it writes (unsigned char) of its 0..255 value (rect.c), a truncation,
    /// where fixpoint's writers round to the nearest step. Half a step lower makes that rounding
    /// flam3's truncation; a sparse region's last half step (0.5 to 1 of 255) is dark, as flam3's.
    bool truncates = false;

    bool plain() const {
        return vibrancy == 1 && highlight_power == -1 && gamma_threshold == 0 && !alpha_background &&
               !truncates;
    }

    double alpha(double a) const {
        const double g = 1.0 / gamma, t = gamma_threshold;
        if (!(a > 0)) return 0;
        if (a < t) {
            const double frac = a / t;
            return (1.0 - frac) * a * (std::pow(t, g) / t) + frac * std::pow(a, g);
        }
        return std::pow(a, g);
    }

    /// One pixel from (a, colour, coverage).
    void pixel(const float* p, fp::Rgb bg, float* out) const {
        const double a = p[0];
        double open = 1.0 - double(p[4]);
        double rgb[3] = {0, 0, 0};
        if (alpha_background) open = 1.0 - std::clamp(alpha(a), 0.0, 1.0);
        if (a > 0) {
            const double al = alpha(a), ls = brightness * vibrancy * al / a;
            const double c[3] = {double(p[1]) * a, double(p[2]) * a, double(p[3]) * a};
            const double maxc = std::max({c[0], c[1], c[2]});
            if (maxc > 0) {
                const bool saturated = ls * maxc > 1.0;
                const double newls = 1.0 / maxc;
                if (saturated && highlight_power >= 0) {
                    double v[3] = {newls * c[0], newls * c[1], newls * c[2]};
                    desaturate(v, std::pow(newls / ls, highlight_power));
                    std::copy_n(v, 3, rgb);
                } else {
                    const double adj = saturated ? std::min(1.0, -highlight_power) : 1.0;
                    for (int k = 0; k < 3; ++k) rgb[k] = ((1.0 - adj) * newls + adj * ls) * c[k];
                }
            }
            if (vibrancy != 1)
                for (int k = 0; k < 3; ++k)
                    rgb[k] += (1.0 - vibrancy) * brightness * std::pow(c[k], 1.0 / gamma);
        }
        const double b[3] = {bg.r, bg.g, bg.b};
        const double low = truncates ? 0.5 / 255.0 : 0.0;
        for (int k = 0; k < 3; ++k)
            out[k] = float(std::max(0.0, std::clamp(rgb[k] + open * b[k], 0.0, 1.0) - low));
    }

    /// Multiplies the HSV saturation of v (channels in [0, 1]) by s.
    static void desaturate(double* v, double s) {
        // HSV's channels are V (1 - S w_k), w_k fixed by the hue: scaling S keeps V (the largest
        // channel) and moves every channel towards it by the same factor.
        const double mx = std::max({v[0], v[1], v[2]});
        for (int k = 0; k < 3; ++k) v[k] = mx - (mx - v[k]) * s;
    }
};

} // namespace fp_colourers
