// Drawing an mfs's polygons with Cairo: raster (an antialiased image surface, handed to the
// host as an fp::Image) and vector (SVG, PDF documents as bytes).
//
// Polygons come in drawing order as runs of one colour; a run is filled as one path with the
// nonzero winding rule, so the shared edges of neighbouring tiles of one colour leave no
// antialiasing seam. Cairo draws on one thread, in order: the bytes depend only on the recipe.
#pragma once

#include "cairo_out.hpp"
#include "uninitialised.hpp"

#include <fixpoint/errors.hpp>
#include <fixpoint/render.hpp>
#include <fixpoint/types.hpp>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace fp_mfs {

enum class DrawMode { Fill, Outline, Points };

/// Polygons of n vertices (x, y in world coordinates, polygon p at [p n, (p + 1) n)), each
/// with a colour; `order` gives the drawing order of a polygon's vertices.
struct Layer {
    std::size_t n = 0;
    fp_render::Buffer<double> x, y;
    std::vector<fp::Rgb> colour;
    std::vector<std::size_t> order;
    std::size_t count() const { return n ? x.size() / n : 0; }
};

struct Label {
    double x, y; ///< world coordinates of the centre
    std::string text;
};

struct Scene {
    int width = 512, height = 512;
    fp::Box view;
    fp::Rgb background{1, 1, 1};
    DrawMode mode = DrawMode::Fill;
    double line_width = 1;
    std::vector<Layer> layers;
    std::vector<Layer> highlights; ///< stroked on top, thick
    std::vector<Label> labels;
    fp::Rgb mark_colour{1, 0, 0};
    double label_size = 14;
    /// Polled while drawing (a scene of 5e7 polygons takes seconds); null: not cancellable.
    const fp::RenderContext* ctx = nullptr;
};

inline void draw_scene(cairo_t* cr, const Scene& s) {
    const double sx = s.width / (s.view.xmax - s.view.xmin), sy = s.height / (s.view.ymax - s.view.ymin);
    auto px = [&](double x) { return (x - s.view.xmin) * sx; };
    auto py = [&](double y) { return (s.view.ymax - y) * sy; };
    cairo_set_source_rgb(cr, s.background.r, s.background.g, s.background.b);
    cairo_paint(cr);
    cairo_set_fill_rule(cr, CAIRO_FILL_RULE_WINDING);
    cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
    cairo_set_line_width(cr, s.line_width);
    auto finish = [&](DrawMode mode) {
        if (mode == DrawMode::Outline)
            cairo_stroke(cr);
        else
            cairo_fill(cr);
    };
    auto trace = [&](const Layer& L, std::size_t p) {
        const std::size_t b = p * L.n;
        for (std::size_t k = 0; k < L.n; ++k) {
            const std::size_t v = b + L.order[k];
            if (k == 0)
                cairo_move_to(cr, px(L.x[v]), py(L.y[v]));
            else
                cairo_line_to(cr, px(L.x[v]), py(L.y[v]));
        }
        cairo_close_path(cr);
    };
    for (const Layer& L : s.layers) {
        const std::size_t m = L.count();
        std::size_t run = 0;
        for (std::size_t p = 0; p < m; ++p) {
            if (p % 4096 == 0 && s.ctx && s.ctx->cancelled()) throw fp::Cancelled();
            const fp::Rgb c = L.colour[p];
            if (p == 0 || !(c == L.colour[p - 1]) || run == 65536) {
                if (p) finish(s.mode);
                cairo_set_source_rgb(cr, c.r, c.g, c.b);
                run = 0;
            }
            ++run;
            if (s.mode == DrawMode::Points) {
                const double r = 0.5 * s.line_width + 0.5;
                for (std::size_t k = 0; k < L.n; ++k)
                    cairo_rectangle(cr, px(L.x[p * L.n + k]) - r, py(L.y[p * L.n + k]) - r, 2 * r, 2 * r);
            } else {
                trace(L, p);
            }
        }
        if (m) finish(s.mode);
    }
    cairo_set_source_rgb(cr, s.mark_colour.r, s.mark_colour.g, s.mark_colour.b);
    cairo_set_line_width(cr, 2 * s.line_width + 1);
    for (const Layer& L : s.highlights) {
        for (std::size_t p = 0; p < L.count(); ++p) trace(L, p);
        cairo_stroke(cr);
    }
    if (!s.labels.empty()) {
        cairo_select_font_face(cr, "DejaVu Sans", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_BOLD);
        cairo_set_font_size(cr, s.label_size);
        for (const Label& l : s.labels) {
            cairo_text_extents_t e;
            cairo_text_extents(cr, l.text.c_str(), &e);
            cairo_move_to(cr, px(l.x) - e.x_bearing - e.width / 2, py(l.y) - e.y_bearing - e.height / 2);
            cairo_show_text(cr, l.text.c_str());
        }
    }
}

/// The scene as 8-bit sRGB values scaled to floats in [0, 1], RGB, top row first.
inline std::vector<float> raster(const Scene& s) {
    return fp_render::cairo_raster(s.width, s.height, [&](cairo_t* cr) { draw_scene(cr, s); });
}

/// The scene as an SVG (recipe in a <metadata> element) or PDF document.
inline std::string vector_document(const Scene& s, bool pdf, const std::string& recipe) {
    return fp_render::cairo_document(s.width, s.height, pdf, recipe, s.ctx,
                                     [&](cairo_t* cr) { draw_scene(cr, s); });
}

} // namespace fp_mfs
