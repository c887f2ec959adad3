// The chaos-game renderer's class: what the recipe fixed at construction (chaos-game.cpp), and the
// parts of a render, each in the file of its concern:
//   chaos-game.cpp              construction (maps, weights, the fused kernels' tables), schema
//   chaos-game/plan.cpp         memory: the whole render's bytes, and a render in strips
//   chaos-game/render.cpp       the render: workers over blocks, the sum of their histograms, ranks
//   chaos-game/checkpoint.cpp   a checkpointed render's save and resume
//   chaos-game/block.cpp        one block of chains, step by step (Block: its stages)
//   chaos-game/moves.cpp        a step's moves: map choice, grouping by map, start points, programs
//   chaos-game/kernels.cpp      the vectorised kernels (kernels-inl.hpp), dispatched per target
#pragma once

#include "checkpoint.hpp"
#include "histogram.hpp"
#include "kernels.hpp"
#include "picture.hpp"
#include "sets.hpp"

#include <fixpoint/fixpoint.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

namespace fp_chaos {

template <class T, bool Rules, bool Colour>
class Block;

class ChaosGame final : public fp::Renderer {
public:
    explicit ChaosGame(const fp::ParamBag& p);

    int width() const override { return sets_ == Sets::beside ? 2 * frame_.width : frame_.width; }
    int height() const override { return frame_.height; }
    std::optional<fp::Box> region() const override {
        return frame_.has_region ? std::optional(frame_.region) : std::nullopt;
    }
    uint64_t memory_bytes(unsigned workers) const override;
    bool streams_rows() const override {
        return sets_ == Sets::none && (finish_.active() || colourer_->resolves_rows());
    }
    uint64_t memory_within(unsigned workers, uint64_t budget) const override;
    void render_rows(fp::RenderContext& ctx, fp::RenderStats& stats, fp::RowSink& sink) const override;
    uint64_t work_units() const override;
    fp::Image render(fp::RenderContext& ctx, fp::RenderStats& stats) const override;
    bool has_vector_output() const override { return sets_ == Sets::only; }
    bool keeps_checkpoints() const override { return sets_ != Sets::only; }
    fp::HistogramShape histogram_shape() const override;
    fp::Image finish_histogram(const fp::Histogram& h, const fp::RenderStats& stats,
                               fp::RenderContext& ctx) const override;
    std::string render_vector(fp::RenderContext& ctx, fp::RenderStats& stats, fp::VectorFormat format,
                              const std::string& recipe) const override;

private:
    template <class T, bool Rules, bool Colour>
    friend class Block;

    // ---- chaos-game/render.cpp
    /// Rows [row0, row0 + rows) of the histogram into `total` (all rows: the whole render), with
    /// colour sums (and last colours) when `colour`; with `pixels`, the image's buffer is
    /// allocated alongside. Without colour and with `hits_total` (its reader reads hit counts
    /// alone: HistogramSummary, or a colourer whose reads_hits_only() is true), `total` is hit
    /// counts alone (fp::Histogram::hits), except in a checkpointed render, whose checkpoints
    /// hold fp::HistBin bins. stats: this pass's counts.
    template <class T>
    void render_t(fp::RenderContext& ctx, fp::RenderStats& stats, fp::Histogram& total,
                  std::vector<float>* pixels, uint32_t row0, uint32_t rows, bool colour,
                  bool hits_total) const;
    /// The workers' histograms summed into total (rows in parallel), their points drawn counted
    /// into stats; each bin's last colour the latest of the workers' and of `folded_last`.
    void sum_workers(fp::RenderContext& ctx, fp::RenderStats& stats, std::vector<WorkerHist>& hists,
                     fp::Histogram& total, const std::vector<LastWrite>& folded_last, uint32_t rows,
                     bool hits8, bool last, std::vector<LastWrite>& rank_last) const;
    /// The workers' histograms added into total (and their last writes into `last`), then
    /// cleared: a checkpointed render's fold before each checkpoint.
    void fold(fp::RenderContext& ctx, std::vector<WorkerHist>& hists, fp::Histogram& total,
              std::vector<LastWrite>& last, size_t px) const;
    /// The ranks' shares folded into rank 0's.
    void combine_ranks(fp::RenderContext& ctx, fp::RenderStats& stats, fp::Histogram& total,
                       std::vector<LastWrite>& rank_last) const;
    /// The image of a whole histogram (rank 0's, summed): finished or resolved, the sets
    /// drawn over or beside it; `pixels`: the image's buffer when made already (else empty).
    fp::Image image_of(const fp::Histogram& total, fp::RenderContext& ctx, std::vector<float> pixels) const;
    /// HistogramSummary::density of this render's histograms.
    double density() const;
    /// The sets of the maps on the background, as a width x height picture.
    void draw_set_panel(cairo_t* cr) const;

    // ---- chaos-game/fit.cpp
    /// Whether fit_view may refine the pre-run's view by the render's own chains (not with a
    /// camera, which turns the points about the view's centre).
    bool probe_fits() const;
    /// fit_view by the render's own chains: frame_ and hist_'s view from where the first
    /// points of each chain land (fit.cpp says how).
    void fit_by_probe();

    // ---- chaos-game/plan.cpp
    /// The render in strips (plan.cpp's "Strips"), each strip's pixels into the sink.
    template <class T>
    void render_strips(fp::RenderContext& ctx, fp::RenderStats& stats, fp::RowSink& sink,
                       uint32_t summary_rows, uint32_t rows) const;
    /// Bytes of the workers' histograms and the total for a strip of `rows` rows, with colour
    /// sums (and last colours) or hits only.
    uint64_t strip_bytes(unsigned workers, uint64_t rows, bool colour, bool hits_total) const;
    /// The workers' block state.
    uint64_t scratch_bytes(unsigned workers) const;
    /// How a render in strips fits `budget`: rows per strip of the summary pass and of the
    /// colour pass, and the memory it then takes; strips of one row when even those do not fit
    /// (then bytes > budget).
    struct Plan {
        uint32_t summary_rows, rows;
        uint64_t bytes;
    };
    Plan plan(unsigned workers, uint64_t budget) const;

    // ---- chaos-game/checkpoint.cpp
    /// A checkpointed render's state from the payload it resumes from: its tasks, the chains'
    /// final states, the histogram (into total, and last writes into `last`), the stats. `mine`:
    /// the blocks this process runs (a shard's share; all of them otherwise).
    template <class T>
    void resume(fp::CheckpointSource& in, std::vector<Task>& tasks, Keeping& keep, fp::Histogram& total,
                std::vector<LastWrite>& last, BlockResult& base, const std::vector<Span>& mine) const;
    /// Writes the checkpoint: the tasks not done, the final states, the histogram folded into
    /// total and `last`.
    template <class T>
    void save(fp::RenderContext& ctx, const std::vector<Task>& tasks, const Keeping& keep,
              const fp::Histogram& total, const std::vector<LastWrite>& last, const BlockResult& base) const;

    // ---- chaos-game/block.cpp
    /// Runs task t's chains to their end (true), or, in a checkpointed render (keep), until a
    /// checkpoint is due (false: their state is in t.saved).
    template <class T>
    bool run_block(Task& t, Scratch<T>& s, WorkerHist& hist, fp::RenderContext& ctx, uint32_t row0,
                   uint32_t rows, bool colour, Keeping* keep) const;

    // ---- chaos-game/moves.cpp
    /// Rules on: a map per chain among those allowed (not its previous map, not a map whose set
    /// holds its point), k when none is allowed (restart set) or the chain is inactive.
    template <class T>
    void choose_rules(Scratch<T>& s, size_t nb) const;
    /// Rules off: a map per chain by Walker's alias table.
    template <class T>
    void choose_alias(Scratch<T>& s, size_t nb) const;
    /// The chains grouped by their chosen map, one IterationScheme::step call per map on its
    /// points at step index n, and the new points back in place.
    template <class T>
    void move_chains(Scratch<T>& s, size_t nb, uint64_t n) const;
    /// The points block.cpp's bookkeeping plots when the recipe has final maps or a camera
    /// (has_finals_): each chain's point through the final maps in order (flam3's finalxform:
    /// the plotted point only, the chain goes on from its own), then the camera (rotate, y_axis),
    /// into s.fx, s.fy; with `colour`, the chains' colours through the final maps' colour rules
    /// into s.fr, s.fg, s.fb (the chains' own stay).
    template <class T>
    void finals(Scratch<T>& s, size_t nb, uint64_t n, bool colour) const;
    /// flam3's opacity: the points at step n whose map's visible_ draw fails go to the dummy bin
    /// (their bins idx[i] := dummy), from the chain's key at that step.
    template <class T>
    void hide(Scratch<T>& s, size_t nb, uint64_t n, uint32_t dummy) const;
    /// The random keys of the staged points [at, at + len) whose lanes are `lanes`, at step n
    /// (fp::map_key), in the scratch's gk; null when no map draws random numbers.
    template <class T>
    const uint64_t* keys(Scratch<T>& s, const uint32_t* lanes, size_t at, size_t len, uint64_t n) const;
    /// A start point for each of the m lanes list[0..m).
    template <class T>
    void new_starts(Scratch<T>& s, const uint32_t* list, size_t m) const;
    /// The scheme's step at step index n as the fused step's program (into `out`): false when
    /// a map gives none, or the maps give different ones (that step then takes the generic
    /// path).
    template <class T>
    bool lane_program(uint64_t n, LaneProgram<T>& out) const;
    /// The fused step's tables; Colour false: those of a pass that counts hits only.
    template <class T, bool Colour>
    const LaneTables<T>& lane_tables() const {
        if constexpr (std::is_same_v<T, float>)
            return Colour ? *lanes_f_ : *lanes_f_hits_;
        else
            return Colour ? *lanes_d_ : *lanes_d_hits_;
    }

    // ---- chaos-game.cpp
    /// The fused kernels' tables of the maps (fused_, program_, lanes_*, tallies_).
    void setup_fused(const std::vector<fp::KnownKernel>& kk, fp::ColourRule crule);

    enum class Sets { none, over, beside, only };
    Sets sets_ = Sets::none;
    SetStyle set_style_;
    std::optional<fp::Box> set_view_; ///< the region of the sets' own picture (beside, only); else the view
    std::vector<SetDrawing> set_drawings_;

    fp::Frame frame_; ///< width, height, view (region), background: the image's
    fp::Frame hist_;  ///< the histogram's: frame_ with supersample times its width and height
    fp::FinishSpec finish_;
    uint64_t points_ = 1000000, seed_ = 1, skip_ = 20, chains_ = 4096;
    /// A restarted chain's age (`restart_skip`: skip - restart_skip; 0, the whole skip, by default).
    uint32_t restart_age_ = 0;
    /// `escape` (0: none): a point beyond it in |x| or |y| is bad (flam3's 1e10); the generic path.
    double escape_ = 0;
    bool has_start_ = false;
    fp::Vec2 start_;
    fp::Box start_box_; ///< where random start points are drawn (the view unless start_box)
    bool rules_ = true, double_ = false, colour_ = true;
    bool last_ = false; ///< the colourer's pixel rule is last (paper 02's Algorithm 2 as written)
    /// The colourer's palette_index(): the chains carry a palette index, blended toward each
    /// map's `color` by its `color_speed` (map_index_, map_speed_: k + 1 entries).
    bool palette_ = false;
    std::vector<float> map_index_, map_speed_;
    /// Colour stealing (`picture`; picture.hpp): each chain's colour point (Chains::ci, cv) moves
    /// by its map's colour map (colour_maps_: k + 1 entries, the last the identity), and the
    /// point takes the picture's colour there; the colourer's update() is not called.
    bool steal_ = false;
    fp_render::Picture picture_;
    std::vector<std::array<double, 6>> colour_maps_;
    /// The colour stealing step of lanes [0, nb): the moved lanes' colour points and colours.
    template <class T>
    void steal(Scratch<T>& s, size_t nb, const unsigned char* moved) const;
    bool fused_ = false; ///< the fused step (fused-inl.hpp's fused_t) runs the block steps
    /// With fused_: the scheme is not Picard, and the fused step runs its program
    /// (IterationScheme::program) at each step where every map gives the same one.
    bool program_ = false;
    std::shared_ptr<LaneTables<float>> lanes_f_, lanes_f_hits_;
    std::shared_ptr<LaneTables<double>> lanes_d_, lanes_d_hits_;
    /// With fused_ and the map rule on at most tally_maps maps: the workers' bins are tallies
    /// (see "Tallies"); else null.
    std::shared_ptr<const Tallies> tallies_;

    std::vector<std::shared_ptr<const fp::Transform>> maps_;
    bool random_maps_ = false; ///< some map draws random numbers (Transform::uses_random)
    /// Maps applied to the plotted points only (`final`), with their colours as the maps' are
    /// kept (final_colours_, final_index_, final_speed_); the camera: rotation about the view's
    /// centre (cam_: cos, sin) and the y axis down (flam3's).
    std::vector<std::shared_ptr<const fp::Transform>> final_;
    std::vector<fp::Rgb> final_colours_;
    std::vector<float> final_index_, final_speed_;
    /// flam3's opacity of a final map: the chance that a plotted point goes through it (drawn
    /// from the chain's key); 1: every point, no draw.
    std::vector<double> final_opacity_;
    bool random_final_ = false, has_finals_ = false, rotate_ = false, y_down_ = false;
    /// Some map's `opacity` is below 1: visible_[j] the chance that a point of map j is plotted
    /// (k + 1 entries, the last for the chains that did not move).
    bool has_opacity_ = false;
    std::vector<double> visible_;
    /// Some map's `chaos` (flam3's xaos) is not all 1: the draw's weights depend on the chain's
    /// previous map. Row r of (k + 1) x k: r = 0 for no previous map (the weights), r = i + 1
    /// after map i (weight_j chaos_ij): Walker's tables xaos_thr_, xaos_alias_, and integer
    /// weights xaos_q_ (sum below 2^32, 0 where the weight is 0) for the draw under the rules.
    bool has_xaos_ = false;
    std::vector<uint32_t> xaos_thr_, xaos_alias_, xaos_q_;
    std::vector<unsigned char> xaos_set_; ///< 1 for the maps with a set (the rules' test)
    void xaos_tables(const std::vector<double>& w, const std::vector<double>& chaos);
    /// The draw with xaos (scalar, one pcg32 output per chain as the others): by row prev + 1
    /// of the tables; with the rules, by xaos_q_ among the maps whose set does not hold the point.
    template <class T>
    void choose_xaos(Scratch<T>& s, size_t nb) const;
    double cam_[2] = {1, 0};
    std::vector<uint32_t> region_maps_;       ///< indices of the maps with a set
    std::vector<uint32_t> q_;                 ///< integer weights (rules on)
    bool uniform_ = true;                     ///< every weight the same (the rules' draw)
    std::vector<uint32_t> alias_thr_, alias_; ///< Walker's alias table (rules off; on, with unequal weights)
    std::vector<fp::Rgb> colours_;            ///< k + 1 entries (the last one is never used)
    /// The maps' colours as deposits carry them (fp::quantise_colour): the tallies' colours,
    /// and a point's last colour under the map rule on the fused path.
    std::vector<std::array<uint16_t, 3>> map_q_;
    fp::Rgb initial_colour_;
    std::shared_ptr<const fp::IterationScheme> iteration_;
    std::shared_ptr<const fp::Colourer> colourer_;
};

} // namespace fp_chaos
