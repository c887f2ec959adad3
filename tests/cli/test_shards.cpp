// Shards (docs/cluster.md): `render --shard K/N --histogram PART.fph` renders the K-th of N shares
// of the chains (the blocks MPI rank K-1 of N would take), and `fixpoint merge` sums them. The
// merged image is the single render's bytes, and the merged histogram its --histogram file,
// for every colour path, both precisions, strip plans, any thread counts and any order and
// grouping of the merges; a missing, doubled, foreign or damaged shard gets one line, exit 2,
// and nothing written.
#include "cli.hpp"
#include "configs.hpp"

#include <gtest/gtest.h>
#include <zlib.h>

#include <algorithm>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

using namespace fp::test;

namespace {

namespace fs = std::filesystem;

struct Case {
    const char* name;
    const char* config; ///< under the source tree
    const char* points;
    const char* memory; ///< small enough for several strips at this size
    std::vector<std::string> extra;
};

void PrintTo(const Case& c, std::ostream* os) { *os << c.name; }

class Shards : public ::testing::TestWithParam<Case> {};

TEST_P(Shards, MergedInAnyOrderAndGroupingGiveTheSingleRendersBytes) {
    const Case& c = GetParam();
    const std::string dir = scratch_dir(std::string("shards_") + c.name);
    const std::vector<std::string> base =
        with({source_dir() + "/" + c.config, "--set", std::string("renderer.points=") + c.points, "--set",
              "renderer.width=160", "--set", "renderer.height=120", "--set", "renderer.supersample=2"},
             c.extra);
    const auto full = run_cli(with(
        {"render", "--quiet", "--threads", "2", "-o", dir + "/full.png", "--histogram", dir + "/full.fph"},
        base));
    ASSERT_EQ(full.rc, 0) << full.err;
    // Three shards, each on another thread count; the second in strips.
    const char* threads[] = {"1", "2", "3"};
    for (int k = 1; k <= 3; ++k) {
        std::vector<std::string> args = {"render",
                                         "--threads",
                                         threads[k - 1],
                                         "--shard",
                                         std::to_string(k) + "/3",
                                         "--histogram",
                                         dir + "/part-" + std::to_string(k) + ".fph"};
        if (k == 2) args.insert(args.end(), {"--memory", c.memory});
        const auto r = run_cli(with(args, base));
        ASSERT_EQ(r.rc, 0) << r.err;
        EXPECT_NE(
            r.err.find(dir + "/part-" + std::to_string(k) + ".fph: shard " + std::to_string(k) + "/3, "),
            std::string::npos)
            << r.err;
        if (k == 2) {
            EXPECT_NE(r.err.find(" strips of "), std::string::npos) << r.err;
        }
    }
    const std::string p1 = dir + "/part-1.fph", p2 = dir + "/part-2.fph", p3 = dir + "/part-3.fph";
    EXPECT_FALSE(read_file(p1) == read_file(p2)) << "two shards hold the same sums";
    // Every order, into the image.
    for (const auto& order :
         std::vector<std::vector<std::string>>{{p1, p2, p3}, {p3, p1, p2}, {p2, p3, p1}}) {
        const std::string out = dir + "/merged.png";
        const auto r = run_cli(with(with({"merge", "--quiet"}, order), {"-o", out}));
        ASSERT_EQ(r.rc, 0) << r.err;
        EXPECT_TRUE(read_file(out) == read_file(dir + "/full.png"))
            << c.name << ": merged from " << order.front();
        fs::remove(out);
    }
    // A merge of two, merged again with the third: the histogram of the part, then the whole
    // render's own --histogram file, byte for byte.
    auto r = run_cli({"merge", "--quiet", p3, p2, "-o", dir + "/p23.fph"});
    ASSERT_EQ(r.rc, 0) << r.err;
    r = run_cli({"merge", p1, dir + "/p23.fph", "-o", dir + "/whole.fph"});
    ASSERT_EQ(r.rc, 0) << r.err;
    EXPECT_NE(r.err.find("(the whole render; "), std::string::npos) << r.err;
    EXPECT_TRUE(read_file(dir + "/whole.fph") == read_file(dir + "/full.fph")) << c.name;
    r = run_cli({"merge", "--quiet", dir + "/p23.fph", p1, "-o", dir + "/grouped.png"});
    ASSERT_EQ(r.rc, 0) << r.err;
    EXPECT_TRUE(read_file(dir + "/grouped.png") == read_file(dir + "/full.png")) << c.name << ": grouped";
    // The merged histogram tones as the full one does.
    r = run_cli({"tone", "--quiet", dir + "/whole.fph", "-o", dir + "/toned.png"});
    ASSERT_EQ(r.rc, 0) << r.err;
    EXPECT_TRUE(read_file(dir + "/toned.png") == read_file(dir + "/full.png"));
}

INSTANTIATE_TEST_SUITE_P(
    ColourPaths, Shards,
    ::testing::Values(Case{"density", "bench/circles.yaml", "200000", "6M", {}},
                      Case{"flame_mean", "bench/sierpinski.yaml", "200000", "9M", {}},
                      Case{"flame_double",
                           "bench/sierpinski.yaml",
                           "200000",
                           "9M",
                           {"--set", "renderer.precision=double", "--set", "renderer.colourer.vibrancy=0.5"}},
                      Case{"set_colour_last", "configs/inversion/fig6a.yaml", "200000", "9M", {}},
                      Case{"palette_double",
                           "configs/palettes/fern.yaml",
                           "200000",
                           "9M",
                           {"--set", "renderer.precision=double"}}),
    [](const auto& info) { return std::string(info.param.name); });

// A folder with a small config and its shards part-1..3 of 3.
struct Parts {
    std::string dir;
    std::vector<std::string> before;
    std::string part(int k) const { return dir + "/part-" + std::to_string(k) + ".fph"; }
};

Parts parts(const std::string& name, int n = 3) {
    Parts p{scratch_dir(name), {}};
    write_file(p.dir + "/s.yaml",
               chaos_game({"width: 48", "height: 32", "points: 20000", "chains: 64"}, sierpinski));
    for (int k = 1; k <= n; ++k) {
        const auto r = run_cli({"render", "--quiet", p.dir + "/s.yaml", "--shard",
                                std::to_string(k) + "/" + std::to_string(n), "--histogram", p.part(k)});
        EXPECT_EQ(r.rc, 0) << r.err;
    }
    p.before = files_in(p.dir);
    return p;
}

// One line, exit 2, and the folder as it was. Returns the line.
std::string refused(const Parts& p, const std::vector<std::string>& args) {
    const auto r = run_cli(args);
    EXPECT_EQ(r.rc, 2) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_EQ(files_in(p.dir), p.before) << "something was written";
    return r.err.empty() ? r.err : r.err.substr(0, r.err.size() - 1);
}

TEST(Shards, OneShardOfOneIsTheWholeRender) {
    const Parts p = parts("shards_one", 1);
    auto r = run_cli({"render", "--quiet", p.dir + "/s.yaml", "-o", p.dir + "/full.png"});
    ASSERT_EQ(r.rc, 0) << r.err;
    r = run_cli({"merge", "--quiet", p.part(1), "-o", p.dir + "/merged.png"});
    ASSERT_EQ(r.rc, 0) << r.err;
    EXPECT_TRUE(read_file(p.dir + "/merged.png") == read_file(p.dir + "/full.png"));
}

TEST(Shards, AMissingDoubledOrForeignShardIsRefused) {
    const Parts p = parts("shards_bad");
    const std::string out = p.dir + "/out.png";
    EXPECT_EQ(
        refused(p, {"merge", p.part(1), p.part(3), "-o", out}),
        "merge: shard 2/3 of the render is missing: no file given holds it (render it with --shard K/N, "
        "then merge every shard)");
    EXPECT_EQ(refused(p, {"merge", p.part(2), "-o", out}),
              "merge: shards 1/3 and 3/3 of the render are missing: no file given holds them (render it with "
              "--shard K/N, then merge every shard)");
    EXPECT_EQ(refused(p, {"merge", p.part(1), p.part(2), p.part(1), p.part(3), "-o", out}),
              "merge: '" + p.part(1) + "' is given twice: give each shard once");
    // The same shard under two names; a merge that holds one already.
    fs::copy_file(p.part(2), p.dir + "/copy.fph");
    Parts q = p;
    q.before = files_in(p.dir);
    EXPECT_EQ(refused(q, {"merge", p.part(1), p.part(2), p.dir + "/copy.fph", p.part(3), "-o", out}),
              "'" + p.dir + "/copy.fph' and '" + p.part(2) + "' both hold shard 2/3: give each shard once");
    // Another seed: another recipe.
    auto r = run_cli({"render", "--quiet", p.dir + "/s.yaml", "--set", "renderer.seed=9", "--shard", "2/3",
                      "--histogram", p.dir + "/seed9.fph"});
    ASSERT_EQ(r.rc, 0) << r.err;
    // Another plan: the second of two.
    r = run_cli(
        {"render", "--quiet", p.dir + "/s.yaml", "--shard", "2/2", "--histogram", p.dir + "/half.fph"});
    ASSERT_EQ(r.rc, 0) << r.err;
    q.before = files_in(p.dir);
    EXPECT_EQ(refused(q, {"merge", p.part(1), p.dir + "/seed9.fph", p.part(3), "-o", out}),
              "'" + p.dir + "/seed9.fph' is a shard of another recipe than '" + p.part(1) +
                  "' (its line 14 is 'seed: 1', this recipe's 'seed: 9')");
    EXPECT_EQ(refused(q, {"merge", p.part(1), p.dir + "/half.fph", "-o", out}),
              "'" + p.dir + "/half.fph' holds shard 2/2, '" + p.part(1) +
                  "' shard 1/3: only shards of one plan of N merge");
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

TEST(Shards, ADamagedShardOrOneOfAnotherVersionIsRefused) {
    Parts p = parts("shards_damaged");
    const std::string out = p.dir + "/out.png";
    std::string s = read_file(p.part(2));
    s[s.size() / 2] = char(s[s.size() / 2] ^ 0x21);
    write_file(p.part(2), s);
    forge(p.part(3), [](std::string& b) { b[19 + 4 + 8] = b[19 + 4 + 8] == 'x' ? 'y' : 'x'; });
    p.before = files_in(p.dir);
    EXPECT_EQ(
        refused(p, {"merge", p.part(1), p.part(2), p.part(3), "-o", out}),
        "'" + p.part(2) +
            "' is not a histogram fixpoint can finish: it is corrupt or cut short (its checksum does not "
            "match its contents)");
    const std::string line = refused(p, {"merge", p.part(3), p.part(1), "-o", p.dir + "/two.fph"});
    EXPECT_NE(line.find("'" + p.part(1) + "' was made by render version "), std::string::npos) << line;
    EXPECT_NE(line.find(": only shards of one render merge"), std::string::npos) << line;
}

TEST(Shards, BadRequestsGetOneLineAndNothingWritten) {
    const Parts p = parts("shards_requests");
    const std::string cfg = p.dir + "/s.yaml";
    EXPECT_EQ(refused(p, {"render", cfg, "--shard", "2/3"}),
              "--shard: name the shard's file with --histogram PART.fph (fixpoint merge sums them)");
    EXPECT_EQ(refused(p, {"render", cfg, "--shard", "2/3", "--histogram", p.dir + "/x.fph", "-o",
                          p.dir + "/x.png"}),
              "--shard: a shard makes a histogram, not an image: not with -o '" + p.dir +
                  "/x.png' (fixpoint merge makes the image of every shard)");
    for (const char* bad : {"0/3", "4/3", "3", "a/b", "1/0", "1/70000", "/3", "-1/3"})
        EXPECT_EQ(
            refused(p, {"render", cfg, "--shard", bad, "--histogram", p.dir + "/x.fph"}),
            std::string("--shard: '") + bad +
                "' is not K/N: the K-th of N equal shares of the chains, 1 <= K <= N <= 65536 (such as 2/8)");
    EXPECT_EQ(refused(p, {"render", cfg, "--shard", "1/3", "--histogram", p.dir + "/x.fph", "--vary",
                          "renderer.seed=1,2"}),
              "--shard renders a share of one recipe's chains: not with --vary, --quality, --draft, --tile, "
              "--repeat, --dpi or --print-size");
    // A shard is not an image's histogram: tone refuses it.
    EXPECT_EQ(refused(p, {"tone", p.part(1), "-o", p.dir + "/t.png"}),
              "'" + p.part(1) +
                  "' holds shard 1/3 of a render: merge every shard into the image with fixpoint merge");
    // The output: named, not a shard, not there unless --force, in a folder that exists.
    EXPECT_EQ(refused(p, {"merge", p.part(1), p.part(2)}),
              "merge: name the output with -o: an image (.png, .exr, .tif) or a histogram (.fph)");
    EXPECT_EQ(refused(p, {"merge", p.part(1), p.part(2), "-o", p.part(2)}),
              "merge: -o '" + p.part(2) + "' is one of the shards: name a new file");
    EXPECT_EQ(refused(p, {"merge", p.part(1), p.part(2), "-o", p.dir + "/no/m.fph"}),
              "merge: cannot write '" + p.dir + "/no/m.fph': no folder '" + p.dir + "/no'");
    EXPECT_EQ(refused(p, {"merge", p.part(1), "-o", p.dir + "/m.fph", "--set", "renderer.colourer.gamma=2"}),
              "merge: --set changes the image's finish: not with -o '" + p.dir +
                  "/m.fph', a histogram (fixpoint tone finishes it)");
    EXPECT_EQ(refused(p, {"merge", p.part(1), cfg, "-o", p.dir + "/m.png"}),
              "merge: '" + cfg + "' is not a histogram file: name the .fph files that render --shard wrote");
    // Renderers that keep no histogram do not shard.
    const std::string line = refused(p, {"render", source_dir() + "/configs/orbit-trap/fig10a.yaml",
                                         "--shard", "1/2", "--histogram", p.dir + "/t.fph"});
    EXPECT_NE(line.find("renderer: orbit-trap keeps no histogram (--shard; chaos-game renders keep one)"),
              std::string::npos)
        << line;
}

TEST(Shards, AShardKeepsCheckpointsOfItsOwn) {
    const Parts p = parts("shards_checkpoint");
    const std::string cfg = p.dir + "/s.yaml";
    // Shard 2 at 20 000 points with a checkpoint, resumed to 60 000: a fresh shard 2 at 60 000.
    auto r = run_cli({"render", "--quiet", cfg, "--shard", "2/3", "--histogram", p.dir + "/a.fph",
                      "--checkpoint", p.dir + "/ck.bin"});
    ASSERT_EQ(r.rc, 0) << r.err;
    EXPECT_TRUE(read_file(p.dir + "/a.fph") == read_file(p.part(2)));
    r = run_cli({"render", "--quiet", cfg, "--set", "renderer.points=60000", "--shard", "2/3", "--histogram",
                 p.dir + "/more.fph", "--resume", p.dir + "/ck.bin"});
    ASSERT_EQ(r.rc, 0) << r.err;
    r = run_cli({"render", "--quiet", cfg, "--set", "renderer.points=60000", "--shard", "2/3", "--histogram",
                 p.dir + "/fresh.fph"});
    ASSERT_EQ(r.rc, 0) << r.err;
    EXPECT_TRUE(read_file(p.dir + "/more.fph") == read_file(p.dir + "/fresh.fph"));
    // Another shard's checkpoint is not this one's.
    r = run_cli({"render", cfg, "--set", "renderer.points=60000", "--shard", "3/3", "--histogram",
                 p.dir + "/other.fph", "--resume", p.dir + "/ck.bin"});
    EXPECT_EQ(r.rc, 2) << r.err;
    EXPECT_NE(r.err.find("# shard 2/3"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(p.dir + "/other.fph"));
}

} // namespace
