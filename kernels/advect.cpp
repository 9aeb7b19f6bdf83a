#include "kernels/advect.h"

#include <cmath>

namespace ardcell {
namespace {

// Where and with which weights to sample a view bilinearly.
struct Sample {
  int i0, j0;
  float s1, t1;  // weights of i0 + 1 and j0 + 1
};

// Limits of the back-traced point along one axis: inside the domain walls (unless periodic over
// a whole field) and inside the view, with room for the +1 neighbour.
struct AxisLimits {
  float lo, hi;
  int view_min, view_max;  // valid i0 in [view_min, view_max - 2]
  bool wrap;
  float period;
};

AxisLimits axis_limits(int view_min, int view_max, int n, bool periodic) {
  AxisLimits a{};
  a.view_min = view_min;
  a.view_max = view_max;
  // Wrapping needs the whole periodic domain plus its ghost layer in the view.
  a.wrap = periodic && view_min <= -1 && view_max >= n + 1;
  a.period = float(n);
  const float domain_lo = periodic ? -1e30f : -0.5f;
  const float domain_hi = periodic ? 1e30f : float(n) - 0.5f;
  a.lo = std::max(domain_lo, float(view_min));
  a.hi = std::min(domain_hi, float(view_max - 1));
  return a;
}

inline void locate(const AxisLimits& a, float p, int& i0, float& s1) {
  if (a.wrap) {
    p = p - a.period * std::floor(p / a.period);  // [0, n): cell n - 1 interpolates to ghost n
    if (!(p < a.period)) p = 0.0f;                // p / n rounded up to 1
  }
  p = std::min(std::max(p, a.lo), a.hi);
  int i = int(std::floor(p));
  i = std::min(std::max(i, a.view_min), a.view_max - 2);
  i0 = i;
  s1 = p - float(i);
}

inline float bilinear(const View<const float>& q, const Sample& s) {
  const float* r0 = q.row(s.j0);
  const float* r1 = q.row(s.j0 + 1);
  const float s0 = 1.0f - s.s1, t0 = 1.0f - s.t1;
  return t0 * (s0 * r0[s.i0] + s.s1 * r0[s.i0 + 1]) + s.t1 * (s0 * r1[s.i0] + s.s1 * r1[s.i0 + 1]);
}

}  // namespace

void advect_scalar(View<const float> q0, View<const float> u, View<const float> v, View<float> q,
                   Box2 region, const AdvectParams& params) {
  if (region.empty()) return;
  const Box2& b = q0.box();
  ARDCELL_CHECK(b.width() >= 2 && b.height() >= 2, "advect: source view too small");
  const AxisLimits ax = axis_limits(b.min.x, b.max.x, params.domain.x, params.periodic);
  const AxisLimits ay = axis_limits(b.min.y, b.max.y, params.domain.y, params.periodic);
  const float k = params.dt_over_h;
  for (int y = region.min.y; y < region.max.y; ++y) {
    const float* ur = u.row(y);
    const float* vr = v.row(y);
    float* out = q.row(y);
    for (int x = region.min.x; x < region.max.x; ++x) {
      Sample s;
      locate(ax, float(x) - k * ur[x], s.i0, s.s1);
      locate(ay, float(y) - k * vr[x], s.j0, s.t1);
      out[x] = bilinear(q0, s);
    }
  }
}

void advect_velocity(View<const float> u0, View<const float> v0, View<float> u, View<float> v,
                     Box2 region, const AdvectParams& params) {
  if (region.empty()) return;
  const Box2 b = u0.box().intersected(v0.box());
  ARDCELL_CHECK(b.width() >= 2 && b.height() >= 2, "advect: source view too small");
  const AxisLimits ax = axis_limits(b.min.x, b.max.x, params.domain.x, params.periodic);
  const AxisLimits ay = axis_limits(b.min.y, b.max.y, params.domain.y, params.periodic);
  const float k = params.dt_over_h;
  for (int y = region.min.y; y < region.max.y; ++y) {
    const float* ur = u0.row(y);
    const float* vr = v0.row(y);
    float* uo = u.row(y);
    float* vo = v.row(y);
    for (int x = region.min.x; x < region.max.x; ++x) {
      Sample s;
      locate(ax, float(x) - k * ur[x], s.i0, s.s1);
      locate(ay, float(y) - k * vr[x], s.j0, s.t1);
      uo[x] = bilinear(u0, s);
      vo[x] = bilinear(v0, s);
    }
  }
}

}  // namespace ardcell
