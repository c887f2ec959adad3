// Open MPI ranks: `mpirun -np N fixpoint render ...` splits one render (or a --vary
// collection) over N processes. Started only when this process was launched by mpirun; a
// build without MPI (FIXPOINT_MPI=OFF, or libopenmpi-dev absent) is always one rank and
// refuses to run as several. Everything here is called from the main thread.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>

namespace fp::host::ranks {

/// Starts MPI when launched by mpirun. Throws fp::InputError when launched as several ranks by
/// a build without MPI (every rank would write the same file).
void init(int* argc, char*** argv);
/// Ends MPI (a no-op when it was not started).
void finalize();
/// Whether this build has MPI.
bool compiled();
unsigned rank();
unsigned size();
/// The ranks of this job on this machine (Open MPI's local size; 1 without MPI): they share
/// its memory, which the check before a render counts.
unsigned on_this_machine();
/// Ends every rank of the job at once, with `code` (a rank failed mid-render: the others
/// would wait for it forever).
[[noreturn]] void abort(int code);

/// Under mpirun, a rank that fails mid-render tells rank 0 before it ends the job (a message
/// of a few bytes, sent at once): rank 0, then stopped by mpirun as every rank is, knows that
/// the job's line was that rank's and adds no "interrupted" of its own.
void tell_failure();
/// On rank 0: whether a rank told its failure (waiting up to `wait_ms` for the message).
bool failure_told(int wait_ms);
/// Ends this rank with `code` without MPI_Abort: the job is ending already (mpirun stops
/// every rank on a Ctrl-C, and when a rank aborts), and MPI_Abort would add its banner.
[[noreturn]] void quit(int code);

/// RenderContext::combine over the ranks: a binomial tree to rank 0 in pieces of at most
/// 64 MiB, then (everywhere) a broadcast.
void combine(void* data, std::size_t bytes, std::size_t record,
             const std::function<void(const void*, void*, std::size_t)>& fold, bool everywhere);

/// Point-to-point bytes, in pieces (a --vary child's image to rank 0).
void send(unsigned to, const void* data, std::size_t bytes);
void recv(unsigned from, void* data, std::size_t bytes);

/// The checks before a render, agreed: every rank says its verdict (code 0: fine) and all
/// learn the first failing rank's code and error line. When every rank passed, their
/// `fingerprint`s (of what each will render: the recipe, with the plugins' hashes) must be
/// rank 0's: a rank with another seed, config or plugin build would mix its work into an image
/// that no recipe reproduces, so all learn a refusal (code 2) naming the first that differs.
/// Collective.
struct Verdict {
    int code = 0;
    std::string message;
};
Verdict agree(int code, const std::string& message, std::uint64_t fingerprint = 0);

/// Thrown by agree_checks on every rank when a rank failed its checks or would render another
/// recipe: rank 0 prints the verdict's line, every rank exits with its code.
struct Refused {
    Verdict verdict;
};

/// Under mpirun, once every check before a render has passed on this rank (phase checking):
/// agree with the others on the verdict and on the fingerprint of `recipes` (what this rank
/// will render), then enter the render phase; a rank that failed makes every rank stop here
/// with its error line (ranks::Refused), before any rank starts the work and its collective
/// calls. Nothing to do on one process or outside the checking phase.
void agree_checks(const std::string& recipes);

/// The fingerprint of a render's text for agree (FNV-1a, 64 bits: an identity, not a
/// security measure).
std::uint64_t fingerprint(const std::string& text);

/// Where this rank stands, so that an error is reported the right way: before the agreement a
/// failing rank joins it (one line from rank 0, every rank exits); after it, the others may
/// be waiting in a combine, so the job is aborted.
enum class Phase { free, checking, rendering };
Phase phase();
void set_phase(Phase p);

} // namespace fp::host::ranks
