// The conformance suite as a GoogleTest program: `fixpoint_conformance_runner FILE...` runs
// every check on each plugin file (third-party authors can run it on theirs, or use
// `fixpoint conformance FILE`). The paths are collected before InitGoogleTest.
#include <fixpoint/host/conformance/conformance.hpp>
#include <fixpoint/host/core/registry.hpp>

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace {

std::vector<std::string> g_files;

class Conformance : public testing::TestWithParam<std::string> {};

TEST_P(Conformance, Plugin) {
    fp::host::Registry reg;
    for (const auto& d : fp::host::Registry::default_dirs()) reg.load_dir(d);
    // Every plugin of the file (a family library holds many).
    for (const auto* entry : reg.of_file(reg.load_file(GetParam()))) {
        const auto findings = fp::host::run_conformance(reg, *entry);
        for (const auto& f : findings) ADD_FAILURE() << entry->desc->name << ": " << f;
    }
}

std::string test_name(const testing::TestParamInfo<std::string>& info) {
    std::string s = std::filesystem::path(info.param).stem().string();
    for (char& c : s)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    return s;
}

} // namespace

INSTANTIATE_TEST_SUITE_P(Plugins, Conformance, testing::ValuesIn(g_files), test_name);

int main(int argc, char** argv) {
    for (int i = 1; i < argc; ++i)
        if (argv[i][0] != '-') g_files.emplace_back(argv[i]);
    testing::InitGoogleTest(&argc, argv);
    return RUN_ALL_TESTS();
}
