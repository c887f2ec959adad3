#include <fixpoint/host/ranks.hpp>
#include <fixpoint/host/runtime.hpp>

#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <fixpoint/errors.hpp>

#include <cctype>
#include <cmath>
#include <cstdio>
#include <exception>
#include <fstream>
#include <string>
#include <thread>
#include <unistd.h>

namespace fp::host {

struct Runtime::Impl {
    // TBB caps its workers at the core count unless told otherwise (and warns on stderr);
    // --threads N means N, even above the core count.
    tbb::global_control limit;
    tbb::task_arena arena;
    explicit Impl(unsigned n) : limit(tbb::global_control::max_allowed_parallelism, n), arena(int(n)) {}
};

Runtime::Runtime(unsigned threads, const std::atomic<bool>* cancel, bool distributed)
    : threads_(threads ? threads : 1), cancel_(cancel), distributed_(distributed && ranks::size() > 1),
      impl_(std::make_unique<Impl>(threads_)) {}

unsigned Runtime::rank() const { return distributed_ ? ranks::rank() : 0; }
unsigned Runtime::ranks() const { return distributed_ ? ranks::size() : 1; }
void Runtime::combine(void* data, std::size_t bytes, std::size_t record,
                      const std::function<void(const void*, void*, std::size_t)>& fold, bool everywhere) {
    if (distributed_) ranks::combine(data, bytes, record, fold, everywhere);
}

Runtime::~Runtime() = default;

void Runtime::set_checkpoints(std::string path, double every_s, CheckpointHeader header,
                              std::unique_ptr<CheckpointFile> resume) {
    checkpoint_path_ = std::move(path);
    checkpoint_every_ = every_s;
    checkpoint_header_ = std::move(header);
    resume_ = std::move(resume);
    checkpoint_due_ =
        std::chrono::steady_clock::now() + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                               std::chrono::duration<double>(checkpoint_every_));
}

bool Runtime::checkpoint_due() const {
    return !checkpoint_path_.empty() && std::chrono::steady_clock::now() >= checkpoint_due_;
}

void Runtime::write_checkpoint(const std::function<void(CheckpointSink&)>& body) {
    if (checkpoint_path_.empty()) return;
    write_checkpoint_file(checkpoint_path_, checkpoint_header_, body);
    ++written_;
    // The next one a whole period after this one ended (a slow disk does not make them pile up).
    checkpoint_due_ =
        std::chrono::steady_clock::now() + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                               std::chrono::duration<double>(checkpoint_every_));
}

void Runtime::parallel_for(std::size_t n, const std::function<void(std::size_t, unsigned)>& task) {
    impl_->arena.execute([&] {
        // Grain 1: tasks are coarse (a block of chains, a tile); which worker runs which
        // task does not change the result, because renderers merge exactly.
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1),
                          [&](const tbb::blocked_range<std::size_t>& r) {
                              const int idx = tbb::this_task_arena::current_thread_index();
                              const unsigned worker = idx < 0 ? 0u : unsigned(idx) % threads_;
                              for (std::size_t i = r.begin(); i != r.end(); ++i) task(i, worker);
                          });
    });
}

unsigned hardware_threads() {
    const unsigned n = std::thread::hardware_concurrency();
    return n ? n : 1;
}

std::uint64_t available_memory() {
    std::ifstream in("/proc/meminfo");
    std::string key;
    std::uint64_t kb = 0;
    std::string unit;
    while (in >> key >> kb >> unit)
        if (key == "MemAvailable:") return kb * 1024;
    const long pages = sysconf(_SC_AVPHYS_PAGES), size = sysconf(_SC_PAGESIZE);
    return pages > 0 && size > 0 ? std::uint64_t(pages) * std::uint64_t(size) : UINT64_MAX;
}

std::string format_bytes(std::uint64_t b) {
    const char* units[] = {"B", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
    double v = double(b);
    int u = 0;
    while (v >= 1024 && u < 6) v /= 1024, ++u;
    char buf[32];
    std::snprintf(buf, sizeof buf, u ? "%.1f %s" : "%.0f %s", v, units[u]);
    return buf;
}

std::uint64_t parse_size(const std::string& text, const std::string& option) {
    const auto bad = [&] {
        return InputError(option + " '" + text +
                          "': a size such as 8G, 512M or 1.5GiB (binary units: K, M, G, T)");
    };
    std::size_t used = 0;
    double v = 0;
    try {
        v = std::stod(text, &used);
    } catch (const std::exception&) {
        throw bad();
    }
    std::string unit = text.substr(used);
    for (char& c : unit) c = char(std::toupper(static_cast<unsigned char>(c)));
    if (unit.size() > 1 && unit.back() == 'B') unit.pop_back();
    if (unit.size() > 1 && unit.back() == 'I') unit.pop_back();
    if (unit == "B") unit.clear();
    static const std::string units = "KMGT";
    double scale = 1;
    if (!unit.empty()) {
        const std::size_t k = unit.size() == 1 ? units.find(unit[0]) : std::string::npos;
        if (k == std::string::npos) throw bad();
        scale = std::ldexp(1.0, 10 * int(k + 1));
    }
    if (!(v >= 0) || !std::isfinite(v) || v * scale >= 1.8e19 || text.empty() ||
        !std::isdigit(static_cast<unsigned char>(text[0])))
        throw bad();
    const std::uint64_t bytes = std::uint64_t(v * scale);
    if (bytes < (std::uint64_t(1) << 20))
        throw InputError(option + " '" + text + "': at least 1M: a render needs more than that");
    return bytes;
}

} // namespace fp::host
