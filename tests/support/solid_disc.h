#pragma once
// The solid obstacle of the solver tests: a disc a fifth of the grid's smaller side across, off
// centre (1 = solid), with a halo of 1.
#include <algorithm>

#include "runtime/field.h"

namespace ardcell {

inline Field<uint8_t> solid_disc(Int2 size) {
  Field<uint8_t> solid(size, 1);
  const float r = 0.1f * float(std::min(size.x, size.y));
  const float cx = 0.4f * float(size.x), cy = 0.55f * float(size.y);
  for (int j = 0; j < size.y; ++j)
    for (int i = 0; i < size.x; ++i)
      solid(i, j) = (float(i) - cx) * (float(i) - cx) + (float(j) - cy) * (float(j) - cy) < r * r;
  return solid;
}

}  // namespace ardcell
