#include "kernels/sources.h"

#include <cmath>

namespace ardcell {

void add_scaled(View<const float> s, View<float> x, Box2 region, float scale) {
  for (int y = region.min.y; y < region.max.y; ++y) {
    const float* __restrict sr = s.row(y);
    float* __restrict xr = x.row(y);
    for (int i = region.min.x; i < region.max.x; ++i) xr[i] += scale * sr[i];
  }
}

void add_splat(View<float> f, Box2 region, const SplatParams& splat) {
  if (!(splat.radius > 0.0f)) return;
  const float reach = 3.0f * splat.radius;
  const Box2 near{{int(std::floor(splat.cx - reach)), int(std::floor(splat.cy - reach))},
                  {int(std::ceil(splat.cx + reach)) + 1, int(std::ceil(splat.cy + reach)) + 1}};
  const Box2 r = region.intersected(near);
  if (r.empty()) return;
  const float inv_r2 = 1.0f / (splat.radius * splat.radius);
  for (int y = r.min.y; y < r.max.y; ++y) {
    float* row = f.row(y);
    const float dy2 = (float(y) - splat.cy) * (float(y) - splat.cy);
    for (int x = r.min.x; x < r.max.x; ++x) {
      const float dx = float(x) - splat.cx;
      row[x] += splat.amount * std::exp(-(dx * dx + dy2) * inv_r2);
    }
  }
}

void set_inflow_stripes(View<float> dye, Int2 size, int stripes, BoundarySide side) {
  const int bands = 2 * stripes;
  const bool column = side == BoundarySide::kLeft || side == BoundarySide::kRight;
  const int n = column ? size.y : size.x;
  const int at = side == BoundarySide::kLeft     ? 0
                 : side == BoundarySide::kRight  ? size.x - 1
                 : side == BoundarySide::kBottom ? 0
                                                 : size.y - 1;
  for (int k = 0; k < n; ++k) {
    const float value = (k * bands / n) % 2 ? 1.0f : 0.0f;
    if (column)
      dye(at, k) = value;
    else
      dye(k, at) = value;
  }
}

}  // namespace ardcell
