#include "host/render/polar_plot.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace ardcell {
namespace {

// Anti-aliased thick segments: each pixel near the segment takes the colour in proportion to
// how much of it the stroke covers (distance to the segment within half the width).
class Canvas {
 public:
  explicit Canvas(ImageRgb8& image) : image_(image) {}

  void segment(double x0, double y0, double x1, double y1, double width, Rgb8 c) {
    const double half = 0.5 * width;
    const int xa = std::max(0, int(std::floor(std::min(x0, x1) - half - 1)));
    const int xb = std::min(image_.width - 1, int(std::ceil(std::max(x0, x1) + half + 1)));
    const int ya = std::max(0, int(std::floor(std::min(y0, y1) - half - 1)));
    const int yb = std::min(image_.height - 1, int(std::ceil(std::max(y0, y1) + half + 1)));
    const double dx = x1 - x0, dy = y1 - y0, len2 = dx * dx + dy * dy;
    for (int y = ya; y <= yb; ++y)
      for (int x = xa; x <= xb; ++x) {
        const double px = x + 0.5 - x0, py = y + 0.5 - y0;
        const double t = len2 > 0 ? std::clamp((px * dx + py * dy) / len2, 0.0, 1.0) : 0.0;
        const double d = std::hypot(px - t * dx, py - t * dy);
        const double cover = std::clamp(half + 0.5 - d, 0.0, 1.0);
        if (cover > 0) blend(x, y, c, cover);
      }
  }

  void circle(double cx, double cy, double r, double width, Rgb8 c) {
    constexpr int kSegments = 256;
    for (int i = 0; i < kSegments; ++i) {
      const double a0 = 2 * std::numbers::pi * i / kSegments;
      const double a1 = 2 * std::numbers::pi * (i + 1) / kSegments;
      segment(cx + r * std::cos(a0), cy - r * std::sin(a0), cx + r * std::cos(a1),
              cy - r * std::sin(a1), width, c);
    }
  }

 private:
  void blend(int x, int y, Rgb8 c, double cover) {
    uint8_t* p = image_.row(y) + 3 * x;
    const uint8_t src[3] = {c.r, c.g, c.b};
    for (int k = 0; k < 3; ++k)
      p[k] = uint8_t(std::lround(double(p[k]) + cover * (double(src[k]) - double(p[k]))));
  }

  ImageRgb8& image_;
};

}  // namespace

PolarPlotLayout polar_plot_layout(int size) {
  // The margin holds two-digit to three-digit angle labels of the caller's font.
  return {0.5 * size, 0.5 * size, 0.38 * size};
}

PolarPlotInfo draw_polar_plot(std::span<const double> samples, int size, ImageRgb8& image) {
  image.resize(size, size);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      uint8_t* p = image.row(y) + 3 * x;
      p[0] = kPolarBackgroundRgb.r;
      p[1] = kPolarBackgroundRgb.g;
      p[2] = kPolarBackgroundRgb.b;
    }
  const PolarPlotLayout L = polar_plot_layout(size);
  const double line = std::max(1.0, size / 256.0);
  Canvas canvas(image);
  for (int i = 1; i <= 4; ++i)
    canvas.circle(L.cx, L.cy, L.radius * i / 4.0, line * 0.75, kPolarGridRgb);
  for (int deg = 0; deg < 180; deg += 30) {
    if (deg % 90 == 0) continue;
    const double a = deg * std::numbers::pi / 180, c = std::cos(a), s = std::sin(a);
    canvas.segment(L.cx - L.radius * c, L.cy + L.radius * s, L.cx + L.radius * c,
                   L.cy - L.radius * s, line * 0.75, kPolarGridRgb);
  }
  const double reach = L.radius * kPolarAxisReach;
  canvas.segment(L.cx - reach, L.cy, L.cx + reach, L.cy, line, kPolarAxisRgb);
  canvas.segment(L.cx, L.cy - reach, L.cx, L.cy + reach, line, kPolarAxisRgb);

  PolarPlotInfo info;
  for (double v : samples) {
    if (!std::isfinite(v)) {
      ++info.non_finite;
      continue;
    }
    info.scale = std::max(info.scale, std::abs(v));
    if (v < 0) info.has_negative = true;
  }
  const std::size_t n = samples.size();
  if (!(info.scale > 0) || n < 2) return info;
  auto point = [&](double value, double theta, double& x, double& y) {
    const double r = L.radius * std::abs(value) / info.scale;
    x = L.cx + r * std::cos(theta);
    y = L.cy - r * std::sin(theta);
  };
  const double width = 2.0 * line;
  for (std::size_t k = 0; k < n; ++k) {
    const double v0 = samples[k], v1 = samples[(k + 1) % n];
    if (!std::isfinite(v0) || !std::isfinite(v1)) continue;
    const double t0 = 2 * std::numbers::pi * double(k) / double(n);
    const double t1 = 2 * std::numbers::pi * double(k + 1) / double(n);
    double x0, y0, x1, y1;
    point(v0, t0, x0, y0);
    point(v1, t1, x1, y1);
    if ((v0 < 0) == (v1 < 0)) {
      canvas.segment(x0, y0, x1, y1, width, v0 < 0 ? kPolarNegativeRgb : kPolarPositiveRgb);
      continue;
    }
    // A sign change: the curve passes through the centre where p crosses zero.
    canvas.segment(x0, y0, L.cx, L.cy, width, v0 < 0 ? kPolarNegativeRgb : kPolarPositiveRgb);
    canvas.segment(L.cx, L.cy, x1, y1, width, v1 < 0 ? kPolarNegativeRgb : kPolarPositiveRgb);
  }
  return info;
}

std::vector<double> polar_maxima_degrees(std::span<const double> samples) {
  std::vector<double> out;
  const std::size_t n = samples.size();
  if (n < 3) return out;
  double lo = samples[0], hi = samples[0];
  for (double v : samples) {
    if (!std::isfinite(v)) return out;
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  // Rounding alone makes an isotropic propagator ripple at ~1e-16 relative: not a lobe.
  if (hi - lo <= 1e-9 * std::max(std::abs(hi), std::abs(lo))) return out;
  for (std::size_t k = 0; k < n; ++k) {
    const double prev = samples[(k + n - 1) % n], cur = samples[k], next = samples[(k + 1) % n];
    if (!(cur > 0 && cur > prev && cur >= next)) continue;
    const double curvature = prev - 2 * cur + next;
    const double offset =
        curvature < 0 ? std::clamp(0.5 * (prev - next) / curvature, -0.5, 0.5) : 0.0;
    double deg = (double(k) + offset) * 360.0 / double(n);
    if (deg < 0) deg += 360.0;
    if (deg >= 360.0 - 1e-9) deg = std::max(0.0, deg - 360.0);  // rounding just below 360
    out.push_back(deg);
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace ardcell
