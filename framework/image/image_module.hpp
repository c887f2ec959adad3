// The image module (fixpoint-image.so): fixpoint's use of OpenImageIO, in a library of its
// own that the host loads the first time it reads or writes a raster image
// (framework/src/image_io.cpp). OpenImageIO as Debian builds it links about 260 libraries;
// their relocations took about 0.2 s at the start of every process, most of `fixpoint
// --version` or of a `validate`. The host and the module are built together: the table
// below is their whole interface, and `abi` tells a stale module from the one built with
// the host.
//
// Errors: fp::InputError and fp::InternalError (the SDK's types, shared by both) pass
// through as exceptions; a failed write of a streamed image comes back as text, for the host
// to raise as fp::host::WriteError (its own type).
#pragma once

#include <fixpoint/host/core/image_io.hpp>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace fp::host::image_module {

constexpr std::uint32_t abi = 1;

/// The module's encoder of a streamed image (opaque to the host).
struct Stream;

struct Api {
    std::uint32_t abi;
    /// The bytes of the file of a whole image: PNG, EXR or TIFF (`format`), tiled or not, as
    /// fp::host::write_image describes.
    std::vector<unsigned char> (*encode)(const Image& img, const std::string& path, Format format,
                                         int bit_depth, const std::string& recipe,
                                         const Resolution& resolution, bool tiled);
    /// An encoder writing a width x height RGB image into the open file `fd`; null, with the
    /// reason in `error`, when it cannot start.
    Stream* (*stream_open)(const std::string& path, Format format, int fd, int width, int height,
                           int bit_depth, const std::string& recipe, const Resolution& resolution, bool tiled,
                           std::string& error);
    /// The next `rows` rows from y0 (in order); false, with the reason in `error`, when the
    /// file or the encoder failed.
    bool (*stream_rows)(Stream* s, int y0, int rows, const float* rgb, std::string& error);
    /// Ends the encoding (the file is then whole, not yet synced); false as stream_rows.
    bool (*stream_close)(Stream* s, std::string& error);
    void (*stream_free)(Stream* s);
    /// fp::host::quantise_pixels.
    void (*quantise)(const Image& img, int bit_depth, void* out);
    /// A raster image's ImageDescription and Software attributes.
    std::pair<std::string, std::string> (*read_description)(const std::string& path);
    Image (*read_image)(const std::string& path);
    /// The sheet of contact_sheet, drawn on the layout the host computed.
    Image (*contact_sheet)(const std::vector<Image>& children, const std::vector<std::string>& captions,
                           const SheetLayout& layout, bool* captions_drawn);
    Comparison (*compare)(const std::string& a, const std::string& b, double threshold);
};

} // namespace fp::host::image_module

/// The module's one exported symbol.
extern "C" const fp::host::image_module::Api* fixpoint_image_module();
