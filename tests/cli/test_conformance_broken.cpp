// The conformance suite catches the mistakes scheme authors make: each fixture of
// tests/fixtures/schemes/ has one, and `fixpoint conformance FILE` must report exactly it.
#include "cli.hpp"

#include <gtest/gtest.h>

#include <sched.h>
#include <string>

using namespace fp::test;

namespace {

const std::string dir = fixtures_dir() + "/schemes/";

// `fixpoint conformance` on fixture `name`: exit 1, and the one finding `finding`.
void expect_finding(const std::string& name, const std::string& finding) {
    const std::string file = dir + "broken-" + name + ".so";
    const auto r = run_cli({"conformance", file});
    EXPECT_EQ(r.rc, 1);
    EXPECT_EQ(r.out, "FAIL broken-" + name + " (" + file + ")\n  - " + finding + "\n0 passed, 1 failed\n");
}

TEST(ConformanceBroken, AFloatPathWrongAtLargeStepsIsFound) {
    expect_finding(
        "float-only",
        "iteration-scheme: the float path differs from double at step n = 16777217 (on the test "
        "contraction): the point (-0.22879221368182567, -0.7799489576926688) goes to (-0.09427798, "
        "-0.7435479) in float, (0.08507434222227375, -0.6950131873734181) in double");
}

TEST(ConformanceBroken, NaNFromFiniteInputIsItsOwnFinding) {
    expect_finding("nan", "iteration-scheme: step() gives a non-finite result for finite input at step n = 0 "
                          "(double, on the test contraction): (-0.22879221368182567, -0.7799489576926688) -> "
                          "(nan, 0.716717416014342)");
}

TEST(ConformanceBroken, StateKeptBetweenCallsIsFound) {
    expect_finding("stateful",
                   "iteration-scheme: step() depends on earlier calls: the same points gave another "
                   "result at step n = 4294967301 (double, on the test contraction) after other "
                   "steps had run (keep no state between calls)");
}

TEST(ConformanceBroken, AFalsePicardPromiseIsFound) {
    expect_finding("false-picard", "iteration-scheme: is_picard() is true, but step() is not exactly T(p) at "
                                   "step n = 0 (double, on the test contraction), first for the point (inf, "
                                   "-0.7799489576926688)");
}

TEST(ConformanceBroken, AKernelTouchingThePointsItselfIsFound) {
    expect_finding(
        "hand-written",
        "iteration-scheme: program() does not compute step() at step n = 0 (double, on the test "
        "contraction): for the point (0.6348089102430801, -0.2694297947261113) its instructions give "
        "(0.5665211518912268, -0.20685100950812146), step() (0.5, -0.20685100950812146) (a kernel "
        "that reads or writes the points itself overrides program() to return false)");
}

// A race shows only when threads really run at once, and which step it hits first varies:
// the test needs two CPUs, matches the message up to the step, and allows six runs (one run
// finds it nearly always: 30 of 30 idle, 27 of 30 beside a second test run; CI runs the
// tests two at a time, and the sanitizer build slows the threads).
TEST(ConformanceBroken, ARacyPerStepCacheIsFound) {
    cpu_set_t cpus;
    if (sched_getaffinity(0, sizeof cpus, &cpus) == 0 && CPU_COUNT(&cpus) < 2)
        GTEST_SKIP() << "a race needs two CPUs";
    const std::string file = dir + "broken-racy-cache.so";
    fp::test::CliResult r;
    for (int attempt = 0; attempt < 6 && r.rc != 1; ++attempt) r = run_cli({"conformance", file});
    EXPECT_EQ(r.rc, 1) << r.out;
    const std::string head =
        "FAIL broken-racy-cache (" + file +
        ")\n  - iteration-scheme: results differ when 6 threads step at once: a thread got "
        "another result than the serial one at step n = ";
    const std::string tail = " (state shared between calls without synchronisation, such as a per-step cache "
                             "in a mutable member?)\n0 passed, 1 failed\n";
    EXPECT_EQ(r.out.substr(0, head.size()), head) << r.out;
    ASSERT_GE(r.out.size(), tail.size());
    EXPECT_EQ(r.out.substr(r.out.size() - tail.size()), tail) << r.out;
}

TEST(ConformanceBroken, VerboseListsEveryCheck) {
    const std::string file = dir + "broken-nan.so";
    const auto quiet = run_cli({"conformance", file});
    const auto r = run_cli({"conformance", "--verbose", file});
    EXPECT_EQ(r.rc, 1);
    // The default output, with the list of checks between the findings and the summary line.
    const std::string summary = "0 passed, 1 failed\n";
    const std::string before = quiet.out.substr(0, quiet.out.size() - summary.size());
    EXPECT_EQ(r.out.substr(0, before.size()), before);
    EXPECT_EQ(r.out.substr(r.out.size() - summary.size()), summary);
    for (const char* line :
         {"    PASS metadata: summary, version, parameter names and docs\n",
          "    PASS build: the example builds\n", "    PASS parameters: an unknown parameter is refused\n",
          "    FAIL iteration-scheme: finite output for finite input\n",
          "    PASS iteration-scheme: no state kept between calls\n",
          "    PASS iteration-scheme: a batch equals point-by-point, bit for bit\n",
          "    PASS iteration-scheme: masked-out points stay, active ones get the unmasked "
          "result\n",
          "    PASS iteration-scheme: the float path agrees with the double path\n",
          "    PASS iteration-scheme: the same results when 6 threads step at once\n"})
        EXPECT_NE(r.out.find(line), std::string::npos) << line << r.out;
    EXPECT_EQ(quiet.out.find("    PASS"), std::string::npos) << quiet.out;
}

} // namespace

// Plugins named rather than given as files, and --example: mistakes in the command itself are
// bad input (exit 2, one line), not failed checks.
TEST(ConformanceBroken, NamesAndExamplesOnTheCommandLine) {
    const auto named = run_cli({"conformance", "mann", "--example", "{alpha: 0.25}"});
    EXPECT_EQ(named.rc, 0) << named.out << named.err;
    EXPECT_EQ(named.out.rfind("PASS mann (", 0), 0u) << named.out;
    const auto unknown = run_cli({"conformance", "manm"});
    EXPECT_EQ(unknown.rc, 2);
    EXPECT_EQ(unknown.err, "unknown plugin 'manm' (did you mean 'mann'?)\n");
    const auto list = run_cli({"conformance", "mann", "--example", "[1, 2]"});
    EXPECT_EQ(list.rc, 2);
    EXPECT_EQ(list.err, "--example:1:1: expected a mapping of parameters, got a list\n");
    const auto two = run_cli({"conformance", "mann", "picard", "--example", "{}"});
    EXPECT_EQ(two.rc, 2);
    EXPECT_EQ(two.err, "--example: name the one plugin it is an example of\n");
    // A value the plugin refuses is a finding about the example, as with the plugin's own.
    const auto bad = run_cli({"conformance", "mann", "--example", "{alpha: x}"});
    EXPECT_EQ(bad.rc, 1);
    EXPECT_EQ(bad.out.rfind("FAIL mann (", 0), 0u) << bad.out;
}
