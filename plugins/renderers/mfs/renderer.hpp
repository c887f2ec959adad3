// The mfs renderer's class (mfs.cpp: what it computes, its construction and schema; mfs/scene.cpp:
// the structures' polygons, generation by generation, and the scene they make).
#pragma once

#include "mfs_address.hpp"
#include "mfs_draw.hpp"

#include <fixpoint/fixpoint.hpp>
#include <fixpoint/vertex_map.hpp>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace fp_mfs {

using std::size_t;
using std::uint32_t;
using std::uint64_t;

/// The first index of an address at the top structure (generate's `first`): none.
constexpr uint32_t no_first = ~uint32_t(0);

/// Polygons of one generation: n vertices each, and the address of each (len indices).
struct Gen {
    fp_render::Buffer<double> x, y; // written in full before they are read
    fp_render::Buffer<uint32_t> addr;
    size_t len = 0;
};

class Mfs final : public fp::Renderer {
public:
    explicit Mfs(const fp::ParamBag& p);

    int width() const override { return frame_.width; }
    int height() const override { return frame_.height; }
    // (The view given, or the points' box the constructor fitted.)
    std::optional<fp::Box> region() const override { return frame_.region; }
    uint64_t memory_bytes(unsigned) const override {
        return uint64_t(total_ * bytes_per_polygon() + double(frame_.width) * double(frame_.height) * 16.0);
    }
    uint64_t work_units() const override { return uint64_t(total_); }
    fp::Image render(fp::RenderContext& ctx, fp::RenderStats& stats) const override;
    // Beyond the memory budget: the polygons stay whole (they are the scene), the picture is
    // drawn band by band, each band a surface of its own with the scene moved up by its first
    // row (a whole number of pixels: the same coverage, the same bytes).
    bool streams_rows() const override { return true; }
    uint64_t memory_within(unsigned, uint64_t budget) const override {
        return scene_bytes() + uint64_t(band_rows(budget)) * row_bytes();
    }
    void render_rows(fp::RenderContext& ctx, fp::RenderStats& stats, fp::RowSink& sink) const override;
    bool has_vector_output() const override { return true; }
    std::string render_vector(fp::RenderContext& ctx, fp::RenderStats& stats, fp::VectorFormat format,
                              const std::string& recipe) const override;
    std::vector<std::string> polygon_addresses(std::int64_t level) const override;

    size_t vertex_count() const { return n_; }
    double total() const { return total_; }
    /// Append the structure started from `start` (n points) to `out`: its own polygons, then
    /// its placements. `depth` is the level of `start` in the top structure, `first` the first
    /// index of its address there (no_first at the top).
    void generate(const std::vector<fp::Vec2>& start, size_t depth, uint32_t first, std::vector<Layer>& out,
                  fp::RenderContext* ctx, std::vector<Label>* labels) const;

private:
    struct Placement {
        std::vector<Address> at;
        std::vector<std::vector<uint32_t>> pieces;
        std::shared_ptr<const Mfs> mfs;
    };

    double bytes_per_polygon() const { return double(n_) * 16.0 * 3.0 + 12.0 + 4.0 * double(path_.size()); }
    uint64_t scene_bytes() const { return uint64_t(total_ * bytes_per_polygon()); }
    /// A row of a band: its Cairo surface (4 bytes a pixel) and its floats (12).
    uint64_t row_bytes() const { return uint64_t(frame_.width) * 16; }
    /// Rows per band within `budget`: at least one.
    int band_rows(uint64_t budget) const {
        const uint64_t left = budget > scene_bytes() ? budget - scene_bytes() : 0;
        return int(std::clamp<uint64_t>(left / row_bytes(), 1, uint64_t(frame_.height)));
    }
    Gen grow(const std::vector<fp::Vec2>& start, size_t levels, bool filters, fp::RenderContext* ctx) const;
    std::vector<fp::Vec2> polygon_at(const std::vector<fp::Vec2>& start, const Address& a) const;
    fp::Rgb colour_of(const uint32_t* addr, size_t len, size_t depth, uint32_t first) const;
    fp_mfs::Scene scene(fp::RenderContext& ctx, fp::RenderStats& stats) const;

    fp::Frame frame_; ///< width, height, view (region: given, or the points' box), background
    size_t n_ = 0;
    std::vector<std::shared_ptr<const fp::VertexMap>> maps_;
    std::vector<std::vector<uint32_t>> systems_;
    std::vector<uint32_t> path_;
    std::vector<fp::Vec2> points_;
    std::vector<size_t> order_;
    std::vector<Placement> placements_;
    std::vector<Address> placed_; ///< placement and `hide` addresses, sorted (the target drops them)
    bool draw_target_ = true, labels_ = false;
    fp_mfs::DrawMode mode_ = fp_mfs::DrawMode::Fill;
    std::string colour_by_ = "fixed";
    fp::Rgb colour_, mark_colour_;
    double line_width_ = 1, label_size_ = 14;
    Address only_;
    std::vector<Address> highlight_;
    double total_ = 0;
};

} // namespace fp_mfs
