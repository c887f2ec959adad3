// Colour stealing, superfractal's and chaos-game's: the picture colours are stolen from (the
// built-in `hues`, or a PNG file read with Cairo), and what stealing does.
//
// Colour stealing (Barnsley, "Superfractals", 2006; "Ergodic theory, fractal tops and colour
// stealing", 2003; paper 03, Sec. V, proposes it for GM superfractals but gives no details)
// ------------------------------------------------------------------------------------------
// superfractal: with `picture`, a second IFS, the colour IFS, runs in lockstep with the fractal: each map
// f_j has a colour map g_j on the picture square [0, 1]^2 (its `colour_map`, affine
// [a, b, c, d, e, f]: u' = a u + b v + e, v' = c u + d v + f), and each buffer point carries
// a colour point (u, v) beside (x, y). When a share of a new buffer is f_j of source points,
// its colour points are g_j of the same source points' colour points: the same IFS, map and
// source buffer choices, the same source point. A child's point thus inherits its colour
// point from the parent point it came from, and after the steps (u, v) is the colour IFS's
// point with the fractal point's address. The child is deposited with the colour of the
// picture at (u, v) (nearest pixel; the square clamped to the picture), and the colourer only
// resolves the histogram: each pixel shows the mean colour of its points, shaded as the
// colourer says; its update() is not called. Colour points start at (1/2, 1/2) (a contraction
// forgets it; a colour map that keeps v, as the default, reads the picture's middle row).
// The default colour map of map t (from 0) of an IFS of m maps is ((u + t) / m, v): u is the
// point's address as a base-m fraction, Barnsley's "fractal homeomorphism" onto an interval;
// for curves made of just-touching pieces (F and G of paper 03, eq. (2)) the colour then runs
// continuously along every child. `picture` is `hues` (built in, 512 x 512: the hue wheel along
// u, deep to light along v) or a PNG file, relative to the config (the host resolves it) and read with Cairo
// (the image's recipe names the file, not its pixels). The colour IFS draws nothing from the
// random streams: a render with a picture has the geometry of the render without, pixel for
// pixel, and colour points are copied with their points when bad values are repaired.
// Barnsley's colour-stealing pictures colour each pixel by the point of the highest address
// through it (the "fractal top"); the histogram gives the mean of the colours of the points
// that fall in the pixel instead, which differs only where pieces overlap.
//
// chaos-game: each chain carries a colour point (u, v) beside its point, from (1/2, 1/2), and
// when map j moves the chain, map j's colour map moves (u, v); the point is plotted with the
// picture's colour at the new (u, v). The colour IFS runs in lockstep with the chain's own
// choices, so (u, v) is the colour IFS's point of the chain's address read backwards (its
// last maps first): the chaos game's points are the IFS attractor's point of that address
// (for contractive maps), and the colour is the same function of the point as in the buffer
// algorithm. The default colour maps and the picture are the superfractal's; the chains'
// streams, and so the geometry, are those of the render without a picture.
#pragma once

#include "cairo_out.hpp"

#include <fixpoint/fixpoint.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>
#include <vector>

namespace fp_render {

/// The picture colours are stolen from: 8-bit RGB, top row first. The point (u, v) of the
/// picture square [0, 1]^2 (v up) reads the pixel of column min(floor(u w), w - 1), row
/// min(floor((1 - v) h), h - 1), u and v clamped to [0, 1] first (NaN to 0).
struct Picture {
    int w = 0, h = 0;
    std::vector<unsigned char> rgb;

    fp::Rgb at(double u, double v) const {
        const double uc = u > 0.0 ? (u < 1.0 ? u : 1.0) : 0.0, vc = v > 0.0 ? (v < 1.0 ? v : 1.0) : 0.0;
        const int col = std::min(int(uc * double(w)), w - 1),
                  row = std::min(int((1.0 - vc) * double(h)), h - 1);
        const unsigned char* p = rgb.data() + 3 * (size_t(row) * size_t(w) + size_t(col));
        return fp::Rgb{float(p[0]) / 255.0f, float(p[1]) / 255.0f, float(p[2]) / 255.0f};
    }
};

/// The built-in picture `hues`, 512 x 512: the hue wheel along u (red at u = 0 and 1, then
/// yellow, green, cyan, blue, magenta), from deep (v = 0: value 0.45, saturation 1) to light
/// (v = 1: value 1, saturation 0.55).
inline Picture hues_picture() {
    Picture pic;
    pic.w = pic.h = 512;
    pic.rgb.resize(size_t(pic.w) * size_t(pic.h) * 3);
    for (int row = 0; row < pic.h; ++row) {
        const double v = 1.0 - (double(row) + 0.5) / double(pic.h);
        const double val = 0.45 + 0.55 * v, sat = 1.0 - 0.45 * v;
        for (int col = 0; col < pic.w; ++col) {
            const double h6 = 6.0 * (double(col) + 0.5) / double(pic.w);
            const int sector = std::min(int(h6), 5);
            const double f = h6 - double(sector);
            const double p = val * (1 - sat), q = val * (1 - sat * f), t = val * (1 - sat * (1 - f));
            double c[3];
            switch (sector) {
            case 0: c[0] = val, c[1] = t, c[2] = p; break;
            case 1: c[0] = q, c[1] = val, c[2] = p; break;
            case 2: c[0] = p, c[1] = val, c[2] = t; break;
            case 3: c[0] = p, c[1] = q, c[2] = val; break;
            case 4: c[0] = t, c[1] = p, c[2] = val; break;
            default: c[0] = val, c[1] = p, c[2] = q; break;
            }
            unsigned char* out = pic.rgb.data() + 3 * (size_t(row) * size_t(pic.w) + size_t(col));
            for (int k = 0; k < 3; ++k) out[k] = (unsigned char)(std::lround(c[k] * 255.0));
        }
    }
    return pic;
}

/// A PNG file read with Cairo, composited over black (its alpha, if any, is dropped so).
inline Picture png_picture(const std::string& file) {
    using fp_render::CairoContext;
    using fp_render::CairoSurface;
    auto refuse = [&](const std::string& why) {
        throw fp::ParamError("picture", "cannot read the picture \"" + fp::excerpt(file, 200) + "\": " + why +
                                            " (give a PNG file, relative to the config, or hues)");
    };
    {
        // Cairo tells a missing file apart, but reports any file that is not a PNG as "out of
        // memory": look at the signature first.
        // A FIFO or a device would block the open (or the read) for ever: a picture is a file.
        std::error_code ec;
        const auto st = std::filesystem::status(file, ec);
        if (!std::filesystem::exists(st)) refuse("no such file");
        if (!std::filesystem::is_regular_file(st)) refuse("it is not a regular file");
        std::ifstream in(file, std::ios::binary);
        if (!in) refuse("it cannot be opened");
        char sig[8] = {};
        in.read(sig, 8);
        if (in.gcount() != 8 || std::memcmp(sig, "\x89PNG\r\n\x1a\n", 8) != 0) refuse("it is not a PNG file");
    }
    const CairoSurface png(cairo_image_surface_create_from_png(file.c_str()));
    if (const cairo_status_t st = cairo_surface_status(png.get()); st != CAIRO_STATUS_SUCCESS)
        refuse(std::string("Cairo cannot decode it (") + cairo_status_to_string(st) + ")");
    Picture pic;
    pic.w = cairo_image_surface_get_width(png.get());
    pic.h = cairo_image_surface_get_height(png.get());
    const CairoSurface rgb(cairo_image_surface_create(CAIRO_FORMAT_RGB24, pic.w, pic.h));
    {
        const CairoContext cr(cairo_create(rgb.get()));
        cairo_set_source_rgb(cr.get(), 0, 0, 0);
        cairo_paint(cr.get());
        cairo_set_source_surface(cr.get(), png.get(), 0, 0);
        cairo_paint(cr.get());
    }
    cairo_surface_flush(rgb.get());
    const unsigned char* data = cairo_image_surface_get_data(rgb.get());
    const int stride = cairo_image_surface_get_stride(rgb.get());
    pic.rgb.resize(size_t(pic.w) * size_t(pic.h) * 3);
    for (int r = 0; r < pic.h; ++r) {
        const auto* row = reinterpret_cast<const std::uint32_t*>(data + size_t(r) * size_t(stride));
        for (int c = 0; c < pic.w; ++c) {
            unsigned char* out = pic.rgb.data() + 3 * (size_t(r) * size_t(pic.w) + size_t(c));
            out[0] = (unsigned char)((row[c] >> 16) & 0xff);
            out[1] = (unsigned char)((row[c] >> 8) & 0xff);
            out[2] = (unsigned char)(row[c] & 0xff);
        }
    }
    return pic;
}

} // namespace fp_render
