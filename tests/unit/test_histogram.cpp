// fp::Histogram in its two forms: fp::HistBin bins, or hit counts alone (Histogram::hits, ABI
// 14). Its readers (size, hits_at, HistogramSummary) must see the same counts in either; and
// fp::quantise_colour, the unit of the colour sums.
#include <fixpoint/fixpoint.hpp>

#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <vector>

namespace {

// A 5 x 4 histogram with hand-placed hits: row 0 empty; row 1 hits at columns 1 (3) and 3 (2);
// row 2 at column 0 (1); row 3 at column 4 (7).
fp::Histogram bins_form() {
    fp::Histogram h;
    h.resize(5, 4);
    h.bins[5 + 1] = {3, 10, 20, 30};
    h.bins[5 + 3] = {2, 1, 2, 3};
    h.bins[10 + 0] = {1, 0, 0, 0};
    h.bins[15 + 4] = {7, 5, 5, 5};
    return h;
}

fp::Histogram hits_form(const fp::Histogram& b) {
    fp::Histogram h;
    h.width = b.width;
    h.height = b.height;
    for (const fp::HistBin& x : b.bins) h.hits.push_back(x.hits);
    return h;
}

TEST(Histogram, BothFormsReadTheSame) {
    const fp::Histogram b = bins_form(), h = hits_form(b);
    ASSERT_EQ(b.size(), 20u);
    ASSERT_EQ(h.size(), 20u);
    EXPECT_TRUE(h.bins.empty());
    for (std::size_t i = 0; i < 20; ++i) EXPECT_EQ(h.hits_at(i), b.hits_at(i)) << i;
    EXPECT_EQ(h.hits_at(6), 3u);
    EXPECT_EQ(h.hits_at(19), 7u);
}

// The summary by hand: 13 hits; sum of hits x column = 3*1 + 2*3 + 1*0 + 7*4 = 37; of hits x
// row = 3*1 + 2*1 + 1*2 + 7*3 = 28; largest 7; per row the first and last hit columns.
TEST(Histogram, SummaryOfEitherFormIsTheHandComputedOne) {
    const fp::Histogram b = bins_form(), h = hits_form(b);
    for (const fp::Histogram* form : {&b, &h}) {
        const fp::HistogramSummary s = fp::HistogramSummary::of(*form);
        EXPECT_EQ(s.max_hits, 7u);
        EXPECT_EQ(std::uint64_t(s.hits), 13u);
        EXPECT_EQ(std::uint64_t(s.hits_column), 37u);
        EXPECT_EQ(std::uint64_t(s.hits_row), 28u);
        EXPECT_EQ(s.first, (std::vector<std::int32_t>{-1, 1, 0, 4}));
        EXPECT_EQ(s.last, (std::vector<std::int32_t>{-1, 3, 0, 4}));
    }
    // And row by row: rows 2..3 of the hit counts alone, added after rows 0..1 of the bins.
    fp::HistogramSummary s;
    s.begin(5, 4);
    fp::Histogram top, bottom;
    top.width = bottom.width = 5;
    top.height = bottom.height = 2;
    top.bins.assign(b.bins.begin(), b.bins.begin() + 10);
    bottom.hits.assign(h.hits.begin() + 10, h.hits.end());
    s.add(top, 0);
    s.add(bottom, 2);
    EXPECT_EQ(std::uint64_t(s.hits_row), 28u);
    EXPECT_EQ(s.first, (std::vector<std::int32_t>{-1, 1, 0, 4}));
}

TEST(Histogram, HitCountsOfTheWrongSizeAreRefused) {
    fp::Histogram h;
    h.width = 5;
    h.height = 4;
    h.hits.assign(19, 1);
    fp::HistogramSummary s;
    s.begin(5, 4);
    EXPECT_THROW(s.add(h, 0), fp::InternalError);
}

} // namespace

TEST(Histogram, QuantiseColourRoundsClampedChannels) {
    // round(c * 65535), c clamped to [0, 1] and NaN taken as 0; ties round up (x + 0.5, then
    // truncated): 0.5 * 65535 = 32767.5 gives 32768.
    EXPECT_EQ(fp::quantise_colour(0.0f), 0u);
    EXPECT_EQ(fp::quantise_colour(1.0f), 65535u);
    EXPECT_EQ(fp::quantise_colour(0.5f), 32768u);
    EXPECT_EQ(fp::quantise_colour(0.25f), 16384u); // 16383.75
    EXPECT_EQ(fp::quantise_colour(1.0f / 65535.0f), 1u);
    EXPECT_EQ(fp::quantise_colour(0.4f / 65535.0f), 0u); // 0.4 rounds down
    EXPECT_EQ(fp::quantise_colour(-0.3f), 0u);
    EXPECT_EQ(fp::quantise_colour(7.0f), 65535u);
    EXPECT_EQ(fp::quantise_colour(std::numeric_limits<float>::quiet_NaN()), 0u);
    EXPECT_EQ(fp::quantise_colour(std::numeric_limits<float>::infinity()), 65535u);
}
