// Cairo plumbing shared by the renderers that draw (mfs's polygons, chaos-game's sets): RAII
// for Cairo's objects, a drawing as an fp::Image (8-bit values scaled to [0, 1]) or as an
// SVG or PDF document with the recipe embedded. Cairo draws on one thread, in order: the
// bytes depend only on what is drawn.
#pragma once

#include <cairo-pdf.h>
#include <cairo-svg.h>
#include <cairo.h>

#include <fixpoint/fixpoint.hpp>

#include <cstddef>
#include <cstdint>
#include <exception>
#include <memory>
#include <string>
#include <thread>
#include <vector>

namespace fp_render {

// Cairo objects destroyed on every way out (a cancel throws from the middle of drawing).
struct CairoDeleter {
    void operator()(cairo_t* cr) const { cairo_destroy(cr); }
    void operator()(cairo_surface_t* s) const { cairo_surface_destroy(s); }
};
using CairoContext = std::unique_ptr<cairo_t, CairoDeleter>;
using CairoSurface = std::unique_ptr<cairo_surface_t, CairoDeleter>;

/// draw(cr) on an opaque width x height surface, as RGB floats in [0, 1], top row first.
template <class Draw>
std::vector<float> cairo_raster(int width, int height, Draw&& draw) {
    const CairoSurface surface(cairo_image_surface_create(CAIRO_FORMAT_RGB24, width, height));
    cairo_surface_t* surf = surface.get();
    draw(CairoContext(cairo_create(surf)).get());
    cairo_surface_flush(surf);
    const unsigned char* data = cairo_image_surface_get_data(surf);
    const int stride = cairo_image_surface_get_stride(surf);
    std::vector<float> px(std::size_t(width) * std::size_t(height) * 3);
    for (int r = 0; r < height; ++r) {
        const auto* row = reinterpret_cast<const std::uint32_t*>(data + std::size_t(r) * std::size_t(stride));
        for (int c = 0; c < width; ++c) {
            const std::uint32_t v = row[c];
            float* o = &px[(std::size_t(r) * std::size_t(width) + std::size_t(c)) * 3];
            o[0] = float((v >> 16) & 0xff) / 255.0f;
            o[1] = float((v >> 8) & 0xff) / 255.0f;
            o[2] = float(v & 0xff) / 255.0f;
        }
    }
    return px;
}

/// draw(cr) on a transparent surface, composited over `rgb` (width x height x 3 floats) in
/// place: out = drawn + (1 - alpha) out, with Cairo's premultiplied 8-bit values scaled to
/// [0, 1]. The pixels under nothing drawn keep their bits.
template <class Draw>
void cairo_over(int width, int height, float* rgb, Draw&& draw) {
    const CairoSurface surface(cairo_image_surface_create(CAIRO_FORMAT_ARGB32, width, height));
    cairo_surface_t* surf = surface.get();
    draw(CairoContext(cairo_create(surf)).get());
    cairo_surface_flush(surf);
    const unsigned char* data = cairo_image_surface_get_data(surf);
    const int stride = cairo_image_surface_get_stride(surf);
    for (int r = 0; r < height; ++r) {
        const auto* row = reinterpret_cast<const std::uint32_t*>(data + std::size_t(r) * std::size_t(stride));
        for (int c = 0; c < width; ++c) {
            const std::uint32_t v = row[c];
            if (v == 0) continue;
            const float keep = 1.0f - float(v >> 24) / 255.0f;
            float* o = &rgb[(std::size_t(r) * std::size_t(width) + std::size_t(c)) * 3];
            o[0] = float((v >> 16) & 0xff) / 255.0f + keep * o[0];
            o[1] = float((v >> 8) & 0xff) / 255.0f + keep * o[1];
            o[2] = float(v & 0xff) / 255.0f + keep * o[2];
        }
    }
}

/// Where a document's bytes go, and the render's cancel flag: once it is set, Cairo's writes
/// fail, so that finishing a surface (its destructor too, when a cancel throws from the
/// drawing) stops writing at once instead of emitting the whole document first (13-30 s for
/// a large mfs SVG).
struct DocumentSink {
    std::string doc;
    const fp::RenderContext* ctx = nullptr;
    bool cancelled() const { return ctx && ctx->cancelled(); }
};

inline cairo_status_t append_bytes(void* closure, const unsigned char* data, unsigned int length) {
    auto* sink = static_cast<DocumentSink*>(closure);
    if (sink->cancelled()) return CAIRO_STATUS_WRITE_ERROR;
    sink->doc.append(reinterpret_cast<const char*>(data), length);
    return CAIRO_STATUS_SUCCESS;
}

/// draw(cr) as an SVG (recipe in a <metadata> element) or PDF (recipe as the Subject, a fixed
/// creation date so that the same recipe gives the same bytes) document; empty when Cairo
/// failed. fp::Cancelled when `ctx` (may be null) is cancelled meanwhile.
template <class Draw>
std::string cairo_document(int width, int height, bool pdf, const std::string& recipe,
                           const fp::RenderContext* ctx, Draw&& draw) {
    // (The sink outlives the surface, which writes to it when destroyed.)
    auto sink = std::make_shared<DocumentSink>();
    sink->ctx = ctx;
    std::string& doc = sink->doc;
    CairoSurface surface(pdf ? cairo_pdf_surface_create_for_stream(append_bytes, sink.get(), width, height)
                             : cairo_svg_surface_create_for_stream(append_bytes, sink.get(), width, height));
    cairo_surface_t* surf = surface.get();
    // A cancel throws from the drawing; destroying the surface then replays everything drawn
    // into the document (the surface is paginated: 30 s for the 1.4e7 polygons of a large mfs),
    // however its writes fail. That work is left to a thread of its own, which frees the
    // surface in the end (a server goes on) or dies with the process (the CLI exits now).
    struct Abandon {
        CairoSurface& surface;
        std::shared_ptr<DocumentSink> sink;
        ~Abandon() {
            if (!std::uncaught_exceptions() || !surface) return;
            std::thread([s = surface.release(), keep = sink] { cairo_surface_destroy(s); }).detach();
        }
    } abandon{surface, sink};
    if (pdf) {
        cairo_pdf_surface_set_metadata(surf, CAIRO_PDF_METADATA_SUBJECT, recipe.c_str());
        cairo_pdf_surface_set_metadata(surf, CAIRO_PDF_METADATA_CREATOR, "fixpoint");
        cairo_pdf_surface_set_metadata(surf, CAIRO_PDF_METADATA_CREATE_DATE, "2000-01-01T00:00:00Z");
    }
    draw(CairoContext(cairo_create(surf)).get());
    cairo_surface_finish(surf);
    if (sink->cancelled()) throw fp::Cancelled();
    if (cairo_surface_status(surf) != CAIRO_STATUS_SUCCESS) return {};
    if (!pdf) {
        // After the <svg ...> start tag: the recipe as character data (']]>' split so that
        // the CDATA section cannot end early).
        const auto open = doc.find("<svg");
        const auto end = open == std::string::npos ? open : doc.find('>', open);
        if (end != std::string::npos) {
            std::string safe;
            for (std::size_t i = 0; i < recipe.size(); ++i) {
                if (recipe.compare(i, 3, "]]>") == 0) {
                    safe += "]]]]><![CDATA[>";
                    i += 2;
                } else {
                    safe += recipe[i];
                }
            }
            doc.insert(end + 1, "\n<metadata id=\"fixpoint-recipe\"><![CDATA[\n" + safe + "]]></metadata>");
        }
    }
    return doc;
}

} // namespace fp_render
