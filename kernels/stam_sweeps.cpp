#include "kernels/stam_sweeps.h"

#if defined(__AVX512F__)
#include <immintrin.h>
#endif

namespace ardcell {

#if defined(__AVX512F__) && defined(__FMA__)
namespace {

// One row of the sweep, 16 cells at a time. The row's own values are loaded once and the x - 1
// and x + 1 neighbours shifted in from the adjacent vectors (a zero-masked valignd: the unmasked
// intrinsic trips -Wmaybe-uninitialized in GCC 12), one load fewer per vector and none split across
// cache lines; the tail is masked. The arithmetic is the scalar loop's in its order: ((x(-1) +
// x(+1)) + x(y-1)) + x(y+1), fused multiply-add with b (as the compiler contracts b + a s), times
// 1/c, so the result is bit for bit the same.
inline __mmask16 lanes(int n) {
  return n >= 16 ? __mmask16(0xFFFF) : n > 0 ? __mmask16((1u << n) - 1) : __mmask16(0);
}

void jacobi_row_avx512(const float* b, const float* xb, const float* xm, const float* xa,
                       float* out, int n, __m512 a, __m512 inv_c) {
  __m512 prev = _mm512_set1_ps(xm[-1]);                  // lane 15 is the left neighbour of cell 0
  __m512 cur = _mm512_maskz_loadu_ps(lanes(n + 1), xm);  // + the right neighbour if n < 16
  for (int x = 0; x < n; x += 16) {
    const int left = n - x;
    // The next vector, or at the row's end the one right neighbour it still needs.
    const __m512 next = _mm512_maskz_loadu_ps(lanes(left - 16 + 1), xm + x + 16);
    const __m512 l = _mm512_castsi512_ps(
        _mm512_maskz_alignr_epi32(0xFFFF, _mm512_castps_si512(cur), _mm512_castps_si512(prev), 15));
    const __m512 r = _mm512_castsi512_ps(
        _mm512_maskz_alignr_epi32(0xFFFF, _mm512_castps_si512(next), _mm512_castps_si512(cur), 1));
    const __mmask16 m = lanes(left);
    const __m512 sum =
        _mm512_add_ps(_mm512_add_ps(_mm512_add_ps(l, r), _mm512_maskz_loadu_ps(m, xb + x)),
                      _mm512_maskz_loadu_ps(m, xa + x));
    _mm512_mask_storeu_ps(
        out + x, m, _mm512_mul_ps(_mm512_fmadd_ps(a, sum, _mm512_maskz_loadu_ps(m, b + x)), inv_c));
    prev = cur;
    cur = next;
  }
}

}  // namespace
#endif

void stam_jacobi_sweep(View<const float> x0, View<const float> x_in, View<float> x_out, Box2 region,
                       const StamSweepParams& params) {
#if defined(__AVX512F__) && defined(__FMA__)
  if (region.empty()) return;
  const __m512 av = _mm512_set1_ps(params.a), icv = _mm512_set1_ps(params.inv_c);
  const int x0i = region.min.x;
  for (int y = region.min.y; y < region.max.y; ++y)
    jacobi_row_avx512(x0.row(y) + x0i, x_in.row(y - 1) + x0i, x_in.row(y) + x0i,
                      x_in.row(y + 1) + x0i, x_out.row(y) + x0i, region.width(), av, icv);
#else
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
#endif
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
