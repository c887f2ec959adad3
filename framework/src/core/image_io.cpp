// Image files: formats, checks and atomic writes here; the encoding and decoding of raster
// images through OpenImageIO in the image module (framework/image/), loaded on first use.
#include <fixpoint/errors.hpp>
#include <fixpoint/host/core/image_io.hpp>
#include <fixpoint/text.hpp>

#include "../../image/image_module.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <dlfcn.h>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <mutex>
#include <random>
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

int open_temp_beside(const fs::path& target, fs::path& tmp) {
    // The random part: unguessable enough that a link cannot be planted ahead, and unique
    // between the threads of one process (serve writes side by side).
    static std::mutex m;
    static std::random_device seed;
    static std::mt19937_64 rng(seed());
    for (int attempt = 0; attempt < 64; ++attempt) {
        std::uint64_t r;
        {
            const std::lock_guard<std::mutex> lock(m);
            r = rng();
        }
        char hex[17];
        std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(r));
        tmp = target.parent_path() /
              ("." + target.filename().string() + ".tmp-" + std::to_string(::getpid()) + "-" + hex);
        const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
        if (fd >= 0 || errno != EEXIST) {
            if (fd < 0) tmp.clear();
            return fd;
        }
    }
    tmp.clear();
    errno = EEXIST;
    return -1;
}

static void check_image_module(const std::string& path);

void check_output(const std::string& path, bool folder_may_be_made) {
    // A NUL ends the name the system sees: "x.sh\0.png" would pass the checks below as a PNG
    // and write "x.sh". Control characters are refused with it: no file name needs them.
    for (const char ch : path)
        if (static_cast<unsigned char>(ch) < 0x20 || ch == 0x7f)
            throw InputError("cannot write " + quote(path, 200) + ": the name holds a control character");
    if (!is_vector(format_for(path))) check_image_module(path);
    const fs::path target(path);
    std::error_code ec;
    if (fs::is_directory(target, ec)) throw InputError("cannot write '" + path + "': it is a folder");
    fs::path dir = target.parent_path().empty() ? fs::path(".") : target.parent_path();
    if (!fs::is_directory(dir, ec)) {
        if (!folder_may_be_made)
            throw InputError("cannot write '" + path + "': folder '" + dir.string() + "' does not exist");
        // The folder is made later: the nearest one above it that exists must take it.
        while (!dir.empty() && !fs::exists(fs::symlink_status(dir, ec))) dir = dir.parent_path();
        if (dir.empty()) dir = ".";
        if (!fs::is_directory(dir, ec))
            throw InputError("cannot write '" + path + "': '" + dir.string() + "' is not a folder");
        if (::access(dir.c_str(), W_OK | X_OK) != 0)
            throw InputError("cannot write '" + path + "': cannot make a folder in '" + dir.string() +
                             "': " + std::strerror(errno));
        return;
    }
    // Probe with a temporary file as the real write will make.
    fs::path probe;
    const int fd = open_temp_beside(target, probe);
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

// ---------------------------------------------------------------- the image module
namespace {
std::mutex module_mutex;
std::string module_path_set; // set_image_module_path's, else beside the executable
const image_module::Api* module_api = nullptr;

std::string module_path() {
    if (!module_path_set.empty()) return module_path_set;
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (ec) throw InputError("cannot find fixpoint's image module: /proc/self/exe: " + ec.message());
    return (exe.parent_path() / FIXPOINT_IMAGE_MODULE_REL_PATH).lexically_normal().string();
}
} // namespace

void set_image_module_path(const std::string& path) {
    const std::lock_guard<std::mutex> lock(module_mutex);
    module_path_set = path;
}

/// The image module's table, the module loaded the first time (and kept: its objects live
/// in the process until it ends). fp::InputError when it cannot be loaded.
static const image_module::Api& image_api() {
    const std::lock_guard<std::mutex> lock(module_mutex);
    if (module_api) return *module_api;
    const std::string path = module_path();
    void* lib = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!lib) {
        const char* why = ::dlerror();
        throw InputError("cannot load fixpoint's image module " + quote(path, 200) + ": " +
                         excerpt(why ? why : "unknown error", 200) + " (reinstall fixpoint)");
    }
    using Entry = const image_module::Api* (*)();
    const auto entry = reinterpret_cast<Entry>(::dlsym(lib, "fixpoint_image_module"));
    const image_module::Api* api = entry ? entry() : nullptr;
    if (!api || api->abi != image_module::abi)
        throw InputError("fixpoint's image module " + quote(path, 200) +
                         " was built with another fixpoint (reinstall fixpoint)");
    module_api = api;
    return *api;
}

/// Before a render that writes a raster image to `path`: the image module is there (a look
/// at its file, not a load, which takes 0.2 s: `validate` stays quick), so that a broken
/// install is said before the render rather than after it.
static void check_image_module(const std::string& path) {
    std::string module;
    {
        const std::lock_guard<std::mutex> lock(module_mutex);
        if (module_api) return;
        module = module_path();
    }
    std::error_code ec;
    if (!fs::is_regular_file(module, ec))
        throw InputError("cannot write " + quote(path, 200) + ": fixpoint's image module " +
                         quote(module, 200) + " is missing (reinstall fixpoint)");
}

/// The format of a raster image file at `path`. fp::InputError for SVG and PDF.
static Format raster_format(const std::string& path) {
    const Format f = format_for(path);
    if (is_vector(f))
        throw InputError("'" + path +
                         "': SVG and PDF are written only by renderers with vector output (use .png, "
                         ".exr, .tif or .tiff)");
    return f;
}

void write_image(const Image& img, const std::string& path, int bit_depth, const std::string& recipe,
                 const Resolution& resolution, Tiled tiled, const std::atomic<bool>* cancel) {
    const bool tiles = tiled_file(path, img.width, img.height, tiled);
    const Format f = raster_format(path);
    // Encoded in memory, then written here: OpenImageIO's writers do not all check their
    // writes to a file (image_module::Api::encode).
    const std::vector<unsigned char> bytes =
        image_api().encode(img, path, f, bit_depth, recipe, resolution, tiles);
    write_bytes(reinterpret_cast<const char*>(bytes.data()), bytes.size(), path, cancel);
}

std::string encode_image(const Image& img, Format format, int bit_depth, const std::string& recipe,
                         const Resolution& resolution, Tiled tiled) {
    if (is_vector(format)) throw InternalError("encode_image: a raster format");
    const std::string name = format == Format::Png   ? "image.png"
                             : format == Format::Exr ? "image.exr"
                                                     : "image.tif";
    const bool tiles = tiled_file(name, img.width, img.height, tiled);
    const std::vector<unsigned char> bytes =
        image_api().encode(img, name, format, bit_depth, recipe, resolution, tiles);
    return {bytes.begin(), bytes.end()};
}

struct StreamedImage::Impl {
    std::string path;
    fs::path tmp;
    int fd = -1;
    const image_module::Api* api = nullptr;
    image_module::Stream* enc = nullptr;
    int height = 0, next = 0;
    bool done = false;

    Impl() = default;
    Impl(const Impl&) = delete;
    Impl& operator=(const Impl&) = delete;
    /// Unfinished (an error, a cancel, or a constructor that failed half way): the encoder
    /// is dropped and the partial file removed.
    ~Impl() {
        if (enc) api->stream_free(enc);
        if (done) return;
        if (fd >= 0) ::close(fd);
        std::error_code ec;
        if (!tmp.empty()) fs::remove(tmp, ec);
    }

    [[noreturn]] void fail(const std::string& why) {
        throw WriteError("cannot write '" + path + "': " + why);
    }
};

StreamedImage::StreamedImage(const std::string& path, int width, int height, int bit_depth,
                             const std::string& recipe, const Resolution& resolution, Tiled tiled)
    : impl_(std::make_unique<Impl>()) {
    Impl& m = *impl_;
    m.path = path;
    m.height = height;
    const bool tiles = tiled_file(path, width, height, tiled);
    const Format f = raster_format(path);
    m.api = &image_api();
    m.fd = open_temp_beside(fs::path(path), m.tmp); // (m.tmp empty when it fails: nothing to remove)
    if (m.fd < 0) m.fail(std::strerror(errno));
    std::string error;
    m.enc = m.api->stream_open(path, f, m.fd, width, height, bit_depth, recipe, resolution, tiles, error);
    if (!m.enc) m.fail(error);
}

WriteError::~WriteError() = default;

StreamedImage::~StreamedImage() = default;

void StreamedImage::rows(int y0, int rows, const float* rgb) {
    Impl& m = *impl_;
    if (y0 != m.next || rows < 0 || y0 + rows > m.height)
        throw InternalError("StreamedImage: rows out of order");
    std::string error;
    if (!m.api->stream_rows(m.enc, y0, rows, rgb, error)) m.fail(error);
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
    std::string error;
    if (!m.api->stream_close(m.enc, error)) m.fail(error);
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
    image_api().quantise(img, bit_depth, out);
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

void write_bytes(const std::string& bytes, const std::string& path, const std::atomic<bool>* cancel) {
    write_bytes(bytes.data(), bytes.size(), path, cancel);
}

void write_bytes(const char* data, std::size_t size, const std::string& path,
                 const std::atomic<bool>* cancel) {
    if (cancel && cancel->load()) throw Cancelled();
    const fs::path target(path);
    fs::path tmp;
    const int fd = open_temp_beside(target, tmp);
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
    if (cancel && cancel->load()) {
        ::unlink(tmp.c_str());
        throw Cancelled();
    }
    std::error_code ec;
    fs::rename(tmp, target, ec);
    if (ec) {
        fs::remove(tmp, ec);
        throw InputError("cannot write '" + path + "': " + ec.message());
    }
}

FileSet::~FileSet() {
    std::error_code ec;
    for (const auto& f : written_) fs::remove(f, ec);
}

void FileSet::poll() const {
    if (cancel_ && cancel_->load()) throw Cancelled();
}

void FileSet::image(const Image& img, const std::string& path, int bit_depth, const std::string& recipe,
                    Tiled tiled, const Resolution& resolution) {
    poll();
    write_image(img, path, bit_depth, recipe, resolution, tiled, cancel_);
    written_.push_back(path);
}

void FileSet::bytes(const std::string& data, const std::string& path) {
    poll();
    write_bytes(data, path, cancel_);
    written_.push_back(path);
}

std::string read_recipe(const std::string& path) {
    // A device or a pipe (/dev/zero) would be read for ever: a recipe lives in a file.
    std::error_code ec;
    const auto st = fs::status(path, ec);
    if (ec) throw InputError("cannot read " + quote(path, 200) + ": " + ec.message());
    if (!fs::is_regular_file(st))
        throw InputError("cannot read " + quote(path, 200) + ": not a regular file");
    if (format_for_or_png(path) == Format::Svg) return read_svg_recipe(path);
    const auto [desc, software] = image_api().read_description(path);
    if (desc.empty() || software.rfind("fixpoint", 0) != 0)
        throw InputError("'" + path + "' holds no fixpoint recipe (it was not written by fixpoint)");
    return desc;
}

Image read_image(const std::string& path) { return image_api().read_image(path); }

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
    return image_api().contact_sheet(children, captions, L, captions_drawn);
}

Comparison compare_images(const std::string& a, const std::string& b, double threshold) {
    return image_api().compare(a, b, threshold);
}

} // namespace fp::host
