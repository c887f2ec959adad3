// The finishing stage: a histogram, accumulated at `supersample` times the image's size in
// each direction, made into the image (issue 42; docs/finishing.md). Three steps, in flam3's
// order (flam3 3.1.1, rect.c), each exact and in a fixed order, so the bytes are the same on any
// number of workers and for any plan of strips:
//
//   linear    each bin's density a in [0, 1] and its colour, from the colourer
//             (Colourer::linear); the channels kept are (a, a r, a g, a b, coverage), coverage 1
//             where the bin has hits;
//   estimate  adaptive density estimation (flam3's): each bin's channels spread by a disc
//             kernel whose radius shrinks with the bin's hits (DensityKernels);
//   filter    the spatial filter down to the image (spatial_taps), separable;
//   display   each pixel from its filtered channels (Colourer::display): gamma and the rest of
//             the tone after the filter, as flam3 has it.
//
// With supersample 1, no filter and no estimator the stage is off, and the colourer's
// resolve() shades the bins directly (today's bytes).
#pragma once

#include <fixpoint/histogram.hpp>
#include <fixpoint/params.hpp>
#include <fixpoint/types.hpp>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

namespace fp {

class Colourer;
class Filter;
class ParamBag;
class RenderContext;

struct FinishSpec {
    int supersample = 1;
    /// The spatial filter; null: none (with supersample N, the mean of each pixel's N x N bins).
    std::shared_ptr<const Filter> filter;
    /// flam3's estimator_radius, estimator_minimum and estimator_curve (in image pixels);
    /// radius 0: no estimation.
    double estimator_radius = 0, estimator_minimum = 0, estimator_curve = 0.4;
    /// The hits per image pixel (on average over the image) at which the estimator's kernels are
    /// chosen: a bin's counted hits are scaled by this over the histogram's own mean, so the
    /// kernels, and with them the picture, do not change as the points grow, only its noise
    /// falls. 0: the hits as they are (flam3's, whose kernels shrink as the points grow).
    double estimator_quality = 0;

    bool estimates() const { return estimator_radius > 0; }
    bool active() const { return supersample > 1 || filter || estimates(); }
    /// Rows of the supersampled histogram beyond an image strip's own (N rows a pixel row) that
    /// its pixels read: the filter's reach, the estimator's largest kernel and its counting
    /// window.
    int halo() const;
    /// The stage's buffers for a strip of `rows` image rows of `width` pixels, in bytes.
    std::uint64_t bytes(int width, int rows) const;

    /// Reads the parameters declared by supersample_param, filter_param and the estimator_*
    /// params; throws ParamError for a filter whose taps have no weight.
    static FinishSpec read(const ParamBag& p);
};

/// The finishing parameters, for a renderer's schema (and FinishSpec::read).
constexpr ParamSpec supersample_param =
    param::integer("supersample", "the histogram is this many times the image in each direction, filtered "
                                  "down to it (anti-aliasing)")
        .def("1")
        .min(1)
        .max(16);
constexpr ParamSpec filter_param =
    param::object("filter", Kind::Filter,
                  "the reconstruction filter from the histogram to the image ({type: gaussian, radius: "
                  "0.5}: flam3's); unset: none (with supersample N, the mean of each pixel's N x N bins)")
        .opt()
        .as(ParamRole::finish);
constexpr ParamSpec estimator_radius_param =
    param::real("estimator_radius", "flam3's adaptive density estimation: the kernel radius, in image "
                                    "pixels, of a bin with one hit (0: none)")
        .def("0")
        .min(0)
        .max(64)
        .as(ParamRole::finish);
constexpr ParamSpec estimator_minimum_param =
    param::real("estimator_minimum", "the smallest kernel radius of the density estimation, in image pixels")
        .def("0")
        .min(0)
        .max(64)
        .as(ParamRole::finish);
constexpr ParamSpec estimator_quality_param =
    param::real("estimator_quality",
                "the density estimation's kernels as they are at this many hits per image pixel (on "
                "average over the image), whatever the points drawn: more points then give the same "
                "picture with less noise; 0: from the hits as they are (flam3's, sharper as the points grow)")
        .def("0")
        .min(0)
        .max(1e12)
        .as(ParamRole::finish);
constexpr ParamSpec estimator_curve_param =
    param::real("estimator_curve",
                "how fast the kernel shrinks with the hits: radius / (hits + 1)^curve (flam3's)")
        .def("0.4")
        .above(0)
        .max(4)
        .as(ParamRole::finish);

/// The spatial filter's taps as flam3 builds them (flam3_create_spatial_filter), one axis:
/// with support s, radius r and supersample N, fw = 2 s N r; width = int(fw) + 1, raised by one
/// to the parity of N; tap i is value(((2i + 1) / width - 1) s width / fw), the taps normalised
/// to sum 1 (flam3's 2-D kernel is the product of two: the same weights, separably). Pixel p's
/// taps start at bin p N - (width - N) / 2. Without a filter: N taps of 1 / N.
std::vector<double> spatial_taps(const Filter* filter, int supersample);

/// flam3's density-estimation kernels (flam3_create_de_filters, and rect.c's de_thread for
/// their use). With R, m and N: kernel k has width h_k = (R N + 1) / (k' + 1)^curve, k' = k up
/// to 100 and 100 + (k - 100)^(1 / curve) beyond (flam3 condenses the small kernels), not below
/// m N + 1; its coefficients are gaussian(1.5 d / h) over the disc d <= h (d in bins),
/// normalised over that disc, and applied over the square |dx|, |dy| <= ceil(h) - 1, so a
/// kernel whose h is an integer drops its rim (flam3 keeps the energy only where h is not
/// one). A bin's count c is its hits summed over the (2 floor(N / 2) + 1)^2 bins around it,
/// times (N / (N + 1))^2 for an even N; it takes kernel ceil(c) - 1 up to 100, beyond that 100 +
/// floor((c - 100)^curve), at most the last. With estimator_quality Q, c is first multiplied by
/// Q P / H, P the image's pixels and H the histogram's hits (count_scale).
struct DensityKernels {
    struct Kernel {
        int reach = 0;            ///< ceil(h) - 1: the half-width of the square applied
        double width = 0;         ///< h
        std::vector<float> coefs; ///< (2 reach + 1)^2, row-major from (-reach, -reach)
    };
    std::vector<Kernel> kernels;
    double max_filtered_counts = 0;
    int window = 0; ///< floor(N / 2): the counting window's half-width
    double window_scale = 1;
    double curve = 0.4;

    /// Throws ParamError for a minimum above the radius or more than 1e7 kernels (flam3's
    /// limits).
    static DensityKernels make(const FinishSpec& spec);
    /// The kernel of a bin whose counted hits are c (> 0).
    std::size_t index(double c) const;
    /// What a bin's counted hits are multiplied by before index(): 1, or with estimator_quality
    /// Q, Q (image pixels) / (the histogram's hits): the counts of a histogram of Q hits a pixel.
    static double count_scale(const FinishSpec& spec, const HistogramSummary& whole);
};

/// Finishes image rows [o0, o0 + on) (image `width` pixels wide) from `part`: rows [p0, p0 +
/// part.height) of the supersampled histogram, whose summary is `whole` and which must hold
/// every row within spec.halo() rows of the strip's (or up to the histogram's edges). 3 floats
/// a pixel into rgb. Bins outside the histogram are unknown: a filter window at an edge is
/// renormalised over the bins it covers. ctx null: serial; else on its workers, polled for a
/// cancel (the same bytes either way, and for any strips).
void finish(const FinishSpec& spec, const Colourer& colourer, const Histogram& part, int p0,
            const HistogramSummary& whole, int width, int o0, int on, Rgb background, float* rgb,
            RenderContext* ctx);

} // namespace fp
