#include "cli.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <poll.h>
#include <sstream>
#include <stdexcept>
#include <sys/resource.h>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

extern char** environ;

namespace fp::test {

namespace {

// The CLI under test is built with the same flags as this file (one build folder, one set
// of flags), so this tells whether the CLI runs under ASan.
#if defined(__SANITIZE_ADDRESS__)
constexpr bool asan_build = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr bool asan_build = true;
#else
constexpr bool asan_build = false;
#endif
#else
constexpr bool asan_build = false;
#endif

// The child's environment: ours, with the limit handed to ASan in an ASan build (options
// appended last win over the user's own ASAN_OPTIONS).
std::vector<std::string> child_environment(const CliLimits& limits) {
    std::vector<std::string> env;
    for (char** e = environ; *e; ++e) env.emplace_back(*e);
    if (asan_build && limits.address_space) {
        const std::string cap = "max_allocation_size_mb=" +
                                std::to_string(std::max<std::uint64_t>(1, limits.address_space >> 20));
        auto it = std::find_if(env.begin(), env.end(),
                               [](const std::string& v) { return v.starts_with("ASAN_OPTIONS="); });
        if (it == env.end())
            env.push_back("ASAN_OPTIONS=" + cap);
        else
            *it += (it->size() > std::strlen("ASAN_OPTIONS=") ? ":" : "") + cap;
    }
    return env;
}

// Make `fd` the child's `target` descriptor, open across exec (every pipe end is close-on-exec).
void move_fd(int fd, int target) {
    if (fd == target)
        fcntl(fd, F_SETFD, 0);
    else
        dup2(fd, target);
}

} // namespace

bool cli_address_space_limited() { return !asan_build; }

bool cli_sanitized() { return asan_build; }

std::uint64_t default_cli_address_space() {
    const std::uint64_t threads = std::max(1u, std::thread::hardware_concurrency());
    return (std::uint64_t(4) << 30) + threads * (std::uint64_t(128) << 20);
}

// fork and exec rather than posix_spawn, which cannot set a resource limit on the child.
// Between fork and exec the child only makes async-signal-safe calls (the test process may
// have threads): everything it needs is prepared before the fork.
CliResult run_cli(const std::vector<std::string>& args, const std::string& input, const CliLimits& limits) {
    int in[2], out[2], err[2], exec_status[2];
    if (pipe2(in, O_CLOEXEC) || pipe2(out, O_CLOEXEC) || pipe2(err, O_CLOEXEC) ||
        pipe2(exec_status, O_CLOEXEC))
        throw std::runtime_error("pipe failed");
    std::vector<std::string> all = {FIXPOINT_BIN};
    all.insert(all.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (auto& a : all) argv.push_back(a.data());
    argv.push_back(nullptr);
    std::vector<std::string> env = child_environment(limits);
    std::vector<char*> envp;
    for (auto& e : env) envp.push_back(e.data());
    envp.push_back(nullptr);
    rlimit as{};
    const bool limit_as =
        cli_address_space_limited() && limits.address_space && getrlimit(RLIMIT_AS, &as) == 0;
    // Never looser than the limit this process runs under.
    if (limit_as) as.rlim_cur = std::min<rlim_t>(as.rlim_cur, rlim_t(limits.address_space));

    // A child that dies before reading all its input (a crash, the limit) fails its test
    // through its exit status; it must not kill the test process with SIGPIPE.
    static const bool sigpipe_ignored = (std::signal(SIGPIPE, SIG_IGN), true);
    (void)sigpipe_ignored;

    const pid_t pid = fork();
    if (pid < 0) throw std::runtime_error("cannot start " FIXPOINT_BIN ": fork failed");
    if (pid == 0) {
        int e = 0;
        if (limit_as && setrlimit(RLIMIT_AS, &as) != 0) e = errno;
        if (!e) {
            std::signal(SIGPIPE, SIG_DFL); // an ignored signal would stay ignored across exec
            move_fd(in[0], 0);
            move_fd(out[1], 1);
            move_fd(err[1], 2);
            execve(FIXPOINT_BIN, argv.data(), envp.data());
            e = errno;
        }
        // Tell the parent why, through the pipe that exec would have closed.
        [[maybe_unused]] const ssize_t n = write(exec_status[1], &e, sizeof e);
        _exit(127);
    }
    close(in[0]);
    close(out[1]);
    close(err[1]);
    close(exec_status[1]);
    int exec_errno = 0;
    ssize_t got;
    do got = read(exec_status[0], &exec_errno, sizeof exec_errno);
    while (got < 0 && errno == EINTR);
    close(exec_status[0]);
    if (got == sizeof exec_errno) {
        for (int fd : {in[1], out[0], err[0]}) close(fd);
        waitpid(pid, nullptr, 0);
        throw std::runtime_error("cannot start " FIXPOINT_BIN ": " + std::string(std::strerror(exec_errno)));
    }
    std::size_t written = 0;
    if (input.empty()) close(in[1]), in[1] = -1;
    CliResult r;
    bool out_open = true, err_open = true;
    while (out_open || err_open) {
        pollfd fds[3] = {{out[0], POLLIN, 0}, {err[0], POLLIN, 0}, {in[1], POLLOUT, 0}};
        poll(fds, in[1] >= 0 ? 3 : 2, -1);
        char buf[65536];
        for (int k = 0; k < 2; ++k) {
            if (!(fds[k].revents & (POLLIN | POLLHUP))) continue;
            const ssize_t n = read(fds[k].fd, buf, sizeof buf);
            if (n > 0)
                (k == 0 ? r.out : r.err).append(buf, std::size_t(n));
            else
                (k == 0 ? out_open : err_open) = false;
        }
        if (in[1] >= 0 && (fds[2].revents & (POLLOUT | POLLERR))) {
            const ssize_t n = write(in[1], input.data() + written, input.size() - written);
            if (n > 0) written += std::size_t(n);
            if (n <= 0 || written == input.size()) close(in[1]), in[1] = -1;
        }
    }
    if (in[1] >= 0) close(in[1]);
    close(out[0]);
    close(err[0]);
    int status = 0;
    waitpid(pid, &status, 0);
    r.rc = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    return r;
}

std::string scratch_dir(const std::string& name) {
    const auto dir = std::filesystem::path(FIXPOINT_TEST_SCRATCH) / name;
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir.string();
}

void write_file(const std::string& path, const std::string& text) {
    std::ofstream f(path, std::ios::binary);
    f << text;
}

std::string read_file(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    std::stringstream s;
    s << f.rdbuf();
    return s.str();
}

std::vector<std::map<std::string, std::string>> read_tsv(const std::string& path) {
    std::istringstream in(read_file(path));
    auto split = [](const std::string& l) {
        std::vector<std::string> f;
        std::size_t a = 0;
        for (;;) {
            const auto b = l.find('\t', a);
            f.push_back(l.substr(a, b == std::string::npos ? b : b - a));
            if (b == std::string::npos) return f;
            a = b + 1;
        }
    };
    std::string line;
    std::getline(in, line);
    const auto head = split(line);
    std::vector<std::map<std::string, std::string>> rows;
    while (std::getline(in, line)) {
        const auto f = split(line);
        std::map<std::string, std::string> r;
        for (std::size_t i = 0; i < head.size() && i < f.size(); ++i) r[head[i]] = f[i];
        rows.push_back(r);
    }
    return rows;
}

std::string source_dir() { return FIXPOINT_SOURCE_DIR; }

std::string fixpoint_bin() { return FIXPOINT_BIN; }

std::string fixtures_dir() { return FIXPOINT_FIXTURES; }

std::string run_bad_input(const std::string& name, const std::string& yaml,
                          const std::vector<std::string>& args, const CliLimits& limits) {
    const std::string dir = scratch_dir(name);
    write_file(dir + "/bad.yaml", yaml);
    const auto cwd = std::filesystem::current_path();
    std::filesystem::current_path(dir);
    const auto r = run_cli(args, "", limits);
    std::filesystem::current_path(cwd);
    EXPECT_EQ(r.rc, 2) << r.err;
    EXPECT_FALSE(r.err.empty());
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    if (!r.err.empty()) {
        EXPECT_EQ(r.err.back(), '\n');
    }
    // Nothing written: no output and no temporary file.
    for (const auto& e : std::filesystem::directory_iterator(dir))
        EXPECT_EQ(e.path().filename(), "bad.yaml") << "left behind: " << e.path();
    return r.err.empty() ? r.err : r.err.substr(0, r.err.size() - 1);
}

std::string replace_once(std::string s, const std::string& from, const std::string& to) {
    const auto at = s.find(from);
    if (at == std::string::npos) throw std::runtime_error("test setup: '" + from + "' not in the text");
    return s.replace(at, from.size(), to);
}

Shell shell(const std::string& dir, const std::string& command) {
    const std::string err_file = dir + ".stderr";
    const std::string full =
        "cd '" + dir + "' && bash -c '" + command + "' 2>'" + err_file + "' >/dev/null </dev/null";
    const int status = std::system(full.c_str());
    Shell r;
    r.rc = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    r.err = read_file(err_file);
    std::filesystem::remove(err_file);
    return r;
}

std::vector<std::string> files_in(const std::string& dir) {
    std::vector<std::string> names;
    for (const auto& e : std::filesystem::directory_iterator(dir))
        names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
}

BusyLoad::BusyLoad(int n) {
    for (int i = 0; i < n; ++i) {
        const pid_t pid = ::fork();
        if (pid == 0) {
            volatile unsigned long spin = 0;
            for (;;) spin = spin + 1;
        }
        if (pid > 0) pids_.push_back(pid);
    }
}

BusyLoad::~BusyLoad() {
    for (const int pid : pids_) ::kill(pid, SIGKILL);
    for (const int pid : pids_) ::waitpid(pid, nullptr, 0);
}

namespace {

// A process's user + system time so far, in seconds (/proc/PID/stat, fields 14 and 15).
double cpu_seconds(pid_t pid) {
    std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
    std::string stat;
    std::getline(in, stat);
    const auto close = stat.rfind(')'); // (the command name may hold spaces)
    if (close == std::string::npos) return 0;
    std::istringstream rest(stat.substr(close + 2));
    std::string field;
    unsigned long long utime = 0, stime = 0;
    for (int i = 3; i <= 15 && rest >> field; ++i) {
        if (i == 14) utime = std::stoull(field);
        if (i == 15) stime = std::stoull(field);
    }
    return double(utime + stime) / double(::sysconf(_SC_CLK_TCK));
}

// Whether `pid` catches signal `sig` (its SigCgt mask in /proc/PID/status).
bool catches(pid_t pid, int sig) {
    std::ifstream in("/proc/" + std::to_string(pid) + "/status");
    std::string line;
    while (std::getline(in, line))
        if (line.rfind("SigCgt:", 0) == 0) return (std::stoull(line.substr(7), nullptr, 16) >> (sig - 1)) & 1;
    return false;
}

} // namespace

Interrupted interrupt_cli(const std::vector<std::string>& args, const std::string& dir, double delay, int sig,
                          double give_up) {
    Interrupted r;
    // Everything the child needs made before fork (no allocation between fork and exec).
    std::vector<std::string> a = {FIXPOINT_BIN};
    a.insert(a.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (auto& x : a) argv.push_back(x.data());
    argv.push_back(nullptr);
    const pid_t pid = ::fork();
    if (pid == 0) {
        if (::chdir(dir.c_str()) != 0) ::_exit(127);
        const int null = ::open("/dev/null", O_RDWR);
        ::dup2(null, 0), ::dup2(null, 1), ::dup2(null, 2);
        ::execv(FIXPOINT_BIN, argv.data());
        ::_exit(127);
    }
    // Up to a minute for the handler (a slow start under a sanitizer and a loaded machine).
    for (int i = 0; i < 1200 && !catches(pid, sig); ++i)
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    std::this_thread::sleep_for(std::chrono::duration<double>(delay));
    const double cpu0 = cpu_seconds(pid);
    const auto t0 = std::chrono::steady_clock::now();
    ::kill(pid, sig);
    int status = 0;
    rusage ru{};
    for (;;) {
        const pid_t w = ::wait4(pid, &status, WNOHANG, &ru);
        if (w == pid) break;
        if (std::chrono::steady_clock::now() - t0 > std::chrono::duration<double>(give_up)) {
            r.hung = true;
            ::kill(pid, SIGKILL);
            ::wait4(pid, &status, 0, &ru);
            break;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    r.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const double total = double(ru.ru_utime.tv_sec) + double(ru.ru_utime.tv_usec) * 1e-6 +
                         double(ru.ru_stime.tv_sec) + double(ru.ru_stime.tv_usec) * 1e-6;
    r.cpu = std::max(0.0, total - cpu0);
    r.rc = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    return r;
}

} // namespace fp::test
