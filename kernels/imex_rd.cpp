#include "kernels/imex_rd.h"

namespace ardcell {

void sbdf_rhs_tile(View<float> a, View<float> b, View<float> a_prev, View<float> b_prev,
                   Box2 region, const SbdfRhsParams& p) {
  const double dt = p.dt;
  for (int y = region.min.y; y < region.max.y; ++y) {
    float* ar = a.row(y);
    float* br = b.row(y);
    float* ap = a_prev.row(y);
    float* bp = b_prev.row(y);
    for (int x = region.min.x; x < region.max.x; ++x) {
      const double A = ar[x], B = br[x];
      double ra = 0, rb = 0;
      if (p.react) reaction_rates(p.reaction, A, B, ra, rb);
      double rhs_a, rhs_b;
      if (p.order == 2) {
        const double A1 = ap[x], B1 = bp[x];
        double ra1 = 0, rb1 = 0;
        if (p.react) reaction_rates(p.reaction, A1, B1, ra1, rb1);
        rhs_a = (4.0 * A - A1) / 3.0 + 2.0 / 3.0 * dt * (2.0 * ra - ra1);
        rhs_b = (4.0 * B - B1) / 3.0 + 2.0 / 3.0 * dt * (2.0 * rb - rb1);
      } else {
        rhs_a = A + dt * ra;
        rhs_b = B + dt * rb;
      }
      ap[x] = ar[x];
      bp[x] = br[x];
      ar[x] = float(rhs_a);
      br[x] = float(rhs_b);
    }
  }
}

}  // namespace ardcell
