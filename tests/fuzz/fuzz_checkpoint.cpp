// libFuzzer target: the bytes are a checkpoint file, and go through what `fixpoint render
// --resume FILE` does with one: the file's checks (magic, format, CRC-32, sizes:
// CheckpointFile), the comparison with the recipe (check_against), then the resume of the
// render (tests/fuzz/checkpoint.yaml) from its payload, whose every field the renderer bounds
// by the recipe. A payload that passes them must resume into a render as short as the
// recipe's: a forged one once ran for hours (a chain's points left unbounded), which
// libFuzzer's -timeout reports.
//
// The input's last 4 bytes are replaced by the CRC-32 of the rest before it is read: a mutation
// would otherwise fail the checksum and never reach the payload, and a forged checkpoint (its
// CRC recomputed) is what the payload's bounds are for. Refusals (fp::InputError) are the
// expected answers; anything else escaping is a finding (printed, then abort()). Writes one
// temporary file, the input, rewritten for each run.
#include <fixpoint/fixpoint.hpp>
#include <fixpoint/host/core/checkpoint.hpp>
#include <fixpoint/host/core/pipeline.hpp>
#include <fixpoint/host/core/registry.hpp>
#include <fixpoint/host/core/runtime.hpp>
#include <fixpoint/version.hpp>

#include "verdict.hpp"

#include <unistd.h>
#include <zlib.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <memory>
#include <string>

namespace {

const fp::host::Pipeline* g_pipeline = nullptr;
std::string g_file; // the input, as a file (CheckpointFile reads a path)

void resume(const std::uint8_t* data, std::size_t size) {
    using namespace fp::host;
    std::string bytes(reinterpret_cast<const char*>(data), size);
    if (size >= 4) {
        const auto crc = std::uint32_t(::crc32(::crc32(0, nullptr, 0), data, uInt(size - 4)));
        for (int i = 0; i < 4; ++i) bytes[size - 4 + std::size_t(i)] = char((crc >> (8 * i)) & 0xff);
    }
    std::FILE* f = std::fopen(g_file.c_str(), "wb");
    if (!f || std::fwrite(bytes.data(), 1, size, f) != size || std::fclose(f) != 0)
        fp::fuzz::finding("fuzz_checkpoint", "a write", g_file.c_str());
    const Pipeline& p = *g_pipeline;
    const CheckpointHeader header = checkpoint_header(p); // (what the CLI writes: its seeds pass)
    auto file = std::make_unique<CheckpointFile>(g_file);
    file->check_against(header);
    Runtime rt(1, nullptr);
    rt.set_checkpoints("", 0, header, std::move(file)); // (no path: resumes, writes none)
    fp::RenderStats stats;
    (void)p.renderer->render(rt, stats);
}

} // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    try {
        static fp::host::Registry reg;
        for (const auto& d : fp::host::Registry::default_dirs()) reg.load_dir(d);
        static const fp::host::Pipeline p = fp::host::load_pipeline(reg, FIXPOINT_FUZZ_CHECKPOINT_CONFIG, {});
        g_pipeline = &p;
        char name[] = "/tmp/fuzz_checkpoint-XXXXXX";
        const int fd = ::mkstemp(name);
        if (fd < 0) fp::fuzz::finding("fuzz_checkpoint", "mkstemp", name);
        ::close(fd);
        g_file = name;
        std::atexit([] { ::unlink(g_file.c_str()); });
    } catch (const std::exception& e) {
        std::fprintf(stderr, "fuzz_checkpoint: loading the plugins and the recipe: %s\n", e.what());
        std::abort();
    }
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    // Refused: not a checkpoint, damaged, of another recipe, or a payload out of bounds.
    fp::fuzz::verdict("fuzz_checkpoint", [&] { resume(data, size); });
    return 0;
}
