#include "host/rd_parallel_gray_scott.h"

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <cstring>
#include <thread>
#include <utility>
#include <vector>

#if defined(__AVX512F__)
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
struct RowCoeffs {
  float ca, cb, pa, pb, q, dt;
};

RowCoeffs row_coeffs(const GrayScott9Params& p) {
  return {0.05f * p.diffusion_a,
          0.05f * p.diffusion_b,
          1.0f - 1.8f * p.diffusion_a - p.dt * p.F,
          1.0f - 1.8f * p.diffusion_b - p.dt * (p.F + p.k),
          p.dt * p.F,
          p.dt};
}

struct RowConsts {
  Vec four, ca, cb, pa, pb, q, dt;
};

// (r0 + r2) + 4 r1: the vertical (1 4 1) sum of kLanes columns.
[[gnu::always_inline]] inline Vec column_sum(Vec r0, Vec r1, Vec r2, const RowConsts& k) {
  return (r0 + r2) + k.four * r1;
}

// kLanes output cells of both chemicals from the vertical sums left of, at and right of them.
template <bool kUnitDt>
[[gnu::always_inline]] inline void update_cells(Vec va_prev, Vec va, Vec va_next, Vec vb_prev,
                                                Vec vb, Vec vb_next, Vec A, Vec B, float* ao,
                                                float* bo, const RowConsts& k) {
  const Vec sa = (lefts(va_prev, va, kLaneSeq) + rights(va, va_next, kLaneSeq)) + k.four * va;
  const Vec sb = (lefts(vb_prev, vb, kLaneSeq) + rights(vb, vb_next, kLaneSeq)) + k.four * vb;
  const Vec abb = kUnitDt ? A * (B * B) : k.dt * (A * (B * B));
  store(ao, (k.ca * sa + (k.pa * A + k.q)) - abb);
  store(bo, (k.cb * sb + k.pb * B) + abb);
}

// kRows (1 or 2) consecutive output rows from the kRows + 2 input rows around them. Rows
// point at x = 0 (64-byte aligned) and hold x = -kLanes .. kLanes * (nv + 1) - 1, with the
// periodic ghosts at x = -1 and x = n filled in. Every output lane depends only on input
// lanes x - 1 .. x + 1, so lanes x < n are exact and lanes past n (padding) are harmless. The
// vertical sums are formed once per vector and shifted in registers for the horizontal pass;
// two rows per call share the loads of their two middle input rows. Both variants evaluate
// every cell with the same expressions (update_cells), hence the same bits.
template <int kRows, bool kUnitDt>
void gray_scott9_rows_simd(const float* const* a_rows, const float* const* b_rows,
                           float* const* a_out, float* const* b_out, int nv, const RowCoeffs& c) {
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
  Vec va_prev[kRows], va[kRows], vb_prev[kRows], vb[kRows];
  for (int r = 0; r < kRows; ++r) {
    // Only the last lane of the vector before x = 0 is read: the ghost column x = -1.
    va_prev[r] = splat((a[r][-1] + a[r + 2][-1]) + 4.0f * a[r + 1][-1]);
    vb_prev[r] = splat((b[r][-1] + b[r + 2][-1]) + 4.0f * b[r + 1][-1]);
    va[r] = column_sum(load(a[r]), load(a[r + 1]), load(a[r + 2]), k);
    vb[r] = column_sum(load(b[r]), load(b[r + 1]), load(b[r + 2]), k);
  }
  for (int j = 0; j < nv; ++j) {
    const int x = j * kLanes, xn = x + kLanes;
    Vec an[kRows + 2], bn[kRows + 2];
    for (int r = 0; r < kRows + 2; ++r) {
      an[r] = load(a[r] + xn);
      bn[r] = load(b[r] + xn);
    }
    for (int r = 0; r < kRows; ++r) {
      const Vec va_next = column_sum(an[r], an[r + 1], an[r + 2], k);
      const Vec vb_next = column_sum(bn[r], bn[r + 1], bn[r + 2], k);
      update_cells<kUnitDt>(va_prev[r], va[r], va_next, vb_prev[r], vb[r], vb_next,
                            load(a[r + 1] + x), load(b[r + 1] + x), ao[r] + x, bo[r] + x, k);
      va_prev[r] = va[r];
      va[r] = va_next;
      vb_prev[r] = vb[r];
      vb[r] = vb_next;
    }
  }
}

using RowsKernel = void (*)(const float* const*, const float* const*, float* const*, float* const*,
                            int, const RowCoeffs&);

// Periodic ghosts of a freshly written row; the padding past x = n is zeroed so that it
// stays finite.
void finish_row(float* r, int n, int nv) {
  r[-1] = r[n - 1];
  r[n] = r[0];
  for (int x = n + 1; x < nv * kLanes; ++x) r[x] = 0.0f;
}

// One meeting point per block of steps. Spins up to 20000 pauses (a few hundred microseconds,
// about one block), then sleeps in the kernel so that a loaded machine is not made worse.
// With 200 pauses a waiter usually went to sleep and paid a futex wake-up per block: quiet
// 400^2, 2000 steps, 6 runs each: 52-70 ms (spin 200) against 47-59 ms (spin 20000).
class BlockBarrier {
 public:
  explicit BlockBarrier(int n) : n_(n) {}
  void wait() {
    const int gen = gen_.load(std::memory_order_acquire);
    if (count_.fetch_add(1, std::memory_order_acq_rel) == n_ - 1) {
      count_.store(0, std::memory_order_relaxed);
      gen_.fetch_add(1, std::memory_order_release);
      gen_.notify_all();
      return;
    }
    for (int spins = 0; spins < 20000; ++spins) {
      if (gen_.load(std::memory_order_acquire) != gen) return;
#if defined(__x86_64__) || defined(__i386__)
      __builtin_ia32_pause();
#endif
    }
    while (gen_.load(std::memory_order_acquire) == gen) gen_.wait(gen, std::memory_order_acquire);
  }

 private:
  const int n_;
  std::atomic<int> count_{0};
  std::atomic<int> gen_{0};
};

void wrap_rows_x(FieldF& f, int y0, int y1) {
  const int nx = f.nx();
  for (int y = y0; y < y1; ++y) {
    float* r = f.row(y);
    r[-1] = r[nx - 1];
    r[nx] = r[0];
  }
}

void copy_row(FieldF& f, int from, int to) {
  std::memcpy(f.row(to) - 1, f.row(from) - 1, sizeof(float) * std::size_t(f.nx() + 2));
}

}  // namespace

void wrap_periodic(FieldF& f) {
  wrap_rows_x(f, 0, f.ny());
  copy_row(f, f.ny() - 1, -1);
  copy_row(f, 0, f.ny());
}

void ParallelGrayScott9::RowStore::resize(int rows, std::ptrdiff_t stride) {
  stride_ = stride;
  const std::size_t bytes = std::size_t(rows) * std::size_t(stride) * sizeof(float);
  data_.reset(static_cast<float*>(std::aligned_alloc(64, std::max<std::size_t>(bytes, 64))));
  ARDCELL_CHECK(data_ != nullptr, "out of memory for the Gray-Scott rows");
  std::memset(data_.get(), 0, bytes);
}

ParallelGrayScott9::ParallelGrayScott9(Int2 size, const GrayScott9Params& params, int threads,
                                       int block_steps)
    : size_(size), params_(params) {
  ARDCELL_CHECK(size.x > 0 && size.y > 0, "grid must be non-empty");
  ARDCELL_CHECK(block_steps > 0, "block_steps must be positive");
  if (threads <= 0) threads = int(std::max(1u, std::thread::hardware_concurrency()));
  threads_ = std::clamp(threads, 1, size.y);
  // A block's halo must lie within the neighbouring band's published edge rows.
  block_steps_ = std::min(block_steps, size.y / threads_);
  a_ = FieldF(size, 1);
  b_ = FieldF(size, 1);
  vectors_ = (size.x + kLanes - 1) / kLanes;
  // x = -RowStore::kPad .. kLanes * (vectors_ + 1) - 1, rounded up to whole 64-byte lines.
  stride_ = (RowStore::kPad + std::ptrdiff_t(kLanes) * (vectors_ + 1) + 15) / 16 * 16;
  grid_a_.resize(size.y, stride_);
  grid_b_.resize(size.y, stride_);
  bands_.resize(std::size_t(threads_));
  for (int t = 0; t < threads_; ++t) {
    Band& band = bands_[std::size_t(t)];
    band.y0 = int(int64_t(size.y) * t / threads_);
    band.y1 = int(int64_t(size.y) * (t + 1) / threads_);
    band.ring.resize(std::max(1, block_steps_ - 1) * kRingRows * 2, stride_);
    band.next.assign(std::size_t(block_steps_ + 1), 0);
    band.edges.resize(2 * 2 * 2 * block_steps_, stride_);
  }
}

void ParallelGrayScott9::seed_square() {
  a_.fill(1.0f);
  b_.fill(0.0f);
  for (int y = 0; y < 10; ++y)
    for (int x = 0; x < 10; ++x) {
      const int px = size_.x / 2 + x - 5, py = size_.y / 2 + y - 5;
      if (px >= 0 && px < size_.x && py >= 0 && py < size_.y) b_(px, py) = 1.0f;
    }
}

float* ParallelGrayScott9::band_row(Band& band, int parity, int y, int chem) {
  const int kmax = block_steps_;
  int edge = -1;
  if (y - band.y0 < kmax) {
    edge = y - band.y0;
  } else if (band.y1 - y <= kmax) {
    edge = 2 * kmax - (band.y1 - y);
  }
  if (edge < 0) return chem == 0 ? grid_a_.row(y) : grid_b_.row(y);
  return band.edges.row(((parity * 2 + chem) * 2) * kmax + edge);
}

void ParallelGrayScott9::copy_whole_row(const float* from, float* to) const {
  std::memcpy(to - RowStore::kPad, from - RowStore::kPad, sizeof(float) * std::size_t(stride_));
}

void ParallelGrayScott9::run(int64_t steps) {
  if (steps <= 0) return;
  const int nx = size_.x, ny = size_.y, n = threads_, nv = vectors_, kmax = block_steps_;
  const std::size_t row_bytes = sizeof(float) * std::size_t(nx);
  for (Band& band : bands_)
    for (int y = band.y0; y < band.y1; ++y) {
      float* ra = band_row(band, 0, y, 0);
      float* rb = band_row(band, 0, y, 1);
      std::memcpy(ra, a_.row(y), row_bytes);
      std::memcpy(rb, b_.row(y), row_bytes);
      finish_row(ra, nx, nv);
      finish_row(rb, nx, nv);
    }
  const RowCoeffs coeffs = row_coeffs(params_);
  const bool unit_dt = params_.dt == 1.0f;  // drops a multiply: dt * abb == abb then
  const RowsKernel kernel[2] = {
      unit_dt ? &gray_scott9_rows_simd<1, true> : &gray_scott9_rows_simd<1, false>,
      unit_dt ? &gray_scott9_rows_simd<2, true> : &gray_scott9_rows_simd<2, false>};
  BlockBarrier barrier(n);
  auto work = [&](int t) {
    Band& band = bands_[std::size_t(t)];
    Band& above = bands_[std::size_t((t + n - 1) % n)];
    Band& below = bands_[std::size_t((t + 1) % n)];
    const int y0 = band.y0, y1 = band.y1;
    auto ring_row = [&](int level, int y, int chem) {
      const int slot = int(unsigned(y + kRingRows * ny) % unsigned(kRingRows));
      return band.ring.row(((level - 1) * kRingRows + slot) * 2 + chem);
    };
    int* next = band.next.data();  // next[l]: the next row level l computes
    int parity = 0;
    for (int64_t done = 0; done < steps;) {
      const int k = int(std::min<int64_t>(kmax, steps - done));
      // Level 0 and level k: a band's rows more than kmax from its ends are updated in place
      // (level k writes row y after level 1 has read it for the last time); the kmax rows at
      // either end, which the neighbours read as halo, alternate between two copies by block
      // parity.
      auto level0 = [&](int y, int chem) -> const float* {
        if (y < y0) return band_row(above, parity, above.y1 - (y0 - y), chem);
        if (y >= y1) return band_row(below, parity, below.y0 + (y - y1), chem);
        return band_row(band, parity, y, chem);
      };
      auto input = [&](int level, int y, int chem) -> const float* {
        return level == 0 ? level0(y, chem) : ring_row(level, y, chem);
      };
      // Level l (1 .. k) spans the band grown by k - l rows. Wavefront: each sweep lets every
      // level compute its next two rows (one at a span's end) once its inputs, rows y - 1 ..
      // y + 2 of level l - 1, exist, and as long as it does not overwrite ring rows that
      // level l + 1 still reads (rows >= next[l + 1] - 1).
      for (int l = 1; l <= k; ++l) next[l] = y0 - (k - l);
      // With k = 1 the only level reads rows y - 1 .. y + 1 in place, so its rows go through
      // the ring and are written back once no longer read.
      int written_back = y0;
      while (next[k] < y1) {
        bool progressed = false;
        for (int l = 1; l <= k; ++l) {
          const int y = next[l];
          const int rows = std::min(2, y1 + (k - l) - y);
          if (rows <= 0) continue;
          if (l > 1 && next[l - 1] < y + rows + 1) continue;
          if (l < k && y + rows - kRingRows >= next[l + 1]) continue;
          if (l == k && k > 1 && next[1] < y + rows + 1) continue;
          const bool to_grid = l == k && k > 1;
          const float* a_in[4];
          const float* b_in[4];
          float* a_out[2];
          float* b_out[2];
          for (int r = 0; r < rows + 2; ++r) {
            a_in[r] = input(l - 1, y - 1 + r, 0);
            b_in[r] = input(l - 1, y - 1 + r, 1);
          }
          for (int r = 0; r < rows; ++r) {
            a_out[r] = to_grid ? band_row(band, 1 - parity, y + r, 0) : ring_row(l, y + r, 0);
            b_out[r] = to_grid ? band_row(band, 1 - parity, y + r, 1) : ring_row(l, y + r, 1);
          }
          kernel[rows - 1](a_in, b_in, a_out, b_out, nv, coeffs);
          for (int r = 0; r < rows; ++r) {
            finish_row(a_out[r], nx, nv);
            finish_row(b_out[r], nx, nv);
          }
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
      parity = 1 - parity;
      barrier.wait();
      done += k;
    }
  };
  if (n == 1) {
    work(0);
  } else {
    std::vector<std::jthread> pool;
    pool.reserve(std::size_t(n - 1));
    for (int t = 1; t < n; ++t) pool.emplace_back(work, t);
    work(0);
  }
  const int final_parity = int(((steps + kmax - 1) / kmax) % 2);
  for (Band& band : bands_)
    for (int y = band.y0; y < band.y1; ++y) {
      std::memcpy(a_.row(y), band_row(band, final_parity, y, 0), row_bytes);
      std::memcpy(b_.row(y), band_row(band, final_parity, y, 1), row_bytes);
    }
  wrap_periodic(a_);
  wrap_periodic(b_);
}

}  // namespace ardcell
