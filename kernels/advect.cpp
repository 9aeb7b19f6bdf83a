#include "kernels/advect.h"

#include <algorithm>
#include <array>
#include <cmath>

#if defined(__AVX2__) && defined(__FMA__)
#include <immintrin.h>
#define ARDCELL_ADVECT_AVX2 1
#endif

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
  // Written so that a NaN lands on lo (a broken velocity must not index out of the view).
  p = p > a.lo ? p : a.lo;
  p = p < a.hi ? p : a.hi;
  // floor is exact: the cell does not depend on where the view starts (a shift by view_min
  // before truncating rounds p - view_min, so a block with a deep halo would pick another cell
  // than the whole grid for p just below an integer).
  int i = int(std::floor(p));
  i = std::min(std::max(i, a.view_min), a.view_max - 2);
  i0 = i;
  s1 = p - float(i);
}

// Written as nested lerps a + s (b - a), so a constant field is reproduced exactly.
inline float bilinear(const View<const float>& q, const Sample& s) {
  const float* r0 = q.row(s.j0);
  const float* r1 = q.row(s.j0 + 1);
  const float low = r0[s.i0] + s.s1 * (r0[s.i0 + 1] - r0[s.i0]);
  const float high = r1[s.i0] + s.s1 * (r1[s.i0 + 1] - r1[s.i0]);
  return low + s.t1 * (high - low);
}

// The back-traced point of cell (x, y): the midpoint rule (RK2). The velocity at the midpoint
// x - dt/2 u(x) is interpolated from (u, v) with the same clamps as the sample.
inline void back_trace(const View<const float>& u, const View<const float>& v, const AxisLimits& ax,
                       const AxisLimits& ay, float k, int x, int y, float ux, float vy, Sample& s) {
  Sample mid;
  locate(ax, float(x) - 0.5f * k * ux, mid.i0, mid.s1);
  locate(ay, float(y) - 0.5f * k * vy, mid.j0, mid.t1);
  const float um = bilinear(u, mid), vm = bilinear(v, mid);
  locate(ax, float(x) - k * um, s.i0, s.s1);
  locate(ay, float(y) - k * vm, s.j0, s.t1);
}

}  // namespace

namespace {

#if defined(ARDCELL_ADVECT_AVX2)
// locate() on 8 lanes. Each step is the scalar one: max_ps(p, lo) is p > lo ? p : lo (a NaN
// lands on lo), min_ps(p, hi) is p < hi ? p : hi, floor_ps is std::floor.
struct AxisLanes {
  __m256 lo, hi;
  __m256i view_min, view_max2;
  explicit AxisLanes(const AxisLimits& a)
      : lo(_mm256_set1_ps(a.lo)),
        hi(_mm256_set1_ps(a.hi)),
        view_min(_mm256_set1_epi32(a.view_min)),
        view_max2(_mm256_set1_epi32(a.view_max - 2)) {}
};

inline void locate8(const AxisLanes& a, __m256 p, __m256i& i0, __m256& s1) {
  p = _mm256_max_ps(p, a.lo);
  p = _mm256_min_ps(p, a.hi);
  __m256i i = _mm256_cvttps_epi32(_mm256_floor_ps(p));
  i = _mm256_min_epi32(_mm256_max_epi32(i, a.view_min), a.view_max2);
  i0 = i;
  s1 = _mm256_sub_ps(p, _mm256_cvtepi32_ps(i));
}

// bilinear() on 8 lanes: the four corners gathered (each row's two neighbours as one 8-byte
// element: half the gathered elements of four float gathers, about 20% faster on Zen 4), the
// same nested lerps as fused multiply-adds (what the compiler contracts the scalar a + s (b - a)
// to).
struct GatherView {
  const float* base;  // element (0, 0) of the view's coordinates, as an offset from data()
  __m256i stride;
  int stride_i;
  explicit GatherView(const View<const float>& q)
      : base(q.data()),
        stride(_mm256_set1_epi32(int(q.stride()))),
        stride_i(int(q.stride())),
        origin_(q.box().min) {}
  __m256 at(__m256i i0, __m256i j0, __m256 s1, __m256 t1) const {
    const __m256i idx = _mm256_add_epi32(
        _mm256_mullo_epi32(_mm256_sub_epi32(j0, _mm256_set1_epi32(origin_.y)), stride),
        _mm256_sub_epi32(i0, _mm256_set1_epi32(origin_.x)));
    // Pairs (i0, i0 + 1) of a row as one 8-byte gather element: 4 cells per gather.
    const __m128i lo = _mm256_castsi256_si128(idx), hi = _mm256_extracti128_si256(idx, 1);
    const double* b0 = reinterpret_cast<const double*>(base);
    const double* b1 = reinterpret_cast<const double*>(base + stride_i);
    // The masked form with a zero source: the plain intrinsic's undefined source trips
    // -Wmaybe-uninitialized in GCC 12.
    const auto pairs = [](const double* row, __m128i at) {
      const __m256d all = _mm256_castsi256_pd(_mm256_set1_epi64x(-1));
      return _mm256_castpd_ps(_mm256_mask_i32gather_pd(_mm256_setzero_pd(), row, at, all, 4));
    };
    const __m256 p0l = pairs(b0, lo), p0h = pairs(b0, hi);
    const __m256 p1l = pairs(b1, lo), p1h = pairs(b1, hi);
    // Deinterleave: lanes come out in the order 0 1 4 5 2 3 6 7; put them back.
    const auto fix = [](__m256 v) {
      return _mm256_castpd_ps(_mm256_permute4x64_pd(_mm256_castps_pd(v), 0xD8));
    };
    const __m256 r00 = fix(_mm256_shuffle_ps(p0l, p0h, 0x88));
    const __m256 r01 = fix(_mm256_shuffle_ps(p0l, p0h, 0xDD));
    const __m256 r10 = fix(_mm256_shuffle_ps(p1l, p1h, 0x88));
    const __m256 r11 = fix(_mm256_shuffle_ps(p1l, p1h, 0xDD));
    const __m256 low = _mm256_fmadd_ps(s1, _mm256_sub_ps(r01, r00), r00);
    const __m256 high = _mm256_fmadd_ps(s1, _mm256_sub_ps(r11, r10), r10);
    return _mm256_fmadd_ps(t1, _mm256_sub_ps(high, low), low);
  }

 private:
  Int2 origin_;
};
#endif

}  // namespace

void advect_fields(View<const float> u, View<const float> v, std::span<const View<const float>> q0,
                   std::span<const View<float>> q, Box2 region, const AdvectParams& params) {
  ARDCELL_CHECK(q0.size() == q.size() && q0.size() <= std::size_t(kMaxAdvectFields),
                "advect_fields: one output per input, at most kMaxAdvectFields");
  if (region.empty() || q0.empty()) return;
  Box2 b = u.box().intersected(v.box());
  for (const View<const float>& f : q0) {
    ARDCELL_CHECK(f.box() == q0[0].box(), "advect_fields: every source field needs one box");
    b = b.intersected(f.box());
  }
  ARDCELL_CHECK(b.width() >= 2 && b.height() >= 2, "advect: source view too small");
  const AxisLimits ax = axis_limits(b.min.x, b.max.x, params.domain.x, params.periodic);
  const AxisLimits ay = axis_limits(b.min.y, b.max.y, params.domain.y, params.periodic);
  const float k = params.dt_over_h;
  const std::size_t nf = q0.size();
#if defined(ARDCELL_ADVECT_AVX2)
  const bool vector = !ax.wrap && !ay.wrap;
  const AxisLanes lx(ax), ly(ay);
  const GatherView gu(u), gv(v);
  std::array<GatherView, kMaxAdvectFields> gq{gu, gu, gu, gu};
  for (std::size_t i = 0; i < nf; ++i) gq[i] = GatherView(q0[i]);
  const __m256 half_k = _mm256_set1_ps(0.5f * k), kk = _mm256_set1_ps(k);
  const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
#endif
  for (int y = region.min.y; y < region.max.y; ++y) {
    const float* ur = u.row(y);
    const float* vr = v.row(y);
    int x = region.min.x;
#if defined(ARDCELL_ADVECT_AVX2)
    if (vector) {
      const __m256 fy = _mm256_set1_ps(float(y));
      for (; x + 8 <= region.max.x; x += 8) {
        const __m256 fx = _mm256_cvtepi32_ps(_mm256_add_epi32(_mm256_set1_epi32(x), lane));
        __m256i mi, mj, i0, j0;
        __m256 ms, mt, s1, t1;
        locate8(lx, _mm256_fnmadd_ps(half_k, _mm256_loadu_ps(ur + x), fx), mi, ms);
        locate8(ly, _mm256_fnmadd_ps(half_k, _mm256_loadu_ps(vr + x), fy), mj, mt);
        const __m256 um = gu.at(mi, mj, ms, mt), vm = gv.at(mi, mj, ms, mt);
        locate8(lx, _mm256_fnmadd_ps(kk, um, fx), i0, s1);
        locate8(ly, _mm256_fnmadd_ps(kk, vm, fy), j0, t1);
        for (std::size_t i = 0; i < nf; ++i)
          _mm256_storeu_ps(q[i].row(y) + x, gq[i].at(i0, j0, s1, t1));
      }
    }
#endif
    for (; x < region.max.x; ++x) {
      Sample s;
      back_trace(u, v, ax, ay, k, x, y, ur[x], vr[x], s);
      for (std::size_t i = 0; i < nf; ++i) q[i].row(y)[x] = bilinear(q0[i], s);
    }
  }
}

namespace {

// Bilinear sampling of a face-centred component: sample coordinate = point + offset, clamped to
// [lo, hi] (the faces and rows that exist) and to the view.
struct FaceSampler {
  View<const float> f;
  AxisLimits ax, ay;
  float ox, oy;

  FaceSampler(View<const float> field, Int2 faces, Int2 offset_twice, bool periodic, Int2 period)
      : f(field), ox(0.5f * offset_twice.x), oy(0.5f * offset_twice.y) {
    const Box2& b = field.box();
    ax = axis_limits(b.min.x, b.max.x, faces.x - 1, periodic);
    ay = axis_limits(b.min.y, b.max.y, faces.y - 1, periodic);
    // axis_limits clamps to [-0.5, n - 0.5] of a cell grid of n cells; faces run over [0, n - 1].
    if (!periodic) {
      ax.lo = std::max(0.0f, float(b.min.x));
      ax.hi = std::min(float(faces.x - 1), float(b.max.x - 1));
      ay.lo = std::max(0.0f, float(b.min.y));
      ay.hi = std::min(float(faces.y - 1), float(b.max.y - 1));
    } else {
      ax.wrap = ax.wrap && b.min.x <= -1 && b.max.x >= period.x + 1;
      ay.wrap = ay.wrap && b.min.y <= -1 && b.max.y >= period.y + 1;
      ax.period = float(period.x);
      ay.period = float(period.y);
    }
  }

  float at(float px, float py) const {
    Sample s;
    locate(ax, px + ox, s.i0, s.s1);
    locate(ay, py + oy, s.j0, s.t1);
    return bilinear(f, s);
  }
};

// The departure point of cell (x, y) under the face velocities (row y's uf at ul, vf's rows y
// and y + 1 at vb, va): the midpoint rule, the midpoint's velocity sampled from the faces.
inline void mac_departure(const FaceSampler& su, const FaceSampler& sv, const AxisLimits& ax,
                          const AxisLimits& ay, float k, int x, const float* ul, const float* vb,
                          const float* va, int y, Sample& s) {
  const float ux = 0.5f * (ul[x] + ul[x + 1]), vy = 0.5f * (vb[x] + va[x]);
  const float mx = float(x) - 0.5f * k * ux, my = float(y) - 0.5f * k * vy;
  locate(ax, float(x) - k * su.at(mx, my), s.i0, s.s1);
  locate(ay, float(y) - k * sv.at(mx, my), s.j0, s.t1);
}

// q_hat + (q0 - q_back) / 2 at a cell, clamped to the four cells of q0 around the sample s.
inline float corrected(const View<const float>& q0, const Sample& s, float q_hat, float q0_here,
                       float q_back) {
  const float* r0 = q0.row(s.j0);
  const float* r1 = q0.row(s.j0 + 1);
  const float lo = std::min(std::min(r0[s.i0], r0[s.i0 + 1]), std::min(r1[s.i0], r1[s.i0 + 1]));
  const float hi = std::max(std::max(r0[s.i0], r0[s.i0 + 1]), std::max(r1[s.i0], r1[s.i0 + 1]));
  const float q = q_hat + 0.5f * (q0_here - q_back);
  // Written so that a NaN lands on lo, as locate() does.
  return std::min(q > lo ? q : lo, hi);
}

}  // namespace

void advect_scalar_mac(View<const float> q0, View<const float> uf, View<const float> vf,
                       View<float> q, Box2 region, const AdvectParams& params) {
  if (region.empty()) return;
  const Int2 n = params.domain;
  const bool periodic = params.periodic;
  // uf(i, j) sits at x = i - 0.5, y = j; vf(i, j) at x = i, y = j - 0.5 (cell coordinates).
  const FaceSampler su(uf, {n.x + 1, n.y}, {1, 0}, periodic, n);
  const FaceSampler sv(vf, {n.x, n.y + 1}, {0, 1}, periodic, n);
  const Box2& b = q0.box();
  ARDCELL_CHECK(b.width() >= 2 && b.height() >= 2, "advect: source view too small");
  const AxisLimits ax = axis_limits(b.min.x, b.max.x, n.x, periodic);
  const AxisLimits ay = axis_limits(b.min.y, b.max.y, n.y, periodic);
  const float k = params.dt_over_h;
#if defined(ARDCELL_ADVECT_AVX2)
  // advect_fields' 8 lanes: the same operations as the scalar loop below, the products that
  // GCC contracts there as the fused multiply-adds here.
  const bool vector =
      !ax.wrap && !ay.wrap && !su.ax.wrap && !su.ay.wrap && !sv.ax.wrap && !sv.ay.wrap;
  const AxisLanes lx(ax), ly(ay), lux(su.ax), luy(su.ay), lvx(sv.ax), lvy(sv.ay);
  const GatherView gq(q0), gu(uf), gv(vf);
  const __m256 half = _mm256_set1_ps(0.5f), half_k = _mm256_set1_ps(0.5f * k),
               kk = _mm256_set1_ps(k);
  const __m256 oux = _mm256_set1_ps(su.ox), ouy = _mm256_set1_ps(su.oy),
               ovx = _mm256_set1_ps(sv.ox), ovy = _mm256_set1_ps(sv.oy);
  const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
#endif
  for (int y = region.min.y; y < region.max.y; ++y) {
    const float* ul = uf.row(y);
    const float* vb = vf.row(y);
    const float* va = vf.row(y + 1);
    float* out = q.row(y);
    int x = region.min.x;
#if defined(ARDCELL_ADVECT_AVX2)
    if (vector) {
      const __m256 fy = _mm256_set1_ps(float(y));
      for (; x + 8 <= region.max.x; x += 8) {
        const __m256 fx = _mm256_cvtepi32_ps(_mm256_add_epi32(_mm256_set1_epi32(x), lane));
        const __m256 ux = _mm256_mul_ps(
            half, _mm256_add_ps(_mm256_loadu_ps(ul + x), _mm256_loadu_ps(ul + x + 1)));
        const __m256 vy =
            _mm256_mul_ps(half, _mm256_add_ps(_mm256_loadu_ps(vb + x), _mm256_loadu_ps(va + x)));
        const __m256 mx = _mm256_fnmadd_ps(half_k, ux, fx), my = _mm256_fnmadd_ps(half_k, vy, fy);
        __m256i fi, fj, i0, j0;
        __m256 fs, ft, s1, t1;
        locate8(lux, _mm256_add_ps(mx, oux), fi, fs);
        locate8(luy, _mm256_add_ps(my, ouy), fj, ft);
        const __m256 um = gu.at(fi, fj, fs, ft);
        locate8(lvx, _mm256_add_ps(mx, ovx), fi, fs);
        locate8(lvy, _mm256_add_ps(my, ovy), fj, ft);
        const __m256 vm = gv.at(fi, fj, fs, ft);
        locate8(lx, _mm256_fnmadd_ps(kk, um, fx), i0, s1);
        locate8(ly, _mm256_fnmadd_ps(kk, vm, fy), j0, t1);
        _mm256_storeu_ps(out + x, gq.at(i0, j0, s1, t1));
      }
    }
#endif
    for (; x < region.max.x; ++x) {
      Sample s;
      mac_departure(su, sv, ax, ay, k, x, ul, vb, va, y, s);
      out[x] = bilinear(q0, s);
    }
  }
}

// One field, and the velocity itself: the shared back-trace with one or two fields (the
// vectorised path, the same bits as the scalar one).
void advect_scalar(View<const float> q0, View<const float> u, View<const float> v, View<float> q,
                   Box2 region, const AdvectParams& params) {
  const View<const float> in[] = {q0};
  const View<float> out[] = {q};
  advect_fields(u, v, in, out, region, params);
}

void advect_velocity(View<const float> u0, View<const float> v0, View<float> u, View<float> v,
                     Box2 region, const AdvectParams& params) {
  const View<const float> in[] = {u0, v0};
  const View<float> out[] = {u, v};
  advect_fields(u0, v0, in, out, region, params);
}

void maccormack_correct(View<const float> u, View<const float> v,
                        std::span<const View<const float>> q0,
                        std::span<const View<const float>> q_hat,
                        std::span<const View<const float>> q_back, std::span<const View<float>> q,
                        Box2 region, const AdvectParams& params) {
  ARDCELL_CHECK(q0.size() == q.size() && q_hat.size() == q.size() && q_back.size() == q.size(),
                "maccormack_correct: one q_hat, q_back and output per input");
  if (region.empty() || q0.empty()) return;
  Box2 b = u.box().intersected(v.box());
  for (const View<const float>& f : q0) {
    ARDCELL_CHECK(f.box() == q0[0].box(), "maccormack_correct: every source field needs one box");
    b = b.intersected(f.box());
  }
  ARDCELL_CHECK(b.width() >= 2 && b.height() >= 2, "advect: source view too small");
  const AxisLimits ax = axis_limits(b.min.x, b.max.x, params.domain.x, params.periodic);
  const AxisLimits ay = axis_limits(b.min.y, b.max.y, params.domain.y, params.periodic);
  const float k = params.dt_over_h;
  for (int y = region.min.y; y < region.max.y; ++y) {
    const float* ur = u.row(y);
    const float* vr = v.row(y);
    for (int x = region.min.x; x < region.max.x; ++x) {
      Sample s;
      back_trace(u, v, ax, ay, k, x, y, ur[x], vr[x], s);
      for (std::size_t i = 0; i < q0.size(); ++i)
        q[i].row(y)[x] =
            corrected(q0[i], s, q_hat[i].row(y)[x], q0[i].row(y)[x], q_back[i].row(y)[x]);
    }
  }
}

void maccormack_correct_mac(View<const float> q0, View<const float> q_hat, View<const float> q_back,
                            View<const float> uf, View<const float> vf, View<float> q, Box2 region,
                            const AdvectParams& params) {
  if (region.empty()) return;
  const Int2 n = params.domain;
  const FaceSampler su(uf, {n.x + 1, n.y}, {1, 0}, params.periodic, n);
  const FaceSampler sv(vf, {n.x, n.y + 1}, {0, 1}, params.periodic, n);
  const Box2& b = q0.box();
  ARDCELL_CHECK(b.width() >= 2 && b.height() >= 2, "advect: source view too small");
  const AxisLimits ax = axis_limits(b.min.x, b.max.x, n.x, params.periodic);
  const AxisLimits ay = axis_limits(b.min.y, b.max.y, n.y, params.periodic);
  const float k = params.dt_over_h;
  for (int y = region.min.y; y < region.max.y; ++y) {
    const float* ul = uf.row(y);
    const float* vb = vf.row(y);
    const float* va = vf.row(y + 1);
    for (int x = region.min.x; x < region.max.x; ++x) {
      Sample s;
      mac_departure(su, sv, ax, ay, k, x, ul, vb, va, y, s);
      q.row(y)[x] = corrected(q0, s, q_hat.row(y)[x], q0.row(y)[x], q_back.row(y)[x]);
    }
  }
}

}  // namespace ardcell
