#include <fixpoint/errors.hpp>
#include <fixpoint/host/core/ranks.hpp>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <thread>
#include <vector>

#ifdef FIXPOINT_HAVE_MPI
#include <mpi.h>
#endif

namespace fp::host::ranks {

namespace {
bool g_started = false;
unsigned g_rank = 0, g_size = 1;
Phase g_phase = Phase::free;

// The ranks mpirun (Open MPI, or another launcher through PMIx/PMI) says this job has.
unsigned launched_size() {
    for (const char* var : {"OMPI_COMM_WORLD_SIZE", "PMIX_SIZE", "PMI_SIZE"})
        if (const char* v = std::getenv(var)) return unsigned(std::max(1L, std::strtol(v, nullptr, 10)));
    return std::getenv("PMIX_RANK") ? 2u : 1u; // under a launcher, size unknown: start MPI to ask
}
} // namespace

bool compiled() {
#ifdef FIXPOINT_HAVE_MPI
    return true;
#else
    return false;
#endif
}

void init(int* argc, char*** argv) {
    const unsigned n = launched_size();
#ifdef FIXPOINT_HAVE_MPI
    if (n <= 1 && !std::getenv("OMPI_COMM_WORLD_SIZE")) return; // not under mpirun: no MPI at all
    int provided = 0;
    // Funnelled: only the main thread talks to MPI (the renderers' workers never do).
    MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided);
    // Errors come back as codes; a failed call is reported and the job aborted.
    MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
    int r = 0, s = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &r);
    MPI_Comm_size(MPI_COMM_WORLD, &s);
    g_started = true;
    g_rank = unsigned(r);
    g_size = unsigned(s);
#else
    (void)argc, (void)argv;
    if (n > 1)
        throw InputError("fixpoint: launched as " + std::to_string(n) +
                         " MPI ranks, but this build has no MPI (install libopenmpi-dev and rebuild, "
                         "or run without mpirun)");
#endif
}

void finalize() {
#ifdef FIXPOINT_HAVE_MPI
    if (g_started) MPI_Finalize();
#endif
    g_started = false;
}

unsigned rank() { return g_rank; }
unsigned on_this_machine() {
    if (g_size <= 1) return 1;
    const char* v = std::getenv("OMPI_COMM_WORLD_LOCAL_SIZE");
    const long n = v ? std::strtol(v, nullptr, 10) : 0;
    return n > 0 ? unsigned(std::min<long>(n, g_size)) : 1u;
}
unsigned size() { return g_size; }
Phase phase() { return g_phase; }
void set_phase(Phase p) { g_phase = p; }

void abort(int code) {
#ifdef FIXPOINT_HAVE_MPI
    if (g_started) MPI_Abort(MPI_COMM_WORLD, code);
#endif
    std::_Exit(code);
}

void quit(int code) { std::_Exit(code); }

#ifdef FIXPOINT_HAVE_MPI
namespace {
constexpr int failure_tag = 9;
} // namespace

void tell_failure() {
    if (!g_started || g_size <= 1 || g_rank == 0) return;
    // Four bytes go eagerly (below every transport's eager limit): the send returns at once.
    int one = 1;
    (void)MPI_Send(&one, 1, MPI_INT, 0, failure_tag, MPI_COMM_WORLD);
}

bool failure_told(int wait_ms) {
    if (!g_started || g_size <= 1 || g_rank != 0) return false;
    for (int i = 0; i <= wait_ms; i += 10) {
        int flag = 0;
        if (MPI_Iprobe(MPI_ANY_SOURCE, failure_tag, MPI_COMM_WORLD, &flag, MPI_STATUS_IGNORE) ==
                MPI_SUCCESS &&
            flag)
            return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return false;
}

namespace {
// MPI counts are ints: pieces of at most 64 MiB, whole records each.
constexpr std::size_t piece_bytes = std::size_t(64) << 20;

void check(int rc, const char* what) {
    if (rc == MPI_SUCCESS) return;
    char text[MPI_MAX_ERROR_STRING];
    int len = 0;
    MPI_Error_string(rc, text, &len);
    throw InternalError(std::string("MPI: ") + what + ": " + std::string(text, std::size_t(len)));
}
} // namespace

void combine(void* data, std::size_t bytes, std::size_t record,
             const std::function<void(const void*, void*, std::size_t)>& fold, bool everywhere) {
    if (g_size <= 1 || bytes == 0) return;
    if (record == 0 || bytes % record) throw InternalError("combine: bytes not a whole number of records");
    const std::size_t per = std::max<std::size_t>(1, piece_bytes / record) * record;
    std::vector<unsigned char> in(std::min(per, bytes));
    auto* base = static_cast<unsigned char*>(data);
    for (std::size_t off = 0; off < bytes; off += per) {
        const std::size_t n = std::min(per, bytes - off);
        unsigned char* piece = base + off;
        // Binomial tree: at step s, a rank with bit s set sends its folded piece to rank - s
        // and is done; the ranks below fold it in. Exact folds make the order irrelevant.
        for (unsigned s = 1; s < g_size; s <<= 1) {
            if (g_rank & s) {
                check(MPI_Send(piece, int(n), MPI_BYTE, int(g_rank - s), 7, MPI_COMM_WORLD), "send");
                break;
            }
            if (g_rank + s < g_size) {
                check(MPI_Recv(in.data(), int(n), MPI_BYTE, int(g_rank + s), 7, MPI_COMM_WORLD,
                               MPI_STATUS_IGNORE),
                      "receive");
                fold(in.data(), piece, n / record);
            }
        }
        if (everywhere) check(MPI_Bcast(piece, int(n), MPI_BYTE, 0, MPI_COMM_WORLD), "broadcast");
    }
}

void send(unsigned to, const void* data, std::size_t bytes) {
    auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t off = 0; off < bytes; off += piece_bytes)
        check(
            MPI_Send(p + off, int(std::min(piece_bytes, bytes - off)), MPI_BYTE, int(to), 8, MPI_COMM_WORLD),
            "send");
}

void recv(unsigned from, void* data, std::size_t bytes) {
    auto* p = static_cast<unsigned char*>(data);
    for (std::size_t off = 0; off < bytes; off += piece_bytes)
        check(MPI_Recv(p + off, int(std::min(piece_bytes, bytes - off)), MPI_BYTE, int(from), 8,
                       MPI_COMM_WORLD, MPI_STATUS_IGNORE),
              "receive");
}

Verdict agree(int code, const std::string& message, std::uint64_t fingerprint) {
    if (g_size <= 1) return {code, message};
    std::vector<int> codes(g_size);
    check(MPI_Allgather(&code, 1, MPI_INT, codes.data(), 1, MPI_INT, MPI_COMM_WORLD), "allgather");
    std::vector<std::uint64_t> prints(g_size);
    check(MPI_Allgather(&fingerprint, 1, MPI_UINT64_T, prints.data(), 1, MPI_UINT64_T, MPI_COMM_WORLD),
          "allgather");
    const auto first = std::find_if(codes.begin(), codes.end(), [](int c) { return c != 0; });
    if (first == codes.end()) {
        const auto other =
            std::find_if(prints.begin(), prints.end(), [&](std::uint64_t f) { return f != prints[0]; });
        if (other == prints.end()) return {};
        return {2, "fixpoint: rank " + std::to_string(other - prints.begin()) + " of " +
                       std::to_string(g_size) +
                       " would render another recipe than rank 0 (another config, --set, seed or plugin "
                       "build on its machine): every rank must render the same; nothing rendered"};
    }
    const int root = int(first - codes.begin());
    Verdict v{*first, g_rank == unsigned(root) ? message : std::string()};
    int len = int(v.message.size());
    check(MPI_Bcast(&len, 1, MPI_INT, root, MPI_COMM_WORLD), "broadcast");
    v.message.resize(std::size_t(len));
    check(MPI_Bcast(v.message.data(), len, MPI_CHAR, root, MPI_COMM_WORLD), "broadcast");
    return v;
}
#else
void tell_failure() {}
bool failure_told(int) { return false; }
void combine(void*, std::size_t, std::size_t, const std::function<void(const void*, void*, std::size_t)>&,
             bool) {}
void send(unsigned, const void*, std::size_t) { throw InternalError("send: a build without MPI"); }
void recv(unsigned, void*, std::size_t) { throw InternalError("recv: a build without MPI"); }
Verdict agree(int code, const std::string& message, std::uint64_t) { return {code, message}; }
#endif

std::uint64_t fingerprint(const std::string& text) {
    std::uint64_t h = 14695981039346656037ull;
    for (const unsigned char c : text) h = (h ^ c) * 1099511628211ull;
    return h;
}

void agree_checks(const std::string& recipes) {
    if (size() <= 1 || phase() != Phase::checking) return;
    const Verdict v = agree(0, "", fingerprint(recipes));
    set_phase(v.code ? Phase::free : Phase::rendering);
    if (v.code) throw Refused{v};
}

} // namespace fp::host::ranks
