#include "kernels/gray_scott9.h"

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <utility>
#include <vector>

#include "runtime/row_executor.h"

#if defined(__AVX512F__) || defined(__AVX__)
#include <immintrin.h>
#endif

namespace ardcell {
namespace {

// Vector width follows the ISA the translation unit is built for, so that no vector type
// wider than the target's registers crosses a function boundary (-Wpsabi) and a generic
// build still gets SSE/NEON code.
#if defined(__AVX512F__)
constexpr int kLanes = 16;
#elif defined(__AVX__)
constexpr int kLanes = 8;
#else
constexpr int kLanes = 4;
#endif
using Vec = float __attribute__((vector_size(kLanes * sizeof(float))));

[[gnu::always_inline]] inline Vec load(const float* p) {
  Vec v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
[[gnu::always_inline]] inline void store(float* p, Vec v) { std::memcpy(p, &v, sizeof v); }
[[gnu::always_inline]] inline Vec splat(float s) { return Vec{} + s; }
// a * b + c. This file is built with -ffp-contract=off (CMakeLists.txt), so the compiler never
// fuses on its own: where a fused multiply-add is wanted it is written here, and every inlined
// copy of an expression then rounds alike (contraction decided per copy had made cells at
// x = 0 differ between schedules in AVX2 builds). Rounded once on every target, as the per-step
// kernel's std::fma and the OpenCL twin's fma are (kernels/explicit_rd.h), so that all give the
// same bits: lane by lane with fmaf where the intrinsics are missing (one instruction on
// aarch64; a libm call, slow but exact, on an x86 build without FMA).
[[gnu::always_inline]] inline Vec fma(Vec a, Vec b, Vec c) {
#if defined(__AVX512F__)
  return Vec(_mm512_fmadd_ps(__m512(a), __m512(b), __m512(c)));
#elif defined(__FMA__) && defined(__AVX__)
  return Vec(_mm256_fmadd_ps(__m256(a), __m256(b), __m256(c)));
#else
  Vec r;
  for (int i = 0; i < kLanes; ++i) r[i] = __builtin_fmaf(a[i], b[i], c[i]);
  return r;
#endif
}
// c - a * b, rounded once.
[[gnu::always_inline]] inline Vec fnma(Vec a, Vec b, Vec c) {
#if defined(__AVX512F__)
  return Vec(_mm512_fnmadd_ps(__m512(a), __m512(b), __m512(c)));
#elif defined(__FMA__) && defined(__AVX__)
  return Vec(_mm256_fnmadd_ps(__m256(a), __m256(b), __m256(c)));
#else
  Vec r;
  for (int i = 0; i < kLanes; ++i) r[i] = __builtin_fmaf(-a[i], b[i], c[i]);
  return r;
#endif
}

// [prev[L-1], cur[0 .. L-2]]: the left neighbours of cur's lanes.
template <std::size_t... I>
[[gnu::always_inline]] inline Vec lefts(Vec prev, Vec cur, std::index_sequence<I...>) {
#if defined(__AVX512F__)
  return Vec(_mm512_castsi512_ps(_mm512_mask_alignr_epi32(
      _mm512_castps_si512(cur), 0xFFFF, _mm512_castps_si512(cur), _mm512_castps_si512(prev), 15)));
#else
  return __builtin_shufflevector(prev, cur, int(kLanes - 1 + I)...);
#endif
}
// [cur[1 .. L-1], next[0]]: the right neighbours of cur's lanes.
template <std::size_t... I>
[[gnu::always_inline]] inline Vec rights(Vec cur, Vec next, std::index_sequence<I...>) {
#if defined(__AVX512F__)
  return Vec(_mm512_castsi512_ps(_mm512_mask_alignr_epi32(
      _mm512_castps_si512(cur), 0xFFFF, _mm512_castps_si512(next), _mm512_castps_si512(cur), 1)));
#else
  return __builtin_shufflevector(cur, next, int(1 + I)...);
#endif
}
constexpr auto kLaneSeq = std::make_index_sequence<kLanes>{};

// Seed 001's update with the constants folded (L9 = 0.05 S - 1.8 c, S the (1 4 1) x (1 4 1)
// sum):
//   A' = ca S_A + pa A + q - dt A B^2,   ca = 0.05 DA, pa = 1 - 1.8 DA - dt F, q = dt F
//   B' = cb S_B + pb B + dt A B^2,       cb = 0.05 DB, pb = 1 - 1.8 DB - dt (F + k)
using RowCoeffs = GrayScott9Blocked::RowCoeffs;

RowCoeffs row_coeffs(const GrayScott9Params& p) {
  RowCoeffs r;
  static_cast<GrayScott9Coeffs&>(r) = gray_scott9_coeffs(p);
  return r;
}

struct RowConsts {
  Vec four, ca, cb, pa, pb, q, dt;
};

// (r0 + r2) + 4 r1: the vertical (1 4 1) sum of kLanes columns.
[[gnu::always_inline]] inline Vec column_sum(Vec r0, Vec r1, Vec r2, const RowConsts& k) {
  return fma(k.four, r1, r0 + r2);
}

// kLanes output cells of both chemicals from the vertical sums left of, at and right of them.
template <bool kUnitDt>
[[gnu::always_inline]] inline void update_cells(Vec va_prev, Vec va, Vec va_next, Vec vb_prev,
                                                Vec vb, Vec vb_next, Vec A, Vec B, float* ao,
                                                float* bo, const RowConsts& k) {
  const Vec sa = fma(k.four, va, lefts(va_prev, va, kLaneSeq) + rights(va, va_next, kLaneSeq));
  const Vec sb = fma(k.four, vb, lefts(vb_prev, vb, kLaneSeq) + rights(vb, vb_next, kLaneSeq));
  // A B^2 (times dt) enters both updates fused: A' = ca S_A + (pa A + q) - A B^2.
  const Vec bb = kUnitDt ? B * B : k.dt * (B * B);
  store(ao, fnma(A, bb, fma(k.ca, sa, fma(k.pa, A, k.q))));
  store(bo, fma(A, bb, fma(k.cb, sb, k.pb * B)));
}

// kRows (1 or 2) consecutive output rows from the kRows + 2 input rows around them, vectors
// [jlo, jhi) of the nv in a row. Rows point at x = 0 (64-byte aligned) and hold x = -kLanes ..
// kLanes * (nv + 1) - 1, with the periodic ghosts at x = -1 and x = n filled in. Every output
// lane depends only on input lanes x - 1 .. x + 1, so lanes x < n are exact and lanes past n
// (padding) are harmless. The vertical sums are formed once per vector and shifted in
// registers for the horizontal pass; two rows per call share the loads of their two middle
// input rows. Where the range stops short of a row's end, the neighbouring vector is taken to
// hold the fixed point (c.fixed_a, c.fixed_b) and is not read: outside the range, rows may hold
// stale values. All variants evaluate every cell with the same expressions (column_sum,
// update_cells), hence the same bits.
template <int kRows, bool kUnitDt>
void gray_scott9_rows_simd(const float* const* a_rows, const float* const* b_rows,
                           float* const* a_out, float* const* b_out, int nv, int jlo, int jhi,
                           const RowCoeffs& c) {
  // Local copies, so that the stores below cannot be taken to modify the row pointers.
  const float* a[kRows + 2];
  const float* b[kRows + 2];
  float* ao[kRows];
  float* bo[kRows];
  for (int r = 0; r < kRows + 2; ++r) {
    a[r] = a_rows[r];
    b[r] = b_rows[r];
  }
  for (int r = 0; r < kRows; ++r) {
    ao[r] = a_out[r];
    bo[r] = b_out[r];
  }
  const RowConsts k{splat(4.0f), splat(c.ca), splat(c.cb), splat(c.pa),
                    splat(c.pb), splat(c.q),  splat(c.dt)};
  const Vec fixed_va = column_sum(splat(c.fixed_a), splat(c.fixed_a), splat(c.fixed_a), k);
  const Vec fixed_vb = column_sum(splat(c.fixed_b), splat(c.fixed_b), splat(c.fixed_b), k);
  Vec va_prev[kRows], va[kRows], vb_prev[kRows], vb[kRows];
  const int x0 = jlo * kLanes;
  for (int r = 0; r < kRows; ++r) {
    // Only the last lane of the vector before x0 is read (at x0 = 0: the ghost x = -1).
    va_prev[r] = jlo > 0 ? fixed_va
                         : column_sum(load(a[r] - kLanes), load(a[r + 1] - kLanes),
                                      load(a[r + 2] - kLanes), k);
    vb_prev[r] = jlo > 0 ? fixed_vb
                         : column_sum(load(b[r] - kLanes), load(b[r + 1] - kLanes),
                                      load(b[r + 2] - kLanes), k);
    va[r] = column_sum(load(a[r] + x0), load(a[r + 1] + x0), load(a[r + 2] + x0), k);
    vb[r] = column_sum(load(b[r] + x0), load(b[r + 1] + x0), load(b[r + 2] + x0), k);
  }
  // One vector of every output row; next_fixed: the vector after it lies outside the range.
  auto advance = [&](int x, bool next_fixed) __attribute__((always_inline)) {
    const int xn = x + kLanes;
    Vec an[kRows + 2], bn[kRows + 2];
    if (!next_fixed)
      for (int r = 0; r < kRows + 2; ++r) {
        an[r] = load(a[r] + xn);
        bn[r] = load(b[r] + xn);
      }
    for (int r = 0; r < kRows; ++r) {
      const Vec va_next = next_fixed ? fixed_va : column_sum(an[r], an[r + 1], an[r + 2], k);
      const Vec vb_next = next_fixed ? fixed_vb : column_sum(bn[r], bn[r + 1], bn[r + 2], k);
      update_cells<kUnitDt>(va_prev[r], va[r], va_next, vb_prev[r], vb[r], vb_next,
                            load(a[r + 1] + x), load(b[r + 1] + x), ao[r] + x, bo[r] + x, k);
      va_prev[r] = va[r];
      va[r] = va_next;
      vb_prev[r] = vb[r];
      vb[r] = vb_next;
    }
  };
  for (int j = jlo; j < jhi - 1; ++j) advance(j * kLanes, false);
  if (jhi < nv)
    advance((jhi - 1) * kLanes, true);
  else
    advance((jhi - 1) * kLanes, false);
}

using RowsKernel = GrayScott9Blocked::RowsKernel;

// Periodic ghosts of a row freshly written over vectors [jlo, jhi) (the rest holds `fixed`);
// the padding past x = n is zeroed so that it stays finite.
void finish_row(float* r, int n, int nv, int jlo, int jhi, float fixed) {
  r[-1] = jhi == nv ? r[n - 1] : fixed;
  r[n] = jlo == 0 ? r[0] : fixed;
  for (int x = n + 1; x < nv * kLanes; ++x) r[x] = 0.0f;
}

// Looks for a uniform state that one step maps to itself bit for bit: steps a strip of one
// vector (ghosts and padding included) that starts at (a, b). Seed 001's A = 1, B = 0 settles
// on A = 1.00000036 after 2 steps. False if the strip does not settle or stops being
// uniform.
bool find_fixed_point(RowsKernel kernel, const RowCoeffs& c, float& a, float& b) {
  constexpr int kWidth = 3 * kLanes;  // x = -kLanes .. 2 kLanes - 1
  alignas(64) float in[2][kWidth], out[2][kWidth];
  for (int step = 0; step < 4096; ++step) {
    std::fill(in[0], in[0] + kWidth, a);
    std::fill(in[1], in[1] + kWidth, b);
    const float* a_rows[3] = {in[0] + kLanes, in[0] + kLanes, in[0] + kLanes};
    const float* b_rows[3] = {in[1] + kLanes, in[1] + kLanes, in[1] + kLanes};
    float* a_out[1] = {out[0] + kLanes};
    float* b_out[1] = {out[1] + kLanes};
    kernel(a_rows, b_rows, a_out, b_out, 1, 0, 1, c);
    const float next_a = out[0][kLanes], next_b = out[1][kLanes];
    for (int x = kLanes; x < 2 * kLanes; ++x)
      if (std::memcmp(&out[0][x], &next_a, sizeof(float)) != 0 ||
          std::memcmp(&out[1][x], &next_b, sizeof(float)) != 0)
        return false;
    if (std::memcmp(&next_a, &a, sizeof(float)) == 0 &&
        std::memcmp(&next_b, &b, sizeof(float)) == 0)
      return true;
    a = next_a;
    b = next_b;
  }
  return false;
}

using Bits = uint32_t __attribute__((vector_size(kLanes * sizeof(uint32_t))));
// A vector's bit patterns, compared as integers (so that -0 differs from +0 and NaNs count).
struct VecBits {
  Bits v;
  VecBits operator^(VecBits o) const { return {v ^ o.v}; }
  VecBits operator|(VecBits o) const { return {v | o.v}; }
  explicit operator bool() const {
    uint64_t words[kLanes / 2];
    std::memcpy(words, &v, sizeof v);
    uint64_t any = 0;
    for (const uint64_t w : words) any |= w;
    return any != 0;
  }
};
[[gnu::always_inline]] inline VecBits bits(Vec v) {
  VecBits b;
  std::memcpy(&b.v, &v, sizeof v);
  return b;
}

// The vectors [first, end) within [jlo, jhi) where row pair (a, b) differs from the fixed rows
// (bit for bit, cells x < n only); {0, 0} if none.
Int2 differing_vectors(const float* a, const float* b, const float* fixed_a, const float* fixed_b,
                       int n, int jlo, int jhi) {
  auto differs = [&](int j) {
    const int x = j * kLanes;
    if (n - x < kLanes) {  // the last vector: lanes past n are padding
      const std::size_t bytes = sizeof(float) * std::size_t(n - x);
      return std::memcmp(a + x, fixed_a + x, bytes) != 0 ||
             std::memcmp(b + x, fixed_b + x, bytes) != 0;
    }
    return bool((bits(load(a + x)) ^ bits(load(fixed_a + x))) |
                (bits(load(b + x)) ^ bits(load(fixed_b + x))));
  };
  int first = jlo;
  while (first < jhi && !differs(first)) ++first;
  if (first == jhi) return {0, 0};
  int end = jhi;
  while (!differs(end - 1)) --end;
  return {first, end};
}

// The periodic ghost rows y = -1 and y = ny (corners included) from the rows they wrap.
void wrap_rows_y(FieldF& f) {
  const std::size_t bytes = sizeof(float) * std::size_t(f.nx() + 2);
  std::memcpy(f.row(-1) - 1, f.row(f.ny() - 1) - 1, bytes);
  std::memcpy(f.row(f.ny()) - 1, f.row(0) - 1, bytes);
}

}  // namespace

void GrayScott9Blocked::RowStore::resize(int rows, std::ptrdiff_t stride) {
  stride_ = stride;
  const std::size_t bytes = std::size_t(rows) * std::size_t(stride) * sizeof(float);
  data_.reset(static_cast<float*>(std::aligned_alloc(64, std::max<std::size_t>(bytes, 64))));
  ARDCELL_CHECK(data_ != nullptr, "out of memory for the Gray-Scott rows");
  std::memset(data_.get(), 0, bytes);
}

GrayScott9Blocked::GrayScott9Blocked(Int2 size, RowExecutor& ex, int bands, int block_steps,
                                     Rows rows)
    : size_(size), ex_(&ex), rows_(rows) {
  ARDCELL_CHECK(size.x > 0 && size.y > 0, "grid must be non-empty");
  ARDCELL_CHECK(block_steps > 0, "block_steps must be positive");
  if (bands <= 0) bands = ex.workers();
  const int n = std::clamp(bands, 1, size.y);
  // A block's halo must lie within the neighbouring band's edge rows.
  block_steps_ = std::min(block_steps, size.y / n);
  // Balancing keeps bands at least this tall: halos stay within the neighbour, and the two
  // ends of a band do not overlap where the grid allows it.
  min_band_rows_ = std::min(2 * block_steps_, size.y / n);
  vectors_ = (size.x + kLanes - 1) / kLanes;
  // x = -kHalo .. kLanes * (vectors_ + 1) - 1: within a row of a field of halo kHalo (whose
  // stride is a multiple of 32 floats of at least nx + 2 kHalo).
  stride_ = RowStore::kPad + std::ptrdiff_t(kLanes) * (vectors_ + 1);
  bands_.resize(std::size_t(n));
  for (int t = 0; t < n; ++t) {
    Band& band = bands_[std::size_t(t)];
    band.y0 = int(int64_t(size.y) * t / n);
    band.y1 = int(int64_t(size.y) * (t + 1) / n);
    band.ring.resize(std::max(1, block_steps_ - 1) * kRingRows * 2, stride_);
    band.next.assign(std::size_t(block_steps_ + 1), 0);
    band.lo.assign(std::size_t(block_steps_ + 1), 0);
    band.hi.assign(std::size_t(block_steps_ + 1), 0);
    band.edges.resize(2 * 2 * block_steps_, stride_);
  }
  fixed_rows_.resize(2, stride_);
  row_activity_.assign(2 * std::size_t(size.y), Int2{0, 0});
  halo_activity_.assign(2 * std::size_t(block_steps_), Int2{0, 0});
}

GrayScott9Blocked::~GrayScott9Blocked() = default;

void GrayScott9Blocked::adopt(FieldF& f) {
  if (fits(f)) return;
  FieldF g = FieldF::over(f.interior(), kHalo);
  const int h = std::min(f.halo(), kHalo);
  copy_box(std::as_const(f).view(), g.view(), f.interior().grown(h));
  f = std::move(g);
}

float* GrayScott9Blocked::band_row(Band& band, int parity, int y, int chem) {
  if (parity == 0) return field_row(y, chem);
  const int kmax = block_steps_;
  int edge = -1;
  if (y - band.y0 < kmax) {
    edge = y - band.y0;
  } else if (band.y1 - y <= kmax) {
    edge = 2 * kmax - (band.y1 - y);
  }
  if (edge < 0) return field_row(y, chem);
  return band.edges.row(chem * 2 * kmax + edge);
}

void GrayScott9Blocked::copy_whole_row(const float* from, float* to) const {
  std::memcpy(to - RowStore::kPad, from - RowStore::kPad, sizeof(float) * std::size_t(stride_));
}

std::vector<int> GrayScott9Blocked::band_starts() const {
  std::vector<int> starts;
  for (const Band& band : bands_) starts.push_back(band.y0);
  return starts;
}

int balanced_boundary_shift(double busy_a, double busy_b, int rows_a, int rows_b, int max_rows) {
  if (rows_a <= 0 || rows_b <= 0 || busy_a + busy_b <= 0) return 0;
  if (std::abs(busy_a - busy_b) < 0.05 * std::max(busy_a, busy_b)) return 0;
  // Rows x moved from a to b equalise (rows_a - x) busy_a / rows_a and (rows_b + x) busy_b /
  // rows_b, taking a row to cost the same throughout a band.
  const double x = (busy_a - busy_b) / (busy_a / rows_a + busy_b / rows_b);
  const int half = int(std::lround(0.5 * x));
  return std::clamp(half == 0 ? (x > 0 ? 1 : -1) : half, -max_rows, max_rows);
}

void GrayScott9Blocked::balance_bands(int parity) {
  const int n = bands();
  if (n < 2 || !balancing_) return;
  if (probe_state_ == 0 && ++blocks_since_balance_ < kBalanceBlocks) return;
  blocks_since_balance_ = 0;
  const int max_rows = std::max(2 * block_steps_, size_.y / (8 * n));
  for (int t = 0; t + 1 < n; ++t) {
    Band& a = bands_[std::size_t(t)];
    Band& b = bands_[std::size_t(t + 1)];
    int shift = 0;
    if (probe_state_ != 0) {
      probe_state_ ^= probe_state_ << 13;  // xorshift32: never 0 again, so it stays a probe
      probe_state_ ^= probe_state_ >> 17;
      probe_state_ ^= probe_state_ << 5;
      shift = int(probe_state_ % 13u) - 6;
    } else {
      shift = balanced_boundary_shift(double(a.busy_ns), double(b.busy_ns), a.y1 - a.y0,
                                      b.y1 - b.y0, max_rows);
    }
    const int to = std::clamp(a.y1 - shift, a.y0 + min_band_rows_, b.y1 - min_band_rows_);
    if (to != a.y1) move_boundary(t, to, parity);
  }
  for (Band& band : bands_) band.busy_ns = 0;
}

void GrayScott9Blocked::move_boundary(int t, int to, int parity) {
  Band& a = bands_[std::size_t(t)];
  Band& b = bands_[std::size_t(t + 1)];
  const int from = a.y1;
  // Rows whose storage depends on the boundary: within block_steps_ of its old or new place.
  const int z0 = std::max(a.y0, std::min(from, to) - block_steps_);
  const int z1 = std::min(b.y1, std::max(from, to) + block_steps_);
  // Through the field's rows (an end row's field row holds the other parity, which the next
  // block rewrites), so that no copy overwrites a row still to be moved.
  for (int y = z0; y < z1; ++y)
    for (int chem = 0; chem < 2; ++chem) {
      float* held = band_row(y < a.y1 ? a : b, parity, y, chem);
      if (held != field_row(y, chem)) copy_whole_row(held, field_row(y, chem));
    }
  a.y1 = to;
  b.y0 = to;
  for (int y = z0; y < z1; ++y)
    for (int chem = 0; chem < 2; ++chem) {
      float* place = band_row(y < a.y1 ? a : b, parity, y, chem);
      if (place != field_row(y, chem)) copy_whole_row(field_row(y, chem), place);
    }
}

void GrayScott9Blocked::prepare_band(int t) {
  Band& band = bands_[std::size_t(t)];
  const int nx = size_.x, ny = size_.y, nv = vectors_, kmax = block_steps_;
  Int2* activity = row_activity_.data() + std::size_t(parity_) * std::size_t(size_.y);
  // A row's periodic x ghosts and padding, and its differing vectors.
  auto prepare_row = [&](int y, Int2& differing) {
    float* ra = field_row(y, 0);
    float* rb = field_row(y, 1);
    finish_row(ra, nx, nv, 0, nv, 0.0f);
    finish_row(rb, nx, nv, 0, nv, 0.0f);
    if (skip_)
      differing = differing_vectors(ra, rb, fixed_rows_.row(0), fixed_rows_.row(1), nx, 0, nv);
  };
  // Rows from the halo: the first and last bands' outer neighbours, read as they are.
  if (rows_ == Rows::kFromHalo && t == 0)
    for (int i = 0; i < kmax; ++i) prepare_row(i - kmax, halo_activity_[std::size_t(i)]);
  if (rows_ == Rows::kFromHalo && t == bands() - 1)
    for (int i = 0; i < kmax; ++i) prepare_row(ny + i, halo_activity_[std::size_t(kmax + i)]);
  for (int y = band.y0; y < band.y1; ++y) {
    if (!resume_) prepare_row(y, activity[y]);
    if (parity_ == 1)
      for (int chem = 0; chem < 2; ++chem) {
        float* place = band_row(band, 1, y, chem);
        if (place != field_row(y, chem)) copy_whole_row(field_row(y, chem), place);
      }
  }
}

void GrayScott9Blocked::step_band(int t) {
  const auto started = std::chrono::steady_clock::now();
  const int nx = size_.x, ny = size_.y, n = bands(), nv = vectors_, kmax = block_steps_;
  const int k = block_k_, parity = parity_;
  const RowCoeffs& coeffs = coeffs_;
  Band& band = bands_[std::size_t(t)];
  Band& above = bands_[std::size_t((t + n - 1) % n)];
  Band& below = bands_[std::size_t((t + 1) % n)];
  const float* fixed_row[2] = {fixed_rows_.row(0), fixed_rows_.row(1)};
  auto ring_row = [&](int level, int y, int chem) {
    const int slot = int(unsigned(y + kRingRows * ny) % unsigned(kRingRows));
    return band.ring.row(((level - 1) * kRingRows + slot) * 2 + chem);
  };
  int* next = band.next.data();  // next[l]: the next row level l computes
  int* lo = band.lo.data();      // level l computes rows [lo[l], hi[l])
  int* hi = band.hi.data();
  int64_t updates = 0;
  const int y0 = band.y0, y1 = band.y1;
  const Int2* activity = row_activity_.data() + std::size_t(parity) * std::size_t(ny);
  Int2* next_activity = row_activity_.data() + std::size_t(1 - parity) * std::size_t(ny);
  // What this block computes: the level-0 rows [rlo, rhi) (band and halo) and vectors
  // [jlo, jhi) that differ from the fixed point, grown by one cell per level. Outside them
  // every level holds the fixed point. Without skipping: everything.
  const bool skipping = skip_ && k > 1;
  int rlo = y0 - k, rhi = y1 + k, jlo = 0, jhi = nv;
  if (skipping) {
    rlo = y1 + k;
    rhi = y0 - k;
    int first = nv, end = 0;
    for (int y = y0 - k; y < y1 + k; ++y) {
      const Int2 v = rows_ == Rows::kPeriodic ? activity[std::size_t((y % ny + ny) % ny)]
                     : y < 0                  ? halo_activity_[std::size_t(y + kmax)]
                     : y >= ny                ? halo_activity_[std::size_t(y - ny + kmax)]
                                              : activity[std::size_t(y)];
      if (v.y <= v.x) continue;
      rlo = std::min(rlo, y);
      rhi = y + 1;
      first = std::min(first, v.x);
      end = std::max(end, v.y);
    }
    // A change within k cells of a row's end reaches the other end through the wrap.
    const int reach = (k + kLanes - 1) / kLanes;
    if (first * kLanes - k >= 0 && end * kLanes - 1 + k < nx) {
      jlo = first - reach;
      jhi = std::min(nv, end + reach);
    }
    for (int y = y0; y < y1; ++y) next_activity[y] = Int2{0, 0};
  }
  const bool idle = rhi <= rlo;  // all at the fixed point: nothing changes in this block
  for (int l = 1; l <= k; ++l) {
    lo[l] = std::max(y0 - (k - l), rlo - l);
    hi[l] = std::min(y1 + (k - l), rhi + l);
    next[l] = lo[l];
  }
  // The band's end rows alternate between two copies; the next copy must hold the fixed point
  // wherever this block does not write it.
  if (skipping)
    for (int y = y0; y < y1; ++y) {
      if (y - y0 >= kmax && y1 - y > kmax) continue;  // updated in place
      if (!idle && y >= lo[k] && y < hi[k] && jlo == 0 && jhi == nv) continue;
      copy_whole_row(fixed_row[0], band_row(band, 1 - parity, y, 0));
      copy_whole_row(fixed_row[1], band_row(band, 1 - parity, y, 1));
    }
  // Level 0 and level k: a band's rows more than kmax from its ends are updated in place (level
  // k writes row y after level 1 has read it for the last time); the kmax rows at either end,
  // which the neighbours read as halo, alternate between two copies by block parity.
  const bool halo_above = rows_ == Rows::kFromHalo && t == 0;
  const bool halo_below = rows_ == Rows::kFromHalo && t == n - 1;
  auto level0 = [&](int y, int chem) -> const float* {
    if (y < y0)
      return halo_above ? field_row(y, chem) : band_row(above, parity, above.y1 - (y0 - y), chem);
    if (y >= y1)
      return halo_below ? field_row(y, chem) : band_row(below, parity, below.y0 + (y - y1), chem);
    return band_row(band, parity, y, chem);
  };
  auto input = [&](int level, int y, int chem) -> const float* {
    if (level == 0) return level0(y, chem);
    if (y < lo[level] || y >= hi[level]) return fixed_row[chem];
    return ring_row(level, y, chem);
  };
  // Level l (1 .. k) spans the band grown by k - l rows (and, when skipping, the changing rows
  // grown by l). Wavefront: each sweep lets every level compute its next two rows (one at a
  // span's end) once its inputs, rows y - 1 .. y + 2 of level l - 1, exist, and as long as it
  // does not overwrite ring rows that level l + 1 still reads (rows >= next[l + 1] - 1). A
  // level's rows outside its span hold the fixed point and need no wait.
  // With k = 1 the only level reads rows y - 1 .. y + 1 in place, so its rows go through the
  // ring and are written back once no longer read.
  int written_back = y0;
  while (!idle && next[k] < hi[k]) {
    bool progressed = false;
    for (int l = 1; l <= k; ++l) {
      const int y = next[l];
      const int rows = std::min(2, hi[l] - y);
      if (rows <= 0) continue;
      if (l > 1 && next[l - 1] < std::min(y + rows + 1, hi[l - 1])) continue;
      if (l < k && next[l + 1] < hi[l + 1] && y + rows - kRingRows >= next[l + 1]) continue;
      if (l == k && k > 1 && next[1] < std::min(y + rows + 1, hi[1])) continue;
      const bool to_band = l == k && k > 1;
      const float* a_in[4];
      const float* b_in[4];
      float* a_out[2];
      float* b_out[2];
      for (int r = 0; r < rows + 2; ++r) {
        a_in[r] = input(l - 1, y - 1 + r, 0);
        b_in[r] = input(l - 1, y - 1 + r, 1);
      }
      for (int r = 0; r < rows; ++r) {
        a_out[r] = to_band ? band_row(band, 1 - parity, y + r, 0) : ring_row(l, y + r, 0);
        b_out[r] = to_band ? band_row(band, 1 - parity, y + r, 1) : ring_row(l, y + r, 1);
      }
      kernel_[rows - 1](a_in, b_in, a_out, b_out, nv, jlo, jhi, coeffs);
      for (int r = 0; r < rows; ++r) {
        finish_row(a_out[r], nx, nv, jlo, jhi, coeffs.fixed_a);
        finish_row(b_out[r], nx, nv, jlo, jhi, coeffs.fixed_b);
        if (skipping && l == k)
          next_activity[y + r] =
              differing_vectors(a_out[r], b_out[r], fixed_row[0], fixed_row[1], nx, jlo, jhi);
      }
      updates += int64_t(rows) * (std::min(jhi * kLanes, nx) - jlo * kLanes);
      next[l] = y + rows;
      progressed = true;
    }
    ARDCELL_CHECK(progressed, "Gray-Scott wavefront stalled");
    for (const int end = k == 1 ? std::min(next[1] - 1, y1) : y0; written_back < end;
         ++written_back) {
      copy_whole_row(ring_row(1, written_back, 0), band_row(band, 1 - parity, written_back, 0));
      copy_whole_row(ring_row(1, written_back, 1), band_row(band, 1 - parity, written_back, 1));
    }
  }
  for (; k == 1 && written_back < y1; ++written_back) {
    copy_whole_row(ring_row(1, written_back, 0), band_row(band, 1 - parity, written_back, 0));
    copy_whole_row(ring_row(1, written_back, 1), band_row(band, 1 - parity, written_back, 1));
  }
  band.updates += updates;
  band.busy_ns += std::chrono::duration_cast<std::chrono::nanoseconds>(
                      std::chrono::steady_clock::now() - started)
                      .count();
}

void GrayScott9Blocked::run(FieldF& a, FieldF& b, int64_t steps, const GrayScott9Params& params,
                            bool resume) {
  last_run_cell_updates_ = 0;
  if (steps <= 0) return;
  ARDCELL_CHECK(a.size() == size_ && b.size() == size_ && fits(a) && fits(b),
                "GrayScott9Blocked::run: fields of the grid's size and halo kHalo (adopt())");
  ARDCELL_CHECK(rows_ == Rows::kPeriodic || steps <= block_steps_,
                "GrayScott9Blocked::run: rows from the halo serve block_steps() steps a run");
  ARDCELL_CHECK(a.origin() == b.origin(), "GrayScott9Blocked::run: a and b over different cells");
  fields_[0] = &a;
  fields_[1] = &b;
  origin_ = a.origin();
  coeffs_ = row_coeffs(params);
  const bool unit_dt = params.dt == 1.0f;  // drops a multiply: dt * abb == abb then
  kernel_[0] = unit_dt ? &gray_scott9_rows_simd<1, true> : &gray_scott9_rows_simd<1, false>;
  kernel_[1] = unit_dt ? &gray_scott9_rows_simd<2, true> : &gray_scott9_rows_simd<2, false>;
  // Blocks of k or k - 1 steps, the longer first: a block of one step records no differing
  // vectors, so it may only be followed by blocks of one step. The first block reads the parity
  // that makes the last one end in the fields (even), so nothing is copied back.
  const int64_t blocks = (steps + block_steps_ - 1) / block_steps_;
  const int64_t short_k = steps / blocks, long_blocks = steps % blocks;
  float fixed_a = a(origin_.x, origin_.y), fixed_b = b(origin_.x, origin_.y);
  skip_ = skip_quiescent_ && short_k + (long_blocks > 0 ? 1 : 0) > 1 &&
          find_fixed_point(kernel_[0], coeffs_, fixed_a, fixed_b);
  if (skip_) {
    coeffs_.fixed_a = fixed_a;
    coeffs_.fixed_b = fixed_b;
    float* fa = fixed_rows_.row(0);
    float* fb = fixed_rows_.row(1);
    std::fill(fa - RowStore::kPad, fa - RowStore::kPad + stride_, fixed_a);
    std::fill(fb - RowStore::kPad, fb - RowStore::kPad + stride_, fixed_b);
  }
  for (Band& band : bands_) band.updates = 0;
  parity_ = int(blocks % 2);
  resume_ = resume && skip_ && activity_valid_ && activity_fields_[0] == a.raw() &&
            activity_fields_[1] == b.raw() &&
            std::memcmp(activity_fixed_, &coeffs_.fixed_a, sizeof(float)) == 0 &&
            std::memcmp(activity_fixed_ + 1, &coeffs_.fixed_b, sizeof(float)) == 0;
  if (resume_ && activity_parity_ != parity_) {
    const std::size_t ny = std::size_t(size_.y);
    std::copy_n(row_activity_.begin() + std::ptrdiff_t(std::size_t(activity_parity_) * ny), ny,
                row_activity_.begin() + std::ptrdiff_t(std::size_t(parity_) * ny));
  }
  const int n = bands();
  // A resumed run whose first block reads the fields has nothing to prepare: no pass (on the
  // threads back end a pass is a round trip to every worker, a wake-up when they sleep).
  if (!resume_ || parity_ == 1 || rows_ == Rows::kFromHalo)
    ex_->for_tasks(n, [this](int t) { prepare_band(t); });
  for (int64_t i = 0; i < blocks; ++i) {
    block_k_ = int(short_k + (i < long_blocks ? 1 : 0));
    ex_->for_tasks(n, [this](int t) { step_band(t); });
    parity_ = 1 - parity_;
    balance_bands(parity_);
  }
  for (const Band& band : bands_) last_run_cell_updates_ += band.updates;
  // The last block (of short_k steps) recorded every row's differing vectors when it skipped.
  activity_valid_ = skip_ && short_k > 1;
  activity_parity_ = parity_;
  activity_fields_[0] = a.raw();
  activity_fields_[1] = b.raw();
  activity_fixed_[0] = coeffs_.fixed_a;
  activity_fixed_[1] = coeffs_.fixed_b;
  if (rows_ == Rows::kPeriodic) {
    wrap_rows_y(a);
    wrap_rows_y(b);
  }
  fields_[0] = fields_[1] = nullptr;
}

}  // namespace ardcell
