// Drafts: a quick, smaller version of the same recipe (`render --draft`, `watch`, the preview
// of `serve`).
//
// A draft of factor f divides the image's width and height by f (at least 1 pixel) and the
// work by f * f where a renderer's parameters name it (chaos-game `points`, superfractal
// `points_per_buffer`), so that a pixel gets about as many points as in the full render and
// the draft looks like a small copy of it; orbit-trap takes 1 sample per pixel. A draft is
// an ordinary recipe: its image carries it, and rendering that recipe gives the same bytes.
#pragma once

#include <fixpoint/host/core/config.hpp>
#include <fixpoint/host/core/pipeline.hpp>

#include <string>
#include <vector>

namespace fp::host {

/// The `--set` assignments ("renderer.width=128") that make the draft of factor `factor`
/// (>= 1; 1: none) of the pipeline `full` (built from the config, its defaults filled in).
std::vector<std::string> draft_overrides(const Pipeline& full, int factor);

/// The factor of `render --draft` and of `watch`'s first image.
constexpr int draft_factor = 4;

/// The factors of `serve`'s progressive preview for an image of width x height, largest first
/// and ending with 1 (the full render): 8, 4, 2, 1, without those that would leave the
/// draft's larger side below 32 pixels.
std::vector<int> preview_factors(int width, int height);

/// The samples (points, pixel samples) per pixel of a finished render, for the preview's
/// caption: stats.samples / (width * height).
double samples_per_pixel(const RenderStats& stats, int width, int height);

} // namespace fp::host
