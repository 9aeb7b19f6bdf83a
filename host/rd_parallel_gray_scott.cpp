#include "host/rd_parallel_gray_scott.h"

#include <algorithm>
#include <atomic>
#include <cstring>
#include <thread>
#include <vector>

namespace ardcell {
namespace {

// One meeting point per step. Spins briefly (a step is tens of microseconds), then yields so
// that a loaded machine is not made worse.
class SpinBarrier {
 public:
  explicit SpinBarrier(int n) : n_(n) {}
  void wait() {
    const int gen = gen_.load(std::memory_order_acquire);
    if (count_.fetch_add(1, std::memory_order_acq_rel) == n_ - 1) {
      count_.store(0, std::memory_order_relaxed);
      gen_.fetch_add(1, std::memory_order_release);
      return;
    }
    for (int spins = 0; gen_.load(std::memory_order_acquire) == gen; ++spins) {
      if (spins > 2000) {
        std::this_thread::yield();
      } else {
#if defined(__x86_64__) || defined(__i386__)
        __builtin_ia32_pause();
#endif
      }
    }
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

ParallelGrayScott9::ParallelGrayScott9(Int2 size, const GrayScott9Params& params, int threads)
    : size_(size), params_(params) {
  ARDCELL_CHECK(size.x > 0 && size.y > 0, "grid must be non-empty");
  if (threads <= 0) threads = int(std::max(1u, std::thread::hardware_concurrency()));
  threads_ = std::clamp(threads, 1, size.y);
  for (int i = 0; i < 2; ++i) {
    a_[i] = FieldF(size, 1);
    b_[i] = FieldF(size, 1);
  }
}

void ParallelGrayScott9::seed_square() {
  FieldF& A = a();
  FieldF& B = b();
  A.fill(1.0f);
  B.fill(0.0f);
  for (int y = 0; y < 10; ++y)
    for (int x = 0; x < 10; ++x) {
      const int px = size_.x / 2 + x - 5, py = size_.y / 2 + y - 5;
      if (px >= 0 && px < size_.x && py >= 0 && py < size_.y) B(px, py) = 1.0f;
    }
}

void ParallelGrayScott9::run(int64_t steps) {
  if (steps <= 0) return;
  wrap_periodic(a_[cur_]);
  wrap_periodic(b_[cur_]);
  const int nx = size_.x, ny = size_.y, n = threads_;
  SpinBarrier barrier(n);
  auto work = [&](int t) {
    const int y0 = int(int64_t(ny) * t / n), y1 = int(int64_t(ny) * (t + 1) / n);
    // Row sums scratch, kept per thread (no allocation inside the step loop).
    std::vector<float> scratch(2 * std::size_t(nx + 2) + 16);
    const Box2 band{{0, y0}, {nx, y1}};
    int cur = cur_;
    for (int64_t s = 0; s < steps; ++s) {
      const int nxt = 1 - cur;
      gray_scott9_explicit_tile(a_[cur].view(), b_[cur].view(), a_[nxt].view(), b_[nxt].view(),
                                band, params_, scratch.data());
      wrap_rows_x(a_[nxt], y0, y1);
      wrap_rows_x(b_[nxt], y0, y1);
      if (y0 == 0) {
        copy_row(a_[nxt], 0, ny);
        copy_row(b_[nxt], 0, ny);
      }
      if (y1 == ny) {
        copy_row(a_[nxt], ny - 1, -1);
        copy_row(b_[nxt], ny - 1, -1);
      }
      barrier.wait();
      cur = nxt;
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
  if (steps % 2) cur_ = 1 - cur_;
}

}  // namespace ardcell
