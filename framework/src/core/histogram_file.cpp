// Histogram files: host/core/histogram_file.hpp says the layout and why.
#include <fixpoint/host/core/histogram_file.hpp>
#include <fixpoint/host/core/image_io.hpp>
#include <fixpoint/host/core/runtime.hpp>

#include <fixpoint/errors.hpp>
#include <fixpoint/text.hpp>

#include <zlib.h>

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <vector>

#include <fcntl.h>
#include <unistd.h>

namespace fs = std::filesystem;

namespace fp::host {

// The bins are written as they lie in memory: little-endian is the layout the file promises.
static_assert(std::endian::native == std::endian::little, "histogram files are little-endian");

namespace {

constexpr char magic[] = "fixpoint histogram\n";
constexpr std::size_t magic_bytes = sizeof magic - 1;
/// 1: a whole render's; 2: a shard's (the shards string, the last colours' order).
constexpr std::uint32_t format_whole = 1, format_shard = 2;
/// The most shares a render may be split into.
constexpr std::size_t max_shards = std::size_t(1) << 16;
/// The trailer: four counts, the stream's size, the CRC.
constexpr std::size_t trailer_bytes = 5 * 8 + 4;
constexpr std::uint64_t max_string = std::uint64_t(16) << 20;
constexpr std::uint32_t form_hits = 1, form_last = 2;

std::size_t bin_bytes(const HistogramShape& s, bool order) {
    return (s.hits_only ? 8 : sizeof(HistBin)) + (s.last ? sizeof(LastColour) : 0) +
           (s.last && order ? sizeof(LastOrder) : 0);
}

void put_le(std::string& out, std::uint64_t v, int bytes) {
    for (int i = 0; i < bytes; ++i) out.push_back(char((v >> (8 * i)) & 0xff));
}

std::uint64_t get_le(const unsigned char* b, int bytes) {
    std::uint64_t v = 0;
    for (int i = 0; i < bytes; ++i) v |= std::uint64_t(b[i]) << (8 * i);
    return v;
}

/// Everything before the stream.
std::string header_bytes(const HistogramFileHeader& h) {
    std::string out(magic, magic_bytes);
    const bool shard = !h.shards.empty();
    put_le(out, shard ? format_shard : format_whole, 4);
    for (const std::string* s : {&h.version, &h.renderer, &h.identity, &h.recipe, &h.shards}) {
        if (s == &h.shards && !shard) break;
        put_le(out, s->size(), 8);
        out += *s;
    }
    put_le(out, std::uint64_t(h.shape.width), 4);
    put_le(out, std::uint64_t(h.shape.height), 4);
    put_le(out, (h.shape.hits_only ? form_hits : 0) | (h.shape.last ? form_last : 0), 4);
    return out;
}

void write_all(int fd, const void* data, std::size_t bytes, const std::string& path) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t done = 0; done < bytes;) {
        const ssize_t w = ::write(fd, p + done, std::min<std::size_t>(bytes - done, std::size_t(1) << 30));
        if (w < 0 && errno == EINTR) continue;
        if (w <= 0)
            throw WriteError("cannot write the histogram " + quote(path, 200) + ": " + std::strerror(errno));
        done += std::size_t(w);
    }
}

} // namespace

bool is_histogram_file(const std::string& path) {
    std::string ext = fs::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return ext == ".fph";
}

std::uint64_t histogram_bytes(const HistogramShape& s, bool order) {
    return std::uint64_t(s.width) * std::uint64_t(s.height) * bin_bytes(s, order);
}

std::string shard_string(unsigned k, unsigned n) {
    std::string s(n, '0');
    if (k < n) s[k] = '1';
    return s;
}

std::string shards_named(const std::string& shards, bool missing) {
    std::vector<std::string> names;
    for (std::size_t i = 0; i < shards.size(); ++i)
        if ((shards[i] == '1') != missing)
            names.push_back(std::to_string(i + 1) + "/" + std::to_string(shards.size()));
    if (names.empty()) return "no shard";
    std::string out = names.size() == 1 ? "shard " : "shards ";
    // (A long list is cut: the count says the rest.)
    const std::size_t shown = std::min<std::size_t>(names.size(), 8);
    for (std::size_t i = 0; i < shown; ++i) {
        if (i) out += i + 1 == names.size() ? " and " : ", ";
        out += names[i];
    }
    if (shown < names.size()) out += " and " + std::to_string(names.size() - shown) + " more";
    return out;
}

// ---------------------------------------------------------------- writing
struct HistogramWriter::Stream {
    z_stream z{};
    uLong crc = ::crc32(0, nullptr, 0);
    std::uint64_t out_bytes = 0;
    std::vector<unsigned char> buf = std::vector<unsigned char>(std::size_t(1) << 20);
    bool open = false;
};

HistogramWriter::HistogramWriter(std::string path, HistogramFileHeader header)
    : path_(std::move(path)), header_(std::move(header)), z_(std::make_unique<Stream>()) {
    fs::path tmp;
    fd_ = open_temp_beside(fs::path(path_), tmp);
    if (fd_ < 0)
        throw WriteError("cannot write the histogram " + quote(path_, 200) + ": " + std::strerror(errno));
    tmp_ = tmp.string();
    // Level 1: a histogram is mostly empty bins and small counts, which the fastest level
    // already packs about tenfold; the higher ones cost several times the time for a few
    // percent.
    if (deflateInit(&z_->z, 1) != Z_OK) throw InternalError("zlib: deflateInit failed");
    z_->open = true;
    const std::string head = header_bytes(header_);
    z_->crc = ::crc32(z_->crc, reinterpret_cast<const Bytef*>(head.data()), uInt(head.size()));
    write_all(fd_, head.data(), head.size(), path_);
}

HistogramWriter::~HistogramWriter() {
    if (z_ && z_->open) deflateEnd(&z_->z);
    if (fd_ >= 0) {
        ::close(fd_);
        ::unlink(tmp_.c_str());
    }
}

void HistogramWriter::put(const void* data, std::size_t bytes, bool finish) {
    Stream& s = *z_;
    s.z.next_in = static_cast<Bytef*>(const_cast<void*>(data));
    s.z.avail_in = uInt(bytes);
    for (;;) {
        s.z.next_out = s.buf.data();
        s.z.avail_out = uInt(s.buf.size());
        const int rc = deflate(&s.z, finish ? Z_FINISH : Z_NO_FLUSH);
        if (rc == Z_STREAM_ERROR) throw InternalError("zlib: deflate failed");
        if (const std::size_t n = s.buf.size() - s.z.avail_out; n) {
            s.crc = ::crc32(s.crc, s.buf.data(), uInt(n));
            write_all(fd_, s.buf.data(), n, path_);
            s.out_bytes += n;
        }
        // Done when the input is taken and deflate left room (it holds nothing back), or, at
        // the finish, when the stream has ended.
        if (finish ? rc == Z_STREAM_END : s.z.avail_in == 0 && s.z.avail_out != 0) break;
    }
}

void HistogramWriter::rows(const Histogram& part, int part_row0, int row0, int rows) {
    const HistogramShape& sh = header_.shape;
    const std::size_t W = std::size_t(sh.width);
    if (row0 != next_row_ || rows < 0 || row0 + rows > sh.height || part.width != sh.width ||
        row0 < part_row0 || row0 + rows > part_row0 + part.height)
        throw InternalError("histogram file: rows handed over out of order or out of the histogram");
    const bool order = sh.last && !header_.shards.empty();
    if ((!sh.hits_only && part.bins.empty()) || (sh.last && part.last.size() != part.size()) ||
        (order && part.last_order.size() != part.size()))
        throw InternalError("histogram file: the rows lack what the histogram's form holds");
    std::vector<std::uint64_t> hits(sh.hits_only ? W : 0);
    for (int r = 0; r < rows; ++r) {
        const std::size_t at = std::size_t(row0 - part_row0 + r) * W;
        if (sh.hits_only) {
            for (std::size_t x = 0; x < W; ++x) hits[x] = part.hits_at(at + x);
            put(hits.data(), W * 8, false);
        } else {
            put(part.bins.data() + at, W * sizeof(HistBin), false);
        }
        if (sh.last) put(part.last.data() + at, W * sizeof(LastColour), false);
        if (order) put(part.last_order.data() + at, W * sizeof(LastOrder), false);
    }
    next_row_ += rows;
}

void HistogramWriter::commit(const RenderStats& st) {
    if (next_row_ != header_.shape.height)
        throw InternalError("histogram file: committed before every row was handed over");
    put(nullptr, 0, true);
    deflateEnd(&z_->z);
    z_->open = false;
    std::string tail;
    for (std::uint64_t v : {st.samples, st.drawn, st.restarts, st.bad_values, z_->out_bytes})
        put_le(tail, v, 8);
    z_->crc = ::crc32(z_->crc, reinterpret_cast<const Bytef*>(tail.data()), uInt(tail.size()));
    put_le(tail, std::uint32_t(z_->crc), 4);
    write_all(fd_, tail.data(), tail.size(), path_);
    const auto fail = [&](const std::string& err) {
        throw WriteError("cannot write the histogram " + quote(path_, 200) + ": " + err);
    };
    if (::fsync(fd_) != 0) fail(std::strerror(errno));
    const int fd = fd_;
    fd_ = -1;
    if (::close(fd) != 0) {
        const std::string err = std::strerror(errno);
        ::unlink(tmp_.c_str());
        fail(err);
    }
    if (::rename(tmp_.c_str(), path_.c_str()) != 0) {
        const std::string err = std::strerror(errno);
        ::unlink(tmp_.c_str());
        fail(err);
    }
}

// ---------------------------------------------------------------- reading
namespace {

/// An opened file, checked whole against its CRC, positioned after its header.
struct Opened {
    std::FILE* f = nullptr;
    HistogramFileHeader header;
    std::uint64_t stream_at = 0, stream_bytes = 0;
    RenderStats stats;
    ~Opened() {
        if (f) std::fclose(f);
    }
};

void open_checked(const std::string& path, Opened& o) {
    const std::string who = quote(path, 200);
    std::error_code ec;
    const auto st = fs::status(path, ec);
    if (ec || !fs::exists(st)) throw InputError("cannot read the histogram " + who + ": no such file");
    if (!fs::is_regular_file(st))
        throw InputError("cannot read the histogram " + who + ": not a regular file");
    const std::uint64_t size = fs::file_size(path, ec);
    o.f = std::fopen(path.c_str(), "rb");
    if (!o.f || ec) throw InputError("cannot read the histogram " + who + ": " + std::strerror(errno));
    const auto fail = [&](const std::string& why) {
        throw InputError(who + " is not a histogram fixpoint can finish: " + why);
    };
    unsigned char head[magic_bytes + 4];
    if (size < sizeof head + trailer_bytes || std::fread(head, 1, sizeof head, o.f) != sizeof head ||
        std::memcmp(head, magic, magic_bytes) != 0)
        fail("it is not a fixpoint histogram file");
    const std::uint64_t fmt = get_le(head + magic_bytes, 4);
    if (fmt != format_whole && fmt != format_shard)
        fail("it has histogram format " + std::to_string(fmt) + "; this fixpoint reads formats " +
             std::to_string(format_whole) + " and " + std::to_string(format_shard));
    {
        // The whole file against its CRC before anything of it is believed: a file cut short
        // or damaged is refused here, not half read.
        uLong crc = ::crc32(::crc32(0, nullptr, 0), head, uInt(sizeof head));
        std::vector<unsigned char> buf(std::size_t(1) << 20);
        for (std::uint64_t at = sizeof head; at < size - 4;) {
            const std::size_t n = std::size_t(std::min<std::uint64_t>(buf.size(), size - 4 - at));
            if (std::fread(buf.data(), 1, n, o.f) != n) fail("it could not be read whole");
            crc = ::crc32(crc, buf.data(), uInt(n));
            at += n;
        }
        unsigned char tail[4];
        if (std::fread(tail, 1, 4, o.f) != 4) fail("it could not be read whole");
        if (get_le(tail, 4) != std::uint32_t(crc))
            fail("it is corrupt or cut short (its checksum does not match its contents)");
    }
    if (std::fseek(o.f, long(sizeof head), SEEK_SET) != 0) fail("it could not be read whole");
    std::uint64_t at = sizeof head;
    const auto get = [&](void* p, std::size_t n) {
        if (at + n > size - trailer_bytes || std::fread(p, 1, n, o.f) != n) fail("its header is cut short");
        at += n;
    };
    const auto get_u = [&](int bytes) {
        unsigned char b[8];
        get(b, std::size_t(bytes));
        return get_le(b, bytes);
    };
    for (std::string* s :
         {&o.header.version, &o.header.renderer, &o.header.identity, &o.header.recipe, &o.header.shards}) {
        if (s == &o.header.shards && fmt != format_shard) break;
        const std::uint64_t n = get_u(8);
        if (n > max_string) fail("its header is damaged");
        s->assign(std::size_t(n), '\0');
        get(s->data(), s->size());
    }
    if (fmt == format_shard) {
        const std::string& sh = o.header.shards;
        if (sh.empty() || sh.size() > max_shards || sh.find_first_not_of("01") != std::string::npos ||
            sh.find('1') == std::string::npos)
            fail("its shards are damaged");
    }
    const std::uint64_t w = get_u(4), h = get_u(4), form = get_u(4);
    if (w < 1 || h < 1 || w > (std::uint64_t(1) << 20) || h > (std::uint64_t(1) << 20) || form > 3)
        fail("its header is damaged");
    o.header.shape = HistogramShape{int(w), int(h), (form & form_hits) != 0, (form & form_last) != 0};
    unsigned char trailer[trailer_bytes - 4];
    if (std::fseek(o.f, long(size - trailer_bytes), SEEK_SET) != 0 ||
        std::fread(trailer, 1, sizeof trailer, o.f) != sizeof trailer)
        fail("it could not be read whole");
    o.stats.samples = get_le(trailer, 8);
    o.stats.drawn = get_le(trailer + 8, 8);
    o.stats.restarts = get_le(trailer + 16, 8);
    o.stats.bad_values = get_le(trailer + 24, 8);
    o.stream_bytes = get_le(trailer + 32, 8);
    if (o.stream_bytes != size - trailer_bytes - at) fail("its histogram's size does not match the file");
    o.stream_at = at;
}

} // namespace

HistogramFileHeader read_histogram_header(const std::string& path) {
    Opened o;
    open_checked(path, o);
    return o.header;
}

HistogramFile read_histogram_file(const std::string& path, std::uint64_t memory) {
    Opened o;
    open_checked(path, o);
    HistogramFile out;
    out.path = path;
    out.header = o.header;
    out.stats = o.stats;
    const HistogramShape& sh = o.header.shape;
    const std::string who = quote(path, 200);
    const bool order = sh.last && !o.header.shards.empty();
    if (histogram_bytes(sh, order) > memory)
        throw InputError(who + ": its " + std::to_string(sh.width) + "x" + std::to_string(sh.height) +
                         " histogram needs " + format_bytes(histogram_bytes(sh, order)) +
                         " of memory; the budget is " + format_bytes(memory));
    Histogram& hist = out.histogram;
    hist.width = sh.width;
    hist.height = sh.height;
    const std::size_t n = std::size_t(sh.width) * std::size_t(sh.height), W = std::size_t(sh.width);
    if (sh.hits_only)
        hist.hits.assign(n, 0);
    else
        hist.bins.assign(n, HistBin{});
    if (sh.last) hist.last.assign(n, LastColour{});
    if (order) hist.last_order.assign(n, LastOrder{});
    // Inflated row by row into place: a row's bins, then its last colours (and their order).
    z_stream z{};
    if (inflateInit(&z) != Z_OK) throw InternalError("zlib: inflateInit failed");
    std::vector<unsigned char> in(std::size_t(1) << 20);
    std::uint64_t left = o.stream_bytes;
    if (std::fseek(o.f, long(o.stream_at), SEEK_SET) != 0) {
        inflateEnd(&z);
        throw InputError(who + ": it could not be read whole");
    }
    bool ended = false;
    const auto fill = [&](void* dst, std::size_t bytes) {
        z.next_out = static_cast<Bytef*>(dst);
        z.avail_out = uInt(bytes);
        while (z.avail_out > 0) {
            if (ended) return false;
            if (z.avail_in == 0) {
                const std::size_t k = std::size_t(std::min<std::uint64_t>(in.size(), left));
                if (k == 0 || std::fread(in.data(), 1, k, o.f) != k) return false;
                left -= k;
                z.next_in = in.data();
                z.avail_in = uInt(k);
            }
            const int rc = inflate(&z, Z_NO_FLUSH);
            if (rc == Z_STREAM_END)
                ended = true;
            else if (rc != Z_OK)
                return false;
        }
        return true;
    };
    bool ok = true;
    for (std::size_t r = 0; ok && r < std::size_t(sh.height); ++r) {
        ok = sh.hits_only ? fill(hist.hits.data() + r * W, W * 8)
                          : fill(hist.bins.data() + r * W, W * sizeof(HistBin));
        if (ok && sh.last) ok = fill(hist.last.data() + r * W, W * sizeof(LastColour));
        if (ok && order) ok = fill(hist.last_order.data() + r * W, W * sizeof(LastOrder));
    }
    // Nothing may follow the last row.
    if (ok && !ended) {
        unsigned char extra = 0;
        ok = !fill(&extra, 1) && ended && z.avail_out == 1;
    }
    inflateEnd(&z);
    if (!ok || left != 0)
        throw InputError(who + " is not a histogram fixpoint can finish: its bins are damaged");
    return out;
}

} // namespace fp::host
