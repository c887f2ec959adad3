// Edits of YAML text that keep the rest of it (host/yaml_edit.hpp): exact texts on small
// configs, and on every config of configs/ the two properties the preview page relies on:
// the edited text reads as --set would make the tree, and no other line changes.
#include <fixpoint/errors.hpp>
#include <fixpoint/host/core/config.hpp>
#include <fixpoint/host/core/yaml_edit.hpp>

#include "host.hpp"
#include <cli.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <functional>

using namespace fp::host;
namespace fs = std::filesystem;

using namespace fp::test;

namespace {

std::string set(const std::string& text, const std::string& path, const std::string& value) {
    return edit_set(text, "t.yaml", path, value);
}
std::string remove(const std::string& text, const std::string& path) {
    return edit_remove(text, "t.yaml", path);
}
std::string append(const std::string& text, const std::string& path, const std::string& value) {
    return edit_append(text, "t.yaml", path, value);
}

const std::string block = "# a pipeline\n"
                          "renderer:\n"
                          "  type: chaos-game   # the game\n"
                          "  width: 1024\n"
                          "  iteration:\n"
                          "    type: mann  # the scheme\n"
                          "    alpha: 0.7\n"
                          "\n"
                          "  # the maps\n"
                          "  maps:\n"
                          "    - {type: inversion, shape: {type: circle, centre: [1, 0], radius: 0.65}}\n"
                          "    # the second\n"
                          "    - type: inversion\n"
                          "      shape: {type: circle, centre: [-1, 0], radius: 1}\n"
                          "      colour: \"#ffd93d\"\n"
                          "    - {type: inversion, shape: {type: circle, radius: 0.5}, colour: 'a, #b'}\n"
                          "# output\n"
                          "output:\n"
                          "  path: x.png\n";

TEST(YamlEdit, ScalarsInABlockMapKeepTheirComments) {
    EXPECT_EQ(set(block, "renderer.width", "800"),
              fp::test::replace_once(block, "  width: 1024\n", "  width: 800\n"));
    EXPECT_EQ(set(block, "renderer.type", "mfs"),
              fp::test::replace_once(block, "type: chaos-game   # the game", "type: mfs   # the game"));
    EXPECT_EQ(set(block, "renderer.iteration.type", " picard "),
              fp::test::replace_once(block, "type: mann  # the scheme", "type: picard  # the scheme"));
}

TEST(YamlEdit, ValuesInAFlowMap) {
    const std::string line = "    - {type: inversion, shape: {type: circle, centre: [1, 0], radius: 0.65}}\n";
    const auto with = [&](const std::string& l) { return fp::test::replace_once(block, line, l); };
    EXPECT_EQ(set(block, "renderer.maps[0].shape.radius", "0.7"),
              with("    - {type: inversion, shape: {type: circle, centre: [1, 0], radius: 0.7}}\n"));
    EXPECT_EQ(set(block, "renderer.maps[0].shape.centre", "[0.5, -0.25]"),
              with("    - {type: inversion, shape: {type: circle, centre: [0.5, -0.25], radius: 0.65}}\n"));
    EXPECT_EQ(set(block, "renderer.maps[0].shape.centre[1]", "2"),
              with("    - {type: inversion, shape: {type: circle, centre: [1, 2], radius: 0.65}}\n"));
    EXPECT_EQ(set(block, "renderer.maps[0].shape", "{type: square, side: 2}"),
              with("    - {type: inversion, shape: {type: square, side: 2}}\n"));
    EXPECT_EQ(set(block, "renderer.maps[0].shape.label", "'x, #y'"),
              with("    - {type: inversion, shape: {type: circle, centre: [1, 0], radius: 0.65, label: 'x, "
                   "#y'}}\n"));
}

TEST(YamlEdit, QuotedStringsEndAtTheirQuote) {
    const std::string t = "a: \"x # y, z\"  # note\nb: {c: 'p, #q', d: 1}\ne: 'it''s'\n";
    EXPECT_EQ(set(t, "a", "2"), "a: 2  # note\nb: {c: 'p, #q', d: 1}\ne: 'it''s'\n");
    EXPECT_EQ(set(t, "b.c", "\"r\""), "a: \"x # y, z\"  # note\nb: {c: \"r\", d: 1}\ne: 'it''s'\n");
    EXPECT_EQ(set(t, "b.d", "'#ff6b6b'"),
              "a: \"x # y, z\"  # note\nb: {c: 'p, #q', d: '#ff6b6b'}\ne: 'it''s'\n");
    EXPECT_EQ(set(t, "e", "[1, 2]"), "a: \"x # y, z\"  # note\nb: {c: 'p, #q', d: 1}\ne: [1, 2]\n");
}

TEST(YamlEdit, BlockCollectionsAreWrittenAnew) {
    // A mapping for a mapping: its keys as lines at the old keys' indentation.
    EXPECT_EQ(set(block, "renderer.iteration", "{type: s-iteration, alpha: 0.5, beta: [1, 2]}"),
              fp::test::replace_once(block, "    type: mann  # the scheme\n    alpha: 0.7\n",
                                     "    type: s-iteration\n    alpha: 0.5\n    beta: [1, 2]\n"));
    // Anything else follows the key on its line; the comment above the first item stays.
    EXPECT_EQ(set(block, "renderer.iteration", "5"),
              fp::test::replace_once(block, "  iteration:\n    type: mann  # the scheme\n    alpha: 0.7\n",
                                     "  iteration: 5\n"));
    const std::string t = "maps:  # the maps\n  # first\n  - a\n  # second\n  - b\nnext: 1\n";
    EXPECT_EQ(set(t, "maps", "{type: mann}"), "maps: {type: mann}  # the maps\n  # first\nnext: 1\n");
    EXPECT_EQ(set(t, "maps", "[c, 'd, e']"), "maps:  # the maps\n  # first\n  - c\n  - 'd, e'\nnext: 1\n");
    // A block item of a list is replaced where it starts, after its dash.
    EXPECT_EQ(
        set(block, "renderer.maps[1]", "{type: affine}"),
        fp::test::replace_once(block,
                               "    - type: inversion\n      shape: {type: circle, centre: [-1, 0], radius: "
                               "1}\n      colour: \"#ffd93d\"\n",
                               "    - type: affine\n"));
}

TEST(YamlEdit, EmptyValuesAreFilledAfterTheColon) {
    EXPECT_EQ(set("a:\nb: 1\n", "a", "2"), "a: 2\nb: 1\n");
    EXPECT_EQ(set("a:   # later\nb: 1\n", "a", "[1]"), "a: [1]   # later\nb: 1\n");
    EXPECT_EQ(set("a: ~\n", "a", "3"), "a: 3\n");
    // An unquoted colour is a comment: the value replaces it.
    EXPECT_EQ(set("colour: #ff6b6b\n", "colour", "'#00ff00'"), "colour: '#00ff00'\n");
    EXPECT_EQ(set("a:\nb: 1\n", "a.c.d", "2"), "a: {c: {d: 2}}\nb: 1\n");
}

TEST(YamlEdit, MissingKeysAreAddedInTheMappingsStyle) {
    EXPECT_EQ(set(block, "renderer.iteration.beta", "0.3"),
              fp::test::replace_once(block, "    alpha: 0.7\n", "    alpha: 0.7\n    beta: 0.3\n"));
    EXPECT_EQ(set(block, "renderer.seed", "7"),
              fp::test::replace_once(block, "colour: 'a, #b'}\n", "colour: 'a, #b'}\n  seed: 7\n"));
    EXPECT_EQ(set(block, "renderer.maps[1].weight", "2"),
              fp::test::replace_once(block, "      colour: \"#ffd93d\"\n",
                                     "      colour: \"#ffd93d\"\n      weight: 2\n"));
    EXPECT_EQ(set(block, "renderer.maps[1].shape.label", "b"),
              fp::test::replace_once(block, "centre: [-1, 0], radius: 1}",
                                     "centre: [-1, 0], radius: 1, label: b}"));
    EXPECT_EQ(set(block, "animation.frames", "24"), block + "animation: {frames: 24}\n");
    EXPECT_EQ(set(block, "output.size.width", "24"),
              fp::test::replace_once(block, "  path: x.png\n", "  path: x.png\n  size: {width: 24}\n"));
    EXPECT_EQ(set("a: {}\n", "a.b", "1"), "a: {b: 1}\n");
    EXPECT_EQ(set("a: { b: 1 , }\n", "a.c", "2"), "a: { b: 1 , c: 2 }\n");
    EXPECT_EQ(set("# nothing yet", "renderer.type", "mfs"), "# nothing yet\nrenderer: {type: mfs}\n");
    EXPECT_EQ(set("", "a", "1"), "a: 1\n");
    EXPECT_EQ(set("a: 1\r\nb:\r\n  c: 2\r\n", "b.d", "3"), "a: 1\r\nb:\r\n  c: 2\r\n  d: 3\r\n");
}

TEST(YamlEdit, ItemsAreRemovedWithTheirLines) {
    EXPECT_EQ(
        remove(block, "renderer.maps[0]"),
        fp::test::replace_once(
            block, "    - {type: inversion, shape: {type: circle, centre: [1, 0], radius: 0.65}}\n", ""));
    EXPECT_EQ(
        remove(block, "renderer.maps[1]"),
        fp::test::replace_once(block,
                               "    - type: inversion\n      shape: {type: circle, centre: [-1, 0], radius: "
                               "1}\n      colour: \"#ffd93d\"\n",
                               ""));
    EXPECT_EQ(
        remove(block, "renderer.maps[2]"),
        fp::test::replace_once(
            block, "    - {type: inversion, shape: {type: circle, radius: 0.5}, colour: 'a, #b'}\n", ""));
    EXPECT_EQ(remove("maps:\n  - a  # the one\nnext: 1\n", "maps[0]"), "maps: []\nnext: 1\n");
    EXPECT_EQ(remove("maps: [a, 'b, c', {d: 1}]\n", "maps[0]"), "maps: ['b, c', {d: 1}]\n");
    EXPECT_EQ(remove("maps: [a, 'b, c', {d: 1}]\n", "maps[1]"), "maps: [a, {d: 1}]\n");
    EXPECT_EQ(remove("maps: [a, 'b, c', {d: 1}]\n", "maps[2]"), "maps: [a, 'b, c']\n");
    EXPECT_EQ(remove("maps: [a]\n", "maps[0]"), "maps: []\n");
    EXPECT_EQ(remove("m: {v: [1, 2, 3]}\n", "m.v[1]"), "m: {v: [1, 3]}\n");
}

TEST(YamlEdit, ItemsAreAppendedInTheListsStyle) {
    EXPECT_EQ(append(block, "renderer.maps", "{type: inversion, shape: {type: circle}}"),
              fp::test::replace_once(block, "colour: 'a, #b'}\n",
                                     "colour: 'a, #b'}\n    - {type: inversion, shape: {type: circle}}\n"));
    EXPECT_EQ(append("maps:\n- a: 1\n  b: 2\n# end\n", "maps", "{a: 3, b: [4, 5]}"),
              "maps:\n- a: 1\n  b: 2\n- a: 3\n  b: [4, 5]\n# end\n");
    EXPECT_EQ(append("maps:\n  -   a: 1\n", "maps", "{a: 3, b: 4}"),
              "maps:\n  -   a: 1\n  -   a: 3\n      b: 4\n");
    EXPECT_EQ(append("view: [1, 2]  # x\n", "view", "3"), "view: [1, 2, 3]  # x\n");
    EXPECT_EQ(append("view: []\n", "view", "'#a, b'"), "view: ['#a, b']\n");
    EXPECT_EQ(append("view: [\n  1,\n]\n", "view", "2"), "view: [\n  1, 2\n]\n");
    EXPECT_EQ(append("view:\nx: 1\n", "view", "{a: 1}"), "view: [{a: 1}]\nx: 1\n");
    EXPECT_EQ(append("x: 1\n", "view", "2"), "x: 1\nview: [2]\n");
}

TEST(YamlEdit, PathsThatDoNotFitAreRefused) {
    EXPECT_EQ(error_of([] { set(block, "renderer.maps[3].weight", "1"); }),
              "renderer.maps[3].weight: index 3 out of range ('renderer.maps' has 3 items)");
    EXPECT_EQ(error_of([] { set(block, "renderer.width.x", "1"); }),
              "renderer.width.x: 'renderer.width' is not a mapping");
    EXPECT_EQ(error_of([] { set(block, "renderer.width[0]", "1"); }),
              "renderer.width[0]: 'renderer.width' is not a list");
    EXPECT_EQ(error_of([] { set(block, "renderer.nothing[0]", "1"); }),
              "renderer.nothing[0]: 'renderer.nothing' does not exist");
    EXPECT_EQ(error_of([] { set(block, "renderer..x", "1"); }), "renderer..x: empty name in path");
    EXPECT_EQ(error_of([] { set(block, "", "1"); }), "empty path (expected one like renderer.width)");
    EXPECT_EQ(error_of([] { remove(block, "renderer.width"); }),
              "renderer.width: not an item of a list (remove takes a path like renderer.maps[2])");
    EXPECT_EQ(error_of([] { remove(block, "renderer.maps[5]"); }),
              "renderer.maps[5]: index 5 out of range ('renderer.maps' has 3 items)");
    EXPECT_EQ(error_of([] { append(block, "renderer.width", "1"); }),
              "renderer.width: 'renderer.width' is not a list");
}

TEST(YamlEdit, ValuesAndTextsThatDoNotParseAreRefused) {
    EXPECT_EQ(error_of([] { set(block, "renderer.width", "[1, 2]]"); }),
              "renderer.width: value:1:7: YAML syntax error: illegal flow end");
    EXPECT_EQ(error_of([] { set(block, "renderer.width", "'abc"); }),
              "renderer.width: value:1:5: YAML syntax error: illegal EOF in scalar");
    EXPECT_EQ(error_of([] { set(block, "renderer.width", "1\n2"); }),
              "renderer.width: the value must be one line of YAML, got '1\\n2'");
    EXPECT_EQ(error_of([] { append(block, "renderer.maps", "{a: 1, a: 2}"); }),
              "renderer.maps: value:1:8: duplicate key 'a'");
    EXPECT_EQ(error_of([] { set("a: [1, 2\n", "a", "1"); }),
              "t.yaml:2:1: YAML syntax error: end of sequence flow not found");
    // A value that would read differently where it lands is refused, not written.
    EXPECT_EQ(error_of([] { set(block, "renderer.maps[0].shape.radius", "1, 2"); }),
              "renderer.maps[0].shape.radius: cannot write '1, 2' in place: the text would read differently "
              "(quote the value?)");
    EXPECT_EQ(error_of([] { remove("a:\n- - 1\n  - 2\n", "a[0][0]"); }),
              "a[0][0]: cannot remove the item in place: the text would read differently");
    EXPECT_EQ(error_of([] { set("a: b\n  c\n", "a", "1"); }),
              "a: cannot write '1' in place: the text would read differently (quote the value?)");
}

// ------------------------------------------------------------------ every config
std::vector<std::string> all_configs() {
    std::vector<std::string> out;
    for (const auto& e : fs::recursive_directory_iterator(fp::test::source_dir() + "/configs"))
        if (e.path().extension() == ".yaml") out.push_back(e.path().string());
    std::sort(out.begin(), out.end());
    return out;
}

std::vector<std::string> lines_of(const std::string& t) {
    std::vector<std::string> out;
    std::size_t a = 0;
    for (std::size_t b; (b = t.find('\n', a)) != std::string::npos; a = b + 1)
        out.push_back(t.substr(a, b - a));
    if (a < t.size()) out.push_back(t.substr(a));
    return out;
}

// The lines of `before` that `after` does not keep, as [first, last] (0-based, last < first
// when none): what is left between the longest common head and tail.
std::pair<int, int> changed_lines(const std::string& before, const std::string& after) {
    const auto a = lines_of(before), b = lines_of(after);
    std::size_t head = 0;
    while (head < a.size() && head < b.size() && a[head] == b[head]) ++head;
    std::size_t tail = 0;
    while (tail < a.size() - head && tail < b.size() - head &&
           a[a.size() - 1 - tail] == b[b.size() - 1 - tail])
        ++tail;
    return {int(head), int(a.size() - tail) - 1};
}

// The last line any node under `n` starts on (0-based).
int last_line(const CNode& n) {
    int l = n.mark.line - 1;
    for (const auto& it : n.items) l = std::max(l, last_line(it));
    for (const auto& kv : n.keys) l = std::max(l, last_line(kv.second));
    return l;
}

struct Param {
    std::string path;
    const CNode* node;
    int key_line; // 0-based
};

// Every value of a mapping under `n` that is a scalar or a list, with its path (keys that
// are not names, like animation's "renderer.maps[0].centre", are skipped: no path reaches them).
void params_of(const CNode& n, const std::string& path, std::vector<Param>& out) {
    for (std::size_t i = 0; i < n.keys.size(); ++i) {
        const auto& [k, v] = n.keys[i];
        if (k.find_first_of(".[]") != std::string::npos) continue;
        const std::string p = path.empty() ? k : path + "." + k;
        if (v.is_scalar() || v.is_seq()) out.push_back({p, &v, n.key_marks[i].line - 1});
        params_of(v, p, out);
    }
    // The first two items of a list and its last: the items between are alike (the time the
    // test takes grows with every edit it makes).
    for (std::size_t i = 0; i < n.items.size(); ++i)
        if (i < 2 || i + 1 == n.items.size())
            params_of(n.items[i], path + "[" + std::to_string(i) + "]", out);
}

std::string emitted_with(const CNode& root, const std::string& assignment) {
    CNode t = root;
    apply_override(t, assignment);
    return emit_yaml(t);
}

TEST(YamlEdit, EveryParameterOfEveryConfig) {
    int edits = 0;
    for (const auto& file : all_configs()) {
        const std::string text = fp::test::read_file(file);
        const CNode root = parse_yaml(text, file);
        std::vector<Param> params;
        params_of(root, "", params);
        ASSERT_FALSE(params.empty()) << file;
        for (const Param& p : params) {
            const bool flow_list = p.node->is_seq() && p.node->mark.line == p.key_line + 1;
            // A number, a quoted string with a comment's and a flow list's characters in it, and
            // a list, in turn.
            const std::string value = std::vector<std::string>{"0.25", "'a, #b'", "[0.5, 'c, d']"}[edits % 3];
            {
                SCOPED_TRACE(file + ": " + p.path + "=" + value);
                const std::string out = edit_set(text, file, p.path, value);
                ++edits;
                EXPECT_EQ(emit_yaml(parse_yaml(out, file)), emitted_with(root, p.path + "=" + value));
                // Only the parameter's own lines change: its key's line to its last line.
                const auto [first, last] = changed_lines(text, out);
                EXPECT_GE(first, p.key_line);
                EXPECT_LE(last, last_line(*p.node));
                if (p.node->is_scalar() || flow_list) {
                    // One line, where the old value's text is replaced by the new one.
                    ASSERT_EQ(first, last);
                    const std::string a = lines_of(text)[std::size_t(first)],
                                      b = lines_of(out)[std::size_t(first)];
                    const std::size_t col = std::size_t(p.node->mark.col - 1),
                                      old = a.size() + value.size() - b.size();
                    EXPECT_EQ(b, a.substr(0, col) + value + a.substr(col + old));
                    // The text replaced is the old value, whole.
                    EXPECT_EQ(emit_yaml(parse_yaml(a.substr(col, old), "old")), emit_yaml(*p.node));
                }
            }
        }
    }
    EXPECT_GT(edits, 2000); // 2670 when written
}

TEST(YamlEdit, EveryListOfEveryConfig) {
    for (const auto& file : all_configs()) {
        const std::string text = fp::test::read_file(file);
        const CNode root = parse_yaml(text, file);
        std::vector<Param> params;
        params_of(root, "", params);
        for (const Param& p : params) {
            if (!p.node->is_seq() || p.node->items.empty()) continue;
            SCOPED_TRACE(file + ": " + p.path);
            const auto& items = p.node->items;
            for (std::size_t i : {std::size_t(0), items.size() / 2, items.size() - 1}) {
                const std::string out = edit_remove(text, file, p.path + "[" + std::to_string(i) + "]");
                CNode want = root;
                CNode& list = override_target(want, p.path, p.path, Mark{});
                list.items.erase(list.items.begin() + long(i));
                EXPECT_EQ(emit_yaml(parse_yaml(out, file)), emit_yaml(want));
                const auto [first, last] = changed_lines(text, out);
                EXPECT_GE(first, items.size() == 1 ? p.key_line : items[i].mark.line - 1);
                EXPECT_LE(last, last_line(items.size() == 1 ? *p.node : items[i]));
            }
            const std::string value = "{type: circle, radius: 0.5}";
            const std::string out = edit_append(text, file, p.path, value);
            CNode want = root;
            override_target(want, p.path, p.path, Mark{}).items.push_back(parse_yaml(value, "value"));
            EXPECT_EQ(emit_yaml(parse_yaml(out, file)), emit_yaml(want));
            // A block list gains lines and loses none; a flow list changes on its last line.
            const auto [first, last] = changed_lines(text, out);
            if (p.node->mark.line == p.key_line + 1) {
                EXPECT_EQ(first, last);
                EXPECT_EQ(first, last_line(*p.node));
            } else {
                EXPECT_EQ(first, last_line(*p.node) + 1);
                EXPECT_EQ(last, first - 1);
            }
        }
    }
}

} // namespace
