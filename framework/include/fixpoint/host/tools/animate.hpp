// `fixpoint animate`: keyframed parameters, one render per frame, and a video by ffmpeg.
//
// The config's top-level `animation:` section (see animate.cpp for the whole format):
//
//   animation:
//     frames: 120                    # frames 0 .. 119
//     fps: 30                        # of the video (default 30)
//     interpolation: smooth          # linear (default), smooth (smoothstep) or catmull-rom
//     loop: true                     # periodic: frame 120 would be frame 0 (default false)
//     keys:                          # a parameter path (as --set takes it): {frame: value, ...}
//       renderer.iteration.alpha: {0: 0.5, 119: 0.9}
//       renderer.maps[0].colour: {0: "#ff6b6b", 119: [0.2, 0.4, 1]}
#pragma once

#include <fixpoint/host/core/config.hpp>
#include <fixpoint/host/core/pipeline.hpp>
#include <fixpoint/host/job/render_job.hpp>

#include <atomic>
#include <functional>
#include <string>
#include <vector>

namespace fp::host {

/// One animated parameter: its path and its keyframes, in frame order.
struct AnimationKey {
    std::string path;
    Mark mark;            ///< where the path stands in animation.keys
    bool integer = false; ///< an integer parameter (from the schema): rounded between keys
    std::vector<std::pair<long, CNode>> frames;
};

/// How values run between keyframes (animate.cpp has the formulas).
enum class Interpolation { linear, smooth, catmull_rom };

struct Animation {
    long frames = 0;
    double fps = 30;
    Interpolation interpolation = Interpolation::linear;
    /// loop: true: the keys repeat with period `frames`, the last keyframe running on into the
    /// first, so that the would-be frame `frames` is frame 0 and the video loops seamlessly.
    bool loop = false;
    /// Motion blur (flam3's temporal_samples and temporal_filter_width, box filter): frame f
    /// sums the histograms of S renders, sample j at time f + w ((j + 1/2) / S - 1/2), each
    /// of its own share j of S of the chains (motion_blur.hpp). S = 1: none.
    long temporal_samples = 1;
    double temporal_filter_width = 1;
    std::vector<AnimationKey> keys;
};

/// The animation section of a config (after --set), checked: the frame count, the keys, their
/// paths (against the config's tree, as --set would apply them) and their values; every key
/// real (AnimationKey::integer is set from the schema by animate and validate_animation). Throws
/// fp::InputError "file:line:col: animation...: why" at the bad node. `root` must have one.
Animation parse_animation(const CNode& root);

/// Whether a config has an `animation:` section.
bool has_animation(const CNode& root);

/// The value of one key at `frame`: a key's value as written at a keyframe, else interpolated.
/// Any frame of a loop (frame `frames` is frame 0); before 0 or after the last a frame holds.
/// A time between frames (motion blur's samples) interpolates as a frame would.
CNode animated_value(const Animation& a, const AnimationKey& k, double frame);

/// The config of one frame: `root` with every key's value at `frame` set, as --set path=value
/// would set it.
CNode frame_config(const CNode& root, const Animation& a, double frame);

/// A value as `--set path=VALUE` takes it (flow YAML on one line).
std::string flow_text(const CNode& n);

struct AnimateOptions {
    std::string config;            ///< a YAML file with an animation: section
    std::vector<std::string> sets; ///< --set, applied before the animation
    std::string pattern;           ///< -o frames/%04d.png
    std::string frames;            ///< --frames A..B; empty: all
    std::string video;             ///< --video out.mp4; empty: none
    unsigned threads = 0;          ///< 0: the render job's default (every core, or one: RenderPlan)
    bool quiet = false, force = false, list = false;
    /// Where progress lines (without quiet) and warnings go, one line each.
    std::function<void(const std::string&)> info, warn;
};

/// `fixpoint animate`. Checks everything (every frame's config and render, every frame's file,
/// the video) before the first render; each frame is rendered and written by the render job with
/// `hooks` (the cancel flag, the progress bar). Returns the exit code; throws fp::InputError for
/// bad input, fp::Cancelled when cancelled (the frames written are kept).
int animate(const Registry& reg, const AnimateOptions& o, const RenderHooks& hooks);

/// The format and the promises, for `fixpoint animate --help`.
const char* animate_help();

/// `fixpoint validate` of a config with an animation section: every frame's config is checked.
/// Returns a one-line summary ("an animation of N frames (K keys)"); empty for a config without
/// one (or an image's recipe). fp::host::Cancelled when `interrupted` is set between frames.
std::string validate_animation(const Registry& reg, const std::string& config,
                               const std::vector<std::string>& sets,
                               const std::atomic<bool>* interrupted = nullptr);

} // namespace fp::host
