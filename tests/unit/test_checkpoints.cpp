// The renderers' checkpoints without the CLI's timing: a context that asks for a checkpoint at
// every n-th poll and keeps each payload in memory.
//
// chaos-game (chaos-game/checkpoint.hpp). For recipes over
// every path of the renderer (hits only and colour through the fused step, the generic step
// with an iteration scheme, last colours, restarts and retired chains, double chains, the lean
// path of one orbit, one map whose streams jump at the end of a steady run, bins that spill
// into 64 bits), on 1 and 2 threads:
//   - a render stopped for many checkpoints gives the bytes of one that never stops;
//   - resumed from the first, a middle and the last but one of them, it gives those bytes;
//   - a finished render of a third of the points, continued to all of them, gives the bytes of
//     a render of all of them from the start (the same stats too);
//   - a payload cut short, or of another size of chains, is refused.
// orbit-trap (orbit-trap/tiles.cpp's "Checkpoints"): stopped between tiles for checkpoints, resumed
// from them, the same pixels and counts; a payload of another image refused.
#include <fixpoint/fixpoint.hpp>
#include <fixpoint/host/core/host.hpp>
#include <fixpoint/host/core/runtime.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

namespace {

fp::host::Host& host() {
    static fp::host::Host h;
    return h;
}

class StringSink final : public fp::CheckpointSink {
public:
    explicit StringSink(std::string& s) : s_(s) {}
    void write(const void* data, std::size_t bytes) override {
        s_.append(static_cast<const char*>(data), bytes);
    }

private:
    std::string& s_;
};

class StringSource final : public fp::CheckpointSource {
public:
    explicit StringSource(std::string s) : s_(std::move(s)) {}
    void read(void* data, std::size_t bytes) override {
        if (bytes > s_.size() - at_) throw fp::InputError("the checkpoint ends early");
        std::memcpy(data, s_.data() + at_, bytes);
        at_ += bytes;
    }
    std::uint64_t left() const override { return s_.size() - at_; }

private:
    std::string s_;
    std::size_t at_ = 0;
};

/// A render that keeps checkpoints: one at every `every`-th poll (0: only the last, at the end),
/// each payload kept; resumed from `from` when given.
class Keeper final : public fp::host::Runtime {
public:
    Keeper(unsigned threads, unsigned every, const std::string* from = nullptr)
        : Runtime(threads, nullptr), every_(every) {
        if (from) source_ = std::make_unique<StringSource>(*from);
    }
    bool checkpointing() const override { return true; }
    bool checkpoint_due() const override { return every_ && ++polls_ % every_ == 0; }
    void write_checkpoint(const std::function<void(fp::CheckpointSink&)>& body) override {
        std::string s;
        StringSink sink(s);
        body(sink);
        saved.push_back(std::move(s));
    }
    fp::CheckpointSource* resume_from() override { return source_.get(); }
    std::vector<std::string> saved;

private:
    unsigned every_;
    mutable std::atomic<unsigned> polls_{0};
    std::unique_ptr<StringSource> source_;
};

struct Render {
    fp::Image img;
    fp::RenderStats stats;
};

Render render(const std::string& yaml, fp::RenderContext& ctx) {
    // (What a caller that asks for none gets: no checkpoint.)
    auto r = host().make<fp::Renderer>(yaml);
    EXPECT_TRUE(r->keeps_checkpoints());
    Render out;
    out.img = r->render(ctx, out.stats);
    return out;
}

Render plain(const std::string& yaml) {
    fp::host::Runtime rt(2, nullptr);
    return render(yaml, rt);
}

std::string circles_maps() {
    std::string m = "maps: [";
    for (int j = 0; j < 5; ++j) {
        const double a = 2 * M_PI * j / 5;
        m += "{type: inversion, shape: {type: circle, centre: [" + std::to_string(std::cos(a)) + ", " +
             std::to_string(std::sin(a)) + "], radius: 0.65}}, ";
    }
    return m + "{type: inversion, shape: {type: circle, centre: [0, 0], radius: 0.4}}]";
}

struct Recipe {
    std::string yaml; ///< "{... points: POINTS ...}"
    long points;
    bool stops = true; ///< long enough for a checkpoint before the end
};

std::string with_points(const Recipe& r, long points) {
    std::string y = r.yaml;
    const auto at = y.find("POINTS");
    return y.replace(at, 6, std::to_string(points));
}

std::vector<Recipe> recipes() {
    const std::string c = "type: chaos-game, width: 96, height: 96, view: [-0.8, 0.8, -0.8, 0.8], ";
    const std::string overlap =
        "type: chaos-game, width: 64, height: 64, view: [-1.5, 2, -1.5, 1.5], skip: 1, maps: [{type: "
        "inversion, shape: {type: circle, centre: [0, 0], radius: 1}}, {type: inversion, shape: {type: "
        "circle, centre: [0.5, 0], radius: 1}}], ";
    return {
        // Hits only, fused (steady runs, lagged deposits).
        {"{" + c + "points: POINTS, colourer: {type: density}, " + circles_maps() + "}", 600000},
        // Colour, fused, with 700 chains (a partial block).
        {"{" + c + "points: POINTS, chains: 700, colourer: {type: map-colour}, " + circles_maps() + "}",
         400000},
        // Last colours (paper 02's Algorithm 2): the (step, chain) order across checkpoints.
        {"{" + c + "points: POINTS, chains: 300, colourer: {type: flame, mode: set-colour}, " +
             circles_maps() + "}",
         300000},
        // The generic step through an iteration scheme that sees the step index.
        {"{" + c +
             "points: POINTS, chains: 200, iteration: {type: mann, alpha: 0.7}, colourer: {type: flame}, " +
             circles_maps() + "}",
         200000},
        // Restarts (no allowed map) in many chains and in the lean path of two.
        {"{" + overlap + "points: POINTS, chains: 500, colourer: {type: density}}", 200000},
        {"{" + overlap + "points: POINTS, chains: 2, colourer: {type: density}}", 60000},
        // Double chains with colour.
        {"{" + c + "points: POINTS, chains: 300, precision: double, colourer: {type: map-colour}, " +
             circles_maps() + "}",
         150000},
        // One orbit of Gumowski-Mira (the lean path), and one expanding affine map whose orbit
        // overflows and restarts (bad values; its streams jump at the end of each steady run).
        {"{type: chaos-game, width: 64, height: 64, view: [-15, 15, -15, 15], points: POINTS, chains: 1, "
         "skip: "
         "0, start: [0, 0.5], precision: double, colourer: {type: density}, maps: [{type: gumowski-mira, mu: "
         "-0.31}]}",
         300000},
        {"{type: chaos-game, width: 64, height: 64, view: [-2, 2, -2, 2], points: POINTS, chains: 100, skip: "
         "2, "
         "colourer: {type: density}, maps: [{type: affine, coefficients: [1.5, 0.2, -0.1, 1.4, 0.01, 0]}]}",
         100000},
        // Four bins of 75000 points with colour: the workers' bins spill into 64 bits.
        {"{type: chaos-game, width: 2, height: 2, view: [0, 1, 0, 1], points: POINTS, chains: 600, colourer: "
         "{type: map-colour}, maps: [{type: affine, coefficients: [0.5, 0, 0, 0.5, 0, 0]}, {type: affine, "
         "coefficients: [0.5, 0, 0, 0.5, 0.5, 0]}, {type: affine, coefficients: [0.5, 0, 0, 0.5, 0.25, "
         "0.5]}]}",
         300000},
        // Fewer points than chains at first: chains that had none start when continued.
        // (Too short to stop: a chain's 2 or 3 points take fewer steps than a poll.)
        {"{" + c + "points: POINTS, chains: 4096, colourer: {type: flame}, " + circles_maps() + "}", 9000,
         false},
    };
}

void expect_same(const Render& a, const Render& b, const std::string& what) {
    ASSERT_EQ(a.img.pixels.size(), b.img.pixels.size()) << what;
    EXPECT_TRUE(a.img.pixels == b.img.pixels) << what;
    EXPECT_EQ(a.stats.samples, b.stats.samples) << what;
    EXPECT_EQ(a.stats.drawn, b.stats.drawn) << what;
    EXPECT_EQ(a.stats.restarts, b.stats.restarts) << what;
    EXPECT_EQ(a.stats.bad_values, b.stats.bad_values) << what;
}

/// A payload without its progress count (PayloadHead::progress, at byte 64): the units the
/// progress bar was told, which a resumed render estimates anew.
std::string state_of(std::string payload) {
    std::memset(payload.data() + 64, 0, 8);
    return payload;
}

TEST(ChaosCheckpoint, StoppedAndResumedRendersAreUninterruptedOnes) {
    for (const Recipe& r : recipes()) {
        if (!r.stops) continue;
        const std::string yaml = with_points(r, r.points);
        const Render want = plain(yaml);
        EXPECT_GT(want.stats.drawn, 0u) << yaml;
        for (unsigned threads : {1u, 2u}) {
            const std::string what = yaml + " on " + std::to_string(threads) + " thread(s)";
            // A checkpoint at every third poll (about every 200 steps of a block).
            Keeper k(threads, 3);
            expect_same(render(yaml, k), want, what + ", stopped for checkpoints");
            ASSERT_GE(k.saved.size(), 2u) << what;
            // Resumed from the first, a middle and the last but one (the last: the finished render).
            for (std::size_t i : {std::size_t(0), k.saved.size() / 2, k.saved.size() - 2}) {
                Keeper again(threads, 0, &k.saved[i]);
                expect_same(render(yaml, again), want,
                            what + ", resumed from checkpoint " + std::to_string(i));
                // It wrote the finished render's checkpoint, which is the same state.
                ASSERT_EQ(again.saved.size(), 1u);
                EXPECT_TRUE(state_of(again.saved.back()) == state_of(k.saved.back())) << what;
            }
        }
    }
}

TEST(ChaosCheckpoint, FinishedRendersContinueToMorePoints) {
    for (const Recipe& r : recipes()) {
        const std::string yaml = with_points(r, r.points);
        const Render want = plain(yaml);
        // A third of the points (itself stopped for checkpoints on the way), finished, its last
        // checkpoint continued to all of them; and a continuation that stops too.
        Keeper first(2, 3);
        render(with_points(r, r.points / 3), first);
        ASSERT_GE(first.saved.size(), 1u);
        Keeper more(2, 0, &first.saved.back());
        expect_same(render(yaml, more), want, yaml + ", continued from a third of its points");
        Keeper stopping(1, 5, &first.saved.back());
        expect_same(render(yaml, stopping), want, yaml + ", continued with checkpoints");
        // The same points again: the finished render as it was.
        Keeper same(2, 0, &more.saved.back());
        expect_same(render(yaml, same), want, yaml + ", resumed when finished");
    }
}

TEST(ChaosCheckpoint, DamagedPayloadsAreRefused) {
    const Recipe r = recipes()[1];
    const std::string yaml = with_points(r, r.points);
    Keeper k(2, 0);
    render(yaml, k);
    const std::string whole = k.saved.back();
    // Cut short.
    const std::string cut = whole.substr(0, whole.size() - 100);
    Keeper a(2, 0, &cut);
    EXPECT_THROW(render(yaml, a), fp::InputError);
    // Longer than the render's state.
    const std::string longer = whole + "x";
    Keeper b(2, 0, &longer);
    EXPECT_THROW(render(yaml, b), fp::InputError);
    // Of another number of chains (the envelope compares recipes; the payload checks itself).
    Keeper c(2, 0, &whole);
    try {
        render(with_points(r, r.points).replace(yaml.find("chains: 700"), 11, "chains: 701"), c);
        ADD_FAILURE() << "a payload of 700 chains resumed as 701";
    } catch (const fp::InputError& e) {
        EXPECT_STREQ(e.what(), "the checkpoint's payload does not fit this render (damaged?)");
    }
}

/// The offsets of the suspended chains' states (ChainRec, 80 bytes) and of the fresh chains' ids
/// in a chain-game payload: PayloadHead (88 bytes), then per task its kind, its size and its
/// records (chaos-game/checkpoint.hpp).
struct PayloadMap {
    std::vector<std::size_t> states, ids;
};
PayloadMap map_payload(const std::string& p) {
    PayloadMap m;
    std::uint64_t tasks = 0;
    std::memcpy(&tasks, p.data() + 72, 8);
    std::size_t at = 88;
    for (std::uint64_t t = 0; t < tasks; ++t) {
        std::uint64_t kind = 0, n = 0;
        std::memcpy(&kind, p.data() + at, 8);
        std::memcpy(&n, p.data() + at + 8, 8);
        at += 16;
        for (std::uint64_t i = 0; i < n; ++i) (kind ? m.states : m.ids).push_back(at + i * (kind ? 80 : 4));
        at += n * (kind ? 80 : 4);
    }
    return m;
}

// A forged payload (issue 43, item 10: a checkpoint whose CRC was recomputed over a changed
// payload) is bounded by the recipe: a chain with more points left than its share would run for
// hours; a chain named twice would be drawn twice.
TEST(ChaosCheckpoint, ForgedPayloadsAreBoundedByTheRecipe) {
    const Recipe r = recipes()[0];
    ASSERT_TRUE(r.stops);
    const std::string yaml = with_points(r, r.points);
    Keeper k(2, 3);
    render(yaml, k);
    ASSERT_GE(k.saved.size(), 2u);
    const std::string mid = k.saved[0];
    const PayloadMap m = map_payload(mid);
    const auto refused = [&](std::string forged, const char* what, const std::string& why) {
        Keeper again(2, 0, &forged);
        try {
            render(yaml, again);
            ADD_FAILURE() << what << ": resumed";
        } catch (const fp::InputError& e) {
            EXPECT_EQ(std::string(e.what()), why) << what;
        }
    };
    std::string more_left = mid;
    const std::uint64_t huge = std::uint64_t(1) << 50;
    std::memcpy(more_left.data() + m.states[0] + 24, &huge, 8);
    refused(more_left, "points left past the chain's share",
            "the checkpoint's payload holds a chain state this render cannot have (damaged?)");
    std::string bad_map = mid;
    const std::uint32_t map = 1000;
    std::memcpy(bad_map.data() + m.states[0] + 44, &map, 4);
    refused(bad_map, "a previous map that does not exist",
            "the checkpoint's payload holds a chain state this render cannot have (damaged?)");
    std::vector<std::size_t> active;
    for (const std::size_t at : m.states) {
        std::uint32_t a = 0;
        std::memcpy(&a, mid.data() + at + 56, 4);
        if (a) active.push_back(at);
    }
    ASSERT_GE(active.size(), 2u);
    std::string twice = mid;
    std::memcpy(twice.data() + active[1] + 40, mid.data() + active[0] + 40, 4);
    refused(twice, "a chain twice", "the checkpoint's payload names a chain twice (damaged?)");
    // The unforged payload still resumes to the uninterrupted bytes.
    Keeper again(2, 0, &mid);
    expect_same(render(yaml, again), plain(yaml), "the unforged checkpoint");
}

// An orbit-trap render (affine mapping, the circles of paper 04's Fig. 1a, 4 samples a pixel).
const std::string orbit_trap =
    "{type: orbit-trap, width: 96, height: 80, samples: 4, mapping: {type: affine, "
    "coefficients: [1.1, 0.3, -0.2, 0.9, 0.05, 0]}, traps: {type: circles, preset: "
    "fig-1a}}";

TEST(OrbitTrapCheckpoint, StoppedAndResumedRendersAreUninterruptedOnes) {
    const Render want = plain(orbit_trap);
    EXPECT_GT(want.stats.drawn, 0u);
    for (unsigned threads : {1u, 2u}) {
        Keeper k(threads, 3);
        expect_same(render(orbit_trap, k), want, "stopped for checkpoints");
        ASSERT_GE(k.saved.size(), 3u);
        for (std::size_t i : {std::size_t(0), k.saved.size() / 2, k.saved.size() - 2}) {
            Keeper again(threads, 0, &k.saved[i]);
            expect_same(render(orbit_trap, again), want, "resumed from checkpoint " + std::to_string(i));
            ASSERT_EQ(again.saved.size(), 1u);
            EXPECT_TRUE(again.saved.back() == k.saved.back());
        }
    }
    // A payload of another image is refused.
    Keeper k(2, 0);
    render(orbit_trap, k);
    Keeper other(2, 0, &k.saved.back());
    std::string wider = orbit_trap;
    wider.replace(wider.find("width: 96"), 9, "width: 97");
    EXPECT_THROW(render(wider, other), fp::InputError);
}

} // namespace
