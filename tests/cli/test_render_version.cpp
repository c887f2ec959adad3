// The render version (host/core/render_version.hpp): recorded in recipes and checkpoints, an
// older recipe rendered silently where no change since touches it, else with one warning line
// naming the changes, and refused with --strict.
#include <fixpoint/host/core/config.hpp>
#include <fixpoint/host/core/pipeline.hpp>
#include <fixpoint/host/core/render_version.hpp>
#include <fixpoint/host/job/render_job.hpp>
#include <fixpoint/version.hpp>

#include "cli.hpp"
#include "configs.hpp"
#include "host.hpp"

#include <gtest/gtest.h>

using namespace fp::host;
using namespace fp::test;

namespace {

const std::string& circles = small_circles;

// One Gumowski-Mira map: a chaos game without paper 01's rules.
const std::string gm = R"(renderer:
  type: chaos-game
  width: 24
  height: 16
  points: 4000
  chains: 8
  view: [-20, 20, -20, 20]
  maps:
    - {type: gumowski-mira, alpha: 0.008, mu: -0.496}
)";

Pipeline pipeline(const std::string& text) {
    return load_pipeline(fp::test::host().registry(), parse_config(text, "recipe.yaml"));
}

} // namespace

// The changelog as built in: version 1 first, consecutive, each later one naming what changed.
TEST(RenderVersion, TheChangelogIsWellFormed) {
    const auto& log = render_changes();
    ASSERT_FALSE(log.empty());
    EXPECT_EQ(log.front().version, 1);
    EXPECT_GE(render_version(), 2);
    int last = 0;
    for (const auto& c : log) {
        EXPECT_TRUE(c.version == last || c.version == last + 1) << c.version;
        EXPECT_FALSE(c.what.empty());
        EXPECT_EQ(c.date.size(), 10u) << c.date; // 2026-12-01
        last = c.version;
    }
    EXPECT_EQ(last, render_version());
    EXPECT_EQ(render_version_tag(),
              std::string(FIXPOINT_VERSION) + " (render version " + std::to_string(render_version()) + ")");
}

// Version 2's change (the rules' draw) touches renders of chaos-game with inversions only.
// (Recipes that name no parameter: version 3's change touches only those with sets.)
TEST(RenderVersion, ChangesTouchTheRendersOfTheirPlugins) {
    const RecipeParams bare = [](const std::string&) { return std::optional<std::string>(); };
    EXPECT_EQ(changes_since(1, {"chaos-game", "circle", "inversion", "picard"}, bare).size(), 1u);
    EXPECT_TRUE(changes_since(1, {"chaos-game", "gumowski-mira"}, bare).empty());
    EXPECT_TRUE(changes_since(1, {"orbit-trap", "wallpaper"}, bare).empty());
    EXPECT_TRUE(changes_since(render_version(), {"chaos-game", "inversion"}).empty());
    const std::string d = render_version_difference(1, {"chaos-game", "inversion"}, bare);
    EXPECT_EQ(d.rfind("the recipe is of render version 1, this fixpoint renders version " +
                          std::to_string(render_version()) + ": chaos-game draws the maps",
                      0),
              0u)
        << d;
    EXPECT_NE(d.find("; the image may differ (docs/render-versions.md)"), std::string::npos) << d;
    EXPECT_EQ(render_version_difference(1, {"mfs", "subdivision"}, bare), "");
    EXPECT_NE(render_version_difference(render_version() + 1, {}).find("newer than this fixpoint's"),
              std::string::npos);
}

// Version 3's change (the sets' panel fitted by default) names parameters: it touches the
// chaos games with sets beside or only that leave set_view out, read from the recipe itself.
TEST(RenderVersion, AChangeOfADefaultTouchesTheRecipesThatLeaveItOut) {
    const auto v3 = [](const std::string& yaml) {
        const CNode root = parse_config(yaml, "r.yaml");
        const auto cs = changes_since(2, {"chaos-game", "inversion", "circle"}, params_of(root));
        return std::count_if(cs.begin(), cs.end(), [](const RenderChange& c) { return c.version == 3; });
    };
    const std::string head = "renderer:\n  type: chaos-game\n";
    EXPECT_EQ(v3(head + "  sets: beside\n"), 1);
    EXPECT_EQ(v3(head + "  sets: \"only\"\n"), 1);
    EXPECT_EQ(v3(head + "  sets: beside\n  set_view: [-2, 2, -2, 2]\n"), 0);
    EXPECT_EQ(v3(head + "  sets: over\n"), 0);
    EXPECT_EQ(v3(head), 0);
    EXPECT_EQ(v3(head + "  fit_view: true\n"), 1);
    EXPECT_EQ(v3(head + "  fit_view: false\n"), 0);
    EXPECT_EQ(v3(head + "  sets: only\n  fit_view: true\n"), 2);
    EXPECT_EQ(v3("renderer: {type: chaos-game, sets: only, set_view: ~}\n"), 1);
    // Without a recipe to read, every render of its plugins (what may differ is said).
    EXPECT_EQ(changes_since(2, {"chaos-game"}).size(), 2u); // the sets' panel, fit_view
    // End to end: a recipe of version 2 with sets beside is told, the same without sets is not.
    const std::string old = "render_version: 2\n" + circles;
    EXPECT_TRUE(pipeline(old).warnings.empty());
    std::string with_sets = old;
    with_sets.replace(with_sets.find("  maps:"), 0, "  sets: beside\n");
    const Pipeline told = pipeline(with_sets);
    ASSERT_EQ(told.may_differ.size(), 1u);
    EXPECT_NE(told.may_differ[0].find("the sets' panel of `sets` beside or only shows the sets whole"),
              std::string::npos)
        << told.may_differ[0];
}

// Recipes record the version; a config written by hand is of this version; a recipe without
// it is of version 1.
TEST(RenderVersion, RecipesRecordItAndOlderOnesAreTold) {
    const Pipeline now = pipeline(circles);
    EXPECT_NE(now.recipe.find("\nrender_version: " + std::to_string(render_version()) + "\n"),
              std::string::npos)
        << now.recipe;
    EXPECT_TRUE(now.warnings.empty());
    EXPECT_TRUE(now.may_differ.empty());
    EXPECT_NE(checkpoint_header(now).version.find("(render version "), std::string::npos);

    const Pipeline old = pipeline("fixpoint_version: \"0.1.0\"\n" + circles);
    ASSERT_EQ(old.may_differ.size(), 1u);
    EXPECT_EQ(old.warnings, old.may_differ);
    EXPECT_EQ(old.may_differ[0].rfind("the recipe is of render version 1", 0), 0u) << old.may_differ[0];
    // The same recipe of version 1 without inversions: nothing changed for it, nothing said.
    EXPECT_TRUE(pipeline("fixpoint_version: \"0.1.0\"\n" + gm).warnings.empty());
    EXPECT_TRUE(pipeline("render_version: 1\n" + gm).warnings.empty());
    // This version, said: nothing to say.
    EXPECT_TRUE(
        pipeline("render_version: " + std::to_string(render_version()) + "\n" + circles).warnings.empty());
    // A newer one is told.
    const Pipeline newer =
        pipeline("render_version: " + std::to_string(render_version() + 1) + "\n" + circles);
    ASSERT_EQ(newer.may_differ.size(), 1u);
    EXPECT_NE(newer.may_differ[0].find("newer than this fixpoint's"), std::string::npos);
    // Not a whole number from 1: refused where it stands.
    for (const char* bad : {"0", "two", "2.5", "[2]", "-1"})
        EXPECT_EQ(error_of([&] {
                      pipeline(std::string("render_version: ") + bad + "\n" + circles);
                  }).rfind("recipe.yaml:1:17: render_version: expected a whole number from 1", 0),
                  0u)
            << bad;
}

// --strict (RenderRequest::strict): what may differ is refused at render_version:, before any
// work; without it the render goes on.
TEST(RenderVersion, StrictRefusesWhatMayDiffer) {
    RenderRequest r;
    r.keep_image = true;
    r.strict = true;
    EXPECT_NO_THROW(plan_render(pipeline(circles), r));
    EXPECT_NO_THROW(plan_render(pipeline("fixpoint_version: \"0.1.0\"\n" + gm), r));
    const std::string e = error_of([&] { plan_render(pipeline("render_version: 1\n" + circles), r); });
    EXPECT_EQ(e.rfind("recipe.yaml:1:17: the recipe is of render version 1", 0), 0u) << e;
    EXPECT_NE(e.find("; refused (--strict)"), std::string::npos) << e;
    r.strict = false;
    EXPECT_NO_THROW(plan_render(pipeline("render_version: 1\n" + circles), r));
}

// The CLI: one warning line, or with --strict one error line, exit 2 and no file.
TEST(RenderVersion, TheCliWarnsOrRefuses) {
    const auto dir = scratch_dir("render_version");
    write_file(dir + "/old.yaml", "fixpoint_version: \"0.1.0\"\n" + circles);
    auto r = run_cli({"render", "--quiet", dir + "/old.yaml", "-o", dir + "/old.png"});
    EXPECT_EQ(r.rc, 0) << r.err;
    EXPECT_EQ(r.err.rfind("warning: the recipe is of render version 1, this fixpoint renders version", 0), 0u)
        << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    r = run_cli({"render", "--quiet", "--strict", dir + "/old.yaml", "-o", dir + "/strict.png"});
    EXPECT_EQ(r.rc, 2);
    EXPECT_EQ(r.err.rfind(dir + "/old.yaml:1:1: the recipe is of render version 1", 0), 0u) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir + "/strict.png"));
    // The image's recipe records this version: rendered again with --strict, the same bytes.
    r = run_cli({"render", "--quiet", "--strict", dir + "/old.png", "-o", dir + "/again.png"});
    EXPECT_EQ(r.rc, 0) << r.err;
    EXPECT_EQ(r.err, "");
    EXPECT_TRUE(read_file(dir + "/old.png") == read_file(dir + "/again.png"));
}
