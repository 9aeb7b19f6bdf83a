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

void pressure_rhs_cut(View<const float> u, View<const float> v, View<const float> open_x,
                      View<const float> open_y, View<float> rhs, Box2 region,
                      const ProjectParams& params) {
  const float k = -0.5f * params.h;
  for (int y = region.min.y; y < region.max.y; ++y) {
    const float* __restrict um = u.row(y);
    const float* __restrict vb = v.row(y - 1);
    const float* __restrict vm = v.row(y);
    const float* __restrict va = v.row(y + 1);
    const float* __restrict ox = open_x.row(y);
    const float* __restrict oyb = open_y.row(y);
    const float* __restrict oya = open_y.row(y + 1);
    float* __restrict out = rhs.row(y);
    for (int x = region.min.x; x < region.max.x; ++x)
      out[x] = k * (ox[x + 1] * (um[x] + um[x + 1]) - ox[x] * (um[x - 1] + um[x]) +
                    oya[x] * (vm[x] + va[x]) - oyb[x] * (vb[x] + vm[x]));
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

void face_velocities(View<const float> u, View<const float> v, View<const float> p, View<float> uf,
                     View<float> vf, Box2 region, const ProjectParams& params, bool top_faces) {
  const float inv_h = 1.0f / params.h;
  for (int y = region.min.y; y < region.max.y; ++y) {
    const float* ur = u.row(y);
    const float* pr = p.row(y);
    float* out = uf.row(y);
    for (int x = region.min.x; x <= region.max.x; ++x)
      out[x] = 0.5f * (ur[x - 1] + ur[x]) - (pr[x] - pr[x - 1]) * inv_h;
  }
  const int last_face_row = top_faces ? region.max.y : region.max.y - 1;
  for (int y = region.min.y; y <= last_face_row; ++y) {
    const float* vb = v.row(y - 1);
    const float* vm = v.row(y);
    const float* pb = p.row(y - 1);
    const float* pm = p.row(y);
    float* out = vf.row(y);
    for (int x = region.min.x; x < region.max.x; ++x)
      out[x] = 0.5f * (vb[x] + vm[x]) - (pm[x] - pb[x]) * inv_h;
  }
}

}  // namespace ardcell
