// Image files: their formats, checks and atomic writes, and (through the image module,
// framework/image/) OpenImageIO's encoding and decoding of raster images.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <utility>

#include <fixpoint/errors.hpp>
#include <fixpoint/render.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace fp::host {

/// Raster images are encoded and decoded by the image module (fixpoint-image.so, through
/// OpenImageIO), loaded the first time one is read or written: a process that writes none
/// (validate, describe, an error) does not pay for OpenImageIO's libraries. It is found
/// beside the executable's folder (lib/fixpoint/ from bin/, in the build tree as installed);
/// a library that links the host elsewhere (the Python module) names it here, before any
/// image is read or written.
void set_image_module_path(const std::string& path);

enum class Format { Png, Exr, Tiff, Svg, Pdf };

/// SVG and PDF: written by renderers with vector output (Renderer::render_vector).
inline bool is_vector(Format f) { return f == Format::Svg || f == Format::Pdf; }

/// Whether `path` names an image whose recipe can be rendered (.png, .exr, .tif, .tiff, .svg).
bool is_recipe_image(const std::string& path);

/// The format for an output path's extension (.png, .exr, .tif, .tiff, .svg, .pdf; any case).
/// Throws fp::InputError for anything else.
Format format_for(const std::string& path);

/// Check, before rendering, that `path` has a known format and that its folder takes a new
/// file (with `folder_may_be_made`, a missing folder is fine where the nearest folder above it
/// that exists takes a new one: it is made before the write). Throws fp::InputError.
void check_output(const std::string& path, bool folder_may_be_made = false);

/// The print resolution an image declares, in pixels per inch (0: none declared).
struct Resolution {
    double x = 0, y = 0;
};

/// Tiles of a tiled TIFF or EXR: square, this many pixels a side (the size viewers of large
/// images read fastest; the last row and column of tiles are cut by the image's edge).
constexpr int tile_side = 256;
/// `output.tiled`: auto (the default: TIFF and EXR images of more than tiled_above pixels),
/// always, or never.
enum class Tiled { Auto, Yes, No };
constexpr std::uint64_t tiled_above = std::uint64_t(1) << 26; // 8192 x 8192
/// Whether an image of width x height written to `path` is tiled. fp::InputError for Tiled::Yes
/// with a format that has no tiles (PNG).
bool tiled_file(const std::string& path, int width, int height, Tiled tiled);

/// Write atomically (a temporary file beside the target, then rename): a failed write never
/// leaves a partial file at `path`. PNG and TIFF take `bit_depth` 8 or 16; EXR is float.
/// `recipe` goes into the ImageDescription metadata; a resolution, when given, into
/// XResolution, YResolution and ResolutionUnit "inch" (TIFF's tags, PNG's pHYs chunk). TIFF
/// and EXR in tiles of tile_side where tiled_file says so.
/// `cancel`, when given, is polled after the encoding and before the file takes `path`'s name
/// (fp::Cancelled: nothing written, a file there before kept).
void write_image(const Image& img, const std::string& path, int bit_depth, const std::string& recipe,
                 const Resolution& resolution = {}, Tiled tiled = Tiled::Auto,
                 const std::atomic<bool>* cancel = nullptr);

/// The bytes of the file write_image would write (PNG, EXR or TIFF), for a front end that sends
/// them rather than keeping a file (serve's preview).
std::string encode_image(const Image& img, Format format, int bit_depth, const std::string& recipe,
                         const Resolution& resolution = {}, Tiled tiled = Tiled::Auto);

/// A write of the output that failed (a full disk): raised by a StreamedImage from inside a
/// render, and reported as it is, not as the renderer's.
class WriteError : public InputError {
public:
    using InputError::InputError;
    ~WriteError() override;
};

/// An image written band by band as a renderer streams it (fp::RowSink, Renderer::render_rows),
/// so that it is never whole in memory: the same file write_image makes of the same pixels,
/// encoded straight into a temporary file beside `path` with every write checked, and renamed
/// over `path` by finish(). Until then, and when anything fails, nothing is left at `path`
/// (the destructor removes the temporary file). PNG, EXR and TIFF.
class StreamedImage final : public RowSink {
public:
    StreamedImage(const std::string& path, int width, int height, int bit_depth, const std::string& recipe,
                  const Resolution& resolution = {}, Tiled tiled = Tiled::Auto);
    /// The memory a tiled file holds while its rows come (a row of tiles), 0 for scanlines.
    static std::uint64_t held_bytes(const std::string& path, int width, int height, Tiled tiled);
    ~StreamedImage() override;
    void rows(int y0, int rows, const float* rgb) override;
    /// Closes the encoder, syncs the file and puts it at `path`. Throws fp::InputError.
    void finish();
    /// The temporary file being written (for a signal handler that must remove it).
    std::string temporary_path() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

/// The pixels as an 8- or 16-bit PNG or TIFF of write_image stores them (OpenImageIO's
/// conversion, the one write_image uses): width * height * channels values of `bit_depth` bits
/// at `out` (std::uint8_t or std::uint16_t).
void quantise_pixels(const Image& img, int bit_depth, void* out);
/// A new temporary file beside `target`, for a write renamed over it when complete: a name of
/// its own (".NAME.tmp-PID-RANDOM"), created with O_CREAT | O_EXCL | O_NOFOLLOW, so that
/// nothing planted at a guessable name (a symbolic link out of the folder) is followed or
/// written through. Returns the descriptor and sets `tmp`; -1 with errno set when it cannot.
int open_temp_beside(const std::filesystem::path& target, std::filesystem::path& tmp);
/// Write a whole file (a vector document) atomically, as write_image does. Throws fp::InputError.
void write_bytes(const std::string& bytes, const std::string& path,
                 const std::atomic<bool>* cancel = nullptr);
void write_bytes(const char* data, std::size_t size, const std::string& path,
                 const std::atomic<bool>* cancel = nullptr);

/// Files written as one whole (a render's image, a collection's children and contact sheet,
/// explore's results): `cancel` is polled before each write and before each file takes its
/// name (fp::Cancelled when set: a Ctrl-C while an image is encoded is not ignored); unless
/// commit() is called, the destructor removes every file written so far, so that a full disk
/// or a Ctrl-C half way leaves none of them.
class FileSet {
public:
    explicit FileSet(const std::atomic<bool>* cancel) : cancel_(cancel) {}
    FileSet(const FileSet&) = delete;
    FileSet& operator=(const FileSet&) = delete;
    ~FileSet();
    void image(const Image& img, const std::string& path, int bit_depth, const std::string& recipe,
               Tiled tiled = Tiled::Auto, const Resolution& resolution = {});
    void bytes(const std::string& data, const std::string& path);
    /// Every file is written: they stay.
    void commit() { written_.clear(); }

private:
    void poll() const;
    const std::atomic<bool>* cancel_;
    std::vector<std::string> written_;
};

/// The recipe embedded in an image written by fixpoint. Throws fp::InputError.
std::string read_recipe(const std::string& path);

/// Read an image as float RGB(A) pixels. Throws fp::InputError.
Image read_image(const std::string& path);

/// A contact sheet: the children in a grid of `columns` (0: about square), each with its
/// caption in a bar beneath it (DejaVu Sans when installed, else OpenImageIO's default font; no
/// caption, and `captions_drawn` false, when no font can be found).
/// The geometry of a contact sheet of children of these sizes (64-bit: a sheet can be huge).
struct SheetLayout {
    int cell_width = 0, cell_height = 0, columns = 1, gap = 2, bar = 18;
    std::int64_t width = 0, height = 0;
};
SheetLayout contact_sheet_layout(const std::vector<std::pair<int, int>>& sizes, int columns);

Image contact_sheet(const std::vector<Image>& children, const std::vector<std::string>& captions, int columns,
                    bool* captions_drawn = nullptr);

struct Comparison {
    double max_error = 0, mean_error = 0;
    std::size_t n_fail = 0; ///< pixels whose error exceeds the threshold
    bool size_mismatch = false;
};
/// Compare two image files with ImageBufAlgo::compare; `threshold` is per channel in [0, 1].
Comparison compare_images(const std::string& a, const std::string& b, double threshold);

} // namespace fp::host
