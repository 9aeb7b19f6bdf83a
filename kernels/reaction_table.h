#pragma once
// The precomputed implicit reaction of seed 000 (section 3): for one dt, the update
// (A, B) -> (A^, B^) of Eqn 6 tabulated on an n x n grid over a concentration box and
// interpolated bilinearly at run time. Inputs outside the box are clamped to it. Halo 0.
// Accuracy: bilinear, so the error is O(cell^2 * |second derivative|); the test states the
// bound met at the default 256 x 256 for each model (reaction_table_test).
#include <vector>

#include "kernels/reaction.h"

namespace ardcell {

// A plain view of a table (pointer + sizes), passable to a tile kernel or an OpenCL buffer.
struct ReactionTableView {
  const float* data = nullptr;  // n*n pairs (A^, B^), row-major in B (data[(j*n + i)*2])
  int n = 0;
  float a_lo = 0, a_hi = 1, b_lo = 0, b_hi = 1;
};

class ReactionTable {
 public:
  ReactionTable() = default;
  // Tabulates the implicit update for (params, dt) on n x n points of `range`.
  ReactionTable(const ReactionParams& params, double dt, const ConcentrationBox& range, int n);

  ReactionTableView view() const {
    return {data_.data(),      n_, float(range_.a_lo), float(range_.a_hi), float(range_.b_lo),
            float(range_.b_hi)};
  }
  bool empty() const { return data_.empty(); }
  double dt() const { return dt_; }
  const ReactionParams& params() const { return params_; }
  // Largest |Newton residual| met while building (every entry is a converged solve).
  double worst_build_residual() const { return worst_residual_; }

 private:
  ReactionParams params_;
  double dt_ = 0;
  ConcentrationBox range_{0, 1, 0, 1};
  int n_ = 0;
  std::vector<float> data_;
  double worst_residual_ = 0;
};

// Bilinear lookup of one cell.
inline void reaction_table_lookup(const ReactionTableView& t, float A, float B, float& a_hat,
                                  float& b_hat) {
  const float sx = (t.n - 1) / (t.a_hi - t.a_lo), sy = (t.n - 1) / (t.b_hi - t.b_lo);
  float fx = (A - t.a_lo) * sx, fy = (B - t.b_lo) * sy;
  fx = fx < 0 ? 0 : (fx > float(t.n - 1) ? float(t.n - 1) : fx);
  fy = fy < 0 ? 0 : (fy > float(t.n - 1) ? float(t.n - 1) : fy);
  int i = int(fx), j = int(fy);
  if (i > t.n - 2) i = t.n - 2;
  if (j > t.n - 2) j = t.n - 2;
  const float u = fx - float(i), v = fy - float(j);
  const float* p00 = t.data + (std::ptrdiff_t(j) * t.n + i) * 2;
  const float* p01 = p00 + std::ptrdiff_t(t.n) * 2;
  const float w00 = (1 - u) * (1 - v), w10 = u * (1 - v), w01 = (1 - u) * v, w11 = u * v;
  a_hat = w00 * p00[0] + w10 * p00[2] + w01 * p01[0] + w11 * p01[2];
  b_hat = w00 * p00[1] + w10 * p00[3] + w01 * p01[1] + w11 * p01[3];
}

// Table-driven implicit reaction over region (outputs may alias inputs).
void reaction_table_tile(View<const float> a, View<const float> b, View<float> a_out,
                         View<float> b_out, Box2 region, const ReactionTableView& table);

}  // namespace ardcell
