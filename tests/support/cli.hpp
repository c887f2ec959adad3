// Run the fixpoint CLI as a user would, and capture what it prints.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace fp::test {

struct CliResult {
    int rc = -1;
    std::string out, err;
};

/// The default address-space limit of the CLI: 4 GiB, enough for every render of the tests,
/// plus 128 MiB per hardware thread, since the CLI starts a worker per thread by default and
/// each one reserves address space of its own (its stack, its malloc arena: 64 MiB).
std::uint64_t default_cli_address_space();

/// What the CLI may use. A bad input that makes the CLI allocate without bound then fails its
/// test (out of memory: exit code 1, or a crash) instead of taking the machine.
struct CliLimits {
    /// RLIMIT_AS of the child, in bytes; 0: none.
    std::uint64_t address_space = default_cli_address_space();
};

/// Whether run_cli applies CliLimits::address_space as RLIMIT_AS. Not in an ASan build
/// (the CLI is built like the tests): ASan reserves terabytes of shadow memory, so any
/// address-space limit would stop it at start; there the same number caps every single
/// allocation instead (ASan's max_allocation_size_mb), which catches a runaway size.
bool cli_address_space_limited();

/// Whether the CLI under test runs under ASan (built like the tests), about 30-50 times slower
/// than the Release build: the few tests whose renders take seconds there choose smaller ones,
/// asserting the same thing (setup.sh runs both builds' tests).
bool cli_sanitized();

/// Run build/bin/fixpoint with `args`, feeding `input` on stdin, within `limits`.
CliResult run_cli(const std::vector<std::string>& args, const std::string& input = "",
                  const CliLimits& limits = {});

/// A fresh empty folder under the build tree for one test.
std::string scratch_dir(const std::string& name);

/// Write `text` to `path`.
void write_file(const std::string& path, const std::string& text);
std::string read_file(const std::string& path);
/// A table of tab-separated columns with a header line (explore's candidates.tsv) as rows
/// of named fields.
std::vector<std::map<std::string, std::string>> read_tsv(const std::string& path);
/// `args` with `more` after them: a command line built of its parts.
inline std::vector<std::string> with(std::vector<std::string> args, const std::vector<std::string>& more) {
    args.insert(args.end(), more.begin(), more.end());
    return args;
}

/// Bad input as a user meets it: write `yaml` to bad.yaml in a fresh scratch folder `name`, run
/// the CLI there with `args`, and check (gtest) that it exits with 2, prints exactly one line on
/// stderr and leaves nothing behind but bad.yaml. Returns that line without its newline.
std::string run_bad_input(const std::string& name, const std::string& yaml,
                          const std::vector<std::string>& args = {"render", "--quiet", "bad.yaml", "-o",
                                                                  "out.png"},
                          const CliLimits& limits = {});

/// `s` with the first `from` replaced by `to`; throws when `from` is not in `s` (a test setup bug).
std::string replace_once(std::string s, const std::string& from, const std::string& to);

/// A bash command run in `dir` (for ulimit, traps and background jobs): its exit code (128 + N
/// when killed by signal N) and what it wrote to standard error (kept outside `dir`, so that
/// the folder holds only what the command left).
struct Shell {
    int rc = -1;
    std::string err;
};
Shell shell(const std::string& dir, const std::string& command);

/// The names in `dir`, sorted.
std::vector<std::string> files_in(const std::string& dir);

/// A loaded machine for as long as it lives: `n` processes that spin on a core each. The
/// latency tests (cancel) run beside them, so that their bounds are known to hold under load.
class BusyLoad {
public:
    explicit BusyLoad(int n = 2);
    ~BusyLoad();
    BusyLoad(const BusyLoad&) = delete;
    BusyLoad& operator=(const BusyLoad&) = delete;

private:
    std::vector<int> pids_;
};

/// The CLI run with `args` in `dir`, sent `sig` `delay` seconds after it catches that signal
/// (SigCgt in /proc: a signal before its handler is installed would be lost), and waited for.
struct Interrupted {
    int rc = -1;       ///< its exit code (128 + N when killed by signal N)
    double wall = 0;   ///< seconds from the signal to its exit
    double cpu = 0;    ///< its user and system time in them: the work it did after the signal,
                       ///< which another process holding a core does not inflate as it does `wall`
    bool hung = false; ///< still running `give_up` seconds after the signal (then killed)
};
Interrupted interrupt_cli(const std::vector<std::string>& args, const std::string& dir, double delay,
                          int sig = 2 /* SIGINT */, double give_up = 120);

/// The source tree's configs/ folder and tests/ folder.
std::string source_dir();

/// The CLI under test (build/bin/fixpoint), and the folder of the plugin fixtures built by tests/.
/// (Functions, not macros in every test: the test files' compile lines then name no path of
/// this checkout, so a compiler cache serves them to a clone anywhere: setup.sh.)
std::string fixpoint_bin();
std::string fixtures_dir();

} // namespace fp::test
