// OpenImageIO output and input. Keep spdlog/fmt out of this file (see image_io.hpp).
#include <fixpoint/errors.hpp>
#include <fixpoint/host/image_io.hpp>
#include <fixpoint/text.hpp>
#include <fixpoint/version.hpp>

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <unistd.h>

namespace fs = std::filesystem;

namespace fp::host {

Format format_for(const std::string& path) {
    std::string ext = fs::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    if (ext == ".png") return Format::Png;
    if (ext == ".exr") return Format::Exr;
    if (ext == ".tif" || ext == ".tiff") return Format::Tiff;
    if (ext == ".svg") return Format::Svg;
    if (ext == ".pdf") return Format::Pdf;
    throw InputError("'" + path + "': unknown output format '" + (ext.empty() ? "(no extension)" : ext) +
                     "' (use .png, .exr, .tif, .tiff, .svg or .pdf)");
}

bool is_recipe_image(const std::string& path) {
    try {
        return format_for(path) != Format::Pdf;
    } catch (const InputError&) {
        return false;
    }
}

static fs::path temp_path_for(const fs::path& target) {
    return target.parent_path() / ("." + target.filename().string() + ".tmp-" + std::to_string(::getpid()));
}

void check_output(const std::string& path) {
    // A NUL ends the name the system sees: "x.sh\0.png" would pass the checks below as a PNG
    // and write "x.sh". Control characters are refused with it: no file name needs them.
    for (const char ch : path)
        if (static_cast<unsigned char>(ch) < 0x20 || ch == 0x7f)
            throw InputError("cannot write " + quote(path, 200) + ": the name holds a control character");
    format_for(path);
    const fs::path target(path);
    std::error_code ec;
    if (fs::is_directory(target, ec)) throw InputError("cannot write '" + path + "': it is a folder");
    const fs::path dir = target.parent_path().empty() ? fs::path(".") : target.parent_path();
    if (!fs::is_directory(dir, ec))
        throw InputError("cannot write '" + path + "': folder '" + dir.string() + "' does not exist");
    // Probe with the temporary name the real write will use.
    const fs::path probe = temp_path_for(target);
    const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL, 0644);
    if (fd < 0) throw InputError("cannot write '" + path + "': " + std::strerror(errno));
    ::close(fd);
    ::unlink(probe.c_str());
    if (fs::exists(target, ec) && ::access(target.c_str(), W_OK) != 0 && errno != ENOENT)
        throw InputError("cannot write '" + path + "': " + std::strerror(errno));
}

// The writer and the spec of a raster image file: the same for a whole image and a streamed one.
bool tiled_file(const std::string& path, int width, int height, Tiled tiled) {
    const Format f = format_for(path);
    const bool can = f == Format::Tiff || f == Format::Exr;
    if (tiled == Tiled::Yes && !can)
        throw InputError("output.tiled: '" + path +
                         "': only TIFF and EXR images have tiles (write .tif or .exr)");
    if (tiled == Tiled::Auto) return can && std::uint64_t(width) * std::uint64_t(height) > tiled_above;
    return tiled == Tiled::Yes;
}

static std::pair<std::unique_ptr<OIIO::ImageOutput>, OIIO::ImageSpec>
image_writer(const std::string& path, int width, int height, int channels, int bit_depth,
             const std::string& recipe, const Resolution& resolution, bool tiled) {
    const Format f = format_for(path);
    if (is_vector(f))
        throw InputError("'" + path +
                         "': SVG and PDF are written only by renderers with vector output (use .png, "
                         ".exr, .tif or .tiff)");
    const char* oiio_format = f == Format::Png ? "png" : f == Format::Exr ? "openexr" : "tiff";
    OIIO::TypeDesc type = f == Format::Exr  ? OIIO::TypeDesc::FLOAT
                          : bit_depth == 16 ? OIIO::TypeDesc::UINT16
                                            : OIIO::TypeDesc::UINT8;
    OIIO::ImageSpec spec(width, height, channels, type);
    spec.attribute("ImageDescription", recipe);
    spec.attribute("Software", "fixpoint " FIXPOINT_VERSION);
    // No time of writing: the recipe alone decides the bytes. Left unset, the TIFF writer puts
    // the clock in DateTime and the EXR writer in capDate; empty, TIFF has none and EXR an
    // empty capDate.
    spec.attribute("DateTime", "");
    if (f == Format::Exr) spec.attribute("compression", "zip");
    if (resolution.x > 0 && resolution.y > 0) {
        spec.attribute("XResolution", float(resolution.x));
        spec.attribute("YResolution", float(resolution.y));
        spec.attribute("ResolutionUnit", "inch");
    }
    if (tiled) {
        spec.tile_width = spec.tile_height = tile_side;
        spec.tile_depth = 1;
    }
    auto out = OIIO::ImageOutput::create(oiio_format);
    if (!out) throw InternalError(std::string("OpenImageIO has no writer for ") + oiio_format);
    if (tiled && !out->supports("tiles"))
        throw InternalError(std::string("OpenImageIO's ") + oiio_format + " writer cannot write tiles");
    if (tiled) out->threads(1); // (and one tile at a time: write_tile_row)
    if (!out->supports("ioproxy"))
        throw InternalError(std::string("OpenImageIO's ") + oiio_format +
                            " writer cannot write through a proxy");
    return {std::move(out), spec};
}

// One row of tiles (rows [ty, ty + rows) of a `width`-pixel image of `ch` channels at `px`), tile by tile in
// order, each copied whole into a zeroed tile first. OpenImageIO's write_tiles, given many tiles
// at once, compressed them concurrently and wrote them in the order they finished (one render in
// fifteen had other tile offsets), and edge tiles must be whole: this way a whole write and a
// streamed one give the same bytes.
static bool write_tile_row(OIIO::ImageOutput& out, int width, int ch, int ty, int rows, const float* px,
                           std::vector<float>& tile) {
    const std::size_t c = std::size_t(ch);
    tile.resize(std::size_t(tile_side) * tile_side * c);
    for (int tx = 0; tx < width; tx += tile_side) {
        std::fill(tile.begin(), tile.end(), 0.0f);
        const int cols = std::min(tile_side, width - tx);
        for (int r = 0; r < rows; ++r)
            std::copy_n(px + (std::size_t(r) * std::size_t(width) + std::size_t(tx)) * c,
                        std::size_t(cols) * c, tile.data() + std::size_t(r) * tile_side * c);
        if (!out.write_tile(tx, ty, 0, OIIO::TypeDesc::FLOAT, tile.data())) return false;
    }
    return true;
}

void write_image(const Image& img, const std::string& path, int bit_depth, const std::string& recipe,
                 const Resolution& resolution, Tiled tiled) {
    const bool tiles = tiled_file(path, img.width, img.height, tiled);
    auto [out, spec] =
        image_writer(path, img.width, img.height, img.channels, bit_depth, recipe, resolution, tiles);
    const char* oiio_format = out->format_name();
    // OpenImageIO's writers do not all check their writes to a file: past a file-size limit (as
    // on a full disk) the PNG and EXR writers reported success over a truncated file. So the
    // image is encoded in memory and written by write_bytes, which checks every write, the
    // fsync and the close, and leaves nothing behind when one fails.
    OIIO::Filesystem::IOVecOutput mem;
    if (!out->set_ioproxy(&mem))
        throw InternalError(std::string("OpenImageIO's ") + oiio_format + " writer cannot write to memory");
    bool ok = out->open(path, spec);
    if (ok && tiles) {
        std::vector<float> tile;
        for (int ty = 0; ok && ty < img.height; ty += tile_side)
            ok = write_tile_row(*out, img.width, img.channels, ty, std::min(tile_side, img.height - ty),
                                img.pixels.data() +
                                    std::size_t(ty) * std::size_t(img.width) * std::size_t(img.channels),
                                tile);
    } else if (ok) {
        ok = out->write_image(OIIO::TypeDesc::FLOAT, img.pixels.data());
    }
    if (ok) ok = out->close();
    if (!ok) throw InputError("cannot write '" + path + "': " + out->geterror());
    out.reset();
    const auto& buf = mem.buffer();
    write_bytes(reinterpret_cast<const char*>(buf.data()), buf.size(), path);
}

namespace {
// A file for OpenImageIO's writers that checks every write (they do not all check their own:
// see write_image): positioned writes into a descriptor, the first error kept for finish().
class CheckedFile final : public OIIO::Filesystem::IOProxy {
public:
    CheckedFile(const std::string& path, int fd) : IOProxy(path, Write), fd_(fd) {}
    const char* proxytype() const override { return "fixpoint-checked-file"; }
    size_t write(const void* buf, size_t size) override {
        const size_t n = pwrite(buf, size, m_pos);
        m_pos += int64_t(n);
        return n;
    }
    size_t pwrite(const void* buf, size_t size, int64_t offset) override {
        const char* p = static_cast<const char*>(buf);
        size_t done = 0;
        while (done < size && error_.empty()) {
            const ssize_t w = ::pwrite(fd_, p + done, size - done, off_t(offset) + off_t(done));
            if (w < 0 && errno == EINTR) continue;
            if (w <= 0)
                error_ = w < 0 ? std::strerror(errno) : "nothing written";
            else
                done += size_t(w);
        }
        end_ = std::max(end_, offset + int64_t(done));
        return done;
    }
    size_t size() const override { return size_t(end_); }
    const std::string& failure() const { return error_; }

private:
    int fd_;
    int64_t end_ = 0;
    std::string error_;
};
} // namespace

struct StreamedImage::Impl {
    std::string path;
    fs::path tmp;
    int fd = -1;
    std::unique_ptr<CheckedFile> file;
    std::unique_ptr<OIIO::ImageOutput> out;
    int width = 0, height = 0, next = 0;
    bool done = false;
    /// Tiled: the rows of the row of tiles being filled (from row `next` rounded down to a tile).
    bool tiled = false;
    std::vector<float> tile_rows, tile;

    [[noreturn]] void fail(const std::string& why) {
        throw WriteError("cannot write '" + path + "': " + why);
    }
    /// The first failure of the file itself (a full disk) before the encoder's account of it.
    [[noreturn]] void fail_writing() { fail(file->failure().empty() ? out->geterror() : file->failure()); }
};

StreamedImage::StreamedImage(const std::string& path, int width, int height, int bit_depth,
                             const std::string& recipe, const Resolution& resolution, Tiled tiled)
    : impl_(std::make_unique<Impl>()) {
    Impl& m = *impl_;
    m.path = path;
    m.width = width;
    m.height = height;
    m.tiled = tiled_file(path, width, height, tiled);
    auto [out, spec] = image_writer(path, width, height, 3, bit_depth, recipe, resolution, m.tiled);
    if (m.tiled) m.tile_rows.assign(std::size_t(tile_side) * std::size_t(width) * 3, 0.0f);
    m.out = std::move(out);
    m.tmp = temp_path_for(fs::path(path));
    m.fd = ::open(m.tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (m.fd < 0) m.fail(std::strerror(errno));
    m.file = std::make_unique<CheckedFile>(path, m.fd);
    if (!m.out->set_ioproxy(m.file.get()) || !m.out->open(path, spec)) m.fail(m.out->geterror());
}

WriteError::~WriteError() = default;

StreamedImage::~StreamedImage() {
    Impl& m = *impl_;
    if (m.done) return;
    // Unfinished (an error, a cancel): the encoder is dropped and the partial file removed.
    m.out.reset();
    if (m.fd >= 0) ::close(m.fd);
    std::error_code ec;
    fs::remove(m.tmp, ec);
}

void StreamedImage::rows(int y0, int rows, const float* rgb) {
    Impl& m = *impl_;
    if (y0 != m.next || rows < 0 || y0 + rows > m.height)
        throw InternalError("StreamedImage: rows out of order");
    if (m.tiled) {
        // Rows gather into a row of tiles, written once whole (or at the image's last row).
        const std::size_t row = std::size_t(m.width) * 3;
        for (int y = y0; y < y0 + rows; ++y) {
            std::copy_n(rgb + std::size_t(y - y0) * row, row,
                        m.tile_rows.data() + std::size_t(y % tile_side) * row);
            if ((y + 1) % tile_side != 0 && y + 1 != m.height) continue;
            const int ty = y / tile_side * tile_side;
            if (!write_tile_row(*m.out, m.width, 3, ty, y + 1 - ty, m.tile_rows.data(), m.tile) ||
                !m.file->failure().empty())
                m.fail_writing();
        }
        m.next = y0 + rows;
        return;
    }
    // 64 rows at a time: the writer converts what it is given to the file's type in a buffer
    // of its own, which a whole band would make as large as a fifth of the band.
    for (int y = y0; y < y0 + rows; y += 64) {
        const int y1 = std::min(y0 + rows, y + 64);
        const float* at = rgb + std::size_t(y - y0) * std::size_t(m.width) * 3;
        if (!m.out->write_scanlines(y, y1, 0, OIIO::TypeDesc::FLOAT, at) || !m.file->failure().empty())
            m.fail_writing();
    }
    m.next = y0 + rows;
}

std::string StreamedImage::temporary_path() const { return impl_->tmp.string(); }

std::uint64_t StreamedImage::held_bytes(const std::string& path, int width, int height, Tiled tiled) {
    return tiled_file(path, width, height, tiled)
               ? std::uint64_t(tile_side) * std::uint64_t(width) * 3 * sizeof(float)
               : 0;
}

void StreamedImage::finish() {
    Impl& m = *impl_;
    if (m.next != m.height) throw InternalError("StreamedImage: the image is not complete");
    if (!m.out->close() || !m.file->failure().empty()) m.fail_writing();
    m.out.reset();
    // fsync, then close: either may be the first to report a full disk.
    const bool synced = ::fsync(m.fd) == 0;
    const std::string sync_err = synced ? "" : std::strerror(errno);
    const int fd = m.fd;
    m.fd = -1;
    if (::close(fd) != 0 || !synced) m.fail(synced ? std::strerror(errno) : sync_err);
    std::error_code ec;
    fs::rename(m.tmp, m.path, ec);
    if (ec) m.fail(ec.message());
    m.done = true;
}

void quantise_pixels(const Image& img, int bit_depth, void* out) {
    const auto n = static_cast<OIIO::stride_t>(img.pixels.size());
    if (!OIIO::convert_pixel_values(OIIO::TypeDesc::FLOAT, img.pixels.data(),
                                    bit_depth == 16 ? OIIO::TypeDesc::UINT16 : OIIO::TypeDesc::UINT8, out, n))
        throw InternalError("OpenImageIO could not convert the pixels");
}

// The recipe an mfs SVG carries in <metadata id="fixpoint-recipe"> (see plugins/renderers/mfs_draw.hpp).
static std::string read_svg_recipe(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError("cannot read '" + path + "': " + std::strerror(errno));
    const std::string doc((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string open = "<metadata id=\"fixpoint-recipe\"><![CDATA[\n", close = "]]></metadata>";
    const auto a = doc.find(open);
    const auto b = a == std::string::npos ? a : doc.find(close, a);
    if (b == std::string::npos)
        throw InputError("'" + path + "' holds no fixpoint recipe (it was not written by fixpoint)");
    std::string r = doc.substr(a + open.size(), b - a - open.size());
    for (std::size_t at; (at = r.find("]]]]><![CDATA[>")) != std::string::npos;) r.replace(at, 15, "]]>");
    return r;
}

static Format format_for_or_png(const std::string& path) {
    try {
        return format_for(path);
    } catch (const InputError&) {
        return Format::Png; // anything OpenImageIO reads
    }
}

void write_bytes(const std::string& bytes, const std::string& path) {
    write_bytes(bytes.data(), bytes.size(), path);
}

void write_bytes(const char* data, std::size_t size, const std::string& path) {
    const fs::path target(path);
    const fs::path tmp = temp_path_for(target);
    const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd < 0) throw InputError("cannot write '" + path + "': " + std::strerror(errno));
    std::size_t done = 0;
    while (done < size) {
        const ssize_t w = ::write(fd, data + done, size - done);
        if (w < 0 && errno == EINTR) continue;
        if (w <= 0) {
            const std::string err = std::strerror(errno);
            ::close(fd);
            ::unlink(tmp.c_str());
            throw InputError("cannot write '" + path + "': " + err);
        }
        done += std::size_t(w);
    }
    // fsync, then close: either may be the first to report a full disk.
    const bool synced = ::fsync(fd) == 0;
    const std::string sync_err = synced ? "" : std::strerror(errno);
    if (::close(fd) != 0 || !synced) {
        const std::string err = synced ? std::strerror(errno) : sync_err;
        ::unlink(tmp.c_str());
        throw InputError("cannot write '" + path + "': " + err);
    }
    std::error_code ec;
    fs::rename(tmp, target, ec);
    if (ec) {
        fs::remove(tmp, ec);
        throw InputError("cannot write '" + path + "': " + ec.message());
    }
}

std::string read_recipe(const std::string& path) {
    // A device or a pipe (/dev/zero) would be read for ever: a recipe lives in a file.
    std::error_code ec;
    const auto st = fs::status(path, ec);
    if (ec) throw InputError("cannot read " + quote(path, 200) + ": " + ec.message());
    if (!fs::is_regular_file(st))
        throw InputError("cannot read " + quote(path, 200) + ": not a regular file");
    if (format_for_or_png(path) == Format::Svg) return read_svg_recipe(path);
    auto in = OIIO::ImageInput::open(path);
    if (!in) throw InputError("cannot read '" + path + "': " + OIIO::geterror());
    const std::string desc = in->spec().get_string_attribute("ImageDescription");
    const std::string software = in->spec().get_string_attribute("Software");
    in->close();
    if (desc.empty() || software.rfind("fixpoint", 0) != 0)
        throw InputError("'" + path + "' holds no fixpoint recipe (it was not written by fixpoint)");
    return desc;
}

Image read_image(const std::string& path) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) throw InputError("cannot read '" + path + "': " + OIIO::geterror());
    const auto& spec = in->spec();
    Image img;
    img.width = spec.width;
    img.height = spec.height;
    img.channels = spec.nchannels;
    img.pixels.resize(std::size_t(img.width) * std::size_t(img.height) * std::size_t(img.channels));
    if (!in->read_image(0, 0, 0, img.channels, OIIO::TypeDesc::FLOAT, img.pixels.data()))
        throw InputError("cannot read '" + path + "': " + in->geterror());
    in->close();
    return img;
}

SheetLayout contact_sheet_layout(const std::vector<std::pair<int, int>>& sizes, int columns) {
    SheetLayout L;
    const int n = int(sizes.size());
    for (const auto& [w, h] : sizes)
        L.cell_width = std::max(L.cell_width, w), L.cell_height = std::max(L.cell_height, h);
    if (columns <= 0) columns = int(std::ceil(std::sqrt(double(n))));
    L.columns = std::max(1, std::min(columns, n));
    const int rows = (n + L.columns - 1) / L.columns;
    L.gap = std::max(2, L.cell_width / 64);
    L.bar = std::max(18, std::min(48, L.cell_height / 10)); // caption bar under each child
    L.width = std::int64_t(L.columns) * L.cell_width + std::int64_t(L.columns + 1) * L.gap;
    L.height = std::int64_t(rows) * (L.cell_height + L.bar) + std::int64_t(rows + 1) * L.gap;
    return L;
}

Image contact_sheet(const std::vector<Image>& children, const std::vector<std::string>& captions, int columns,
                    bool* captions_drawn) {
    const int n = int(children.size());
    if (n == 0) throw InternalError("contact sheet of no images");
    std::vector<std::pair<int, int>> sizes;
    for (const auto& c : children) sizes.emplace_back(c.width, c.height);
    const SheetLayout L = contact_sheet_layout(sizes, columns);
    if (L.width > 1'000'000 || L.height > 1'000'000)
        throw InputError("a contact sheet of " + std::to_string(L.width) + "x" + std::to_string(L.height) +
                         " pixels is too large");
    const int cw = L.cell_width, ch = L.cell_height, gap = L.gap, bar = L.bar;
    columns = L.columns;
    const int W = int(L.width), H = int(L.height);
    OIIO::ImageBuf sheet(OIIO::ImageSpec(W, H, 3, OIIO::TypeDesc::FLOAT));
    OIIO::ImageBufAlgo::zero(sheet);
    const char* font = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
    const std::string fontname = std::filesystem::exists(font) ? font : "";
    bool all_text = true;
    for (int i = 0; i < n; ++i) {
        const Image& c = children[std::size_t(i)];
        const int x0 = gap + (i % columns) * (cw + gap), y0 = gap + (i / columns) * (ch + bar + gap);
        OIIO::ImageBuf child(OIIO::ImageSpec(c.width, c.height, c.channels, OIIO::TypeDesc::FLOAT),
                             const_cast<float*>(c.pixels.data()));
        OIIO::ImageBufAlgo::paste(sheet, x0, y0, 0, 0, child, OIIO::ROI(0, c.width, 0, c.height, 0, 1, 0, 3));
        if (std::size_t(i) < captions.size()) {
            const float white[3] = {1, 1, 1};
            const int size = bar * 2 / 3;
            all_text = OIIO::ImageBufAlgo::render_text(sheet, x0 + gap, y0 + ch + bar - (bar - size) / 2 - 2,
                                                       captions[std::size_t(i)], size, fontname, white) &&
                       all_text;
        }
    }
    if (captions_drawn) *captions_drawn = all_text;
    Image out;
    out.width = W;
    out.height = H;
    out.channels = 3;
    out.pixels.resize(std::size_t(W) * std::size_t(H) * 3);
    sheet.get_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, out.pixels.data());
    return out;
}

Comparison compare_images(const std::string& a, const std::string& b, double threshold) {
    OIIO::ImageBuf A(a), B(b);
    if (!A.read(0, 0, true, OIIO::TypeDesc::FLOAT))
        throw InputError("cannot read '" + a + "': " + A.geterror());
    if (!B.read(0, 0, true, OIIO::TypeDesc::FLOAT))
        throw InputError("cannot read '" + b + "': " + B.geterror());
    Comparison c;
    if (A.spec().width != B.spec().width || A.spec().height != B.spec().height ||
        A.spec().nchannels != B.spec().nchannels) {
        c.size_mismatch = true;
        return c;
    }
    const auto r = OIIO::ImageBufAlgo::compare(A, B, float(threshold), float(threshold));
    c.max_error = r.maxerror;
    c.mean_error = r.meanerror;
    c.n_fail = std::size_t(r.nfail);
    return c;
}

} // namespace fp::host
