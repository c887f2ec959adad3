// The host's YAML stages, tested below the CLI.
#include <fixpoint/host/core/build.hpp>
#include <fixpoint/host/core/config.hpp>
#include <fixpoint/host/core/host.hpp>

#include "cli.hpp"
#include "host.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace fp::host;

using namespace fp::test;

namespace {

TEST(Config, NodesRememberPositions) {
    const CNode n = parse_yaml("a: 1\nb:\n  - [2, 3]\n  - {c: 'x'}\n", "t.yaml");
    ASSERT_TRUE(n.is_map());
    EXPECT_EQ(n.find("a")->mark.str(), "t.yaml:1:4");
    EXPECT_EQ(n.key_mark("b")->str(), "t.yaml:2:1");
    const CNode& b = *n.find("b");
    EXPECT_EQ(b.items[0].items[1].mark.str(), "t.yaml:3:9");
    EXPECT_TRUE(b.items[1].find("c")->quoted);
    EXPECT_FALSE(b.items[0].items[0].quoted);
}

TEST(Config, GuardRefusesWhatYamlCppMishandles) {
    EXPECT_EQ(error_of([] { parse_yaml("a: 1\na: 2\n", "t"); }), "t:2:1: duplicate key 'a'");
    EXPECT_EQ(error_of([] { parse_yaml("{a: {b: 1, b: 2}}", "t"); }), "t:1:12: duplicate key 'b'");
    EXPECT_EQ(error_of([] { parse_yaml("a: &x 1\nb: *x\n", "t"); }),
              "t:1:4: YAML anchors are not supported: write the value out");
    EXPECT_EQ(error_of([] { parse_yaml("{[1]: 2}", "t"); }), "t:1:2: mapping keys must be plain names");
    EXPECT_EQ(error_of([] { parse_yaml(",", "t"); }), "t:1:1: YAML syntax error: unexpected ','");
    EXPECT_EQ(error_of([] { parse_yaml(std::string(max_yaml_bytes + 1, ' '), "t"); }),
              "t: file too large (4194305 bytes; at most 4194304)");
    // Same keys in sibling mappings are fine.
    EXPECT_NO_THROW(parse_yaml("- {a: 1}\n- {a: 2}\n", "t"));
}

TEST(Config, OverridesReplaceAndAdd) {
    CNode n = parse_yaml("r: {maps: [{w: 1}, {w: 2}], s: 3}", "t");
    apply_override(n, "r.maps[1].w=5");
    apply_override(n, "r.s=[1, 2]");
    apply_override(n, "r.new=x");
    EXPECT_EQ(n.find("r")->find("maps")->items[1].find("w")->scalar, "5");
    EXPECT_TRUE(n.find("r")->find("s")->is_seq());
    EXPECT_EQ(n.find("r")->find("new")->scalar, "x");
    EXPECT_EQ(error_of([&] { apply_override(n, "r.maps[2].w=1"); }),
              "--set r.maps[2].w=1: index 2 out of range ('r.maps' has 2 items)");
    EXPECT_EQ(error_of([&] { apply_override(n, "r.s.x=1"); }), "--set r.s.x=1: 'r.s' is not a mapping");
    EXPECT_EQ(error_of([&] { apply_override(n, "novalue"); }), "--set novalue: expected path.to.param=value");
    EXPECT_EQ(error_of([&] { apply_override(n, "r.maps[99999999999999999999].w=1"); }),
              "--set r.maps[99999999999999999999].w=1: index '99999999999999999999' is too large");
    EXPECT_EQ(error_of([&] { apply_override(n, "r.s=[1, "); }).rfind("--set r.s=[1, : ", 0), 0u);
}

TEST(Config, EmitParsesBack) {
    const CNode n = parse_yaml("a: 1\nb: [0.1, -2]\nc: {d: 'quoted text', e: [{f: 1}]}\n", "t");
    const std::string once = emit_yaml(n);
    EXPECT_EQ(emit_yaml(parse_yaml(once, "t2")), once);
}

TEST(Config, RealsRoundTripExactly) {
    for (double v : {0.1, 1.0 / 3.0, -2.5e-300, 6.02214076e23, 0.0, 1e16}) {
        const std::string s = format_real(v);
        EXPECT_EQ(std::stod(s), v) << s;
    }
    EXPECT_EQ(format_real(0.1), "0.1");
    EXPECT_EQ(format_real(2), "2");
}

TEST(Config, EdgeDistanceSuggestions) {
    EXPECT_EQ(edit_distance("radus", "radius"), 1u);
    EXPECT_EQ(suggest("radus", {"radius", "centre", "rotation"}), std::vector<std::string>{"radius"});
    EXPECT_TRUE(suggest("zzzzzz", {"radius", "centre"}).empty());
}

TEST(Host, WrongAbiIsRefusedNamingTheFile) {
    Registry reg;
    const std::string file = fixtures_dir() + "/wrong-abi.so";
    EXPECT_EQ(error_of([&] { reg.load_file(file); }),
              "plugin '" + file + "' was built for plugin ABI " + std::to_string(fp::abi_version + 41) +
                  ", this fixpoint needs ABI " + std::to_string(fp::abi_version) +
                  ": rebuild it against this SDK");
}

TEST(Host, ObjectsKeepTheirLibraryLoaded) {
    std::shared_ptr<const fp::Shape> s;
    {
        Host host;
        s = host.make<fp::Shape>("{type: circle, radius: 2}");
    } // the registry and its handles are gone; the object still works
    double x = 3, y = 0;
    unsigned char in = 1;
    s->inside(fp::Points<const double>{&x, &y, 1}, &in);
    EXPECT_EQ(in, 0);
    x = 1;
    s->inside(fp::Points<const double>{&x, &y, 1}, &in);
    EXPECT_EQ(in, 1);
}

TEST(Host, ResolvedTreeFillsDefaults) {
    Host host;
    const auto t = validate(host.registry(), fp::Kind::Transform,
                            parse_yaml("{type: inversion, shape: {type: circle}}", "t"), "transform");
    const std::string y = emit_yaml(resolved(*t));
    EXPECT_EQ(y, "type: inversion\nshape:\n  type: circle\n  centre: [0, 0]\n  radius: 1\n");
}

} // namespace
