// The command line's words where users stumble (issue 47): validate notes an existing output
// rather than failing, typos of a command or an option get "did you mean", the global options
// may follow the command, and a sequence's declared range is enforced. Each message word for
// word: a change to one is a change users see.
#include "cli.hpp"
#include "configs.hpp"

#include <gtest/gtest.h>

#include <filesystem>

using namespace fp::test;

namespace {

namespace fs = std::filesystem;

const std::string base =
    chaos_game({"width: 64", "height: 64", "points: 20000", "chains: 64"}, three_circles("0.9"));

// The base config in a fresh folder as my.yaml; returns the folder.
std::string folder_with_config(const std::string& name, const std::string& yaml = base) {
    const std::string dir = scratch_dir(name);
    write_file(dir + "/my.yaml", yaml);
    return dir;
}

// The CLI run in `dir`, as a user in that folder (the default output is my.png there).
CliResult run_in(const std::string& dir, const std::vector<std::string>& args) {
    const auto cwd = fs::current_path();
    fs::current_path(dir);
    auto r = run_cli(args);
    fs::current_path(cwd);
    return r;
}

TEST(CliWords, ValidateNotesAnExistingOutputAndSucceeds) {
    const std::string dir = folder_with_config("words_validate");
    const std::string cfg = "my.yaml", png = "my.png";
    const auto fresh = run_in(dir, {"validate", cfg});
    ASSERT_EQ(fresh.rc, 0) << fresh.err;
    EXPECT_EQ(fresh.err, cfg + ": valid: a 64x64 render to " + png + "\n");
    // After a render, its image is there: still valid, with a note of what render would do.
    write_file(dir + "/" + png, "an earlier render");
    const auto again = run_in(dir, {"validate", cfg});
    ASSERT_EQ(again.rc, 0) << again.err;
    EXPECT_EQ(again.err, cfg + ": valid: a 64x64 render to " + png + "\n" + cfg + ": note: '" + png +
                             "' exists: render replaces it only when it is named with -o or given --force\n");
    EXPECT_EQ(read_file(dir + "/" + png), "an earlier render");
    // Named with -o, or with --force, render would replace it: no note. -q says nothing.
    for (const auto& extra : std::vector<std::vector<std::string>>{{"-o", png}, {"--force"}}) {
        const auto r = run_in(dir, with({"validate", cfg}, extra));
        ASSERT_EQ(r.rc, 0) << r.err;
        EXPECT_EQ(r.err, cfg + ": valid: a 64x64 render to " + png + "\n");
    }
    const auto quiet = run_in(dir, {"validate", "-q", cfg});
    EXPECT_EQ(quiet.rc, 0);
    EXPECT_EQ(quiet.err, "");
    // And the render itself still refuses it.
    const auto render = run_in(dir, {"render", "-q", cfg});
    EXPECT_EQ(render.rc, 2);
    EXPECT_EQ(render.err, "'" + png + "' exists: name it with -o to replace it, or add --force\n");
}

TEST(CliWords, TyposGetDidYouMean) {
    const std::string dir = folder_with_config("words_typos");
    const std::string cfg = dir + "/my.yaml";
    const std::string commands =
        "; the commands are render, tone, merge, validate, animate, watch, serve, explore, eval, "
        "to-subdivision, import, export, recipe, addresses, symmetry, plugins, describe, conformance\n";
    auto refused = [](const std::vector<std::string>& args) {
        const auto r = run_cli(args);
        EXPECT_EQ(r.rc, 2) << r.err;
        return r.err;
    };
    EXPECT_EQ(refused({"rendr", cfg}),
              "fixpoint: 'rendr' is not a command (did you mean 'render'?)" + commands);
    EXPECT_EQ(refused({"--plugin-dir", dir, "valdate", cfg}),
              "fixpoint: 'valdate' is not a command (did you mean 'validate'?)" + commands);
    EXPECT_EQ(refused({"frobnicate"}), "fixpoint: 'frobnicate' is not a command" + commands);
    EXPECT_EQ(refused({"render", "--thread", "2", cfg}),
              "fixpoint render: unknown option '--thread' (did you mean '--threads'?) (see fixpoint render "
              "--help)\n");
    EXPECT_EQ(refused({"render", cfg, "--ouput=x.png"}),
              "fixpoint render: unknown option '--ouput' (did you mean '--output'?) (see fixpoint render "
              "--help)\n");
    EXPECT_EQ(refused({"validate", cfg, "--zzzzzz"}),
              "fixpoint validate: unknown option '--zzzzzz' (see fixpoint validate --help)\n");
    // Other mistakes keep CLI11's words.
    EXPECT_EQ(refused({"render"}), "fixpoint: config is required (see fixpoint --help)\n");
    EXPECT_FALSE(fs::exists(dir + "/my.png"));
}

// A sequence parameter's declared range, on a scheme that declares one (the fixture
// ranged-mann: alpha in (0, 1)), loaded with --plugin-dir after the command.
TEST(CliWords, SequenceRangesAreEnforced) {
    const std::string plugins = fixtures_dir() + "/ranged";
    const auto with_alpha = [](const std::string& alpha, const std::string& numbers = "") {
        return replace_once(base, "  chains: 64\n",
                            "  chains: 64\n  iteration: {type: ranged-mann, alpha: " + alpha + numbers +
                                "}\n");
    };
    const std::vector<std::string> args = {"render", "--quiet", "bad.yaml", "--plugin-dir",
                                           plugins,  "-o",      "out.png"};
    const std::string at = "bad.yaml:7:";
    const std::string q = ", numbers: {type: q-system, A: -1.5, B: 0.2}";
    EXPECT_EQ(run_bad_input("range_above", with_alpha("1.5"), args),
              at + "41: renderer.iteration.alpha: must be in (0, 1), got 1.5");
    EXPECT_EQ(run_bad_input("range_bound", with_alpha("0"), args),
              at + "41: renderer.iteration.alpha: must be in (0, 1), got 0");
    EXPECT_EQ(run_bad_input("range_list", with_alpha("[0.2, 0.5, 1]"), args),
              at + "52: renderer.iteration.alpha[2]: must be in (0, 1), got 1");
    EXPECT_EQ(run_bad_input("range_pair", with_alpha("[0.2, -0.5]"), args),
              at + "47: renderer.iteration.alpha[1]: must be in (0, 1), got -0.5");
    EXPECT_EQ(run_bad_input("range_q", with_alpha("0.5+0.1q", q), args),
              at + "41: renderer.iteration.alpha: must be a real number in (0, 1) (a coefficient with a "
                   "declared range is real in every number system), got 0.5+0.1q");
    // A bare pair is one q-number in a q-system: refused by the scheme, with the way out.
    EXPECT_EQ(run_bad_input("range_bare_pair_q", with_alpha("[0.2, 0.5]", q), args),
              at + "41: renderer.iteration.alpha: [0.2, 0.5] is the number 0.2+0.5q here, and a coefficient "
                   "with a declared range is real (write the periodic list with its period twice: [x, y, x, "
                   "y])");
    // In range, it renders (over the reals and in a q-system alike).
    const std::string dir = scratch_dir("range_fine");
    write_file(dir + "/a.yaml", with_alpha("[0.2, 0.7]"));
    write_file(dir + "/b.yaml", with_alpha("[0.2, 0.7, 0.2, 0.7]", q));
    for (const char* name : {"a", "b"}) {
        const auto r = run_cli({"render", "--quiet", dir + "/" + name + ".yaml", "--plugin-dir", plugins,
                                "-o", dir + "/" + name + ".png"});
        EXPECT_EQ(r.rc, 0) << r.err;
    }
    // describe shows the range it enforces.
    const auto d = run_cli({"describe", "ranged-mann", "--plugin-dir", plugins});
    EXPECT_EQ(d.rc, 0) << d.err;
    EXPECT_NE(d.out.find("(0, 1)"), std::string::npos) << d.out;
}

} // namespace
