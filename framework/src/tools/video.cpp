// The video of `fixpoint animate --video` (video.hpp): ffmpeg, found on PATH and run on the
// frames written.
#include "video.hpp"

#include <fixpoint/errors.hpp>
#include <fixpoint/text.hpp>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

extern char** environ;

namespace fp::host {

namespace fs = std::filesystem;

namespace {

std::string find_on_path(const std::string& name) {
    const char* path = std::getenv("PATH");
    std::string dirs = path ? path : "/usr/bin:/bin";
    std::size_t start = 0;
    while (start <= dirs.size()) {
        std::size_t end = dirs.find(':', start);
        if (end == std::string::npos) end = dirs.size();
        const std::string dir = dirs.substr(start, end - start);
        const std::string f = (dir.empty() ? std::string(".") : dir) + "/" + name;
        if (::access(f.c_str(), X_OK) == 0 && !fs::is_directory(f)) return f;
        start = end + 1;
    }
    return "";
}

// ffmpeg's arguments for the video's container (from its extension).
std::vector<std::string> codec_args(const std::string& ext) {
    if (ext == ".gif")
        return {"-vf", "split[a][b];[a]palettegen=stats_mode=full[p];[b][p]paletteuse", "-loop", "0"};
    // H.264 in 4:2:0 needs an even width and height: a lone last row or column is padded.
    std::vector<std::string> v = {"-vf",    "pad=ceil(iw/2)*2:ceil(ih/2)*2", "-c:v", "libx264", "-pix_fmt",
                                  "yuv420p"};
    if (ext == ".mp4" || ext == ".mov") v.insert(v.end(), {"-movflags", "+faststart"});
    return v;
}

std::string lower_ext(const std::string& path) {
    std::string e = fs::path(path).extension().string();
    for (auto& c : e) c = char(std::tolower(static_cast<unsigned char>(c)));
    return e;
}

} // namespace

void check_video(const std::string& video, const std::string& config, bool force) {
    const std::string e = lower_ext(video);
    if (e != ".mp4" && e != ".mkv" && e != ".mov" && e != ".gif")
        throw InputError("--video " + quote(video, 200) + ": expected a .mp4, .mkv, .mov or .gif file");
    std::error_code ec;
    if (fs::equivalent(video, config, ec))
        throw InputError("--video: cannot write " + quote(video, 200) + ": it is the config being animated");
    if (fs::is_directory(video, ec))
        throw InputError("--video: cannot write " + quote(video, 200) + ": it is a folder");
    const fs::path dir =
        fs::path(video).parent_path().empty() ? fs::path(".") : fs::path(video).parent_path();
    if (!fs::is_directory(dir, ec))
        throw InputError("--video: cannot write " + quote(video, 200) + ": folder '" + dir.string() +
                         "' does not exist");
    if (!force && fs::exists(fs::symlink_status(video, ec)))
        throw InputError("--video: " + quote(video, 200) + " exists: add --force to replace it");
    if (find_on_path("ffmpeg").empty())
        throw InputError("--video: ffmpeg not found on PATH (Debian: apt-get install ffmpeg)");
}

void make_video(const std::string& pattern, long first, long count, double fps, const std::string& video,
                const std::atomic<bool>* interrupted) {
    const std::string ffmpeg = find_on_path("ffmpeg");
    if (ffmpeg.empty())
        throw InputError("--video: ffmpeg not found on PATH (Debian: apt-get install ffmpeg)");
    const fs::path target(video);
    const fs::path tmp = target.parent_path() / ("." + target.stem().string() + ".partial-" +
                                                 std::to_string(::getpid()) + target.extension().string());
    std::vector<std::string> args = {
        ffmpeg, "-nostdin",   "-hide_banner",   "-loglevel",          "error",
        "-y",   "-framerate", number_text(fps), "-start_number",      std::to_string(first),
        "-i",   pattern,      "-frames:v",      std::to_string(count)};
    for (auto& s : codec_args(lower_ext(video))) args.push_back(std::move(s));
    args.push_back(tmp.string());
    std::vector<char*> argv;
    for (auto& s : args) argv.push_back(s.data());
    argv.push_back(nullptr);

    int pipefd[2];
    if (::pipe(pipefd) != 0)
        throw InputError(std::string("--video: cannot run ffmpeg: ") + std::strerror(errno));
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 0, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_addopen(&fa, 1, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_adddup2(&fa, pipefd[1], 2);
    posix_spawn_file_actions_addclose(&fa, pipefd[0]);
    posix_spawn_file_actions_addclose(&fa, pipefd[1]);
    pid_t pid = 0;
    const int rc = posix_spawn(&pid, ffmpeg.c_str(), &fa, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&fa);
    ::close(pipefd[1]);
    if (rc != 0) {
        ::close(pipefd[0]);
        throw InputError("--video: cannot run " + ffmpeg + ": " + std::strerror(rc));
    }
    std::string err;
    char buf[4096];
    for (ssize_t n; (n = ::read(pipefd[0], buf, sizeof buf)) != 0;) {
        if (n < 0) {
            if (errno == EINTR) continue;
            break;
        }
        err.append(buf, std::size_t(n));
        if (err.size() > 65536) err.erase(0, err.size() - 65536);
    }
    ::close(pipefd[0]);
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    std::error_code ec;
    if (WIFEXITED(status) && WEXITSTATUS(status) == 0) {
        fs::rename(tmp, target, ec);
        if (!ec) return;
        fs::remove(tmp, ec);
        throw InputError("--video: cannot write " + quote(video, 200) + ": " + ec.message());
    }
    fs::remove(tmp, ec);
    if (interrupted && interrupted->load()) throw Cancelled();
    // The last line ffmpeg printed says why.
    while (!err.empty() && (err.back() == '\n' || err.back() == '\r' || err.back() == ' ')) err.pop_back();
    const auto nl = err.find_last_of("\r\n");
    const std::string last = nl == std::string::npos ? err : err.substr(nl + 1);
    throw InputError("--video: ffmpeg failed (" +
                     (WIFEXITED(status) ? "exit status " + std::to_string(WEXITSTATUS(status))
                                        : "signal " + std::to_string(WTERMSIG(status))) +
                     ")" + (last.empty() ? std::string() : ": " + excerpt(last, 300)));
}

} // namespace fp::host
