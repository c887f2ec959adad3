// fixpoint describe --markdown: a descriptor becomes a Markdown section that says what the
// declaration says, and stays one table row per parameter whatever the doc text holds.
#include <fixpoint/host/tools/describe.hpp>
#include <fixpoint/plugin.hpp>

#include <gtest/gtest.h>

#include <string>

namespace {

constexpr fp::ParamSpec item_params[] = {
    fp::param::real("weight", "relative probability").def("1").above(0),
};
constexpr fp::ParamSpec params[] = {
    fp::param::real("radius", "radius | of the disc").def("1").above(0).max(10),
    fp::param::string("mode", "how to draw").def("a").one_of("a|b|c"),
    fp::param::reals("view", "the region").len(4).opt(),
    fp::param::objects("maps", fp::Kind::Transform, "the maps").min_len(1).items(item_params),
    fp::param::integer("count", "how many"),
};

struct Dummy final : fp::Object {
    explicit Dummy(const fp::ParamBag&) {}
};

const fp::PluginDescriptor desc = fp::describe<Dummy>(fp::Kind::Shape, "dummy", "a test plugin", params)
                                      .with_version("2.1.0")
                                      .with_example("{count: 3}")
                                      .with_runs_code();

TEST(DescribeMarkdown, APluginSectionSaysWhatItsDeclarationSays) {
    fp::host::PluginEntry e;
    e.desc = &desc;
    e.file = "/somewhere/dummy.so";
    const std::string md = fp::host::markdown_plugin(e, 3);
    EXPECT_EQ(md.rfind("### `dummy`\n\nshape, version 2.1.0: a test plugin\n", 0), 0u) << md;
    EXPECT_NE(md.find("**Runs the code its parameters carry**"), std::string::npos) << md;
    EXPECT_NE(md.find("Example: `{count: 3}`"), std::string::npos) << md;
    // A '|' in a doc line is escaped, so the row keeps its five cells; the range is the
    // declared one, open and closed ends as `describe` prints them.
    EXPECT_NE(md.find("| `radius` | real | `1` | (0, 10] | radius \\| of the disc |\n"), std::string::npos)
        << md;
    EXPECT_NE(md.find("| `mode` | string | `a` | one of `a`, `b`, `c` | how to draw |\n"), std::string::npos)
        << md;
    EXPECT_NE(md.find("| `view` | list of reals, exactly 4 | optional |  | the region |\n"),
              std::string::npos)
        << md;
    EXPECT_NE(md.find("| `maps` | list of objects (transform), at least 1 | **required** |  | the maps |\n"),
              std::string::npos)
        << md;
    EXPECT_NE(md.find("| `count` | int | **required** |  | how many |\n"), std::string::npos) << md;
    // The extra keys of a list's items, in a table of their own after the parameters'.
    const auto items = md.find("Each item of `maps` also takes:\n\n| parameter |");
    ASSERT_NE(items, std::string::npos) << md;
    EXPECT_GT(items, md.find("| `count` |"));
    EXPECT_NE(md.find("| `weight` | real | `1` | (0, inf) | relative probability |\n", items),
              std::string::npos)
        << md;
    // Nothing that depends on where the file lies.
    EXPECT_EQ(md.find("somewhere"), std::string::npos) << md;
}

TEST(DescribeMarkdown, TheHeadingLevelIsTheCallersWithinMarkdownsSix) {
    fp::host::PluginEntry e;
    e.desc = &desc;
    EXPECT_EQ(fp::host::markdown_plugin(e, 1).rfind("# `dummy`\n", 0), 0u);
    EXPECT_EQ(fp::host::markdown_plugin(e, 9).rfind("###### `dummy`\n", 0), 0u);
}

} // namespace
