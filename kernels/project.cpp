#include "kernels/project.h"

namespace ardcell {

void pressure_rhs(View<const float> u, View<const float> v, View<float> rhs, Box2 region,
                  const ProjectParams& params) {
  const float k = -0.5f * params.h;
  for (int y = region.min.y; y < region.max.y; ++y) {
    const float* __restrict um = u.row(y);
    const float* __restrict vb = v.row(y - 1);
    const float* __restrict va = v.row(y + 1);
    float* __restrict out = rhs.row(y);
    for (int x = region.min.x; x < region.max.x; ++x)
      out[x] = k * (um[x + 1] - um[x - 1] + va[x] - vb[x]);
  }
}

void subtract_gradient(View<const float> p, View<float> u, View<float> v, Box2 region,
                       const ProjectParams& params) {
  const float k = 0.5f / params.h;
  for (int y = region.min.y; y < region.max.y; ++y) {
    const float* __restrict pb = p.row(y - 1);
    const float* __restrict pm = p.row(y);
    const float* __restrict pa = p.row(y + 1);
    float* __restrict ur = u.row(y);
    float* __restrict vr = v.row(y);
    for (int x = region.min.x; x < region.max.x; ++x) {
      ur[x] -= k * (pm[x + 1] - pm[x - 1]);
      vr[x] -= k * (pa[x] - pb[x]);
    }
  }
}

}  // namespace ardcell
