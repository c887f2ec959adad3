// --tile, --dpi, --print-size (see fixpoint/host/job/print.hpp).
#include <fixpoint/errors.hpp>
#include <fixpoint/host/core/build.hpp>
#include <fixpoint/host/job/print.hpp>
#include <fixpoint/text.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>

namespace fp::host {

namespace {

// One length: a positive number followed by mm, cm or in; in inches.
double length_inches(const std::string& all, const std::string& s) {
    const auto bad = [&]() {
        return InputError("--print-size: expected WIDTH or WIDTHxHEIGHT, each a positive number and a unit "
                          "(mm, cm or in), as 30cm or 30cmx20cm, got " +
                          quote(all));
    };
    double v = 0;
    const char* end = s.data() + s.size();
    const auto [rest, ec] = std::from_chars(s.data(), end, v);
    if (ec != std::errc() || !(v > 0) || !std::isfinite(v)) throw bad();
    const std::string unit(rest, end);
    if (unit == "mm") return v / 25.4;
    if (unit == "cm") return v / 2.54;
    if (unit == "in") return v;
    throw bad();
}

} // namespace

PrintSize parse_print_size(const std::string& s) {
    const auto x = s.find('x');
    if (x == std::string::npos) return {length_inches(s, s), 0};
    return {length_inches(s, s.substr(0, x)), length_inches(s, s.substr(x + 1))};
}

Repeat parse_repeat(const PrintRequest& req) {
    if (req.repeat.empty()) return {};
    if (!req.tile) throw InputError("--repeat: repeats a tile: give --tile too");
    const std::string& s = req.repeat;
    const auto bad = [&]() {
        return InputError("--repeat: expected NxM, copies across and down (1 to 16 each), as 3x3, got " +
                          quote(s));
    };
    const auto x = s.find('x');
    if (x == std::string::npos) throw bad();
    Repeat r;
    const auto [a, ea] = std::from_chars(s.data(), s.data() + x, r.across);
    const auto [b, eb] = std::from_chars(s.data() + x + 1, s.data() + s.size(), r.down);
    if (ea != std::errc() || eb != std::errc() || a != s.data() + x || b != s.data() + s.size() ||
        r.across < 1 || r.across > 16 || r.down < 1 || r.down > 16)
        throw bad();
    return r;
}

Image repeat_image(const Image& img, const Repeat& r) {
    if (r.across == 1 && r.down == 1) return img;
    Image out;
    out.width = img.width * r.across, out.height = img.height * r.down, out.channels = img.channels;
    out.pixels.resize(std::size_t(out.width) * std::size_t(out.height) * std::size_t(out.channels));
    const std::size_t row = std::size_t(img.width) * std::size_t(img.channels);
    for (int j = 0; j < out.height; ++j)
        for (int i = 0; i < r.across; ++i)
            std::copy_n(img.pixels.data() + std::size_t(j % img.height) * row, row,
                        out.pixels.data() + (std::size_t(j) * std::size_t(r.across) + std::size_t(i)) * row);
    return out;
}

Pipeline load_for_print(const Registry& reg, const std::string& config, std::vector<std::string> sets,
                        const PrintRequest& req, bool allow_code) {
    parse_repeat(req); // checked before the render
    if (req.dpi > 0 && !req.print_size.empty()) {
        const PrintSize size = parse_print_size(req.print_size);
        if (req.tile && size.height > 0)
            throw InputError("--print-size: a tile's height follows from its width: give the width only (" +
                             quote(req.print_size) + ")");
        const auto pixels = [&](double inches, const char* what) {
            const double n = std::round(inches * req.dpi);
            if (n < 1 || n > 65536)
                throw InputError("--print-size " + req.print_size + " at --dpi " + format_real(req.dpi) +
                                 ": " + what + " of " + format_real(n) + " pixels (1 to 65536)");
            return std::to_string(static_cast<long long>(n));
        };
        const std::string width = pixels(size.width, "a width");
        if (size.height == 0 && !req.tile) {
            // The width alone: the height follows in proportion, so that the pixels keep their
            // shape over the renderer's view (a tile's height follows from its width anyway).
            const Pipeline before = load_pipeline(reg, config, sets, "", allow_code);
            const double h = std::round(double(before.renderer->height()) * std::stod(width) /
                                        double(before.renderer->width()));
            sets.push_back("renderer.height=" + pixels(h / req.dpi, "a height (in proportion to the width)"));
        }
        sets.push_back("renderer.width=" + width);
        if (size.height > 0) sets.push_back("renderer.height=" + pixels(size.height, "a height"));
    } else if (!req.print_size.empty()) {
        parse_print_size(req.print_size); // checked before the render
    }
    if (!req.tile) return load_pipeline(reg, config, sets, "", allow_code);
    const Pipeline plain = load_pipeline(reg, config, sets, "", allow_code);
    const PluginEntry* r = reg.find(plain.renderer_type);
    bool declares = false;
    for (std::uint32_t i = 0; r && r->desc && i < r->desc->n_params; ++i)
        declares = declares || std::strcmp(r->desc->params[i].name, "tile") == 0;
    if (!declares)
        throw InputError("--tile: the " + plain.renderer_type +
                         " renderer draws no periodic pattern; only orbit-trap renders one period (with a "
                         "wallpaper mapping)");
    sets.push_back("renderer.tile=true");
    try {
        Pipeline p = load_pipeline(reg, config, sets, "", allow_code);
        const Repeat r = parse_repeat(req);
        if (r.across * r.down > 1 && (std::int64_t(p.renderer->width()) * r.across > 65536 ||
                                      std::int64_t(p.renderer->height()) * r.down > 65536))
            throw InputError("--repeat " + req.repeat + ": the " + std::to_string(p.renderer->width()) + "x" +
                             std::to_string(p.renderer->height()) +
                             " tile repeated would be wider or taller than 65536 pixels");
        return p;
    } catch (const InputError& e) {
        // The renderer's refusal of `tile`, said as the option the user gave.
        const std::string m = e.what(), at = "--set renderer.tile=true: renderer.tile: ";
        if (m.rfind(at, 0) == 0) throw InputError("--tile: " + m.substr(at.size()));
        throw;
    }
}

Resolution print_resolution(const PrintRequest& req, int width, int height) {
    if (req.dpi > 0) return {req.dpi, req.dpi};
    if (req.print_size.empty()) return {};
    const PrintSize size = parse_print_size(req.print_size);
    const double x = double(width) / size.width;
    return {x, size.height > 0 ? double(height) / size.height : x};
}

} // namespace fp::host
