#pragma once
// Normwise relative error in the max norm over a field's interior, max |got - ref| / max |ref|:
// the norm the OpenCL parity tests state their 1e-5 bound in.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>

#include "runtime/field.h"

namespace ardcell {

// A field of uniform random values in [lo, hi) over its interior (the halo left at 0).
inline FieldF random_field(Int2 size, int halo, unsigned seed, float lo, float hi) {
  FieldF f(size, halo);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(lo, hi);
  for (int y = 0; y < size.y; ++y)
    for (int x = 0; x < size.x; ++x) f(x, y) = u(rng);
  return f;
}

// The sum of a field's interior in double, row by row.
inline double interior_sum(const FieldF& f) {
  double s = 0.0;
  for (int y = 0; y < f.ny(); ++y)
    for (int x = 0; x < f.nx(); ++x) s += f(x, y);
  return s;
}

// Bit for bit the same cells over `box`, which both fields hold (halo cells allowed): a block's
// owned cells against the same cells of the whole grid.
inline bool same_cells_in(const FieldF& a, const FieldF& b, const Box2& box) {
  for (int y = box.min.y; y < box.max.y; ++y)
    if (std::memcmp(a.row(y) + box.min.x, b.row(y) + box.min.x,
                    std::size_t(box.width()) * sizeof(float)) != 0)
      return false;
  return true;
}

// Bit for bit the same cells, the halo included (same layouts).
inline bool same_cells(const FieldF& a, const FieldF& b) {
  return same_cells_in(a, b, a.with_halo());
}

inline double max_relative_error(const FieldF& got, const FieldF& ref) {
  double diff = 0, mag = 0;
  for (int y = 0; y < ref.ny(); ++y)
    for (int x = 0; x < ref.nx(); ++x) {
      diff = std::max(diff, std::abs(double(got(x, y)) - double(ref(x, y))));
      mag = std::max(mag, std::abs(double(ref(x, y))));
    }
  return diff / std::max(mag, 1e-30);
}

}  // namespace ardcell
