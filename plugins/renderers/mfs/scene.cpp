// The mfs renderer's polygons (mfs.cpp's header: what a structure, its path and its placements
// make): the polygons of a structure, generation by generation, with their addresses and
// colours; the scene of every structure, drawn whole, by bands, or as a vector document.
#include "mfs/renderer.hpp"
#include "palette.hpp"

#include <fixpoint/fixpoint.hpp>
#include <fixpoint/vertex_map.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace fp_mfs {

Gen Mfs::grow(const std::vector<fp::Vec2>& start, size_t levels, bool filters, fp::RenderContext* ctx) const {
    Gen g;
    for (const auto& q : start) g.x.push_back(q.x), g.y.push_back(q.y);
    // Parents are subdivided a block at a time (one call per map and block): the scratch stays
    // small, and a cancel is seen within a block's work however large a level grows.
    constexpr size_t block = 65536;
    fp_render::Buffer<double> tx, ty;
    auto poll = [ctx] {
        if (ctx && ctx->cancelled()) throw fp::Cancelled();
    };
    for (size_t l = 0; l < levels; ++l) {
        poll();
        const auto& ifs = systems_[path_[l]];
        const size_t m = g.x.size() / n_, s = ifs.size(), len = l + 1;
        Gen h;
        h.len = len;
        h.x.resize(m * s * n_), h.y.resize(m * s * n_), h.addr.resize(m * s * len);
        tx.resize(std::min(m, block) * n_), ty.resize(std::min(m, block) * n_);
        for (size_t q0 = 0; q0 < m; q0 += block) {
            poll();
            const size_t q1 = std::min(m, q0 + block), k = (q1 - q0) * n_;
            for (size_t t = 0; t < s; ++t) {
                maps_[ifs[t]]->subdivide({g.x.data() + q0 * n_, g.y.data() + q0 * n_, k},
                                         {tx.data(), ty.data(), k});
                for (size_t q = q0; q < q1; ++q) {
                    const size_t c = q * s + t;
                    std::copy_n(&tx[(q - q0) * n_], n_, &h.x[c * n_]);
                    std::copy_n(&ty[(q - q0) * n_], n_, &h.y[c * n_]);
                    std::copy_n(g.addr.data() + q * l, l, &h.addr[c * len]);
                    h.addr[c * len + l] = ifs[t];
                }
            }
        }
        if (filters && (!placed_.empty() || len <= only_.size())) {
            size_t k = 0;
            for (size_t c = 0; c < m * s; ++c) {
                if (c % block == 0) poll();
                const uint32_t* a = &h.addr[c * len];
                bool keep = len > only_.size() || a[l] == only_[l];
                if (keep && !placed_.empty())
                    keep = !std::binary_search(placed_.begin(), placed_.end(), Address(a, a + len));
                if (!keep) continue;
                if (k != c) {
                    std::copy_n(&h.x[c * n_], n_, &h.x[k * n_]);
                    std::copy_n(&h.y[c * n_], n_, &h.y[k * n_]);
                    std::copy_n(a, len, &h.addr[k * len]);
                }
                ++k;
            }
            h.x.resize(k * n_), h.y.resize(k * n_), h.addr.resize(k * len);
        }
        if (ctx && l + 1 == levels) ctx->progress(h.x.size() / n_); // work_units counts last levels
        g = std::move(h);
    }
    return g;
}

std::vector<fp::Vec2> Mfs::polygon_at(const std::vector<fp::Vec2>& start, const Address& a) const {
    std::vector<double> x(n_), y(n_), cx(n_), cy(n_);
    for (size_t i = 0; i < n_; ++i) x[i] = start[i].x, y[i] = start[i].y;
    for (uint32_t j : a) {
        maps_[j]->subdivide({x.data(), y.data(), n_}, {cx.data(), cy.data(), n_});
        x.swap(cx), y.swap(cy);
    }
    std::vector<fp::Vec2> v(n_);
    for (size_t i = 0; i < n_; ++i) v[i] = {x[i], y[i]};
    return v;
}

fp::Rgb Mfs::colour_of(const uint32_t* addr, size_t len, size_t depth, uint32_t first) const {
    if (colour_by_ == "level") return fp_render::palette_colour(depth + len);
    if (colour_by_ == "ifs") return fp_render::palette_colour(len ? path_[len - 1] : 0);
    if (colour_by_ == "map") return len ? fp_render::palette_colour(addr[len - 1]) : colour_;
    if (colour_by_ == "address") {
        const uint32_t f = first != no_first ? first : len ? addr[0] : no_first;
        return f == no_first ? colour_ : fp_render::palette_colour(f);
    }
    return colour_;
}

void Mfs::generate(const std::vector<fp::Vec2>& start, size_t depth, uint32_t first, std::vector<Layer>& out,
                   fp::RenderContext* ctx, std::vector<Label>* labels) const {
    if (draw_target_) {
        Gen g = grow(start, path_.size(), true, ctx);
        Layer L;
        L.n = n_;
        L.order = order_;
        const size_t m = g.x.size() / n_;
        L.colour.resize(m);
        for (size_t c = 0; c < m; ++c) L.colour[c] = colour_of(&g.addr[c * g.len], g.len, depth, first);
        if (labels)
            for (size_t c = 0; c < m; ++c) {
                double sx = 0, sy = 0;
                for (size_t k = 0; k < n_; ++k) sx += g.x[c * n_ + k], sy += g.y[c * n_ + k];
                labels->push_back(
                    {sx / double(n_), sy / double(n_), address_text(&g.addr[c * g.len], g.len)});
            }
        L.x = std::move(g.x), L.y = std::move(g.y);
        out.push_back(std::move(L));
    }
    for (const auto& P : placements_)
        for (const auto& a : P.at) {
            // `only` keeps the placements under its address (or holding it).
            const size_t common = std::min(a.size(), only_.size());
            if (!std::equal(a.begin(), a.begin() + std::ptrdiff_t(common), only_.begin())) continue;
            const auto poly = polygon_at(start, a);
            const uint32_t f = first != no_first ? first : a.empty() ? no_first : a[0];
            for (const auto& piece : P.pieces) {
                std::vector<fp::Vec2> s;
                for (uint32_t v : piece) s.push_back(poly[v]);
                P.mfs->generate(s, depth + a.size(), f, out, ctx, nullptr);
            }
        }
}

Scene Mfs::scene(fp::RenderContext& ctx, fp::RenderStats& stats) const {
    Scene sc;
    sc.width = frame_.width, sc.height = frame_.height, sc.view = frame_.region,
    sc.background = frame_.background, sc.mode = mode_;
    sc.line_width = line_width_, sc.mark_colour = mark_colour_, sc.label_size = label_size_;
    sc.ctx = &ctx;
    generate(points_, 0, no_first, sc.layers, &ctx, labels_ ? &sc.labels : nullptr);
    if (labels_ && !highlight_.empty()) sc.labels.clear(); // label the highlighted places instead
    for (const auto& a : highlight_) {
        Layer L;
        L.n = n_, L.order = order_;
        for (const auto& q : polygon_at(points_, a)) L.x.push_back(q.x), L.y.push_back(q.y);
        L.colour.push_back(mark_colour_);
        if (labels_) {
            double sx = 0, sy = 0;
            for (size_t k = 0; k < n_; ++k) sx += L.x[k], sy += L.y[k];
            sc.labels.push_back({sx / double(n_), sy / double(n_), address_text(a)});
        }
        sc.highlights.push_back(std::move(L));
    }
    uint64_t polys = 0, inside = 0;
    for (const auto& L : sc.layers) {
        polys += L.count();
        for (size_t c = 0; c < L.count(); ++c) {
            bool in = false;
            for (size_t k = 0; k < L.n && !in; ++k) {
                const double x = L.x[c * L.n + k], y = L.y[c * L.n + k];
                in = x >= frame_.region.xmin && x <= frame_.region.xmax && y >= frame_.region.ymin &&
                     y <= frame_.region.ymax;
            }
            inside += in;
        }
    }
    stats.samples = polys;
    stats.drawn = inside;
    stats.unit = "polygons";
    if (ctx.cancelled()) throw fp::Cancelled();
    return sc;
}

fp::Image Mfs::render(fp::RenderContext& ctx, fp::RenderStats& stats) const {
    const Scene sc = scene(ctx, stats);
    fp::Image img;
    img.width = frame_.width, img.height = frame_.height, img.channels = 3;
    img.pixels = raster(sc);
    return img;
}

void Mfs::render_rows(fp::RenderContext& ctx, fp::RenderStats& stats, fp::RowSink& sink) const {
    const Scene sc = scene(ctx, stats);
    const int rows = band_rows(ctx.memory_budget()), H = frame_.height;
    for (int y0 = 0; y0 < H; y0 += rows) {
        if (ctx.cancelled()) throw fp::Cancelled();
        const int n = std::min(rows, H - y0);
        const std::vector<float> px = fp_render::cairo_raster(frame_.width, n, [&](cairo_t* cr) {
            cairo_translate(cr, 0, -double(y0));
            draw_scene(cr, sc);
        });
        if (ctx.rank() == 0) sink.rows(y0, n, px.data());
    }
    const int bands = (H + rows - 1) / rows;
    stats.how =
        "in " + std::to_string(bands) + " bands of " + std::to_string(rows) + (rows == 1 ? " row" : " rows");
}

std::string Mfs::render_vector(fp::RenderContext& ctx, fp::RenderStats& stats, fp::VectorFormat format,
                               const std::string& recipe) const {
    const Scene sc = scene(ctx, stats);
    std::string doc = vector_document(sc, format == fp::VectorFormat::Pdf, recipe);
    if (doc.empty()) throw fp::InternalError("Cairo could not write the vector document");
    return doc;
}

std::vector<std::string> Mfs::polygon_addresses(std::int64_t level) const {
    const size_t k = level < 0 ? path_.size() : size_t(level);
    if (k > path_.size())
        throw fp::ParamError("path", "level " + std::to_string(k) + " does not exist: the path has " +
                                         std::to_string(path_.size()) +
                                         (path_.size() == 1 ? " level (0 to " : " levels (0 to ") +
                                         std::to_string(path_.size()) + ")");
    Gen g = grow(points_, k, false, nullptr);
    std::vector<std::string> lines;
    const size_t m = g.x.size() / n_;
    for (size_t c = 0; c < m; ++c) {
        if (!only_.empty() &&
            !std::equal(only_.begin(), only_.begin() + std::ptrdiff_t(std::min(k, only_.size())),
                        &g.addr[c * g.len]))
            continue;
        std::string line = address_text(&g.addr[c * g.len], g.len);
        for (size_t i = 0; i < n_; ++i) {
            char buf[80];
            std::snprintf(buf, sizeof buf, " (%.6g, %.6g)", g.x[c * n_ + i], g.y[c * n_ + i]);
            line += buf;
        }
        lines.push_back(std::move(line));
    }
    return lines;
}

} // namespace fp_mfs
