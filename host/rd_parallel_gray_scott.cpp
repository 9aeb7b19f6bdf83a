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

// (r0 + r2) + 4 r1: the vertical (1 4 1) sum of kLanes columns.
[[gnu::always_inline]] inline Vec column_sum(const float* r0, const float* r1, const float* r2) {
  return (load(r0) + load(r2)) + splat(4.0f) * load(r1);
}

// One output row. Rows point at x = 0 (64-byte aligned) and hold x = -RowStore::kPad .. 16 * (nv +
// 1) - 1, with the periodic ghosts at x = -1 and x = n filled in. Every output lane depends
// only on input lanes x - 1 .. x + 1 of the same three rows, so lanes x < n are exact and
// lanes past n (padding) are harmless. The vertical sums are formed once per vector and
// shifted in registers for the horizontal pass: 6 loads and 2 stores per kLanes cells.
template <bool kUnitDt>
void gray_scott9_row_simd(const float* __restrict a0, const float* __restrict a1,
                          const float* __restrict a2, const float* __restrict b0,
                          const float* __restrict b1, const float* __restrict b2,
                          float* __restrict ao, float* __restrict bo, int nv, const RowCoeffs& c) {
  const Vec four = splat(4.0f), ca = splat(c.ca), cb = splat(c.cb), pa = splat(c.pa),
            pb = splat(c.pb), q = splat(c.q), dt = splat(c.dt);
  // Only the last lane of the vector before x = 0 is read: the ghost column x = -1.
  Vec va_prev = splat((a0[-1] + a2[-1]) + 4.0f * a1[-1]);
  Vec vb_prev = splat((b0[-1] + b2[-1]) + 4.0f * b1[-1]);
  Vec va = column_sum(a0, a1, a2), vb = column_sum(b0, b1, b2);
  for (int j = 0; j < nv; ++j) {
    const int x = j * kLanes;
    const Vec va_next = column_sum(a0 + x + kLanes, a1 + x + kLanes, a2 + x + kLanes);
    const Vec vb_next = column_sum(b0 + x + kLanes, b1 + x + kLanes, b2 + x + kLanes);
    const Vec sa = (lefts(va_prev, va, kLaneSeq) + rights(va, va_next, kLaneSeq)) + four * va;
    const Vec sb = (lefts(vb_prev, vb, kLaneSeq) + rights(vb, vb_next, kLaneSeq)) + four * vb;
    const Vec A = load(a1 + x), B = load(b1 + x);
    const Vec abb = kUnitDt ? A * (B * B) : dt * (A * (B * B));
    store(ao + x, (ca * sa + (pa * A + q)) - abb);
    store(bo + x, (cb * sb + pb * B) + abb);
    va_prev = va;
    va = va_next;
    vb_prev = vb;
    vb = vb_next;
  }
}

// Periodic ghosts of a freshly written row; the padding past x = n is zeroed so that it
// stays finite.
void finish_row(float* r, int n, int nv) {
  r[-1] = r[n - 1];
  r[n] = r[0];
  for (int x = n + 1; x < nv * kLanes; ++x) r[x] = 0.0f;
}

// One meeting point per block of steps. Spins briefly (a block is a few hundred
// microseconds), then sleeps in the kernel so that a loaded machine is not made worse.
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
    for (int spins = 0; spins < 200; ++spins) {
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
    band.ring.resize(std::max(1, block_steps_ - 1) * 3 * 2, stride_);
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

float* ParallelGrayScott9::Band::edge_row(int parity, int chem, int i, int kmax) {
  return edges.row(((parity * 2 + chem) * 2) * kmax + i);
}

void ParallelGrayScott9::publish_edges(Band& band, int parity) {
  const int kmax = block_steps_;
  for (int chem = 0; chem < 2; ++chem) {
    RowStore& grid = chem == 0 ? grid_a_ : grid_b_;
    for (int i = 0; i < kmax; ++i) {
      copy_whole_row(grid.row(band.y0 + i), band.edge_row(parity, chem, i, kmax));
      copy_whole_row(grid.row(band.y1 - kmax + i), band.edge_row(parity, chem, kmax + i, kmax));
    }
  }
}

void ParallelGrayScott9::copy_whole_row(const float* from, float* to) const {
  std::memcpy(to - RowStore::kPad, from - RowStore::kPad, sizeof(float) * std::size_t(stride_));
}

void ParallelGrayScott9::run(int64_t steps) {
  if (steps <= 0) return;
  const int nx = size_.x, ny = size_.y, n = threads_, nv = vectors_, kmax = block_steps_;
  const std::size_t row_bytes = sizeof(float) * std::size_t(nx);
  for (int y = 0; y < ny; ++y) {
    float* ra = grid_a_.row(y);
    float* rb = grid_b_.row(y);
    std::memcpy(ra, a_.row(y), row_bytes);
    std::memcpy(rb, b_.row(y), row_bytes);
    finish_row(ra, nx, nv);
    finish_row(rb, nx, nv);
  }
  for (Band& band : bands_) publish_edges(band, 0);
  const RowCoeffs coeffs = row_coeffs(params_);
  const auto row_kernel =
      params_.dt == 1.0f ? &gray_scott9_row_simd<true> : &gray_scott9_row_simd<false>;
  BlockBarrier barrier(n);
  auto work = [&](int t) {
    Band& band = bands_[std::size_t(t)];
    Band& above = bands_[std::size_t((t + n - 1) % n)];
    Band& below = bands_[std::size_t((t + 1) % n)];
    const int y0 = band.y0, y1 = band.y1;
    // Levels 1 .. k - 1 keep a ring of 3 rows per chemical: level l writes row y over row
    // y - 3, which level l + 1 (run after it in the same wavefront step) no longer reads.
    auto ring_row = [&](int level, int y, int chem) {
      return band.ring.row(((level - 1) * 3 + int(unsigned(y + 3 * ny) % 3u)) * 2 + chem);
    };
    int parity = 0;
    for (int64_t done = 0; done < steps;) {
      const int k = int(std::min<int64_t>(kmax, steps - done));
      // Level 0: the band's own rows are updated in place (level k writes row y after level
      // 1 has read it for the last time); rows of the neighbours come from the copies they
      // published before the last barrier.
      auto level0 = [&](int y, int chem) -> const float* {
        if (y < y0) return above.edge_row(parity, chem, 2 * kmax - (y0 - y), kmax);
        if (y >= y1) return below.edge_row(parity, chem, y - y1, kmax);
        return chem == 0 ? grid_a_.row(y) : grid_b_.row(y);
      };
      auto input = [&](int level, int y, int chem) -> const float* {
        return level == 0 ? level0(y, chem) : ring_row(level, y, chem);
      };
      // Wavefront: at step tt, level l computes row tt - (l - 1), whose inputs (rows y - 1 ..
      // y + 1 of level l - 1) exist; level l spans the band grown by k - l rows.
      for (int tt = y0 - (k - 1); tt < y1 + (k - 1); ++tt) {
        for (int l = 1; l <= k; ++l) {
          const int y = tt - (l - 1);
          if (y < y0 - (k - l) || y >= y1 + (k - l)) continue;
          // With k = 1 the only level reads rows y - 1 .. y + 1 in place, so its rows go
          // through the ring and are written back one wavefront step later.
          const bool to_grid = l == k && k > 1;
          float* ao = to_grid ? grid_a_.row(y) : ring_row(l, y, 0);
          float* bo = to_grid ? grid_b_.row(y) : ring_row(l, y, 1);
          row_kernel(input(l - 1, y - 1, 0), input(l - 1, y, 0), input(l - 1, y + 1, 0),
                     input(l - 1, y - 1, 1), input(l - 1, y, 1), input(l - 1, y + 1, 1), ao, bo, nv,
                     coeffs);
          finish_row(ao, nx, nv);
          finish_row(bo, nx, nv);
        }
        if (k == 1 && tt > y0) {
          copy_whole_row(ring_row(1, tt - 1, 0), grid_a_.row(tt - 1));
          copy_whole_row(ring_row(1, tt - 1, 1), grid_b_.row(tt - 1));
        }
      }
      if (k == 1) {
        copy_whole_row(ring_row(1, y1 - 1, 0), grid_a_.row(y1 - 1));
        copy_whole_row(ring_row(1, y1 - 1, 1), grid_b_.row(y1 - 1));
      }
      parity = 1 - parity;
      publish_edges(band, parity);
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
  for (int y = 0; y < ny; ++y) {
    std::memcpy(a_.row(y), grid_a_.row(y), row_bytes);
    std::memcpy(b_.row(y), grid_b_.row(y), row_bytes);
  }
  wrap_periodic(a_);
  wrap_periodic(b_);
}

}  // namespace ardcell
