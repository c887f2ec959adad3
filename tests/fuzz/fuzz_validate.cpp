// libFuzzer target: the bytes are the text of a config file, and go through everything
// `fixpoint validate` checks short of the output file: parse (with the YAML guard), the
// top level, validation against every plugin's schema, the build of every object, then the
// renderer's memory and work estimates.
//
// Bad input is expected and fine: fp::InputError (a ParamError too) is the answer the CLI
// gives a user (exit code 2). Anything else escaping (InternalError, std::exception, an
// unknown exception) is what the CLI reports as an internal error (exit code 1), so it is a
// finding: printed, then abort() makes libFuzzer keep the input. Crashes, leaks, hangs and
// the sanitizers' reports are findings as usual. Writes no file.
#include <fixpoint/fixpoint.hpp>
#include <fixpoint/host/core/config.hpp>
#include <fixpoint/host/core/pipeline.hpp>
#include <fixpoint/host/core/registry.hpp>

#include "verdict.hpp"

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <memory>
#include <string>

namespace {

// The plugins are loaded once, before libFuzzer starts (LLVMFuzzerInitialize): loading them
// on the first input would make their coverage counters appear after libFuzzer has counted
// the modules, and would cost every run of a single input (the regression test) nothing but
// time. Never unloaded: the objects of a run must not outlive their plugin's library.
const fp::host::Registry* g_registry = nullptr;

void validate(const std::string& text) {
    using namespace fp::host;
    // As load_pipeline(reg, path, sets) does for a file: an empty document is an empty mapping.
    CNode root = parse_yaml(text, "fuzz.yaml");
    if (root.type == CNode::Type::Null)
        root = map_node(), root.mark = Mark{std::make_shared<const std::string>("fuzz.yaml"), 1, 1};
    const Pipeline p = load_pipeline(*g_registry, std::move(root));
    // What check_memory and the progress bar ask of a renderer: with one thread and with the
    // most the CLI accepts (--threads 4096).
    volatile std::uint64_t sink = 0;
    sink = sink + p.renderer->memory_bytes(1) + p.renderer->memory_bytes(4096) + p.renderer->work_units();
    sink = sink + std::uint64_t(p.renderer->width()) + std::uint64_t(p.renderer->height()) +
           std::uint64_t(p.renderer->has_vector_output()) + p.recipe.size();
}

} // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    try {
        static fp::host::Registry reg;
        for (const auto& d : fp::host::Registry::default_dirs()) reg.load_dir(d);
        if (reg.all().empty()) {
            std::fprintf(stderr,
                         "fuzz_validate: no plugins in the build's plugin folder or FIXPOINT_PLUGIN_PATH\n");
            std::abort();
        }
        g_registry = &reg;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "fuzz_validate: loading the plugins: %s\n", e.what());
        std::abort();
    }
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    fp::fuzz::verdict("fuzz_validate", [&] { validate(text); });
    return 0;
}
