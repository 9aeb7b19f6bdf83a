#pragma once
// Sources and forces (Stam 1999 add_source, and the splats that stir the ink scene):
//   x += scale * s                                   (add_scaled; Stam uses scale = dt)
//   f += amount * exp(-((x - cx)^2 + (y - cy)^2) / radius^2)   (add_splat, cell units)
// Neither reads a halo: each cell depends only on itself.
#include "runtime/boundary.h"
#include "runtime/field.h"

namespace ardcell {

void add_scaled(View<const float> s, View<float> x, Box2 region, float scale);

struct SplatParams {
  float cx = 0.0f, cy = 0.0f;  // centre, in cells (cell (i, j) is centred at (i, j))
  float radius = 1.0f;         // e-folding radius, in cells
  float amount = 0.0f;         // peak added value
};

// Adds a Gaussian splat to f over region (cells beyond 3 radii get nothing).
void add_splat(View<float> f, Box2 region, const SplatParams& splat);

// The obstacle scene's inflow dye: `stripes` dyed stripes entering through the boundary cells
// of `side` (the top row y = size.y - 1, the left column x = 0, ...): the k-th of those n cells
// is 1 in the odd ones of 2 * stripes equal bands, else 0 (integer arithmetic:
// (k * 2 stripes / n) % 2). Writes those cells only, refreshed each frame
// (host/engine/fluid_step.cpp's add_forces_and_sources).
void set_inflow_stripes(View<float> dye, Int2 size, int stripes, BoundarySide side);

}  // namespace ardcell
