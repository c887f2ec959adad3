// --quality Q: host/job/quality.hpp says what the sample level is and why the stop point is the
// recipe's alone.
#include <fixpoint/host/core/checkpoint.hpp>
#include <fixpoint/host/core/histogram_file.hpp>
#include <fixpoint/host/core/image_io.hpp>
#include <fixpoint/host/core/ranks.hpp>
#include <fixpoint/host/job/quality.hpp>
#include <fixpoint/text.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

namespace fp::host {

void SampleLevel::rows(const Histogram& part, int part_row0, int row0, int rows) {
    const std::size_t W = std::size_t(part.width);
    if (lit_row_.size() != W / std::size_t(n_)) lit_row_.assign(W / std::size_t(n_), 0);
    for (int y = row0; y < row0 + rows; ++y) {
        if (y / n_ != pixel_row_) flush(), pixel_row_ = y / n_;
        const std::size_t at = std::size_t(y - part_row0) * W;
        for (std::size_t x = 0; x < lit_row_.size() * std::size_t(n_); ++x) {
            const std::uint64_t k = part.hits_at(at + x);
            drawn_ += k;
            lit_row_[x / std::size_t(n_)] |= k != 0;
        }
    }
}

void SampleLevel::flush() {
    for (unsigned char& c : lit_row_) lit_ += c, c = 0;
}

double SampleLevel::level() {
    flush();
    if (lit_ == 0) return -std::numeric_limits<double>::infinity();
    return std::log2(double(drawn_) / double(lit_));
}

double sample_level(const HistogramFile& h, int height) {
    const HistogramShape& s = h.header.shape;
    SampleLevel count(height > 0 ? std::max(1, s.height / height) : 1);
    count.rows(h.histogram, 0, 0, h.histogram.height);
    return count.level();
}

namespace {

std::string level_text(double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%.2f", v);
    return b;
}

} // namespace

QualityResult render_to_quality(const QualityRequest& q, const RenderRequest& request,
                                const RenderHooks& hooks) {
    if (!(q.target > 0 && q.target <= 40)) {
        char got[32];
        std::snprintf(got, sizeof got, "%g", q.target);
        throw InputError(
            std::string(
                "--quality: expected a sample level in (0, 40] (log2 of the points per lit pixel), got ") +
            got);
    }
    // With --checkpoint or --resume the rounds continue one another through that file (saved
    // every --checkpoint-every too), so a killed render resumes where it was: `--quality Q
    // --resume FILE` starts at the first round of as many points as FILE holds, or more.
    const bool filed = !request.checkpoint.empty() || !request.resume.empty();
    if (filed && ranks::size() > 1)
        throw InputError(std::string(request.resume.empty() ? "--checkpoint" : "--resume") +
                         ": --quality under mpirun renders each round afresh: it keeps no checkpoints");
    const std::string ck_file = request.checkpoint.empty() ? request.resume : request.checkpoint;
    std::int64_t start = 0; // (the points the checkpoint resumed holds)
    if (!request.resume.empty()) start = CheckpointFile(request.resume).header().points;
    Pipeline p = q.reload(0);
    std::int64_t points = p.points;
    while (points > 0 && points < start && points <= std::int64_t(5e14)) points *= 2;
    if (points != p.points) p = q.reload(points);
    const Renderer& R = *p.renderer;
    if (p.points <= 0 || !R.keeps_checkpoints() || R.histogram_shape().width == 0)
        throw InputError(p.renderer_mark.str() + ": renderer: " + p.renderer_type +
                         " cannot go on to a quality (--quality needs points, checkpoints and a histogram: "
                         "chaos-game has them)");
    // Every check of the final render (its output above all) before the first round.
    const RenderPlan check = plan_render(p, request, hooks.cancel);
    if (check.vector) throw InputError("--quality: a raster image: not " + quote(check.output, 200));
    // The rounds continue one another through a checkpoint kept in memory. A render that streams
    // in strips keeps no whole histogram to continue: each of its rounds renders afresh (twice
    // the points of the last: at most twice the work of the last round in all), streaming its
    // image and kept histogram into temporary files that take their names only in the round
    // that reaches the level. Under mpirun too (the checkpoint is kept on one process): each
    // round is a job of all the ranks, rank 0 counting the level and telling the others.
    const bool ranked = ranks::size() > 1, streams = check.memory.stream, afresh = streams || ranked;
    const auto ck = std::make_shared<std::string>();

    QualityResult res;
    double seconds = 0;
    Image image;
    std::string label = "quality ... of " + level_text(q.target) + " ";
    for (;; points *= 2) {
        ++res.rounds;
        if (res.rounds > 1) p = q.reload(points);
        // Each round renders its image (kept, not written; streamed, into a temporary file) and
        // counts its level from the histogram's rows as they are handed over (no copy of the
        // histogram).
        RenderRequest round = request;
        if (!streams) {
            round.output.clear();
            round.default_file = false;
            round.encode.reset();
            round.keep_image = true;
            if (filed && res.rounds > 1) {
                // (The first round saves into the file as asked; the later ones resume from it,
                // which their checkpoints go on in.)
                round.checkpoint.clear();
                round.resume = ck_file;
            } else if (!filed && !afresh) {
                round.checkpoint_memory = ck; // (one at the end of the round)
            }
            // --histogram: each round keeps its histogram in memory; the last one's is written.
            round.histogram.clear();
            round.keep_histogram = !request.histogram.empty();
        }
        RenderPlan plan = plan_render(p, round, hooks.cancel);
        const HistogramShape shape = p.renderer->histogram_shape();
        SampleLevel count(std::max(1, shape.height / std::max(1, p.renderer->height())));
        RenderHooks h = hooks;
        h.progress_label = label;
        h.histogram_rows = [&count](const Histogram& part, int part_row0, int row0, int rows) {
            count.rows(part, part_row0, row0, rows);
        };
        h.keep_files = [&count, &q] { return count.level() >= q.target; };
        RenderResult r = run_render(plan, h);
        seconds += r.seconds;
        res.level = count.level();
        if (ranked) { // (only rank 0 hears the histogram's rows)
            if (ranks::rank() == 0)
                for (unsigned k = 1; k < ranks::size(); ++k) ranks::send(k, &res.level, sizeof res.level);
            else
                ranks::recv(0, &res.level, sizeof res.level);
        }
        if (res.level >= q.target) {
            image = std::move(r.image);
            res.result = std::move(r);
            if (streams) res.plan = std::move(plan);
            break;
        }
        // (A round that drew nothing was refused by the render job: the level is finite here.)
        if (points > std::int64_t(5e14))
            throw InputError("--quality " + level_text(q.target) + ": the sample level is " +
                             level_text(res.level) + " at " + std::to_string(points) +
                             " points; twice as many is beyond renderer.points' range (1e15)");
        if (q.info)
            q.info("quality " + level_text(res.level) + " of " + level_text(q.target) + " at " +
                   std::to_string(points) + " points: going on to " + std::to_string(2 * points));
        label = "quality " + level_text(res.level) + " of " + level_text(q.target) + " ";
    }
    // The last round's image, written as render writes it, with the recipe of the points it
    // stopped at.
    if (streams) { // (the last round's files took their names)
        res.result.seconds = seconds;
        return res;
    }
    // (The checkpoint file was the rounds': the image is written as a plain render's.)
    RenderRequest written = request;
    written.checkpoint.clear(), written.resume.clear(), written.checkpoint_every.clear();
    res.plan = plan_render(p, written, hooks.cancel);
    res.result.seconds = seconds;
    if (ranks::rank() != 0) return res; // (rank 0 holds the image and writes)
    if (!request.histogram.empty()) {
        // (The last round's recipe is the final plan's: the same pipeline.)
        if (!res.result.kept) throw InternalError("--quality: the last round kept no histogram");
        const HistogramFile& h = *res.result.kept;
        HistogramWriter file(request.histogram, res.plan.histogram);
        file.rows(h.histogram, 0, 0, h.histogram.height);
        file.commit(h.stats);
        res.result.kept.reset();
    }
    write_render(res.plan, image, hooks);
    res.result.wrote = true;
    return res;
}

} // namespace fp::host
