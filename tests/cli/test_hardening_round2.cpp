// Regression tests of the second hardening campaign (issue 43): each failed before its fix.
// A render ends cleanly on every path out: one escaped, readable line, a meaningful exit code,
// nothing half-written.
#include "cli.hpp"
#include "configs.hpp"

#include <gtest/gtest.h>

#include <sys/stat.h>
#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

using namespace fp::test;

namespace {

namespace fs = std::filesystem;

const std::string base =
    chaos_game({"width: 256", "height: 256", "points: 400000", "chains: 64"}, sierpinski);

const std::string bin = fixpoint_bin();

int lines(const std::string& s) { return int(std::count(s.begin(), s.end(), '\n')); }

// Item 6: under `ulimit -f`, SIGXFSZ ended the process (exit 153, no message) and left its
// temporary file. Now the write fails with EFBIG, as on a full disk.
TEST(HardeningRound2, AFileSizeLimitIsAWriteErrorNotASignal) {
    const std::string dir = scratch_dir("round2_xfsz");
    write_file(dir + "/c.yaml", base);
    for (const char* memory : {"", " --memory 5M"}) {
        const auto r = shell(dir, "ulimit -f 4; exec " + bin + " render -q c.yaml -o out.png" + memory);
        EXPECT_EQ(r.rc, 2) << memory << ": " << r.err;
        EXPECT_EQ(r.err, "cannot write 'out.png': File too large\n") << memory;
        EXPECT_EQ(files_in(dir), std::vector<std::string>{"c.yaml"}) << memory;
    }
}

// Item 7: a collection written half way (a full disk, here the file-size limit that the
// contact sheet passes and the children do not) left the children written so far.
TEST(HardeningRound2, ACollectionIsWrittenWholeOrNotAtAll) {
    const std::string dir = scratch_dir("round2_collection");
    write_file(dir + "/c.yaml",
               replace_once(replace_once(base, "width: 256", "width: 48"), "height: 256", "height: 48"));
    const auto r = shell(dir, "ulimit -f 3; exec " + bin +
                                  " render -q c.yaml --vary renderer.points=1000,2000,3000 -o s.png");
    EXPECT_EQ(r.rc, 2) << r.err;
    EXPECT_EQ(lines(r.err), 1) << r.err;
    EXPECT_EQ(files_in(dir), std::vector<std::string>{"c.yaml"});
    // Without the limit, every file.
    const auto ok =
        shell(dir, "exec " + bin + " render -q c.yaml --vary renderer.points=1000,2000,3000 -o s.png");
    EXPECT_EQ(ok.rc, 0) << ok.err;
    EXPECT_EQ(files_in(dir).size(), 5u);
}

// Item 7: a Ctrl-C in a collection's write phase was ignored (exit 0, every file written).
// The signal is sent when the first child's file appears: the others are still being encoded.
TEST(HardeningRound2, CtrlCInACollectionsWritePhaseLeavesNoFile) {
    const std::string dir = scratch_dir("round2_collection_ctrl_c");
    write_file(dir + "/c.yaml", replace_once(replace_once(replace_once(base, "width: 256", "width: 2048"),
                                                          "height: 256", "height: 2048"),
                                             "points: 400000", "points: 4000000"));
    const auto r = shell(dir, bin + " render -q c.yaml --vary renderer.seed=1,2,3,4 -o s.png & pid=$!; " +
                                  "for i in $(seq 12000); do [ -e s-1.png ] && break; sleep 0.01; done; " +
                                  "kill -INT $pid; wait $pid");
    EXPECT_EQ(r.rc, 130) << r.err;
    EXPECT_EQ(r.err, "fixpoint: interrupted; no image written\n");
    EXPECT_EQ(files_in(dir), std::vector<std::string>{"c.yaml"});
}

// Item 7: a FIFO as a superfractal's picture blocked for ever in open().
TEST(HardeningRound2, AFifoAsAPictureIsRefusedAtOnce) {
    const std::string dir = scratch_dir("round2_fifo");
    ASSERT_EQ(::mkfifo((dir + "/pic.png").c_str(), 0644), 0);
    write_file(dir + "/c.yaml", R"(renderer:
  type: superfractal
  width: 64
  height: 64
  points_per_buffer: 1000
  steps: 2
  picture: pic.png
  maps:
    - {type: affine, coefficients: [0.5, 0.375, 0.5, -0.375, -0.0625, 0.5625]}
    - {type: affine, coefficients: [0.5, -0.375, -0.5, -0.375, 0.5625, 1.0625]}
)");
    const auto r = shell(dir, "exec timeout 60 " + bin + " validate c.yaml");
    EXPECT_EQ(r.rc, 2) << r.err;
    EXPECT_NE(r.err.find("cannot read the picture \"pic.png\": it is not a regular file"), std::string::npos)
        << r.err;
    EXPECT_EQ(lines(r.err), 1) << r.err;
}

// Item 11: the memory budget was all of the machine's available memory: under an
// address-space limit, an mfs 32768^2 SVG passed the check and died of memory in the render.
TEST(HardeningRound2, TheMemoryBudgetHonoursTheAddressSpaceLimit) {
    if (!fp::test::cli_address_space_limited())
        GTEST_SKIP() << "ASan: the CLI runs without an address-space limit";
    const std::string dir = scratch_dir("round2_rlimit_as");
    const std::string tri =
        "{type: subdivision, points: [[0, 0], [1, 0], [0.5, 0.6666666666666666]], divisor: "
        "2, S: [2, 0, 0, 1, 1, 0, 1, 0, 1]}";
    write_file(dir + "/mfs.yaml",
               "renderer:\n  type: mfs\n  width: 32768\n  height: 32768\n  path: [0, 0, 0]\n"
               "  maps:\n    - " +
                   tri + "\n    - " + tri + "\n");
    const auto r = run_cli({"validate", dir + "/mfs.yaml", "-o", dir + "/big.svg"});
    EXPECT_EQ(r.rc, 2) << r.err;
    EXPECT_NE(r.err.find("renderer: a 32768x32768 render needs "), std::string::npos) << r.err;
    EXPECT_EQ(lines(r.err), 1) << r.err;
    // As a PNG it streams in bands within the same budget.
    const auto png = run_cli({"validate", dir + "/mfs.yaml", "-o", dir + "/big.png"});
    EXPECT_EQ(png.rc, 0) << png.err;
}

// Item 9: a NUL in a string (a picture's name) was cut silently: another file was read.
TEST(HardeningRound2, ANulInAStringIsRefused) {
    const std::string line = fp::test::run_bad_input(
        "round2_nul", replace_once(base, "  chains: 64\n", "  chains: 64\n  precision: \"fl\\0oat\"\n"));
    EXPECT_NE(line.find("bad.yaml:7:14: renderer.precision: the text holds a NUL character"),
              std::string::npos)
        << line;
}

// Item 9: a file starting "a\0" was decoded as UTF-16; byte-order marks of UTF-16 likewise.
TEST(HardeningRound2, Utf16AndUtf32AreRefusedWithAClearLine) {
    EXPECT_EQ(fp::test::run_bad_input("round2_utf16_nul", std::string("a\0b\0", 4)),
              "bad.yaml:1:2: a NUL byte: a config is UTF-8 text (UTF-16 and UTF-32 are refused)");
    EXPECT_EQ(fp::test::run_bad_input("round2_utf16_bom", std::string("\xff\xfer\0e\0", 6)),
              "bad.yaml:1:1: the text is UTF-16 or UTF-32: fixpoint reads UTF-8 (save it as UTF-8)");
}

// Item 9: a 4 kB output path gave an 8 kB error line; an escape sequence in a name reached the
// terminal.
TEST(HardeningRound2, ErrorLinesAreEscapedAndOfAReadableLength) {
    const std::string dir = scratch_dir("round2_long");
    write_file(dir + "/c.yaml", base);
    const std::string name = std::string(4000, 'a') + "/x.png";
    const auto r = run_cli({"render", "-q", dir + "/c.yaml", "-o", name});
    EXPECT_EQ(r.rc, 2);
    EXPECT_EQ(lines(r.err), 1) << r.err;
    EXPECT_LT(r.err.size(), 1200u) << r.err.size();
    EXPECT_NE(r.err.find("bytes cut ...]"), std::string::npos);
    EXPECT_NE(r.err.find("does not exist"), std::string::npos) << "the reason, at the end, is kept";
    const auto e = run_cli({"render", "-q", dir + "/c.yaml", "-o", dir + "/no\x1b[31m/x.png"});
    EXPECT_EQ(e.rc, 2);
    EXPECT_EQ(e.err.find('\x1b'), std::string::npos) << e.err;
    EXPECT_NE(e.err.find("\\x1b[31m"), std::string::npos) << e.err;
}

// Item 9: validate of a config whose animation is bad said "valid" before the error.
TEST(HardeningRound2, ValidateSaysValidOnlyOfAValidAnimation) {
    const std::string dir = scratch_dir("round2_animation");
    write_file(dir + "/c.yaml",
               replace_once(base, "width: 256", "width: 32") +
                   "animation:\n  frames: 3\n  keys:\n    renderer.height: {0: 32, 2: -5}\n");
    const auto r = run_cli({"validate", dir + "/c.yaml"});
    EXPECT_EQ(r.rc, 2) << r.err;
    EXPECT_EQ(r.err.find("valid:"), std::string::npos) << r.err;
    EXPECT_EQ(lines(r.err), 1) << r.err;
}

} // namespace
