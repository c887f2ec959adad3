// Measures of a rendered pattern, for `fixpoint explore`: raw values computed on an image
// (or on the map that drew it) and their mappings to scores in [0, 1], where 1 is what a
// pleasing pattern tends to have and 0 marks dust (a few scattered pixels) or a blob (a
// filled patch).
//
// Adding a measure is one entry of measure_table() (explore.cpp): its name, default weight,
// a function from a Draft to its raw value (or none) and the score of that value.
#pragma once

#include <fixpoint/render.hpp>
#include <fixpoint/types.hpp>

#include <optional>
#include <string>
#include <vector>

namespace fp::host {

/// Whether each pixel is lit: some channel of R, G, B differs from `background` by more than
/// half a step of an 8-bit image (what an 8-bit PNG of it would show). Row-major, w * h.
std::vector<unsigned char> lit_pixels(const Image& img, Rgb background);

/// Fraction of the pixels that are lit (0 for an empty image).
double coverage(const Image& img, Rgb background);

/// Shannon entropy in bits (0 to 8) of the histogram of grey levels over all pixels: grey =
/// 0.2126 R + 0.7152 G + 0.0722 B clamped to [0, 1], in 256 levels (round(255 grey)).
double grey_entropy(const Image& img);

/// Box-counting dimension of the lit set: minus the least-squares slope of log N(s) against
/// log s for box sizes s = 2, 4, ..., 64, N(s) the number of boxes of a grid of s x s boxes
/// from the image's corner that hold a lit pixel. Sizes above a quarter of the lit set's
/// extent (the larger side of its bounding box) are left out, 2, 4 and 8 always kept: larger
/// boxes count mostly the set's edge. A filled square of side 2^k >= 32 at a multiple of its
/// largest box gives exactly 2, such a line exactly 1; unaligned, a filled square of 100 to
/// 200 pixels gives 1.90 to 1.96 and a line 0.92 to 0.98 (the edge: (L/s + 1)^2 boxes). 0
/// for an image with no lit pixel.
double box_dimension(const std::vector<unsigned char>& lit, int width, int height);
double box_dimension(const Image& img, Rgb background);

// Measures of patterns that fill the image (paper 04's wallpapers, where every candidate's
// coverage is 1 and its dimension 2; wallpaper_measures.cpp):

/// Shannon entropy in bits (0 to 12) of the colours, each channel in 16 levels.
double colour_entropy(const Image& img);
/// Entropy in bits (0 to 5) of the size of the grey level's gradient (Sobel, |g| in 32 bins
/// of 1/16 over [0, 2), larger ones in the last): 0 for a flat picture, low where a few sharp
/// edges cross flat areas, high where edges of every strength mix.
double edge_entropy(const Image& img);
/// The spread of the spatial spectrum: the entropy of the grey level's power in rings of
/// radial frequency 1 to 32 (the central square box-averaged to 64 x 64, mean removed),
/// divided by its largest value, log2 32: near 0 for one smooth wave, near 1 for noise.
double spectral_spread(const Image& img);
/// RMS contrast: the standard deviation of the grey level (0 to 0.5).
double rms_contrast(const Image& img);

// Scores in [0, 1] (the mappings documented in `fixpoint explore --help`):

/// Coverage c: dust below 2% and blobs above 60% are penalised: log-linear from 0 at c <=
/// 0.2% to 1 at 2%, 1 up to 60%, then linear to 0 at 100%.
double coverage_score(double c);
/// Entropy H in bits: H / 6, at most 1 (a density shading that uses many grey levels scores
/// high; a flat or empty image 0).
double entropy_score(double bits);
/// Dimension D: 1 for D in [1.3, 1.8] (a filled blob measures 1.9 and above); linear from 0
/// at D = 0.5 to 1 at 1.3; linear from 1 at 1.8 to 0 at 2.
double dimension_score(double d);
/// Largest Lyapunov exponent L (natural log per step): logistic 1 / (1 + exp(-L / 0.05)):
/// chaos (L > 0, an orbit that spreads into a band) near 1, a regular orbit (L = 0: closed
/// curves, periodic points) 0.5, a strongly contracting one near 0.
double lyapunov_score(double l);
/// The wallpaper measures' scores (calibrated on paper 04's figures: explore --help).
double colour_entropy_score(double bits);
double edge_entropy_score(double bits);
double spectrum_score(double spread);
double group_score(double strength);
double contrast_score(double c);

} // namespace fp::host
