// fit_view by the render's own chains (ChaosGame::fit_by_probe). fit_view.hpp's pre-run plays
// the game on streams of its own, a few thousand steps a chain: right for many chains, whose
// points fill the same attractor whatever the streams, but not for a single orbit. One
// Gumowski-Mira chain choosing at random between two maps (paper 03's superfractal child) is
// another child on another stream, and an area-preserving orbit grows for far longer than
// 4000 steps (configs/gumowski-mira/fig4.yaml fitted by the pre-run alone showed a quarter
// of its child).
//
// The probe counts where the render's own chains go, with the render's own code (render_t,
// hits only, one worker: the same counts on any machine): at most 2^22 of its points, the
// first steps of each of its chains, into 512 bins along the longer side of a box three times
// the pre-run's. If more than 0.1% of them land outside, the box grows threefold and the probe
// runs again (four times at most). The view is then the 0.1% and 99.9% quantiles of the counts
// along each axis (to a bin: 0.6% of the box), framed as fit_view frames (5% margins, square
// pixels). A pure function of the recipe, as the pre-run is.
#include "chaos-game/renderer.hpp"

#include "fit_view.hpp"

#include <fixpoint/fixpoint.hpp>

#include <algorithm>
#include <cstdint>
#include <functional>
#include <vector>

namespace fp_chaos {

namespace {

/// The probe's context: one worker, in this thread, never cancelled.
class Probe final : public fp::RenderContext {
public:
    unsigned workers() const override { return 1; }
    void parallel_for(size_t n, const std::function<void(size_t, unsigned)>& task) override {
        for (size_t i = 0; i < n; ++i) task(i, 0);
    }
    void progress(uint64_t) override {}
    bool cancelled() const override { return false; }
};

/// The box about b's centre `k` times its size.
fp::Box grown(const fp::Box& b, double k) {
    const double cx = 0.5 * (b.xmin + b.xmax), cy = 0.5 * (b.ymin + b.ymax);
    const double hw = 0.5 * k * (b.xmax - b.xmin), hh = 0.5 * k * (b.ymax - b.ymin);
    return {cx - hw, cx + hw, cy - hh, cy + hh};
}

/// The bins of `counts` below which a fraction q of their sum lies (the first bin whose running
/// sum passes q of the total).
size_t quantile_bin(const std::vector<uint64_t>& counts, uint64_t total, double q) {
    const double want = q * double(total);
    uint64_t run = 0;
    for (size_t i = 0; i < counts.size(); ++i) {
        run += counts[i];
        if (double(run) > want) return i;
    }
    return counts.size() - 1;
}

} // namespace

bool ChaosGame::probe_fits() const {
    // (A camera turns the plotted points about the view's centre: the probe's box would turn
    // them about another. Those keep the pre-run's fit.)
    return !rotate_ && !y_down_;
}

void ChaosGame::fit_by_probe() {
    const fp::Frame image = frame_, bins = hist_;
    const uint64_t points = points_;
    points_ = std::min<uint64_t>(points_, std::max<uint64_t>(uint64_t(1) << 22, chains_));
    fp::Box box = frame_.region; // the pre-run's
    const double w = box.xmax - box.xmin, h = box.ymax - box.ymin;
    const int across = 512;
    fp::Frame f = bins;
    f.width = w >= h ? across : std::max(8, int(across * w / h));
    f.height = w >= h ? std::max(8, int(across * h / w)) : across;
    std::vector<uint64_t> cx, cy;
    uint64_t inside = 0;
    for (int round = 0; round < 4; ++round) {
        f.region = box = grown(box, 3);
        frame_ = hist_ = f;
        Probe ctx;
        fp::RenderStats st;
        fp::Histogram total;
        if (double_)
            render_t<double>(ctx, st, total, nullptr, 0, uint32_t(f.height), false, true);
        else
            render_t<float>(ctx, st, total, nullptr, 0, uint32_t(f.height), false, true);
        cx.assign(size_t(f.width), 0), cy.assign(size_t(f.height), 0);
        inside = 0;
        for (size_t r = 0; r < size_t(f.height); ++r)
            for (size_t c = 0; c < size_t(f.width); ++c) {
                const uint64_t n = total.hits[r * size_t(f.width) + c];
                cx[c] += n, cy[r] += n, inside += n;
            }
        if (double(st.samples - inside) <= 0.001 * double(st.samples)) break;
    }
    frame_ = image, hist_ = bins, points_ = points;
    if (inside == 0) return; // nothing landed: the pre-run's view stays
    const double bx = (box.xmax - box.xmin) / f.width, by = (box.ymax - box.ymin) / f.height;
    // (Rows count down from ymax.)
    const fp::Box b{box.xmin + bx * double(quantile_bin(cx, inside, 0.001)),
                    box.xmin + bx * double(quantile_bin(cx, inside, 0.999) + 1),
                    box.ymax - by * double(quantile_bin(cy, inside, 0.999) + 1),
                    box.ymax - by * double(quantile_bin(cy, inside, 0.001))};
    const fp::Box v = fp_render::framed(b, image.width, image.height);
    frame_.region = hist_.region = v;
}

} // namespace fp_chaos
