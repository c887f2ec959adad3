// The conformance checks of renderers (conformance_detail.hpp).
#include "conformance_detail.hpp"

#include <fixpoint/fixpoint.hpp>
#include <fixpoint/host/core/runtime.hpp>

#include <algorithm>
#include <cmath>

namespace fp::host::detail {

namespace {

// A renderer that streams its rows (beyond the memory budget) must give render()'s pixels, in
// order, each row once, within the least budget it names: the host streams exactly then.
class CollectedRows final : public RowSink {
public:
    explicit CollectedRows(std::size_t width) : width_(width) {}
    void rows(int y0, int rows, const float* rgb) override {
        if (y0 != next_ || rows < 0) in_order_ = false;
        pixels_.insert(pixels_.end(), rgb, rgb + std::size_t(std::max(rows, 0)) * width_ * 3);
        next_ = y0 + std::max(rows, 0);
    }
    std::vector<float> pixels_;
    bool in_order_ = true;

private:
    std::size_t width_;
    int next_ = 0;
};

void check_streamed_rows(const Renderer& r, const std::vector<float>& whole, Findings& f) {
    for (unsigned threads : {1u, 2u}) {
        Runtime rt(threads, nullptr);
        rt.set_memory_budget(r.memory_within(threads, 0)); // the least it can do with
        RenderStats st;
        CollectedRows rows(std::size_t(r.width()));
        try {
            r.render_rows(rt, st, rows);
        } catch (const std::exception& e) {
            f.push_back("renderer: render_rows() within memory_within()'s least budget failed: " +
                        std::string(e.what()));
            return;
        }
        if (!rows.in_order_) f.push_back("renderer: render_rows() gave its rows out of order");
        if (rows.pixels_ != whole) {
            f.push_back("renderer: render_rows() on " + std::to_string(threads) +
                        " thread(s) differs from render()");
            return;
        }
    }
}

} // namespace

void check_renderer(const Renderer& r, Findings& f) {
    if (r.width() <= 0 || r.height() <= 0) f.push_back("renderer: non-positive size");
    if (r.memory_bytes(2) == 0) f.push_back("renderer: memory_bytes() is 0");
    if (std::uint64_t(r.width()) * std::uint64_t(r.height()) > 512u * 512u) {
        f.push_back("renderer: the example is too large for the conformance suite (at most 512x512)");
        return;
    }
    auto render = [&](unsigned threads) {
        Runtime rt(threads, nullptr);
        RenderStats st;
        Image img = r.render(rt, st);
        return img.pixels;
    };
    const auto a = render(1), b = render(2);
    if (a.size() != std::size_t(r.width()) * std::size_t(r.height()) * 3)
        f.push_back("renderer: image has the wrong size");
    if (a != b) f.push_back("renderer: 1 and 2 threads give different images");
    std::size_t bad = 0, lit = 0;
    for (float v : a) bad += !std::isfinite(v), lit += v > 0;
    if (bad) f.push_back("renderer: non-finite pixel values");
    if (!lit) f.push_back("renderer: the example renders a black image");
    if (r.streams_rows()) check_streamed_rows(r, a, f);
}

} // namespace fp::host::detail
