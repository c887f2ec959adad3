// A quality target (`fixpoint render --quality Q`): the render goes on, doubling its points,
// until its sample level reaches Q, and the image is written with the points it stopped at.
//
// The sample level is Chaotica's measure: log2 of the points drawn per lit pixel, where a pixel
// is lit when any of its bins (supersample^2 of them) has a hit. It is computed from the exact
// integer histogram, so the stop point is a function of the recipe and Q alone: the rounds
// render P, 2P, 4P, ... points (P: the recipe's renderer.points), each continuing the last
// through a checkpoint (the bytes of a render of that many from the start), and the first
// whose level is Q or more is the image, with renderer.points = that count in its recipe.
// Rendering that recipe again gives the same bytes, with no --quality.
#pragma once

#include <fixpoint/host/job/render_job.hpp>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace fp::host {

/// The sample level counted from a histogram's rows as they come (in order, from row 0), for
/// an image whose pixels are n x n bins.
class SampleLevel {
public:
    explicit SampleLevel(int n) : n_(n) {}
    void rows(const Histogram& part, int part_row0, int row0, int rows);
    /// log2(points drawn / lit pixels) of the rows so far; -infinity when none is lit.
    double level();

private:
    void flush();
    int n_, pixel_row_ = 0;
    std::vector<unsigned char> lit_row_;
    std::uint64_t lit_ = 0;
    uint128 drawn_ = 0;
};

/// The sample level of a kept histogram whose image is `height` pixels high (the histogram is
/// that times its supersample): log2(points drawn / lit pixels); -infinity when none is lit.
double sample_level(const HistogramFile& h, int height);

struct QualityRequest {
    double target = 0; ///< Q, in (0, 40]
    /// The pipeline of the recipe with renderer.points = the given count.
    std::function<Pipeline(std::int64_t points)> reload;
    /// Told after each round that falls short ("quality 5.21 of 7 at 4000000 points").
    std::function<void(const std::string&)> info;
};

struct QualityResult {
    RenderPlan plan;     ///< the last round's (its pipeline: the recipe written)
    RenderResult result; ///< seconds: of every round
    double level = 0;
    int rounds = 0;
};

/// Renders `request` (its output and checks, as render's) to the target. fp::InputError for a
/// renderer without points or checkpoints or histograms (chaos-game has them), a target never
/// reached within the points a recipe may take, or what render refuses.
QualityResult render_to_quality(const QualityRequest& q, const RenderRequest& request,
                                const RenderHooks& hooks);

} // namespace fp::host
