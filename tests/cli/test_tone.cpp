// Kept histograms (docs/histograms.md): `render --histogram FILE.fph` keeps the render's sums,
// and `fixpoint tone FILE.fph --set ...` finishes them again with other finishing parameters. Its
// image is the bytes of a full render of the changed recipe, for every colourer, both precisions,
// on 1, 2 and 3 threads and from a render in strips; and a histogram file that is cut short, of
// another version or of another recipe gets one line, exit 2, and nothing written.
#include "cli.hpp"
#include "configs.hpp"

#include <fixpoint/host/job/quality.hpp>

#include <gtest/gtest.h>
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

using namespace fp::test;

namespace {

// What tone changes: the whole finishing stage, the colourer's tone and the background.
const std::vector<std::string> retone = {"--set", "renderer.filter={type: mitchell, radius: 1.5}",
                                         "--set", "renderer.estimator_radius=3",
                                         "--set", "renderer.estimator_quality=2",
                                         "--set", "renderer.colourer.gamma=3.1",
                                         "--set", "renderer.background=[0.1, 0.05, 0.2]"};

struct Case {
    const char* name;
    const char* config; ///< under the source tree
    const char* points;
    const char* memory; ///< small enough for several strips at this size
    std::vector<std::string> extra;
};

void PrintTo(const Case& c, std::ostream* os) { *os << c.name; }

class Tone : public ::testing::TestWithParam<Case> {};

TEST_P(Tone, EqualsTheFullRenderOnAnyThreadsAndStrips) {
    const Case& c = GetParam();
    const std::string dir = scratch_dir(std::string("tone_") + c.name);
    const std::string config = source_dir() + "/" + c.config;
    const std::vector<std::string> base =
        with({config, "--set", std::string("renderer.points=") + c.points, "--set", "renderer.width=160",
              "--set", "renderer.height=120", "--set", "renderer.supersample=2"},
             c.extra);
    // The histogram, kept by a render with the recipe's own finish, on 2 threads and on 3.
    for (const char* t : {"2", "3"}) {
        const auto r = run_cli(with({"render", "--threads", t, "-o", dir + "/first-" + t + ".png",
                                     "--histogram", dir + "/h-" + t + ".fph"},
                                    base));
        ASSERT_EQ(r.rc, 0) << r.err;
        EXPECT_NE(r.err.find("; histogram to " + dir + "/h-" + t + ".fph"), std::string::npos) << r.err;
    }
    EXPECT_EQ(read_file(dir + "/h-2.fph"), read_file(dir + "/h-3.fph")) << "the file depends on the threads";
    // The full render of the changed recipe.
    const auto full =
        run_cli(with(with({"render", "--quiet", "--threads", "2", "-o", dir + "/full.png"}, base), retone));
    ASSERT_EQ(full.rc, 0) << full.err;
    EXPECT_NE(read_file(dir + "/full.png"), read_file(dir + "/first-2.png"))
        << "the new finish changed nothing";
    for (const char* t : {"1", "2", "3"}) {
        const std::string out = dir + "/tone-" + t + ".png";
        const auto r = run_cli(with({"tone", dir + "/h-2.fph", "--threads", t, "-o", out}, retone));
        ASSERT_EQ(r.rc, 0) << r.err;
        EXPECT_NE(r.err.find("no iterating"), std::string::npos) << r.err;
        EXPECT_EQ(read_file(out), read_file(dir + "/full.png"))
            << c.name << " toned on " << t << " thread(s)";
    }
    // Toned with nothing changed: the first render's bytes.
    const auto same = run_cli({"tone", "--quiet", dir + "/h-2.fph", "-o", dir + "/same.png"});
    ASSERT_EQ(same.rc, 0) << same.err;
    EXPECT_EQ(read_file(dir + "/same.png"), read_file(dir + "/first-2.png"));
    // Kept by a render in strips: the same sums, the same image.
    const auto strips = run_cli(
        with({"render", "--memory", c.memory, "-o", dir + "/strips.png", "--histogram", dir + "/strips.fph"},
             base));
    ASSERT_EQ(strips.rc, 0) << strips.err;
    EXPECT_NE(strips.err.find(" strips of "), std::string::npos) << strips.err;
    EXPECT_EQ(read_file(dir + "/strips.png"), read_file(dir + "/first-2.png"));
    const auto r =
        run_cli(with({"tone", "--quiet", dir + "/strips.fph", "-o", dir + "/tone-strips.png"}, retone));
    ASSERT_EQ(r.rc, 0) << r.err;
    EXPECT_EQ(read_file(dir + "/tone-strips.png"), read_file(dir + "/full.png")) << c.name << " from strips";
}

INSTANTIATE_TEST_SUITE_P(
    Colourers, Tone,
    ::testing::Values(Case{"density", "bench/circles.yaml", "200000", "6M", {}},
                      Case{"flame_mean", "bench/sierpinski.yaml", "200000", "9M", {}},
                      Case{"flame_double",
                           "bench/sierpinski.yaml",
                           "200000",
                           "9M",
                           {"--set", "renderer.precision=double", "--set", "renderer.colourer.vibrancy=0.5"}},
                      Case{"set_colour_last", "configs/inversion/fig6a.yaml", "200000", "9M", {}},
                      Case{"centroid_double", "configs/gumowski-mira/fig6b.yaml", "20000", "6M", {}}),
    [](const auto& info) { return std::string(info.param.name); });

// A histogram file in a fresh folder, from a small render; the folder's names before the bad
// command.
struct Kept {
    std::string dir;
    std::vector<std::string> before;
};

Kept kept(const std::string& name) {
    Kept k{scratch_dir(name), {}};
    write_file(k.dir + "/s.yaml",
               chaos_game({"width: 48", "height: 32", "points: 20000", "chains: 64"}, sierpinski));
    const auto r = run_cli(
        {"render", "--quiet", k.dir + "/s.yaml", "-o", k.dir + "/s.png", "--histogram", k.dir + "/h.fph"});
    EXPECT_EQ(r.rc, 0) << r.err;
    k.before = files_in(k.dir);
    return k;
}

// One line, exit 2, and the folder as it was. Returns the line.
std::string refused(const Kept& k, const std::vector<std::string>& args) {
    const auto r = run_cli(args);
    EXPECT_EQ(r.rc, 2) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_EQ(files_in(k.dir), k.before) << "something was written";
    return r.err.empty() ? r.err : r.err.substr(0, r.err.size() - 1);
}

// The file with its bytes changed by `edit`, its checksum made right again (a forged file).
void forge(const std::string& path, const std::function<void(std::string&)>& edit) {
    std::string s = read_file(path);
    edit(s);
    const uLong crc =
        crc32(crc32(0, nullptr, 0), reinterpret_cast<const Bytef*>(s.data()), uInt(s.size() - 4));
    for (int i = 0; i < 4; ++i) s[s.size() - 4 + size_t(i)] = char((crc >> (8 * i)) & 0xff);
    write_file(path, s);
}

TEST(ToneBadInput, AnotherRecipe) {
    const Kept k = kept("tone_bad_recipe");
    const std::string line =
        refused(k, {"tone", k.dir + "/h.fph", "--set", "renderer.points=30000", "-o", k.dir + "/out.png"});
    EXPECT_EQ(
        line,
        "'" + k.dir +
            "/h.fph' is a histogram of another recipe (its line 13 is 'points: 20000', this "
            "recipe's 'points: 30000'); tone changes only the finishing parameters (describe marks them)");
}

TEST(ToneBadInput, CutShort) {
    const Kept k = kept("tone_bad_cut");
    std::string s = read_file(k.dir + "/h.fph");
    write_file(k.dir + "/h.fph", s.substr(0, s.size() / 2));
    const std::string line = refused(k, {"tone", k.dir + "/h.fph", "-o", k.dir + "/out.png"});
    EXPECT_NE(line.find("is not a histogram fixpoint can finish: "), std::string::npos) << line;
}

TEST(ToneBadInput, DamagedBins) {
    const Kept k = kept("tone_bad_bins");
    // A byte of the compressed bins changed and the checksum recomputed: zlib finds it.
    forge(k.dir + "/h.fph", [](std::string& s) { s[s.size() - 60] = char(s[s.size() - 60] ^ 0x5a); });
    const std::string line = refused(k, {"tone", k.dir + "/h.fph", "-o", k.dir + "/out.png"});
    EXPECT_EQ(line, "'" + k.dir + "/h.fph' is not a histogram fixpoint can finish: its bins are damaged");
}

TEST(ToneBadInput, AnotherVersion) {
    const Kept k = kept("tone_bad_version");
    forge(k.dir + "/h.fph", [](std::string& s) {
        // The version string follows the magic (19 bytes), the format (4) and its length (8).
        s[19 + 4 + 8] = s[19 + 4 + 8] == 'x' ? 'y' : 'x';
    });
    const std::string line = refused(k, {"tone", k.dir + "/h.fph", "-o", k.dir + "/out.png"});
    EXPECT_NE(line.find("h.fph' was made by render version x"), std::string::npos) << line;
    EXPECT_NE(line.find("which may finish other bytes: render it again"), std::string::npos) << line;
}

TEST(ToneBadInput, NotAHistogramFile) {
    const Kept k = kept("tone_bad_kind");
    EXPECT_EQ(refused(k, {"tone", k.dir + "/s.yaml"}),
              "tone: '" + k.dir +
                  "/s.yaml' is not a histogram file: name one (.fph) that render --histogram wrote");
    write_file(k.dir + "/x.fph", "renderer: {type: chaos-game}\n");
    Kept k2 = k;
    k2.before = files_in(k.dir);
    EXPECT_EQ(refused(k2, {"tone", k.dir + "/x.fph"}),
              "'" + k.dir +
                  "/x.fph' is not a histogram fixpoint can finish: it is not a fixpoint histogram file");
}

TEST(ToneBadInput, RenderHistogramChecks) {
    const Kept k = kept("tone_bad_render");
    EXPECT_EQ(
        refused(k, {"render", k.dir + "/s.yaml", "-o", k.dir + "/t.png", "--histogram", k.dir + "/h.bin"}),
        "--histogram: '" + k.dir + "/h.bin': name the file NAME.fph");
    EXPECT_EQ(
        refused(k, {"render", k.dir + "/s.yaml", "-o", k.dir + "/t.png", "--histogram", k.dir + "/h.fph"}),
        "--histogram: '" + k.dir + "/h.fph' exists: add --force to replace it");
    EXPECT_EQ(refused(k, {"render", k.dir + "/s.yaml", "-o", k.dir + "/t.png", "--histogram",
                          k.dir + "/none/h.fph"}),
              "--histogram: cannot write '" + k.dir + "/none/h.fph': no folder '" + k.dir + "/none'");
    const std::string trap = source_dir() + "/configs/orbit-trap/fig10a.yaml";
    const std::string line =
        refused(k, {"render", trap, "-o", k.dir + "/t.png", "--histogram", k.dir + "/t.fph"});
    EXPECT_NE(line.find("renderer: orbit-trap keeps no histogram (--histogram; chaos-game renders keep one)"),
              std::string::npos)
        << line;
}

// The recipe in a histogram file is a config like an image's: `render h.fph` renders it from the
// start, to the bytes of the render that kept it.
TEST(Tone, HistogramFileRendersLikeItsRecipe) {
    const Kept k = kept("tone_render_fph");
    const auto r = run_cli({"render", "--quiet", k.dir + "/h.fph", "-o", k.dir + "/again.png"});
    ASSERT_EQ(r.rc, 0) << r.err;
    EXPECT_EQ(read_file(k.dir + "/again.png"), read_file(k.dir + "/s.png"));
}

} // namespace

// --quality Q (host/job/quality.hpp): the points double from renderer.points until the sample
// level reaches Q; the image is the bytes of a plain render of the points it stopped at, and its
// recipe says them.
namespace {

std::string points_of(const std::string& summary) {
    const auto at = summary.find(": ");
    const auto end = summary.find(" points in ");
    return at == std::string::npos || end == std::string::npos ? "" : summary.substr(at + 2, end - at - 2);
}

} // namespace

TEST(Quality, StopsAtTheFirstDoublingThatReachesItWithThePlainRendersBytes) {
    const std::string dir = scratch_dir("quality_stops");
    write_file(dir + "/s.yaml", chaos_game({"width: 64", "height: 48", "points: 3000", "chains: 64",
                                            "supersample: 2", "filter: {type: gaussian, radius: 0.5}"},
                                           sierpinski));
    const auto q = run_cli({"render", dir + "/s.yaml", "-o", dir + "/q.png", "--quality", "5"});
    ASSERT_EQ(q.rc, 0) << q.err;
    // 3000 points doubled until log2(points per lit pixel) >= 5: the first round falls short.
    EXPECT_NE(q.err.find(" of 5.00 at 3000 points: going on to 6000"), std::string::npos) << q.err;
    const std::string last = q.err.substr(q.err.rfind("q.png: "));
    const std::string points = points_of(last);
    ASSERT_FALSE(points.empty()) << q.err;
    const long long n = std::stoll(points);
    EXPECT_EQ(n % 3000, 0);
    EXPECT_GT(n, 3000);
    EXPECT_NE(last.find("; quality "), std::string::npos) << last;
    EXPECT_NE(last.find("target 5) after "), std::string::npos) << last;
    // The plain render of those points: the same bytes (the recipe holds them).
    const auto plain = run_cli({"render", "--quiet", dir + "/s.yaml", "--set", "renderer.points=" + points,
                                "-o", dir + "/plain.png"});
    ASSERT_EQ(plain.rc, 0) << plain.err;
    EXPECT_EQ(read_file(dir + "/q.png"), read_file(dir + "/plain.png"));
    EXPECT_EQ(files_in(dir), (std::vector<std::string>{"plain.png", "q.png", "s.yaml"}))
        << "a round's checkpoint left";
    // Started half-way, it stops at the same point.
    const auto half = run_cli({"render", dir + "/s.yaml", "--set", "renderer.points=" + std::to_string(n / 2),
                               "-o", dir + "/half.png", "--quality", "5"});
    ASSERT_EQ(half.rc, 0) << half.err;
    EXPECT_EQ(points_of(half.err.substr(half.err.rfind("half.png: "))), points) << half.err;
    EXPECT_EQ(read_file(dir + "/half.png"), read_file(dir + "/q.png"));
}

TEST(Quality, ItsRoundsGoOnThroughACheckpointFileAndResume) {
    // --checkpoint: the rounds continue one another through the file, with the bytes of the
    // rounds in memory. A render stopped at a lower level (as a killed one would be, after a
    // round) and resumed to the higher one starts at the points the file holds and gives the
    // bytes of the uninterrupted render; the file holds the points it stopped at.
    const std::string dir = scratch_dir("quality_checkpoint");
    write_file(dir + "/s.yaml",
               chaos_game({"width: 64", "height: 48", "points: 3000", "chains: 64"}, sierpinski));
    const auto q = run_cli({"render", "--quiet", dir + "/s.yaml", "-o", dir + "/q.png", "--quality", "6"});
    ASSERT_EQ(q.rc, 0) << q.err;
    const auto c = run_cli({"render", "--quiet", dir + "/s.yaml", "-o", dir + "/c.png", "--quality", "6",
                            "--checkpoint", dir + "/c.ck"});
    ASSERT_EQ(c.rc, 0) << c.err;
    EXPECT_EQ(read_file(dir + "/c.png"), read_file(dir + "/q.png"));
    const auto low = run_cli({"render", "--quiet", dir + "/s.yaml", "-o", dir + "/low.png", "--quality", "5",
                              "--checkpoint", dir + "/k.ck"});
    ASSERT_EQ(low.rc, 0) << low.err;
    EXPECT_NE(read_file(dir + "/low.png"), read_file(dir + "/q.png"));
    const auto on = run_cli(
        {"render", dir + "/s.yaml", "-o", dir + "/on.png", "--quality", "6", "--resume", dir + "/k.ck"});
    ASSERT_EQ(on.rc, 0) << on.err;
    // (3000 points reach 4.47, 6000 5.47, 12000 6.47: the file held 6000, two rounds remained.)
    EXPECT_NE(on.err.find(" after 2 rounds"), std::string::npos) << on.err;
    EXPECT_EQ(read_file(dir + "/on.png"), read_file(dir + "/q.png"));
    // The file went on to the stop point: resumed again, one round, the same bytes.
    const auto again = run_cli(
        {"render", dir + "/s.yaml", "-o", dir + "/again.png", "--quality", "6", "--resume", dir + "/k.ck"});
    ASSERT_EQ(again.rc, 0) << again.err;
    EXPECT_NE(again.err.find(" after 1 round"), std::string::npos) << again.err;
    EXPECT_EQ(read_file(dir + "/again.png"), read_file(dir + "/q.png"));
}

TEST(Quality, BadRequestsGetOneLineAndNothingWritten) {
    const Kept k = kept("quality_bad");
    EXPECT_EQ(refused(k, {"render", k.dir + "/s.yaml", "-o", k.dir + "/t.png", "--quality", "0"}),
              "--quality: expected a sample level in (0, 40] (log2 of the points per lit pixel), got 0");
    EXPECT_EQ(refused(k, {"render", k.dir + "/s.yaml", "-o", k.dir + "/t.png", "--quality", "4", "--resume",
                          k.dir + "/none.ck"}),
              "cannot read the checkpoint '" + k.dir + "/none.ck': no such file");
    // --histogram's checks come before the first round: an existing file, nothing written.
    write_file(k.dir + "/h.fph", "kept");
    Kept k3 = k;
    k3.before = files_in(k.dir);
    EXPECT_EQ(refused(k3, {"render", k.dir + "/s.yaml", "-o", k.dir + "/t.png", "--quality", "4",
                           "--histogram", k.dir + "/h.fph"}),
              "--histogram: '" + k.dir + "/h.fph' exists: add --force to replace it");
    EXPECT_EQ(refused(k, {"render", k.dir + "/s.yaml", "-o", k.dir + "/t.png", "--quality", "4", "--draft"}),
              "--quality renders one image to a sample level: not with --vary or --draft");
    const std::string line = refused(k, {"render", source_dir() + "/configs/orbit-trap/fig10a.yaml", "-o",
                                         k.dir + "/t.png", "--quality", "4"});
    EXPECT_NE(
        line.find("renderer: orbit-trap cannot go on to a quality (--quality needs points, checkpoints and a "
                  "histogram: chaos-game has them)"),
        std::string::npos)
        << line;
    // A view that misses the fractal: no point lands, ever.
    write_file(k.dir + "/far.yaml",
               chaos_game({"width: 16", "height: 16", "points: 1000", "chains: 8", "view: [50, 60, 50, 60]"},
                          sierpinski));
    Kept k2 = k;
    k2.before = files_in(k.dir);
    const std::string far =
        refused(k2, {"render", k.dir + "/far.yaml", "-o", k.dir + "/t.png", "--quality", "4"});
    EXPECT_EQ(far, k.dir +
                       "/far.yaml:2:3: renderer: nothing was drawn (0 of 1000 points landed in the image); "
                       "check the view and the parameters");
}

// --quality with --histogram keeps the histogram of the point it stopped at: the file of the
// plain render of those points, byte for byte, and toned it gives the quality render's image.
TEST(Quality, KeepsTheHistogramOfItsStopPoint) {
    const std::string dir = scratch_dir("quality_histogram");
    write_file(dir + "/s.yaml", chaos_game({"width: 64", "height: 48", "points: 3000", "chains: 64",
                                            "supersample: 2", "estimator_radius: 2"},
                                           sierpinski));
    const auto q = run_cli(
        {"render", dir + "/s.yaml", "-o", dir + "/q.png", "--quality", "5", "--histogram", dir + "/q.fph"});
    ASSERT_EQ(q.rc, 0) << q.err;
    const std::string points = points_of(q.err.substr(q.err.rfind("q.png: ")));
    ASSERT_FALSE(points.empty()) << q.err;
    EXPECT_GT(std::stoll(points), 3000) << "one round: nothing continued";
    const auto plain = run_cli({"render", "--quiet", dir + "/s.yaml", "--set", "renderer.points=" + points,
                                "-o", dir + "/plain.png", "--histogram", dir + "/plain.fph"});
    ASSERT_EQ(plain.rc, 0) << plain.err;
    EXPECT_EQ(read_file(dir + "/q.fph"), read_file(dir + "/plain.fph"));
    EXPECT_EQ(read_file(dir + "/q.png"), read_file(dir + "/plain.png"));
    const auto t = run_cli({"tone", "--quiet", dir + "/q.fph", "-o", dir + "/t.png"});
    ASSERT_EQ(t.rc, 0) << t.err;
    EXPECT_EQ(read_file(dir + "/t.png"), read_file(dir + "/q.png"));
}

// A render beyond --memory streams in strips and keeps no histogram to continue: each round
// renders afresh into temporary files, which take their names only in the round that reaches
// the level. Its image and histogram are those of the plain render of the points it stopped
// at; the rounds that fell short leave nothing, and an existing image (--force) is replaced
// only by the last.
TEST(Quality, InStripsEachRoundRendersAfresh) {
    const std::string dir = scratch_dir("quality_strips");
    write_file(dir + "/s.yaml", chaos_game({"width: 400", "height: 300", "points: 20000", "chains: 64",
                                            "supersample: 2", "estimator_radius: 2"},
                                           sierpinski));
    write_file(dir + "/q.png", "an older image");
    const auto q = run_cli({"render", dir + "/s.yaml", "-o", dir + "/q.png", "--force", "--quality", "4.5",
                            "--memory", "6M", "--histogram", dir + "/q.fph"});
    ASSERT_EQ(q.rc, 0) << q.err;
    const std::string last = q.err.substr(q.err.rfind("q.png: "));
    EXPECT_NE(last.find(" strips of "), std::string::npos) << last;
    EXPECT_NE(q.err.find("going on to"), std::string::npos) << "one round: nothing dropped";
    const std::string points = points_of(last);
    ASSERT_FALSE(points.empty()) << q.err;
    EXPECT_EQ(files_in(dir), (std::vector<std::string>{"q.fph", "q.png", "s.yaml"})) << "a round's file left";
    const auto plain = run_cli({"render", "--quiet", dir + "/s.yaml", "--set", "renderer.points=" + points,
                                "-o", dir + "/plain.png", "--histogram", dir + "/plain.fph"});
    ASSERT_EQ(plain.rc, 0) << plain.err;
    EXPECT_EQ(read_file(dir + "/q.png"), read_file(dir + "/plain.png"));
    EXPECT_EQ(read_file(dir + "/q.fph"), read_file(dir + "/plain.fph"));
}

// The sample level by hand: a 2 x 2 image supersampled 2 x 2; pixel (0, 0) has hits in two of
// its bins (3 + 1), pixel (1, 1) in one (4): 8 points over 2 lit pixels, log2(4) = 2.
TEST(Quality, SampleLevelByHand) {
    fp::host::HistogramFile h;
    h.header.shape = fp::HistogramShape{4, 4, true, false};
    h.histogram.width = h.histogram.height = 4;
    h.histogram.hits.assign(16, 0);
    h.histogram.hits[0] = 3;
    h.histogram.hits[1 * 4 + 1] = 1;
    h.histogram.hits[3 * 4 + 3] = 4;
    EXPECT_DOUBLE_EQ(fp::host::sample_level(h, 2), 2.0);
    // Read as a 4 x 4 image (no supersampling): 3 lit pixels.
    EXPECT_DOUBLE_EQ(fp::host::sample_level(h, 4), std::log2(8.0 / 3.0));
    h.histogram.hits.assign(16, 0);
    EXPECT_EQ(fp::host::sample_level(h, 2), -std::numeric_limits<double>::infinity());
}

// A checkpointed render keeps the histogram of the render it finishes: resumed to more points,
// its histogram file is a fresh render's.
TEST(Tone, ResumedRendersKeepTheFreshHistogram) {
    const std::string dir = scratch_dir("tone_resumed");
    write_file(dir + "/s.yaml",
               chaos_game({"width: 80", "height: 60", "points: 100000", "chains: 256"}, sierpinski));
    const auto first = run_cli(
        {"render", "--quiet", dir + "/s.yaml", "-o", dir + "/first.png", "--checkpoint", dir + "/ck.bin"});
    ASSERT_EQ(first.rc, 0) << first.err;
    const auto more =
        run_cli({"render", "--quiet", dir + "/s.yaml", "--set", "renderer.points=200000", "-o",
                 dir + "/more.png", "--resume", dir + "/ck.bin", "--histogram", dir + "/more.fph"});
    ASSERT_EQ(more.rc, 0) << more.err;
    const auto fresh = run_cli({"render", "--quiet", dir + "/s.yaml", "--set", "renderer.points=200000", "-o",
                                dir + "/fresh.png", "--histogram", dir + "/fresh.fph"});
    ASSERT_EQ(fresh.rc, 0) << fresh.err;
    EXPECT_EQ(read_file(dir + "/more.fph"), read_file(dir + "/fresh.fph"));
}
