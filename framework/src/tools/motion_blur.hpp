// Motion blur for `fixpoint animate` (animation.temporal_samples S, temporal_filter_width w:
// flam3's names, its box filter). Frame f is the sum of S renders, sample j of S at time
// t_j = f + w ((j + 1/2) / S - 1/2), each of its own share j of S of the chains (the shards of
// render --shard), summed exactly as fixpoint merge sums shards and finished once with the
// frame's own tone. Every chain runs once, at one time, so a frame of an animation that does
// not move is the plain render of its config, pixel for pixel; where keys move, each chain
// draws the picture at its own moment and the histogram holds the whole shutter.
#pragma once

#include <fixpoint/host/job/render_job.hpp>
#include <fixpoint/host/tools/animate.hpp>

#include <functional>
#include <string>

namespace fp::host {

/// The time of temporal sample j of frame f.
double temporal_time(const Animation& a, long f, long j);

/// What a blurred frame needs of its renderer (a histogram to sum), checked before any render:
/// fp::InputError "animation.temporal_samples: ..." otherwise.
void check_motion_blur(const Animation& a, const Pipeline& frame);

/// The recipe a blurred frame's image holds: the frame's, and a line naming its samples (so
/// that a frame made without blur, or with other samples, is not taken for it).
std::string blurred_recipe(const Animation& a, const Pipeline& frame);

/// Frame f blurred: `at(t)` is the pipeline at time t (the frame's config there); `frame` is
/// at(f) with its recipe blurred_recipe's; `request` writes the frame's file.
RenderResult render_blurred_frame(const Animation& a, long f, const std::function<Pipeline(double)>& at,
                                  const Pipeline& frame, const RenderRequest& request,
                                  const RenderHooks& hooks);

} // namespace fp::host
