// Checkpoint files: host/checkpoint.hpp says the layout and the promises.
#include <fixpoint/host/core/checkpoint.hpp>
#include <fixpoint/host/core/image_io.hpp>
#include <fixpoint/host/core/runtime.hpp>

#include <fixpoint/errors.hpp>
#include <fixpoint/text.hpp>

#include <zlib.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <vector>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace fs = std::filesystem;

namespace fp::host {

namespace {

constexpr char magic[] = "fixpoint checkpoint\n"; // 20 bytes without the NUL
constexpr std::size_t magic_bytes = sizeof magic - 1;
constexpr std::uint32_t format = 1;
/// The envelope's trailer: the payload's size and the CRC.
constexpr std::size_t trailer_bytes = 8 + 4;
/// Longest header string read (the identity is a recipe: a few KiB).
constexpr std::uint64_t max_string = std::uint64_t(16) << 20;

/// Writes to a file descriptor, checking every write, with the CRC of all bytes so far.
class FdSink final : public CheckpointSink {
public:
    FdSink(int fd, std::string path) : fd_(fd), path_(std::move(path)) {}
    void write(const void* data, std::size_t bytes) override {
        const auto* p = static_cast<const unsigned char*>(data);
        for (std::size_t done = 0; done < bytes;) {
            // zlib's crc32 takes a uInt length: pieces of 1 GiB at most.
            const std::size_t n = std::min<std::size_t>(bytes - done, std::size_t(1) << 30);
            const ssize_t w = ::write(fd_, p + done, n);
            if (w < 0 && errno == EINTR) continue;
            if (w <= 0)
                throw WriteError("cannot write the checkpoint " + quote(path_, 200) + ": " +
                                 std::strerror(errno));
            crc_ = ::crc32(crc_, p + done, uInt(w));
            done += std::size_t(w);
            counted_ += std::size_t(w);
        }
    }
    void put64(std::uint64_t v) {
        unsigned char b[8];
        for (int i = 0; i < 8; ++i) b[i] = static_cast<unsigned char>(v >> (8 * i));
        write(b, 8);
    }
    void put32(std::uint32_t v) {
        unsigned char b[4];
        for (int i = 0; i < 4; ++i) b[i] = static_cast<unsigned char>(v >> (8 * i));
        write(b, 4);
    }
    void put_string(const std::string& s) {
        put64(s.size());
        write(s.data(), s.size());
    }
    std::uint64_t counted() const { return counted_; }
    uLong crc() const { return crc_; }

private:
    int fd_;
    std::string path_;
    uLong crc_ = ::crc32(0, nullptr, 0);
    std::uint64_t counted_ = 0;
};

std::uint64_t get64(const unsigned char* b) {
    std::uint64_t v = 0;
    for (int i = 0; i < 8; ++i) v |= std::uint64_t(b[i]) << (8 * i);
    return v;
}

} // namespace

void write_checkpoint_file(const std::string& path, const CheckpointHeader& header,
                           const std::function<void(CheckpointSink&)>& body) {
    // A temporary name of its own beside the file (never one that a planted link could
    // redirect), synced and renamed over it.
    fs::path partial_path;
    const int fd = open_temp_beside(fs::path(path), partial_path);
    const std::string partial = partial_path.string();
    if (fd < 0)
        throw WriteError("cannot write the checkpoint " + quote(path, 200) + ": " + std::strerror(errno));
    try {
        FdSink sink(fd, path);
        sink.write(magic, magic_bytes);
        sink.put32(format);
        sink.put_string(header.version);
        sink.put_string(header.renderer);
        sink.put64(std::uint64_t(header.points));
        sink.put_string(header.identity);
        const std::uint64_t before = sink.counted();
        body(sink);
        sink.put64(sink.counted() - before);
        const std::uint32_t crc = std::uint32_t(sink.crc());
        sink.put32(crc);
        // fsync, then close: either may be the first to report a full disk.
        if (::fsync(fd) != 0)
            throw WriteError("cannot write the checkpoint " + quote(path, 200) + ": " + std::strerror(errno));
    } catch (...) {
        ::close(fd);
        ::unlink(partial.c_str());
        throw;
    }
    if (::close(fd) != 0) {
        const std::string err = std::strerror(errno);
        ::unlink(partial.c_str());
        throw WriteError("cannot write the checkpoint " + quote(path, 200) + ": " + err);
    }
    if (::rename(partial.c_str(), path.c_str()) != 0) {
        const std::string err = std::strerror(errno);
        ::unlink(partial.c_str());
        throw WriteError("cannot write the checkpoint " + quote(path, 200) + ": " + err);
    }
    // The rename itself lasts once the folder is synced.
    const fs::path dir = fs::path(path).parent_path();
    const int dfd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY);
    if (dfd >= 0) {
        ::fsync(dfd);
        ::close(dfd);
    }
}

CheckpointFile::CheckpointFile(const std::string& path) : path_(path) {
    const std::string who = quote(path, 200);
    std::error_code ec;
    const auto st = fs::status(path, ec);
    if (ec || !fs::exists(st)) throw InputError("cannot read the checkpoint " + who + ": no such file");
    if (!fs::is_regular_file(st))
        throw InputError("cannot read the checkpoint " + who + ": not a regular file");
    const std::uint64_t size = fs::file_size(path, ec);
    f_ = std::fopen(path.c_str(), "rb");
    if (!f_ || ec) throw InputError("cannot read the checkpoint " + who + ": " + std::strerror(errno));
    const auto fail = [&](const std::string& why) {
        std::fclose(f_);
        f_ = nullptr;
        throw InputError(who + " is not a checkpoint fixpoint can resume: " + why);
    };
    unsigned char head[magic_bytes + 4];
    if (size < magic_bytes + 4 + trailer_bytes || std::fread(head, 1, sizeof head, f_) != sizeof head ||
        std::memcmp(head, magic, magic_bytes) != 0)
        fail("it is not a fixpoint checkpoint");
    const unsigned char* f = head + magic_bytes;
    const std::uint32_t fmt = std::uint32_t(f[0]) | std::uint32_t(f[1]) << 8 | std::uint32_t(f[2]) << 16 |
                              std::uint32_t(f[3]) << 24;
    if (fmt != format)
        fail("it has checkpoint format " + std::to_string(fmt) + "; this fixpoint reads format " +
             std::to_string(format));
    // The whole file against its CRC, before anything of it is believed.
    {
        uLong crc = ::crc32(0, nullptr, 0);
        crc = ::crc32(crc, head, uInt(sizeof head));
        std::vector<unsigned char> buf(std::size_t(1) << 20);
        std::uint64_t at = sizeof head;
        const std::uint64_t body_end = size - 4;
        while (at < body_end) {
            const std::size_t n = std::size_t(std::min<std::uint64_t>(buf.size(), body_end - at));
            if (std::fread(buf.data(), 1, n, f_) != n) fail("it could not be read whole");
            crc = ::crc32(crc, buf.data(), uInt(n));
            at += n;
        }
        unsigned char tail[4];
        if (std::fread(tail, 1, 4, f_) != 4) fail("it could not be read whole");
        const std::uint32_t stored = std::uint32_t(tail[0]) | std::uint32_t(tail[1]) << 8 |
                                     std::uint32_t(tail[2]) << 16 | std::uint32_t(tail[3]) << 24;
        if (stored != std::uint32_t(crc)) fail("it is corrupt (its checksum does not match its contents)");
    }
    // The header, then the payload's extent from the trailer.
    if (std::fseek(f_, long(sizeof head), SEEK_SET) != 0) fail("it could not be read whole");
    std::uint64_t at = sizeof head;
    const auto get = [&](void* p, std::size_t n) {
        if (at + n > size - trailer_bytes || std::fread(p, 1, n, f_) != n) fail("its header is cut short");
        at += n;
    };
    const auto get_u64 = [&] {
        unsigned char b[8];
        get(b, 8);
        return get64(b);
    };
    const auto get_string = [&] {
        const std::uint64_t n = get_u64();
        if (n > max_string) fail("its header is damaged");
        std::string s(std::size_t(n), '\0');
        get(s.data(), s.size());
        return s;
    };
    header_.version = get_string();
    header_.renderer = get_string();
    header_.points = std::int64_t(get_u64());
    header_.identity = get_string();
    unsigned char trailer[8];
    if (std::fseek(f_, long(size - trailer_bytes), SEEK_SET) != 0 || std::fread(trailer, 1, 8, f_) != 8)
        fail("it could not be read whole");
    const std::uint64_t payload = get64(trailer);
    if (payload != size - trailer_bytes - at) fail("its payload's size does not match the file");
    if (std::fseek(f_, long(at), SEEK_SET) != 0) fail("it could not be read whole");
    left_ = payload;
}

CheckpointFile::~CheckpointFile() {
    if (f_) std::fclose(f_);
}

void CheckpointFile::check_against(const CheckpointHeader& want) const {
    const std::string who = quote(path_, 200);
    if (header_.version != want.version)
        throw InputError(who + " was made by fixpoint " + header_.version + "; this is fixpoint " +
                         want.version + ", which may render other bytes: render from the start");
    if (header_.renderer != want.renderer)
        throw InputError(who + " is a checkpoint of a " + header_.renderer + " render, not of this " +
                         want.renderer + " one");
    if (header_.identity != want.identity)
        throw InputError(who + " is a checkpoint of another recipe (" +
                         recipe_difference(header_.identity, want.identity) +
                         "); only renderer.points may differ, and only upwards");
    if (want.points < header_.points)
        throw InputError(who + " holds " + std::to_string(header_.points) +
                         " points, more than renderer.points " + std::to_string(want.points) +
                         ": a checkpoint continues to as many points or more");
}

void CheckpointFile::read(void* data, std::size_t bytes) {
    if (bytes > left_ || std::fread(data, 1, bytes, f_) != bytes)
        throw InputError("the checkpoint " + quote(path_, 200) + " ends early");
    left_ -= bytes;
}

void MemoryCheckpoint::read(void* data, std::size_t bytes) {
    if (bytes > left()) throw InputError("the checkpoint kept in memory ends early");
    std::memcpy(data, payload_->data() + at_, bytes);
    at_ += bytes;
}

std::string recipe_difference(const std::string& had, const std::string& want) {
    // The first line that differs says what changed.
    std::istringstream a(had), b(want);
    std::string la, lb;
    int line = 0;
    while (true) {
        const bool ga = bool(std::getline(a, la)), gb = bool(std::getline(b, lb));
        ++line;
        if (!ga) la = "(the end)";
        if (!gb) lb = "(the end)";
        if (la != lb || (!ga && !gb)) break;
    }
    const auto trim = [](const std::string& s) {
        const auto p = s.find_first_not_of(' ');
        return quote(p == std::string::npos ? s : s.substr(p), 80);
    };
    return "its line " + std::to_string(line) + " is " + trim(la) + ", this recipe's " + trim(lb);
}

double parse_duration(const std::string& text, const std::string& option) {
    const auto bad = [&] {
        return InputError(option + ": expected a time such as 30s, 5m or 1.5h, got " + quote(text));
    };
    double v = 0;
    std::string unit;
    if (!number_and_unit(text, v, unit)) throw bad();
    double scale = 0;
    if (unit.empty() || unit == "s")
        scale = 1;
    else if (unit == "m" || unit == "min")
        scale = 60;
    else if (unit == "h")
        scale = 3600;
    if (scale == 0 || !std::isfinite(v) || v <= 0 || text.empty() ||
        !(std::isdigit(static_cast<unsigned char>(text[0])) || text[0] == '.'))
        throw bad();
    return v * scale;
}

} // namespace fp::host
