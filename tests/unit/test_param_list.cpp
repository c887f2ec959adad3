// The parameters of a config for the preview page's panel (host/param_list.hpp): exact entries
// on a small config and on hand-written ones (unknown plugins, wrong values), and every config
// of configs/ listed with paths that --set takes and values that read back as the config's.
#include <fixpoint/host/core/config.hpp>
#include <fixpoint/host/core/host.hpp>
#include <fixpoint/host/core/param_list.hpp>

#include <cli.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

using namespace fp::host;
namespace fs = std::filesystem;

namespace {

const Registry& registry() {
    static const Host host;
    return host.registry();
}

std::vector<ParamEntry> list(const std::string& yaml) {
    return list_params(registry(), parse_yaml(yaml, "t.yaml"));
}

const ParamEntry& entry(const std::vector<ParamEntry>& all, const std::string& path) {
    const auto it = std::find_if(all.begin(), all.end(), [&](const ParamEntry& p) { return p.path == path; });
    if (it == all.end()) throw std::runtime_error("no entry " + path);
    return *it;
}

std::vector<std::string> paths(const std::vector<ParamEntry>& all) {
    std::vector<std::string> out;
    for (const auto& p : all) out.push_back(p.path);
    return out;
}

std::vector<std::string> names_of(fp::Kind k) {
    std::vector<std::string> out;
    for (const auto* e : registry().all(k)) out.emplace_back(e->desc->name);
    return out;
}

TEST(ParamList, EntriesOfASmallConfig) {
    const auto all =
        list_params(registry(), load_yaml_file(fp::test::source_dir() + "/configs/inversion/fig4a.yaml"));
    // The renderer's slot first, then its parameters in their declared order; an item of
    // `maps` is followed by its transform's parameters and then the item's own keys.
    std::vector<std::string> item0 = {"renderer.maps[0]",
                                      "renderer.maps[0].shape",
                                      "renderer.maps[0].shape.centre",
                                      "renderer.maps[0].shape.radius",
                                      "renderer.maps[0].centre",
                                      "renderer.maps[0].weight",
                                      "renderer.maps[0].colour",
                                      "renderer.maps[0].color",
                                      "renderer.maps[0].color_speed",
                                      "renderer.maps[0].chaos",
                                      "renderer.maps[0].opacity",
                                      "renderer.maps[0].colour_map"};
    const auto got = paths(all);
    ASSERT_EQ(got.size(), 1 + 12 + 1 + 8 * item0.size() + 3 + 1 + 12 + 16);
    EXPECT_EQ(
        std::vector<std::string>(got.begin(), got.begin() + 14),
        (std::vector<std::string>{"renderer", "renderer.width", "renderer.height", "renderer.view",
                                  "renderer.points", "renderer.seed", "renderer.skip", "renderer.escape",
                                  "renderer.restart_skip", "renderer.start", "renderer.start_box",
                                  "renderer.fit_view", "renderer.chains", "renderer.maps"}));
    EXPECT_EQ(std::vector<std::string>(got.begin() + 14, got.begin() + 26), item0);
    EXPECT_EQ(got[14 + 7 * 12], "renderer.maps[7]");
    EXPECT_EQ(std::vector<std::string>(got.begin() + 14 + 8 * 12, got.end()),
              (std::vector<std::string>{"renderer.final",
                                        "renderer.rotate",
                                        "renderer.y_axis",
                                        "renderer.iteration",
                                        "renderer.colourer",
                                        "renderer.colourer.gamma",
                                        "renderer.colourer.brightness",
                                        "renderer.colourer.mode",
                                        "renderer.colourer.vibrancy",
                                        "renderer.colourer.highlight_power",
                                        "renderer.colourer.gamma_threshold",
                                        "renderer.colourer.density",
                                        "renderer.colourer.contrast",
                                        "renderer.colourer.palette",
                                        "renderer.colourer.palette_stops",
                                        "renderer.colourer.palette_mode",
                                        "renderer.picture",
                                        "renderer.inversion_rules",
                                        "renderer.precision",
                                        "renderer.background",
                                        "renderer.supersample",
                                        "renderer.filter",
                                        "renderer.filter.radius",
                                        "renderer.estimator_radius",
                                        "renderer.estimator_minimum",
                                        "renderer.estimator_curve",
                                        "renderer.estimator_quality",
                                        "renderer.sets",
                                        "renderer.set_view",
                                        "renderer.set_line",
                                        "renderer.set_fill",
                                        "renderer.kernels"}));

    const ParamEntry& r = all[0];
    EXPECT_EQ(r.name, "renderer");
    EXPECT_EQ(r.owner, "");
    EXPECT_EQ(r.kind, "plugin");
    EXPECT_EQ(r.plugin_kind, "renderer");
    EXPECT_EQ(r.value, "chaos-game");
    EXPECT_TRUE(r.written);
    EXPECT_EQ(r.choices, names_of(fp::Kind::Renderer));
    EXPECT_EQ(r.depth, 0);

    const ParamEntry& width = entry(all, "renderer.width");
    EXPECT_EQ(width.name, "width");
    EXPECT_EQ(width.owner, "chaos-game");
    EXPECT_EQ(width.kind, "int");
    EXPECT_EQ(width.value, "1024");
    EXPECT_TRUE(width.written);
    EXPECT_FALSE(width.required);
    EXPECT_EQ(width.default_value, "512");
    EXPECT_EQ(width.min, 1.0);
    EXPECT_EQ(width.max, 65536.0);
    EXPECT_FALSE(width.min_open || width.max_open);
    EXPECT_EQ(width.depth, 0);

    const ParamEntry& seed = entry(all, "renderer.seed");
    EXPECT_EQ(seed.value, "1");
    EXPECT_FALSE(seed.written);
    EXPECT_EQ(seed.min, 0.0);
    EXPECT_EQ(seed.max, std::nullopt);

    const ParamEntry& view = entry(all, "renderer.view");
    EXPECT_EQ(view.kind, "reals");
    EXPECT_EQ(view.value, "[-1.75, 1.75, -1.75, 1.75]");
    EXPECT_EQ(view.default_value, "[-1.5, 1.5, -1.5, 1.5]");

    const ParamEntry& start = entry(all, "renderer.start"); // optional, no default
    EXPECT_EQ(start.kind, "point");
    EXPECT_EQ(start.value, "");
    EXPECT_FALSE(start.written);
    EXPECT_FALSE(start.required);
    EXPECT_EQ(start.default_value, "");

    const ParamEntry& maps = entry(all, "renderer.maps");
    EXPECT_EQ(maps.kind, "list");
    EXPECT_EQ(maps.plugin_kind, "transform");
    EXPECT_EQ(maps.count, 8u);
    EXPECT_TRUE(maps.required);
    EXPECT_TRUE(maps.written);
    EXPECT_EQ(maps.choices, names_of(fp::Kind::Transform));
    EXPECT_EQ(maps.depth, 0);

    const ParamEntry& m4 = entry(all, "renderer.maps[4]");
    EXPECT_EQ(m4.name, "maps[4]");
    EXPECT_EQ(m4.owner, "chaos-game");
    EXPECT_EQ(m4.kind, "plugin");
    EXPECT_EQ(m4.plugin_kind, "transform");
    EXPECT_EQ(m4.value, "inversion");
    EXPECT_TRUE(m4.written);
    EXPECT_EQ(m4.depth, 1);

    const ParamEntry& shape = entry(all, "renderer.maps[4].shape");
    EXPECT_EQ(shape.owner, "inversion");
    EXPECT_EQ(shape.kind, "plugin");
    EXPECT_EQ(shape.plugin_kind, "shape");
    EXPECT_EQ(shape.value, "circle");
    EXPECT_TRUE(shape.required);
    EXPECT_EQ(shape.choices, names_of(fp::Kind::Shape));
    EXPECT_EQ(shape.depth, 2);

    const ParamEntry& radius = entry(all, "renderer.maps[4].shape.radius");
    EXPECT_EQ(radius.owner, "circle");
    EXPECT_EQ(radius.kind, "real");
    EXPECT_EQ(radius.value, "0.21685");
    EXPECT_EQ(radius.default_value, "1");
    EXPECT_EQ(radius.min, 0.0);
    EXPECT_TRUE(radius.min_open);
    EXPECT_EQ(radius.max, std::nullopt);
    EXPECT_EQ(radius.depth, 3);

    const ParamEntry& centre = entry(all, "renderer.maps[4].shape.centre");
    EXPECT_EQ(centre.kind, "point");
    EXPECT_EQ(centre.value, "[0.30667, 0]");

    const ParamEntry& weight = entry(all, "renderer.maps[4].weight");
    EXPECT_EQ(weight.owner, "chaos-game");
    EXPECT_EQ(weight.kind, "real");
    EXPECT_EQ(weight.value, "1");
    EXPECT_FALSE(weight.written);
    EXPECT_EQ(weight.depth, 2);

    const ParamEntry& colour = entry(all, "renderer.maps[4].colour");
    EXPECT_EQ(colour.kind, "colour");
    EXPECT_EQ(colour.value, "\"#ff9f43\"");
    EXPECT_TRUE(colour.written);

    // A slot the config leaves to its default: the default's plugin, without its parameters
    // (a path under it would write keys without the `type:` that names the plugin).
    const ParamEntry& it = entry(all, "renderer.iteration");
    EXPECT_EQ(it.kind, "plugin");
    EXPECT_EQ(it.plugin_kind, "iteration-scheme");
    EXPECT_EQ(it.value, "picard");
    EXPECT_EQ(it.default_value, "{type: picard}");
    EXPECT_FALSE(it.written);
    EXPECT_EQ(it.depth, 0);

    const ParamEntry& mode = entry(all, "renderer.colourer.mode");
    EXPECT_EQ(mode.owner, "flame");
    EXPECT_EQ(mode.kind, "choice");
    EXPECT_EQ(mode.value, "set-colour");
    EXPECT_EQ(mode.default_value, "mean");
    EXPECT_EQ(mode.choices, (std::vector<std::string>{"mean", "last", "set-colour"}));
    EXPECT_EQ(mode.depth, 1);

    const ParamEntry& fill = entry(all, "renderer.set_fill");
    EXPECT_EQ(fill.min, 0.0);
    EXPECT_EQ(fill.max, 1.0);
    const ParamEntry& line = entry(all, "renderer.set_line");
    EXPECT_TRUE(line.min_open);
    EXPECT_FALSE(line.max_open);
    EXPECT_EQ(entry(all, "renderer.fit_view").kind, "bool");
}

TEST(ParamList, UnknownPluginsAndWrongValuesAreListedAsWritten) {
    const auto all = list("renderer:\n"
                          "  type: chaos-game\n"
                          "  width: wide\n"
                          "  iteration: {type: mystery, x: 1}\n"
                          "  colourer: {type: circle}\n"
                          "  maps:\n"
                          "    - {type: nope, weight: 2}\n"
                          "    - 5\n");
    EXPECT_EQ(entry(all, "renderer.width").value, "wide");
    EXPECT_TRUE(entry(all, "renderer.width").written);
    const auto got = paths(all);
    const auto at = [&](const std::string& p) { return std::find(got.begin(), got.end(), p) - got.begin(); };
    // An unknown plugin, and a plugin of another kind: the slot, and nothing under it.
    EXPECT_EQ(entry(all, "renderer.iteration").value, "mystery");
    EXPECT_EQ(got[std::size_t(at("renderer.iteration") + 1)], "renderer.colourer");
    EXPECT_EQ(entry(all, "renderer.colourer").value, "circle");
    EXPECT_EQ(got[std::size_t(at("renderer.colourer") + 1)], "renderer.picture");
    // An item of an unknown transform keeps the item's own keys; an item that is not a
    // mapping has none.
    EXPECT_EQ(
        std::vector<std::string>(got.begin() + at("renderer.maps"), got.begin() + at("renderer.iteration")),
        (std::vector<std::string>{
            "renderer.maps", "renderer.maps[0]", "renderer.maps[0].weight", "renderer.maps[0].colour",
            "renderer.maps[0].color", "renderer.maps[0].color_speed", "renderer.maps[0].chaos",
            "renderer.maps[0].opacity", "renderer.maps[0].colour_map", "renderer.maps[1]", "renderer.final",
            "renderer.rotate", "renderer.y_axis"}));
    EXPECT_EQ(entry(all, "renderer.maps[0]").value, "nope");
    EXPECT_EQ(entry(all, "renderer.maps[0].weight").value, "2");
    EXPECT_EQ(entry(all, "renderer.maps[1]").value, "5");

    EXPECT_EQ(paths(list("renderer: {type: nothing, width: 3}\n")), std::vector<std::string>{"renderer"});
    const auto none = list("output: {path: x.png}\n");
    ASSERT_EQ(none.size(), 1u);
    EXPECT_EQ(none[0].value, "");
    EXPECT_FALSE(none[0].written);
    EXPECT_EQ(paths(list("renderer: {width: 3}\n")), std::vector<std::string>{"renderer"});
}

TEST(ParamList, NestedListsAndSlots) {
    // mfs placements are renderers with their own maps; circles' metric is a slot in a slot.
    const auto all = list("renderer:\n"
                          "  type: orbit-trap\n"
                          "  mapping: {type: wallpaper, group: p1}\n"
                          "  traps: {type: circles, preset: fig-1a, metric: {type: lp, p: 3}}\n");
    const ParamEntry& p = entry(all, "renderer.traps.metric.p");
    EXPECT_EQ(p.owner, "lp");
    EXPECT_EQ(p.value, "3");
    EXPECT_EQ(p.depth, 2);
    EXPECT_EQ(entry(all, "renderer.traps.metric").depth, 1);
    EXPECT_EQ(entry(all, "renderer.mapping.group").kind, "choice");
}

// ------------------------------------------------------------------ every config
std::vector<std::string> all_configs() {
    std::vector<std::string> out;
    for (const auto& e : fs::recursive_directory_iterator(fp::test::source_dir() + "/configs"))
        if (e.path().extension() == ".yaml") out.push_back(e.path().string());
    std::sort(out.begin(), out.end());
    return out;
}

TEST(ParamList, EveryConfigListsPathsThatSetTakes) {
    std::size_t entries = 0;
    for (const auto& file : all_configs()) {
        SCOPED_TRACE(file);
        const CNode root = load_yaml_file(file);
        const auto all = list_params(registry(), root);
        ASSERT_GT(all.size(), 1u);
        entries += all.size();
        for (const ParamEntry& p : all) {
            SCOPED_TRACE(p.path);
            CNode t = root;
            const CNode* n = nullptr;
            EXPECT_NO_THROW(n = &override_target(t, p.path, p.path, Mark{}));
            if (!n || !p.written) continue;
            // A written value reads back as the node it shows; a slot shows its plugin.
            if (p.kind == "plugin") {
                ASSERT_NE(n->find("type"), nullptr);
                EXPECT_EQ(p.value, n->find("type")->scalar);
            } else {
                EXPECT_EQ(emit_yaml(parse_yaml(p.value, "value")), emit_yaml(*n));
            }
        }
    }
    EXPECT_GT(entries, 5000u);
}

} // namespace
