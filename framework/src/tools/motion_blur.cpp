// Motion blur for `fixpoint animate`: motion_blur.hpp says what a blurred frame is.
#include "motion_blur.hpp"

#include <fixpoint/errors.hpp>
#include <fixpoint/host/core/histogram_file.hpp>
#include <fixpoint/text.hpp>

#include <memory>
#include <vector>

namespace fp::host {

namespace {

bool same_shape(const HistogramShape& a, const HistogramShape& b) {
    return a.width == b.width && a.height == b.height && a.hits_only == b.hits_only && a.last == b.last;
}

std::string samples_text(const Animation& a) {
    return std::to_string(a.temporal_samples) + " temporal samples over " +
           number_text(a.temporal_filter_width) + " frame" + (a.temporal_filter_width == 1 ? "" : "s");
}

} // namespace

double temporal_time(const Animation& a, long f, long j) {
    const double S = double(a.temporal_samples);
    return double(f) + a.temporal_filter_width * ((double(j) + 0.5) / S - 0.5);
}

void check_motion_blur(const Animation& a, const Pipeline& frame) {
    if (a.temporal_samples < 2) return;
    const HistogramShape shape = frame.renderer->histogram_shape();
    if (shape.width == 0)
        throw InputError("animation.temporal_samples: motion blur sums the histograms of its samples: " +
                         frame.renderer_type + " keeps none (chaos-game renders keep one)");
    if (frame.points <= 0 || std::int64_t(a.temporal_samples) > frame.points)
        throw InputError("animation.temporal_samples: " + std::to_string(a.temporal_samples) +
                         " samples share the render's chains: more than its points");
}

std::string blurred_recipe(const Animation& a, const Pipeline& frame) {
    if (a.temporal_samples < 2) return frame.recipe;
    return frame.recipe + "# motion blur: " + samples_text(a) + " (flam3's temporal_samples and " +
           "temporal_filter_width, box), each of its own share of the chains\n";
}

RenderResult render_blurred_frame(const Animation& a, long f, const std::function<Pipeline(double)>& at,
                                  const Pipeline& frame, const RenderRequest& request,
                                  const RenderHooks& hooks) {
    const unsigned S = unsigned(a.temporal_samples);
    const HistogramShape shape = frame.renderer->histogram_shape();
    // Every sample's pipeline first: one whose histogram differs (an animated width, height or
    // supersample) cannot be summed, and is refused before any render.
    std::vector<Pipeline> samples;
    for (unsigned j = 0; j < S; ++j) {
        samples.push_back(at(temporal_time(a, f, long(j))));
        if (!same_shape(samples.back().renderer->histogram_shape(), shape))
            throw InputError("animation.temporal_samples: frame " + std::to_string(f) + "'s sample " +
                             std::to_string(j) +
                             " keeps another histogram than the frame (an animated width, height, "
                             "supersample or colourer): motion blur sums histograms of one shape");
    }
    HistogramFile total;
    double seconds = 0;
    for (unsigned j = 0; j < S; ++j) {
        RenderRequest r;
        r.shards = S, r.shard = j + 1;
        r.keep_histogram = true;
        r.threads = request.threads;
        r.source = request.source;
        r.allow_empty = true; // (a sample's share may miss the view: the frame is judged whole)
        RenderPlan plan = plan_render(samples[j], r, hooks.cancel);
        RenderResult part = run_render(plan, hooks);
        if (!part.kept) throw InternalError("motion blur: a sample kept no histogram");
        // (The renderer shares out its chains in blocks: a share may hold none.)
        if (part.stats.samples == 0)
            throw InputError("animation.temporal_samples: frame " + std::to_string(f) + "'s sample " +
                             std::to_string(j) +
                             " has no chains of its own: the render's chains are too few "
                             "for " +
                             std::to_string(S) + " samples (raise renderer.chains)");
        seconds += part.seconds;
        if (j == 0)
            total = *part.kept;
        else
            add_histogram(total, *part.kept);
    }
    // The sum is a whole render's histogram of the frame's recipe: finished with its tone.
    total.header.identity = frame.histogram_identity;
    total.header.recipe = frame.recipe;
    total.header.shards.clear();
    total.histogram.last_order.clear();
    total.path.clear();
    RenderRequest finish = request;
    finish.tone = std::make_shared<const HistogramFile>(std::move(total));
    RenderPlan plan = plan_render(frame, finish, hooks.cancel);
    RenderResult res = run_render(plan, hooks);
    res.seconds += seconds;
    return res;
}

} // namespace fp::host
