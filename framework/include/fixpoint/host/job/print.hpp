// `fixpoint render --tile`, `--dpi` and `--print-size`: one period of a periodic pattern, and the
// print size an image declares.
#pragma once

#include <fixpoint/host/core/image_io.hpp>
#include <fixpoint/host/core/pipeline.hpp>
#include <fixpoint/host/core/registry.hpp>

#include <string>
#include <vector>

namespace fp::host {

/// What the render command was asked for: --tile, --repeat NxM, --dpi N, --print-size SIZE.
struct PrintRequest {
    bool tile = false;
    std::string repeat;     ///< empty: not given
    double dpi = 0;         ///< 0: not given
    std::string print_size; ///< empty: not given
    bool any() const { return tile || !repeat.empty() || dpi > 0 || !print_size.empty(); }
};

/// --print-size: a physical width, or width x height, each a number and a unit (mm, cm or in):
/// "30cm", "30cmx20cm", "12in", "297mmx210mm". In inches; height 0 when not given. Throws
/// fp::InputError naming the option.
struct PrintSize {
    double width = 0, height = 0;
};
PrintSize parse_print_size(const std::string& s);

/// --repeat: "NxM", N copies across and M down, each 1 to 16 (a preview of the tiling; only
/// with --tile). Throws fp::InputError naming the option.
struct Repeat {
    int across = 1, down = 1;
};
Repeat parse_repeat(const PrintRequest& req);

/// The image repeated r.across x r.down times.
Image repeat_image(const Image& img, const Repeat& r);

/// load_pipeline with what `req` implies:
///   --dpi with --print-size: the size in pixels, renderer.width = round(width * dpi) (and
///     renderer.height likewise when a height is given; not with --tile, whose height follows
///     from its width);
///   --tile: renderer.tile = true, for a renderer that declares `tile` (orbit-trap); any other
///     refuses with "--tile: the RENDERER renderer draws no periodic pattern; only orbit-trap
///     renders one period (with a wallpaper mapping)", and the renderer's refusal of `tile`
///     is said as "--tile: ...";
///   --repeat: checked (NxM, with --tile, at most 65536 pixels across and down).
/// `allow_code` as load_pipeline's. Throws fp::InputError.
Pipeline load_for_print(const Registry& reg, const std::string& config, std::vector<std::string> sets,
                        const PrintRequest& req, bool allow_code = false);

/// The resolution to declare for a width x height image: --dpi as given, or, from --print-size
/// alone, pixels / inches (the height's when given, else the width's for both: square pixels).
/// None without either.
Resolution print_resolution(const PrintRequest& req, int width, int height);

} // namespace fp::host
