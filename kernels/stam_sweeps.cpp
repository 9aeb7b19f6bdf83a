#include "kernels/stam_sweeps.h"

namespace ardcell {

void stam_jacobi_sweep(View<const float> x0, View<const float> x_in, View<float> x_out, Box2 region,
                       const StamSweepParams& params) {
  const float a = params.a, inv_c = params.inv_c;
  for (int y = region.min.y; y < region.max.y; ++y) {
    const float* __restrict b = x0.row(y);
    const float* __restrict xb = x_in.row(y - 1);
    const float* __restrict xm = x_in.row(y);
    const float* __restrict xa = x_in.row(y + 1);
    float* __restrict out = x_out.row(y);
    for (int x = region.min.x; x < region.max.x; ++x)
      out[x] = (b[x] + a * (xm[x - 1] + xm[x + 1] + xb[x] + xa[x])) * inv_c;
  }
}

void stam_rbgs_half_sweep(View<const float> x0, View<float> x, Box2 region, int color,
                          const StamSweepParams& params) {
  const float a = params.a, inv_c = params.inv_c;
  for (int y = region.min.y; y < region.max.y; ++y) {
    const float* b = x0.row(y);
    const float* xb = x.row(y - 1);
    float* xm = x.row(y);
    const float* xa = x.row(y + 1);
    int first = region.min.x;
    if (((first + y) & 1) != (color & 1)) ++first;
    for (int i = first; i < region.max.x; i += 2)
      xm[i] = (b[i] + a * (xm[i - 1] + xm[i + 1] + xb[i] + xa[i])) * inv_c;
  }
}

}  // namespace ardcell
