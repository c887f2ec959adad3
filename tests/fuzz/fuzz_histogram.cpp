// libFuzzer target: histogram files (`fixpoint tone FILE.fph`, docs/histograms.md), which may come
// from anywhere. The first byte picks what the rest is:
//   even: a whole file, its last 4 bytes replaced by the CRC-32 of the rest (a mutation would
//     otherwise fail the checksum and never reach the header or the zlib stream), through what
//     tone does with one: read_histogram_file (magic, format, sizes, inflate), the render job's
//     checks against the recipe (tests/fuzz/histogram.yaml), and, where they pass, the finish;
//   odd: the bins themselves, any sums a forged file could hold (its stream recompressed), laid
//     into the recipe's histogram (cycled to fill it) and finished: the filter, the density
//     estimation and flam3's tone must take any integers without undefined behaviour.
// Refusals (fp::InputError) are the expected answers; anything else escaping is a finding.
#include <fixpoint/fixpoint.hpp>
#include <fixpoint/host/core/histogram_file.hpp>
#include <fixpoint/host/core/pipeline.hpp>
#include <fixpoint/host/core/registry.hpp>
#include <fixpoint/host/core/render_version.hpp>
#include <fixpoint/host/job/render_job.hpp>

#include "verdict.hpp"

#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <memory>
#include <string>

namespace {

const fp::host::Pipeline* g_pipeline = nullptr;
std::string g_file; // the input, as a file (read_histogram_file reads a path)

void finish(const std::shared_ptr<const fp::host::HistogramFile>& h) {
    fp::host::RenderRequest r;
    r.tone = h;
    r.threads = 1;
    r.encode = fp::host::Format::Png;
    fp::host::RenderPlan plan = fp::host::plan_render(*g_pipeline, r);
    (void)fp::host::run_render(plan);
}

void from_file(const std::uint8_t* data, std::size_t size) {
    std::string bytes(reinterpret_cast<const char*>(data), size);
    if (size >= 4) {
        const auto crc = std::uint32_t(::crc32(::crc32(0, nullptr, 0), data, uInt(size - 4)));
        for (int i = 0; i < 4; ++i) bytes[size - 4 + std::size_t(i)] = char((crc >> (8 * i)) & 0xff);
    }
    std::FILE* f = std::fopen(g_file.c_str(), "wb");
    if (!f || std::fwrite(bytes.data(), 1, size, f) != size || std::fclose(f) != 0)
        fp::fuzz::finding("fuzz_histogram", "a write", g_file.c_str());
    finish(std::make_shared<fp::host::HistogramFile>(
        fp::host::read_histogram_file(g_file, std::uint64_t(1) << 28)));
}

void from_bins(const std::uint8_t* data, std::size_t size) {
    const fp::host::Pipeline& p = *g_pipeline;
    auto h = std::make_shared<fp::host::HistogramFile>();
    h->header = fp::host::HistogramFileHeader{fp::host::render_version_tag(), p.renderer_type,
                                              p.histogram_identity, p.recipe, p.renderer->histogram_shape()};
    const fp::HistogramShape& s = h->header.shape;
    fp::Histogram& hist = h->histogram;
    hist.width = s.width, hist.height = s.height;
    const std::size_t n = std::size_t(s.width) * std::size_t(s.height);
    hist.bins.resize(n);
    if (s.last) hist.last.resize(n);
    // The bytes cycled over the bins' integers, then their last colours.
    std::size_t at = 0;
    const auto next = [&](void* out, std::size_t k) {
        auto* o = static_cast<std::uint8_t*>(out);
        for (std::size_t i = 0; i < k; ++i, ++at) o[i] = size ? data[at % size] : 0;
    };
    for (auto& b : hist.bins) next(&b, sizeof b);
    for (auto& l : hist.last) next(&l, sizeof l);
    for (const auto& b : hist.bins) h->stats.drawn += b.hits;
    h->stats.samples = h->stats.drawn;
    finish(h);
}

} // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    try {
        static fp::host::Registry reg;
        for (const auto& d : fp::host::Registry::default_dirs()) reg.load_dir(d);
        static const fp::host::Pipeline p = fp::host::load_pipeline(reg, FIXPOINT_FUZZ_HISTOGRAM_CONFIG, {});
        g_pipeline = &p;
        char name[] = "/tmp/fuzz_histogram-XXXXXX";
        const int fd = ::mkstemp(name);
        if (fd < 0) fp::fuzz::finding("fuzz_histogram", "mkstemp", name);
        ::close(fd);
        g_file = name;
        std::atexit([] { ::unlink(g_file.c_str()); });
    } catch (const std::exception& e) {
        std::fprintf(stderr, "fuzz_histogram: loading the plugins and the recipe: %s\n", e.what());
        std::abort();
    }
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size == 0) return 0;
    fp::fuzz::verdict("fuzz_histogram", [&] {
        if (data[0] % 2 == 0)
            from_file(data + 1, size - 1);
        else
            from_bins(data + 1, size - 1);
    });
    return 0;
}
