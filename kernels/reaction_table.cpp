#include "kernels/reaction_table.h"

#include <algorithm>

namespace ardcell {

ReactionTable::ReactionTable(const ReactionParams& params, double dt, const ConcentrationBox& range,
                             int n)
    : params_(params), dt_(dt), range_(range), n_(n) {
  ARDCELL_CHECK(n >= 2, "reaction table needs at least 2 points per axis");
  ARDCELL_CHECK(range.a_hi > range.a_lo && range.b_hi > range.b_lo,
                "reaction table range must be non-empty and finite");
  data_.resize(std::size_t(n) * n * 2);
  for (int j = 0; j < n; ++j) {
    const double B = range.b_lo + (range.b_hi - range.b_lo) * j / (n - 1);
    for (int i = 0; i < n; ++i) {
      const double A = range.a_lo + (range.a_hi - range.a_lo) * i / (n - 1);
      const ImplicitResult r = implicit_reaction_cell(params, dt, A, B);
      worst_residual_ = std::max(worst_residual_, r.residual);
      data_[(std::size_t(j) * n + i) * 2] = float(r.a);
      data_[(std::size_t(j) * n + i) * 2 + 1] = float(r.b);
    }
  }
}

void reaction_table_tile(View<const float> a, View<const float> b, View<float> a_out,
                         View<float> b_out, Box2 region, const ReactionTableView& table) {
  for (int y = region.min.y; y < region.max.y; ++y) {
    const float* ar = a.row(y);
    const float* br = b.row(y);
    float* ao = a_out.row(y);
    float* bo = b_out.row(y);
    for (int x = region.min.x; x < region.max.x; ++x) {
      float ah, bh;
      reaction_table_lookup(table, ar[x], br[x], ah, bh);
      ao[x] = ah;
      bo[x] = bh;
    }
  }
}

}  // namespace ardcell
