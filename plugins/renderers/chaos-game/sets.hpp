// The sets of a chaos game's maps and their centres, drawn with Cairo: the left halves of
// papers 01 and 02's figures ("star-shaped sets with centres of inversion"), an overlay on the
// fractal, or a picture of its own (raster, SVG, PDF).
//
// Each set is filled with its map's colour at `fill` opacity and outlined in that colour; its
// centre is a dot of the map's colour ringed in white, drawn after every set so that no
// other set hides it. World to pixels as the histogram maps points: x from xmin at the left
// edge, y from ymax at the top edge.
#pragma once

#include "cairo_out.hpp"

#include <fixpoint/types.hpp>

#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

namespace fp_chaos {

struct SetDrawing {
    std::vector<fp::Vec2> outline;
    std::optional<fp::Vec2> centre;
    fp::Rgb colour;
};

struct SetStyle {
    double line = 2;   ///< outline width in pixels
    double fill = 0.3; ///< opacity of the fill
};

/// Draw `sets` in the view `v` onto cr (a width x height surface), leaving the rest as it is.
inline void draw_sets(cairo_t* cr, const std::vector<SetDrawing>& sets, const fp::Box& v, int width,
                      int height, const SetStyle& style) {
    const double sx = width / (v.xmax - v.xmin), sy = height / (v.ymax - v.ymin);
    auto px = [&](fp::Vec2 p) { return fp::Vec2{(p.x - v.xmin) * sx, (v.ymax - p.y) * sy}; };
    cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
    cairo_set_fill_rule(cr, CAIRO_FILL_RULE_WINDING);
    for (const auto& s : sets) {
        if (s.outline.size() < 3) continue;
        for (std::size_t i = 0; i < s.outline.size(); ++i) {
            const fp::Vec2 q = px(s.outline[i]);
            if (i == 0)
                cairo_move_to(cr, q.x, q.y);
            else
                cairo_line_to(cr, q.x, q.y);
        }
        cairo_close_path(cr);
        cairo_set_source_rgba(cr, s.colour.r, s.colour.g, s.colour.b, style.fill);
        cairo_fill_preserve(cr);
        cairo_set_source_rgb(cr, s.colour.r, s.colour.g, s.colour.b);
        cairo_set_line_width(cr, style.line);
        cairo_stroke(cr);
    }
    const double r = std::max(2.5, 2 * style.line);
    for (const auto& s : sets) {
        if (!s.centre) continue;
        const fp::Vec2 q = px(*s.centre);
        cairo_new_sub_path(cr);
        cairo_arc(cr, q.x, q.y, r, 0, 2 * M_PI);
        cairo_set_source_rgb(cr, s.colour.r, s.colour.g, s.colour.b);
        cairo_fill_preserve(cr);
        cairo_set_source_rgb(cr, 1, 1, 1);
        cairo_set_line_width(cr, std::max(1.0, style.line / 2));
        cairo_stroke(cr);
    }
}

} // namespace fp_chaos
