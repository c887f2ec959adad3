// `fixpoint render --tile`, `--dpi` and `--print-size`: one period of a periodic pattern, and the
// print size an image declares.
#pragma once

#include <fixpoint/host/image_io.hpp>
#include <fixpoint/host/pipeline.hpp>
#include <fixpoint/host/registry.hpp>

#include <string>
#include <vector>

namespace fp::host {

/// What the render command was asked for: --tile, --dpi N, --print-size SIZE.
struct PrintRequest {
    bool tile = false;
    double dpi = 0;         ///< 0: not given
    std::string print_size; ///< empty: not given
    bool any() const { return tile || dpi > 0 || !print_size.empty(); }
};

/// --print-size: a physical width, or width x height, each a number and a unit (mm, cm or in):
/// "30cm", "30cmx20cm", "12in", "297mmx210mm". In inches; height 0 when not given. Throws
/// fp::InputError naming the option.
struct PrintSize {
    double width = 0, height = 0;
};
PrintSize parse_print_size(const std::string& s);

/// load_pipeline with what `req` implies:
///   --dpi with --print-size: the size in pixels, renderer.width = round(width * dpi) (and
///     renderer.height likewise when a height is given; not with --tile, whose height follows
///     from its width);
///   --tile: renderer.tile = true, for a renderer that declares `tile` (orbit-trap); any other
///     refuses with "--tile: the RENDERER renderer draws no periodic pattern; only orbit-trap
///     renders one period (with a wallpaper mapping)".
/// Throws fp::InputError.
Pipeline load_for_print(const Registry& reg, const std::string& config, std::vector<std::string> sets,
                        const PrintRequest& req);

/// The resolution to declare for a width x height image: --dpi as given, or, from --print-size
/// alone, pixels / inches (the height's when given, else the width's for both: square pixels).
/// None without either.
Resolution print_resolution(const PrintRequest& req, int width, int height);

} // namespace fp::host
