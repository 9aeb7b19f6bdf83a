#pragma once
// A polar plot of a function sampled around a circle: seed 003's Fig. 1, the diffusion
// propagator p_tau(r) at |r| = radius (kernels/gram_charlier.h propagator_on_circle), as the
// curve r(theta) = p(theta) / max |p| with its axes and grid circles, into an RGB image.
// The Gram-Charlier series can go negative: where it does, |p| is drawn in its own colour at
// the same angle, so a negative lobe shows instead of folding into the centre. Labels are the
// caller's (host has no font): polar_plot_layout says where the axes are.
#include <span>
#include <vector>

#include "host/render/colormap.h"
#include "host/render/image.h"

namespace ardcell {

inline constexpr Rgb8 kPolarPositiveRgb{20, 70, 170};  // p > 0
inline constexpr Rgb8 kPolarNegativeRgb{210, 40, 40};  // p < 0, drawn as |p|
inline constexpr Rgb8 kPolarAxisRgb{90, 90, 90};       // the x and y axes
inline constexpr Rgb8 kPolarGridRgb{210, 210, 210};    // circles at 1/4 .. 1, spokes
inline constexpr Rgb8 kPolarBackgroundRgb{255, 255, 255};

// Where the plot sits in a size x size image: the centre and the pixel radius of r = 1; the
// margin around it is left for labels.
struct PolarPlotLayout {
  double cx = 0, cy = 0, radius = 0;
};
PolarPlotLayout polar_plot_layout(int size);
// The axes run this far beyond r = 1 (labels go past their ends).
inline constexpr double kPolarAxisReach = 1.05;

struct PolarPlotInfo {
  double scale = 0;           // max |p| over the finite samples (the curve's r = 1); 0: none
  bool has_negative = false;  // some sample below zero (drawn in kPolarNegativeRgb)
  int non_finite = 0;         // samples that were NaN or +-inf (left out of the curve)
};

// samples[k] is the value at theta_k = 2 pi k / samples.size() from the +x axis, counter-
// clockwise towards +y (image up). Resizes `image` to size x size and draws into it.
PolarPlotInfo draw_polar_plot(std::span<const double> samples, int size, ImageRgb8& image);

// The directions of the lobes: the local maxima of the circular sequence that are above zero,
// in degrees in [0, 360), refined by a parabola through the three samples around each, in
// increasing order. Empty for a flat curve (an isotropic propagator has no preferred direction)
// or one with a non-finite sample.
std::vector<double> polar_maxima_degrees(std::span<const double> samples);

}  // namespace ardcell
