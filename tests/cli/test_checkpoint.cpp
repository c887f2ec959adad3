// Checkpoints from the command line (`fixpoint render --checkpoint FILE`, `--checkpoint-every`,
// `--resume FILE`; framework/src/checkpoint.cpp, chaos-game/checkpoint.hpp): a render killed with
// SIGKILL after its first checkpoint and resumed gives the bytes of an uninterrupted one; a
// finished render continued to more points gives the bytes of a render of that many; and a
// checkpoint that is damaged, not a checkpoint, of another recipe, of another fixpoint version or
// of more points is refused before rendering with one line, exit 2 and no image. (The renders'
// state itself, on every path of chaos-game, is tested in unit/test_chaos_checkpoint.cpp.)
#include "cli.hpp"

#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

using namespace fp::test;

namespace {

namespace fs = std::filesystem;

// The temporary files of a write renamed into place (".NAME.tmp-PID-RANDOM") left in `dir`.
int temp_files(const std::string& dir) {
    int n = 0;
    for (const auto& e : fs::directory_iterator(dir))
        n += e.path().filename().string().find(".tmp-") != std::string::npos;
    return n;
}

/// CRC-32 (the polynomial of zlib's, bit by bit): to rewrite a checkpoint's version and keep it
/// whole otherwise.
std::uint32_t crc32_of(const std::string& s) {
    std::uint32_t c = 0xffffffffu;
    for (unsigned char b : s) {
        c ^= b;
        for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1u)));
    }
    return ~c;
}

void put32(std::string& s, std::size_t at, std::uint32_t v) {
    for (int i = 0; i < 4; ++i) s[at + std::size_t(i)] = char((v >> (8 * i)) & 0xff);
}

const std::string sierpinski =
    "renderer:\n  type: chaos-game\n  width: 128\n  height: 128\n  points: 400000\n"
    "  seed: 1\n  view: [-0.012, 1.012, -1.012, 0.012]\n  colourer: {type: flame}\n"
    "  maps:\n"
    "    - {type: affine, coefficients: [0.5, 0, 0, 0.5, 0, 0]}\n"
    "    - {type: affine, coefficients: [0.5, 0, 0, 0.5, 0.5, 0]}\n"
    "    - {type: affine, coefficients: [0.5, 0, 0, 0.5, 0.25, -0.5]}\n";

/// A scratch folder holding the config and a finished render's checkpoint ck.bin.
std::string with_checkpoint(const std::string& name) {
    const std::string dir = scratch_dir(name);
    write_file(dir + "/s.yaml", sierpinski);
    const auto r = run_cli(
        {"render", "--quiet", dir + "/s.yaml", "-o", dir + "/first.png", "--checkpoint", dir + "/ck.bin"});
    EXPECT_EQ(r.rc, 0) << r.err;
    return dir;
}

/// `render --resume` refused: exit 2, one line (returned without its newline), no image.
std::string refused(const std::string& dir, std::vector<std::string> args) {
    args.insert(args.begin(), {"render", "--quiet"});
    const auto r = run_cli(args);
    EXPECT_EQ(r.rc, 2) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(fs::exists(dir + "/out.png"));
    return r.err.substr(0, r.err.find('\n'));
}

TEST(Checkpoint, KilledRenderResumesToTheSameBytes) {
    const std::string dir = scratch_dir("checkpoint_killed");
    // Paper 02's Mann iteration with switching (the generic step, which sees the step index).
    const std::string config = source_dir() + "/configs/iterations/fig10a.yaml";
    const std::string bin = fixpoint_bin();
    // Long enough to be killed well before its end (about 3 s on two threads of the 2-core
    // machine, a checkpoint every 0.2 s; under ASan 4 million points take about as long);
    // killed once the first checkpoint exists.
    const std::string points = cli_sanitized() ? "renderer.points=4000000" : "renderer.points=100000000";
    write_file(dir + "/kill.sh",
               "cd '" + dir + "' || exit 1\n'" + bin + "' render --quiet --threads 2 '" + config +
                   "' --set " + points +
                   " -o killed.png --checkpoint ck.bin --checkpoint-every 0.2s & pid=$!\n"
                   "while [ ! -e ck.bin ] && kill -0 $pid 2>/dev/null; do sleep 0.01; done\n"
                   "kill -9 $pid\nwait $pid\n");
    const int status = std::system(("bash '" + dir + "/kill.sh'").c_str());
    ASSERT_TRUE(WIFEXITED(status));
    ASSERT_EQ(WEXITSTATUS(status), 128 + 9) << "the render was not killed mid-way (it ended first)";
    ASSERT_TRUE(fs::exists(dir + "/ck.bin"));
    EXPECT_FALSE(fs::exists(dir + "/killed.png"));

    const auto resumed = run_cli({"render", "--threads", "3", config, "--set", points, "-o",
                                  dir + "/resumed.png", "--resume", dir + "/ck.bin"});
    ASSERT_EQ(resumed.rc, 0) << resumed.err;
    EXPECT_NE(resumed.err.find(" checkpoint"), std::string::npos) << resumed.err;
    const auto whole =
        run_cli({"render", "--quiet", "--threads", "2", config, "--set", points, "-o", dir + "/whole.png"});
    ASSERT_EQ(whole.rc, 0) << whole.err;
    EXPECT_TRUE(read_file(dir + "/resumed.png") == read_file(dir + "/whole.png"));
    // The last checkpoint holds the finished render (continued to more points, below), and no
    // partial one is left beside it.
    EXPECT_EQ(temp_files(dir), 0) << "a temporary file is left in " << dir;
}

TEST(Checkpoint, FinishedRenderContinuesToMorePoints) {
    const std::string dir = with_checkpoint("checkpoint_more");
    const auto more = run_cli({"render", "--quiet", dir + "/s.yaml", "--set", "renderer.points=1000000", "-o",
                               dir + "/more.png", "--resume", dir + "/ck.bin"});
    ASSERT_EQ(more.rc, 0) << more.err;
    const auto fresh = run_cli(
        {"render", "--quiet", dir + "/s.yaml", "--set", "renderer.points=1000000", "-o", dir + "/fresh.png"});
    ASSERT_EQ(fresh.rc, 0) << fresh.err;
    EXPECT_TRUE(read_file(dir + "/more.png") == read_file(dir + "/fresh.png"));
    EXPECT_FALSE(read_file(dir + "/more.png") == read_file(dir + "/first.png"));
    // The checkpoint went on in the file resumed: now at 1000000 points, so fewer are refused.
    EXPECT_EQ(refused(dir, {dir + "/s.yaml", "-o", dir + "/out.png", "--resume", dir + "/ck.bin"}),
              "'" + dir +
                  "/ck.bin' holds 1000000 points, more than renderer.points 400000: a checkpoint "
                  "continues to as many points or more");
}

TEST(Checkpoint, DamagedOrForeignCheckpointsAreRefused) {
    const std::string dir = with_checkpoint("checkpoint_refused");
    const std::string ck = dir + "/ck.bin", good = read_file(ck);
    const std::vector<std::string> args = {dir + "/s.yaml", "-o", dir + "/out.png", "--resume", ck};
    const std::string who = "'" + ck + "'";

    // One byte of the histogram changed.
    std::string bad = good;
    bad[bad.size() / 2] = char(bad[bad.size() / 2] ^ 0x10);
    write_file(ck, bad);
    EXPECT_EQ(refused(dir, args), who + " is not a checkpoint fixpoint can resume: it is corrupt (its "
                                        "checksum does not match its contents)");
    // Cut short.
    write_file(ck, good.substr(0, good.size() - 1000));
    EXPECT_EQ(refused(dir, args), who + " is not a checkpoint fixpoint can resume: it is corrupt (its "
                                        "checksum does not match its contents)");
    // Not a checkpoint at all.
    write_file(ck, read_file(dir + "/first.png"));
    EXPECT_EQ(refused(dir, args),
              who + " is not a checkpoint fixpoint can resume: it is not a fixpoint checkpoint");
    // Made by another fixpoint version (whole otherwise: its CRC made anew).
    std::string other = good;
    const std::size_t v = 20 + 4 + 8; // magic, format, the version's length
    other[v] = other[v] == '9' ? '8' : '9';
    put32(other, other.size() - 4, crc32_of(other.substr(0, other.size() - 4)));
    write_file(ck, other);
    const std::string line = refused(dir, args);
    EXPECT_EQ(line.rfind(who + " was made by fixpoint ", 0), 0u) << line;
    EXPECT_NE(line.find(", which may render other bytes: render from the start"), std::string::npos) << line;
    // Of another recipe: the first line that differs is named.
    write_file(ck, good);
    write_file(dir + "/s2.yaml", replace_once(sierpinski, "seed: 1", "seed: 2"));
    EXPECT_EQ(
        refused(dir, {dir + "/s2.yaml", "-o", dir + "/out.png", "--resume", ck}),
        who + " is a checkpoint of another recipe (its line 13 is 'seed: 1', this recipe's 'seed: 2'); only "
              "renderer.points may differ, and only upwards");
    // No such file.
    EXPECT_EQ(refused(dir, {dir + "/s.yaml", "-o", dir + "/out.png", "--resume", dir + "/none.bin"}),
              "cannot read the checkpoint '" + dir + "/none.bin': no such file");
}

TEST(Checkpoint, OptionsAreCheckedBeforeRendering) {
    const std::string dir = with_checkpoint("checkpoint_options");
    const std::string s = dir + "/s.yaml", out = dir + "/out.png";
    // An existing checkpoint is not started over unless asked.
    EXPECT_EQ(refused(dir, {s, "-o", out, "--checkpoint", dir + "/ck.bin"}),
              "--checkpoint: '" + dir +
                  "/ck.bin' exists: continue it with --resume, or add --force to start over");
    EXPECT_EQ(refused(dir, {s, "-o", out, "--checkpoint-every", "5m"}),
              "--checkpoint-every: checkpoints go to a file: add --checkpoint FILE");
    EXPECT_EQ(refused(dir, {s, "-o", out, "--checkpoint", dir + "/c2.bin", "--checkpoint-every", "soon"}),
              "--checkpoint-every: expected a time such as 30s, 5m or 1.5h, got 'soon'");
    EXPECT_EQ(refused(dir, {s, "-o", out, "--checkpoint", out}),
              "--checkpoint: '" + out + "' is the output: a checkpoint needs a file of its own");
    EXPECT_EQ(refused(dir, {s, "-o", out, "--checkpoint", dir + "/./out.png"}),
              "--checkpoint: '" + dir + "/./out.png' is the output: a checkpoint needs a file of its own");
    EXPECT_EQ(refused(dir, {s, "-o", out, "--checkpoint", dir + "/no/such/c.bin"}),
              "--checkpoint: cannot write '" + dir + "/no/such/c.bin': no folder '" + dir + "/no/such'");
    EXPECT_EQ(refused(dir, {s, "-o", out, "--checkpoint", dir + "/c2.bin", "--vary", "renderer.seed=1,2"}),
              "--checkpoint and --resume keep one render: not with --vary");
    // A renderer that keeps none.
    const std::string line = refused(dir, {source_dir() + "/configs/gumowski-mira/fig2-F.yaml", "-o", out,
                                           "--checkpoint", dir + "/c2.bin"});
    EXPECT_NE(line.find(": renderer: superfractal keeps no checkpoints (--checkpoint; chaos-game and "
                        "orbit-trap renders keep them)"),
              std::string::npos)
        << line;
    EXPECT_FALSE(fs::exists(dir + "/c2.bin"));
}

// A checkpoint that cannot be written (a full disk: the file-size limit, SIGXFSZ ignored, fails
// every write past 4 KiB with EFBIG) stops the render with one line, exit 2, no image, and the
// previous checkpoint whole and unchanged.
TEST(Checkpoint, AFailedCheckpointWriteIsAnErrorAndKeepsThePreviousOne) {
    const std::string dir = with_checkpoint("checkpoint_full_disk");
    const std::string before = read_file(dir + "/ck.bin");
    const std::string err = dir + "/err.txt";
    const std::string script =
        "cd '" + dir + "' || exit 1\ntrap '' XFSZ\nulimit -f 4\nexec '" + fixpoint_bin() +
        "' render -q s.yaml --set renderer.points=800000 -o out.png --resume ck.bin 2>'" + err + "'\n";
    write_file(dir + "/full.sh", script);
    const int status = std::system(("bash '" + dir + "/full.sh'").c_str());
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 2);
    const std::string line = read_file(err);
    EXPECT_EQ(line.rfind("cannot write the checkpoint 'ck.bin': ", 0), 0u) << line;
    EXPECT_EQ(std::count(line.begin(), line.end(), '\n'), 1) << line;
    EXPECT_FALSE(fs::exists(dir + "/out.png"));
    EXPECT_EQ(temp_files(dir), 0) << "a temporary file is left in " << dir;
    EXPECT_TRUE(read_file(dir + "/ck.bin") == before);
}

} // namespace
