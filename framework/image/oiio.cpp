// The image module: fixpoint's raster images through OpenImageIO (see image_module.hpp for
// why this is a library of its own). Only the encoding and decoding live here; the host
// decides formats and tiles, and does the atomic writes (framework/src/image_io.cpp).
// Keep spdlog and fmt out of this file: OpenImageIO's headers bundle their own fmt, built
// with exceptions turned off.
#include "image_module.hpp"

#include <fixpoint/errors.hpp>
#include <fixpoint/version.hpp>

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <memory>
#include <mutex>
#include <unistd.h>

namespace fp::host::image_module {
namespace {

// The writer and the spec of a raster image file: the same for a whole image and a streamed one.
std::pair<std::unique_ptr<OIIO::ImageOutput>, OIIO::ImageSpec>
image_writer(Format f, int width, int height, int channels, int bit_depth, const std::string& recipe,
             const Resolution& resolution, bool tiled) {
    if (is_vector(f)) throw InternalError("the image module writes raster images only");
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
bool write_tile_row(OIIO::ImageOutput& out, int width, int ch, int ty, int rows, const float* px,
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

std::vector<unsigned char> encode(const Image& img, const std::string& path, Format format, int bit_depth,
                                  const std::string& recipe, const Resolution& resolution, bool tiles) {
    auto [out, spec] =
        image_writer(format, img.width, img.height, img.channels, bit_depth, recipe, resolution, tiles);
    const char* oiio_format = out->format_name();
    // OpenImageIO's writers do not all check their writes to a file: past a file-size limit (as
    // on a full disk) the PNG and EXR writers reported success over a truncated file. So the
    // image is encoded in memory, and the host writes the bytes, checking every write, the
    // fsync and the close.
    std::vector<unsigned char> bytes;
    OIIO::Filesystem::IOVecOutput mem(bytes);
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
    return bytes;
}

// A file for OpenImageIO's writers that checks every write (they do not all check their own:
// see encode): positioned writes into a descriptor, the first error kept.
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

struct Stream {
    std::unique_ptr<CheckedFile> file;
    std::unique_ptr<OIIO::ImageOutput> out;
    int width = 0;
    int height = 0;
    /// Tiled: the rows of the row of tiles being filled.
    bool tiled = false;
    std::vector<float> tile_rows, tile;

    /// The first failure of the file itself (a full disk) before the encoder's account of it.
    std::string failure() const { return file->failure().empty() ? out->geterror() : file->failure(); }
};

namespace {

Stream* stream_open(const std::string& path, Format format, int fd, int width, int height, int bit_depth,
                    const std::string& recipe, const Resolution& resolution, bool tiled, std::string& error) {
    auto s = std::make_unique<Stream>();
    s->width = width;
    s->height = height;
    s->tiled = tiled;
    auto [out, spec] = image_writer(format, width, height, 3, bit_depth, recipe, resolution, tiled);
    if (tiled) s->tile_rows.assign(std::size_t(tile_side) * std::size_t(width) * 3, 0.0f);
    s->out = std::move(out);
    s->file = std::make_unique<CheckedFile>(path, fd);
    if (!s->out->set_ioproxy(s->file.get()) || !s->out->open(path, spec)) {
        error = s->out->geterror();
        return nullptr;
    }
    return s.release();
}

bool stream_rows(Stream* s, int y0, int rows, const float* rgb, std::string& error) {
    if (s->tiled) {
        // Rows gather into a row of tiles, written once whole (or at the image's last row).
        const std::size_t row = std::size_t(s->width) * 3;
        for (int y = y0; y < y0 + rows; ++y) {
            std::copy_n(rgb + std::size_t(y - y0) * row, row,
                        s->tile_rows.data() + std::size_t(y % tile_side) * row);
            if ((y + 1) % tile_side != 0 && y + 1 != s->height) continue;
            const int ty = y / tile_side * tile_side;
            if (!write_tile_row(*s->out, s->width, 3, ty, y + 1 - ty, s->tile_rows.data(), s->tile) ||
                !s->file->failure().empty()) {
                error = s->failure();
                return false;
            }
        }
        return true;
    }
    // 64 rows at a time: the writer converts what it is given to the file's type in a buffer
    // of its own, which a whole band would make as large as a fifth of the band.
    for (int y = y0; y < y0 + rows; y += 64) {
        const int y1 = std::min(y0 + rows, y + 64);
        const float* at = rgb + std::size_t(y - y0) * std::size_t(s->width) * 3;
        if (!s->out->write_scanlines(y, y1, 0, OIIO::TypeDesc::FLOAT, at) || !s->file->failure().empty()) {
            error = s->failure();
            return false;
        }
    }
    return true;
}

bool stream_close(Stream* s, std::string& error) {
    if (!s->out->close() || !s->file->failure().empty()) {
        error = s->failure();
        return false;
    }
    s->out.reset();
    return true;
}

/// Drops a stream; an unfinished encoder (a cancelled or failed render) is closed with the
/// process's stderr on /dev/null meanwhile. libpng, through OpenImageIO's PNG writer, prints its
/// own line ("libpng error: No IDATs written into file") when an image with no rows yet is
/// closed, before fixpoint's one line; the file is a temporary one, removed next. (A line that
/// another thread writes to stderr in that moment is lost too: on a path that is ending.)
void stream_free(Stream* s) {
    if (!s || !s->out) {
        delete s;
        return;
    }
    static std::mutex quiet;
    const std::lock_guard<std::mutex> lock(quiet);
    std::fflush(stderr);
    const int saved = ::dup(2), null = ::open("/dev/null", O_WRONLY | O_CLOEXEC);
    if (saved >= 0 && null >= 0) ::dup2(null, 2);
    delete s;
    if (saved >= 0 && null >= 0) ::dup2(saved, 2);
    if (null >= 0) ::close(null);
    if (saved >= 0) ::close(saved);
}

void quantise(const Image& img, int bit_depth, void* out) {
    const auto n = static_cast<OIIO::stride_t>(img.pixels.size());
    if (!OIIO::convert_pixel_values(OIIO::TypeDesc::FLOAT, img.pixels.data(),
                                    bit_depth == 16 ? OIIO::TypeDesc::UINT16 : OIIO::TypeDesc::UINT8, out, n))
        throw InternalError("OpenImageIO could not convert the pixels");
}

std::pair<std::string, std::string> read_description(const std::string& path) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) throw InputError("cannot read '" + path + "': " + OIIO::geterror());
    std::pair<std::string, std::string> r{in->spec().get_string_attribute("ImageDescription"),
                                          in->spec().get_string_attribute("Software")};
    in->close();
    return r;
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

Image contact_sheet(const std::vector<Image>& children, const std::vector<std::string>& captions,
                    const SheetLayout& L, bool* captions_drawn) {
    const int n = int(children.size());
    const int cw = L.cell_width, ch = L.cell_height, gap = L.gap, bar = L.bar, columns = L.columns;
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

Comparison compare(const std::string& a, const std::string& b, double threshold) {
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

constexpr Api api{abi,      encode,           stream_open, stream_rows,   stream_close, stream_free,
                  quantise, read_description, read_image,  contact_sheet, compare};

} // namespace
} // namespace fp::host::image_module

extern "C" __attribute__((visibility("default"))) const fp::host::image_module::Api* fixpoint_image_module() {
    return &fp::host::image_module::api;
}
