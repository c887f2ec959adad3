// A pipeline file: the top level of a config.
//
//   renderer: {type: chaos-game, ...}   # required: the Renderer and everything in it
//   output:                             # optional
//     path: fig4a.png                   #   default output path (-o overrides)
//     bit_depth: 8                      #   8 or 16 for PNG and TIFF; EXR is always float
//     tiled: auto                       #   TIFF/EXR in 256 x 256 tiles: auto (> 8192^2), true, false
//   fixpoint_version: 0.1.0             # written into recipes; informational
//   render_version: 2                   # written into recipes (host/core/render_version.hpp)
#pragma once

#include <fixpoint/host/core/build.hpp>
#include <fixpoint/host/core/checkpoint.hpp>
#include <fixpoint/host/core/image_io.hpp>
#include <fixpoint/render.hpp>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace fp::host {

struct Pipeline {
    std::shared_ptr<const Renderer> renderer;
    Mark renderer_mark;
    std::string renderer_type; ///< the renderer plugin's name
    /// The renderer's plugin: what its descriptor declares (parameter roles, abilities) is
    /// asked of it, never its name. (The registry outlives every pipeline.)
    const PluginEntry* renderer_plugin = nullptr;
    std::string output_path; ///< from the config; empty when not given
    Mark output_mark;        ///< where output.path stands (for messages about it)
    int bit_depth = 8;
    Tiled tiled = Tiled::Auto; ///< output.tiled
    Mark tiled_mark;           ///< where it stands (when given)
    /// The resolved recipe: every default filled in, the version; no output path (so that
    /// rendering a recipe gives the same bytes whatever it is written to).
    std::string recipe;
    /// The recipe without renderer.points, and the points (-1: the renderer has none): a
    /// checkpoint continues a render whose identity is the same, to as many points or more.
    std::string identity;
    std::int64_t points = -1;
    /// The recipe without the parameters of the finishing stage (ParamRole::finish: tone,
    /// filter, density estimation, background): a kept histogram (render --histogram) is
    /// finished again (fixpoint tone) by a recipe whose histogram identity is the same.
    std::string histogram_identity;
    /// Things to tell the user before rendering (a plugin that differs from the one the
    /// recipe was made with), one line each, without a "warning:" prefix.
    std::vector<std::string> warnings;
    /// Of those, the ones that say the image may differ from the one the recipe was made of (an
    /// older render version whose changes touch it, another version of a plugin; not another
    /// build of the same version, which the render version covers): --strict refuses them, at
    /// `recipe_mark` (render_version:, else the top of the file).
    std::vector<std::string> may_differ;
    Mark recipe_mark;
    /// Why a render of it takes one thread unless asked for more, or empty: a plugin in it
    /// runs its batches one at a time (ability::one_batch_at_a_time: python-scheme's Python),
    /// so more threads would only wait for each other.
    std::string one_thread;
};

/// The tree of a config file. `path` may name an image fixpoint wrote (PNG, EXR, TIFF, SVG):
/// its recipe is the config, without the recipe's output.path (an image from elsewhere does not
/// choose where fixpoint writes), and a plugin in it that runs code (python-scheme) is refused
/// unless `allow_code` (--allow-python): an image may come from anywhere.
CNode load_config(const std::string& path, bool allow_code);

/// Parse (load_config), apply the overrides (`sets`, then `vary`: one more assignment from
/// --vary), validate, build.
Pipeline load_pipeline(const Registry& reg, const std::string& path, const std::vector<std::string>& sets,
                       const std::string& vary = "", bool allow_code = false);
Pipeline load_pipeline(const Registry& reg, CNode root);

/// What a checkpoint of this pipeline's render records of it, and a resumed one must match.
CheckpointHeader checkpoint_header(const Pipeline& p);

/// Refuse, before it starts, a render that needs more memory than the machine has available
/// with `threads` workers (fp::InputError at the renderer).
void check_memory(const Pipeline& p, unsigned threads);
/// How `fixpoint render` fits its memory budget (check_memory_within).
struct MemoryPlan {
    std::uint64_t budget = 0; ///< this process's, for its Runtime
    bool stream = false;      ///< the whole render does not fit: Renderer::render_rows
};
/// check_memory for `fixpoint render`: the budget is `requested` bytes (--memory; 0: what the
/// machine has available), shared by the MPI ranks on this machine. A render whose buffers fit
/// it renders whole; else, where the renderer streams its rows and `can_stream` (a raster file,
/// nothing that needs the whole image), it streams within the budget
/// (Renderer::memory_within). Refuses (fp::InputError at the renderer) a render that needs more
/// even so, saying the least it needs.
/// `held`: memory the host holds beside a streamed render (a tiled file's row of tiles).
MemoryPlan check_memory_within(const Pipeline& p, unsigned threads, std::uint64_t requested, bool can_stream,
                               std::uint64_t held = 0);

/// output.tiled against the file the image goes to: fp::InputError at output.tiled's place in
/// the config (tiles for a PNG), checked before anything renders.
void check_tiled(const Pipeline& p, const std::string& out);

/// Refuse writing `out` as SVG or PDF from a renderer without vector output (fp::InputError
/// at the renderer); returns whether `out` is a vector format.
bool check_vector_output(const Pipeline& p, const std::string& out);

/// Refuse a render that drew nothing rather than give a silent black image (fp::InputError at
/// the renderer). Returns a warning (without a "warning: " prefix) for one that drew almost
/// nothing, else an empty string.
std::string check_drawn(const Pipeline& p, const RenderStats& st);

} // namespace fp::host
