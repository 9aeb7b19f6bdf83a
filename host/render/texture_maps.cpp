#include "host/render/texture_maps.h"

#include <algorithm>
#include <cmath>

namespace ardcell {
namespace {

// Image row r shows grid row ny - 1 - r (the grid's y axis points up).
int grid_row(int image_row, int ny) { return ny - 1 - image_row; }

template <class Image, int kMax>
HeightRange height_map(const FieldF& field, Image& out) {
  using Pixel = typename decltype(out.pixels)::value_type;
  const HeightRange range = height_range(field);
  const int nx = field.nx(), ny = field.ny();
  out.resize(nx, ny);
  for (int r = 0; r < ny; ++r) {
    const float* src = field.row(grid_row(r, ny));
    Pixel* dst = out.pixels.data() + std::size_t(r) * std::size_t(nx);
    for (int x = 0; x < nx; ++x)
      dst[x] = Pixel(std::lround(normalized_height(src[x], range) * double(kMax)));
  }
  return range;
}

uint8_t to_byte(double component) {
  return uint8_t(std::lround(std::clamp(component * 0.5 + 0.5, 0.0, 1.0) * 255.0));
}

}  // namespace

HeightRange height_range(const FieldF& field) {
  HeightRange r;
  bool any = false;
  for (int y = 0; y < field.ny(); ++y) {
    const float* row = field.row(y);
    for (int x = 0; x < field.nx(); ++x) {
      const float v = row[x];
      if (!std::isfinite(v)) {
        ++r.non_finite;
        continue;
      }
      if (!any) {
        r.lo = r.hi = v;
        any = true;
      }
      r.lo = std::min(r.lo, v);
      r.hi = std::max(r.hi, v);
    }
  }
  return r;
}

double normalized_height(float value, const HeightRange& range) {
  if (std::isnan(value)) return 0.5;
  if (std::isinf(value)) return value > 0 ? 1.0 : 0.0;
  // In double: hi - lo of two finite floats cannot overflow there.
  const double span = double(range.hi) - double(range.lo);
  if (!(span > 0)) return 0.5;
  return std::clamp((double(value) - double(range.lo)) / span, 0.0, 1.0);
}

HeightRange height_map_8(const FieldF& field, ImageGray8& out) {
  return height_map<ImageGray8, 255>(field, out);
}

HeightRange height_map_16(const FieldF& field, ImageGray16& out) {
  return height_map<ImageGray16, 65535>(field, out);
}

HeightRange normal_map(const FieldF& field, const NormalMapOptions& options, ImageRgb8& out) {
  const HeightRange range = height_range(field);
  const int nx = field.nx(), ny = field.ny();
  out.resize(nx, ny);
  if (out.empty()) return range;
  // The normalized heights once (the slopes read each of them four times).
  std::vector<double> h(std::size_t(nx) * std::size_t(ny));
  for (int y = 0; y < ny; ++y)
    for (int x = 0; x < nx; ++x)
      h[std::size_t(y) * std::size_t(nx) + std::size_t(x)] = normalized_height(field(x, y), range);
  auto at = [&](int x, int y) { return h[std::size_t(y) * std::size_t(nx) + std::size_t(x)]; };
  // Central difference along one axis at index i of n: wrapped, or one-sided at the ends.
  auto slope = [&](int i, int n, auto&& sample) {
    if (n < 2) return 0.0;
    if (options.periodic) return 0.5 * (sample((i + 1) % n) - sample((i + n - 1) % n));
    if (i == 0) return sample(1) - sample(0);
    if (i == n - 1) return sample(n - 1) - sample(n - 2);
    return 0.5 * (sample(i + 1) - sample(i - 1));
  };
  // Bounded so that the squared slopes below stay finite (a NaN normal is never written).
  const double s = std::isfinite(options.strength) ? std::clamp(options.strength, -1e6, 1e6) : 0.0;
  for (int r = 0; r < ny; ++r) {
    const int y = grid_row(r, ny);
    uint8_t* dst = out.row(r);
    for (int x = 0; x < nx; ++x) {
      const double dx = slope(x, nx, [&](int i) { return at(i, y); });
      const double dy = slope(y, ny, [&](int j) { return at(x, j); });
      const double gx = -s * dx, gy = -s * dy;
      const double inv = 1.0 / std::sqrt(gx * gx + gy * gy + 1.0);
      dst[3 * x + 0] = to_byte(gx * inv);
      dst[3 * x + 1] = to_byte(gy * inv);
      dst[3 * x + 2] = to_byte(inv);
    }
  }
  return range;
}

}  // namespace ardcell
