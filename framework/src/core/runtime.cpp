#include <fixpoint/host/core/ranks.hpp>
#include <fixpoint/host/core/runtime.hpp>

#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <fixpoint/errors.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <exception>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <sys/resource.h>
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

Runtime::Runtime(unsigned threads, const std::atomic<bool>* cancel, bool distributed, bool serial)
    : threads_(serial    ? 1
               : threads ? threads
                         : 1),
      cancel_(cancel), distributed_(distributed && ranks::size() > 1),
      impl_(serial ? nullptr : std::make_unique<Impl>(threads_)) {}

unsigned Runtime::rank() const { return shard_ ? shard_k_ : distributed_ ? ranks::rank() : 0; }
unsigned Runtime::ranks() const { return shard_ ? shard_n_ : distributed_ ? ranks::size() : 1; }
void Runtime::combine(void* data, std::size_t bytes, std::size_t record,
                      const std::function<void(const void*, void*, std::size_t)>& fold, bool everywhere) {
    if (distributed_ && !shard_) ranks::combine(data, bytes, record, fold, everywhere);
}

Runtime::~Runtime() = default;

void Runtime::set_checkpoints(std::string path, double every_s, CheckpointHeader header,
                              std::unique_ptr<CheckpointSource> resume) {
    checkpoint_path_ = std::move(path);
    checkpoint_every_ = every_s;
    checkpoint_header_ = std::move(header);
    resume_ = std::move(resume);
    checkpoint_due_ =
        std::chrono::steady_clock::now() + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                               std::chrono::duration<double>(checkpoint_every_));
}

bool Runtime::checkpoint_due() const {
    return checkpointing() && std::chrono::steady_clock::now() >= checkpoint_due_;
}

void Runtime::write_checkpoint(const std::function<void(CheckpointSink&)>& body) {
    if (checkpoint_memory_) {
        // (The payload alone: the rounds that read it are of the same recipe, in this process.)
        struct Into final : CheckpointSink {
            std::string* s;
            void write(const void* data, std::size_t bytes) override {
                s->append(static_cast<const char*>(data), bytes);
            }
        } into;
        into.s = checkpoint_memory_.get();
        checkpoint_memory_->clear();
        body(into);
    } else if (!checkpoint_path_.empty()) {
        write_checkpoint_file(checkpoint_path_, checkpoint_header_, body);
    } else {
        return;
    }
    ++written_;
    // The next one a whole period after this one ended (a slow disk does not make them pile up).
    checkpoint_due_ =
        std::chrono::steady_clock::now() + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                               std::chrono::duration<double>(checkpoint_every_));
}

void Runtime::keep_histogram_in(Histogram* h, const HistogramShape& shape, bool order) {
    kept_ = h;
    kept_shape_ = shape;
    kept_order_ = order && shape.last;
    const std::size_t n = std::size_t(shape.width) * std::size_t(shape.height);
    h->width = shape.width, h->height = shape.height;
    h->hits.assign(shape.hits_only ? n : 0, 0);
    h->bins.assign(shape.hits_only ? 0 : n, HistBin{});
    h->last.assign(shape.last ? n : 0, LastColour{});
    h->last_order.assign(kept_order_ ? n : 0, LastOrder{});
}

void Runtime::keep_histogram(const Histogram& part, int part_row0, int row0, int rows) {
    if (histogram_) histogram_->rows(part, part_row0, row0, rows);
    if (rows_) rows_(part, part_row0, row0, rows);
    if (!kept_) return;
    // The rows copied in the form the shape gives (the file's: hit counts alone, or bins).
    if (part.width != kept_->width || row0 < part_row0 || row0 + rows > part_row0 + part.height ||
        row0 + rows > kept_->height || (!kept_shape_.hits_only && part.bins.empty()) ||
        (kept_shape_.last && part.last.size() != part.size()) ||
        (kept_order_ && part.last_order.size() != part.size()))
        throw InternalError("kept histogram: rows out of the histogram, or without what its form holds");
    const std::size_t W = std::size_t(part.width), from = std::size_t(row0 - part_row0) * W,
                      to = std::size_t(row0) * W, n = std::size_t(rows) * W;
    if (kept_shape_.hits_only)
        for (std::size_t i = 0; i < n; ++i) kept_->hits[to + i] = part.hits_at(from + i);
    else
        std::copy_n(part.bins.begin() + std::ptrdiff_t(from), n, kept_->bins.begin() + std::ptrdiff_t(to));
    if (kept_shape_.last)
        std::copy_n(part.last.begin() + std::ptrdiff_t(from), n, kept_->last.begin() + std::ptrdiff_t(to));
    if (kept_order_)
        std::copy_n(part.last_order.begin() + std::ptrdiff_t(from), n,
                    kept_->last_order.begin() + std::ptrdiff_t(to));
}

void Runtime::parallel_for(std::size_t n, const std::function<void(std::size_t, unsigned)>& task) {
    if (!impl_) {
        for (std::size_t i = 0; i < n; ++i) task(i, 0);
        return;
    }
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

namespace {

/// A number read from a one-line file (a cgroup's memory.max), or nothing ("max", missing).
std::optional<std::uint64_t> read_number(const char* path) {
    std::ifstream in(path);
    std::uint64_t v = 0;
    if (in >> v) return v;
    return std::nullopt;
}

/// A "Key: N kB" line of a /proc file, in bytes.
std::optional<std::uint64_t> proc_kb(const char* path, const std::string& want) {
    std::ifstream in(path);
    std::string line;
    while (std::getline(in, line))
        if (line.rfind(want, 0) == 0) {
            std::istringstream ls(line.substr(want.size()));
            std::uint64_t kb = 0;
            if (ls >> kb) return kb * 1024;
        }
    return std::nullopt;
}

} // namespace

std::uint64_t available_memory() {
    std::uint64_t have = UINT64_MAX;
    const auto least = [&](std::optional<std::uint64_t> v) {
        if (v) have = std::min(have, *v);
    };
    // The machine's: MemAvailable (what can be had without swapping).
    if (const auto a = proc_kb("/proc/meminfo", "MemAvailable:")) {
        least(a);
    } else {
        const long pages = sysconf(_SC_AVPHYS_PAGES), size = sysconf(_SC_PAGESIZE);
        if (pages > 0 && size > 0) least(std::uint64_t(pages) * std::uint64_t(size));
    }
    // A container's or a job's: the cgroup's limit less its working set (its use less the
    // file cache it can drop, as the kernel counts before it kills). Past it the kernel kills
    // the process, whatever the machine has.
    const auto cgroup = [&](const char* limit, const char* usage, const char* stat,
                            const std::string& cache) {
        const auto l = read_number(limit);
        if (!l || *l >= (std::uint64_t(1) << 60)) return; // ("max", or no limit)
        const std::uint64_t used = read_number(usage).value_or(0);
        std::uint64_t dropped = 0;
        std::ifstream in(stat);
        std::string key;
        std::uint64_t v = 0;
        while (in >> key >> v)
            if (key == cache) dropped = v;
        const std::uint64_t working = used > dropped ? used - dropped : 0;
        least(*l > working ? *l - working : 0);
    };
    // v2: this process's group (/proc/self/cgroup, "0::/PATH": a Slurm job's, a service's), and
    // the namespace's root (a container's own).
    std::string group;
    {
        std::ifstream in("/proc/self/cgroup");
        for (std::string line; std::getline(in, line);)
            if (line.rfind("0::", 0) == 0) group = line.substr(3);
    }
    for (const std::string& dir : {"/sys/fs/cgroup" + group, std::string("/sys/fs/cgroup")})
        cgroup((dir + "/memory.max").c_str(), (dir + "/memory.current").c_str(),
               (dir + "/memory.stat").c_str(), "inactive_file");
    cgroup("/sys/fs/cgroup/memory/memory.limit_in_bytes", "/sys/fs/cgroup/memory/memory.usage_in_bytes",
           "/sys/fs/cgroup/memory/memory.stat", "total_inactive_file");
    // An address-space limit (ulimit -v): past it an allocation fails, after the checks passed.
    rlimit as{};
    if (getrlimit(RLIMIT_AS, &as) == 0 && as.rlim_cur != RLIM_INFINITY) {
        const std::uint64_t used = proc_kb("/proc/self/status", "VmSize:").value_or(0);
        least(as.rlim_cur > used ? std::uint64_t(as.rlim_cur) - used : 0);
    }
    // Headroom: the estimates count a render's large buffers, not the allocator's slack, the
    // libraries, or what other processes take meanwhile.
    return have == UINT64_MAX ? have : have - have / 8;
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

bool number_and_unit(const std::string& text, double& value, std::string& unit) {
    std::size_t used = 0;
    try {
        value = std::stod(text, &used);
    } catch (const std::exception&) {
        return false;
    }
    unit = text.substr(used);
    return true;
}

std::uint64_t parse_size(const std::string& text, const std::string& option) {
    const auto bad = [&] {
        return InputError(option + " '" + text +
                          "': a size such as 8G, 512M or 1.5GiB (binary units: K, M, G, T)");
    };
    double v = 0;
    std::string unit;
    if (!number_and_unit(text, v, unit)) throw bad();
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
