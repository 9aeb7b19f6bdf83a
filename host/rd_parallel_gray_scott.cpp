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
  const int nx = size_.x, ny = size_.y, n = threads_;
  const std::ptrdiff_t row_len = nx + 2;  // x = -1 .. nx
  wrap_rows_x(a_[cur_], 0, ny);
  wrap_rows_x(b_[cur_], 0, ny);
  SpinBarrier barrier(n);
  int final_cur = cur_;
  auto work = [&](int t) {
    const int y0 = int(int64_t(ny) * t / n), y1 = int(int64_t(ny) * (t + 1) / n);
    // Levels 1 .. kBlockSteps - 1 keep a ring of 4 rows per chemical; the last level writes
    // straight into the next global buffer. Allocated once per run().
    std::vector<float> ring(std::size_t(kBlockSteps) * 4 * 2 * std::size_t(row_len));
    std::vector<float> scratch(2 * std::size_t(row_len) + 16);
    auto ring_row = [&](int level, int y, int chem) {
      const int slot = ((y % 4) + 4) % 4;
      return ring.data() + ((std::size_t(level - 1) * 4 + slot) * 2 + chem) * row_len;
    };
    int cur = cur_;
    for (int64_t done = 0; done < steps;) {
      const int k = int(std::min<int64_t>(kBlockSteps, steps - done));
      const int nxt = 1 - cur;
      auto input = [&](int level, int y, int chem) -> const float* {
        if (level == 0) {
          const FieldF& f = chem == 0 ? a_[cur] : b_[cur];
          return f.row(((y % ny) + ny) % ny) - 1;
        }
        return ring_row(level, y, chem);
      };
      // Wavefront: at each tt, level l computes row tt - (l - 1), whose inputs (rows y - 1 ..
      // y + 1 of level l - 1) are ready; level l spans the band grown by k - l rows.
      for (int tt = y0 - (k - 1); tt < y1 + (k - 1); ++tt) {
        for (int l = 1; l <= k; ++l) {
          const int y = tt - (l - 1);
          if (y < y0 - (k - l) || y >= y1 + (k - l)) continue;
          const float* a_in[3] = {input(l - 1, y - 1, 0), input(l - 1, y, 0),
                                  input(l - 1, y + 1, 0)};
          const float* b_in[3] = {input(l - 1, y - 1, 1), input(l - 1, y, 1),
                                  input(l - 1, y + 1, 1)};
          float* ao = l == k ? a_[nxt].row(y) - 1 : ring_row(l, y, 0);
          float* bo = l == k ? b_[nxt].row(y) - 1 : ring_row(l, y, 1);
          gray_scott9_explicit_row(a_in, b_in, ao + 1, bo + 1, nx, params_, scratch.data());
          ao[0] = ao[nx];  // periodic ghosts in x
          ao[nx + 1] = ao[1];
          bo[0] = bo[nx];
          bo[nx + 1] = bo[1];
        }
      }
      barrier.wait();
      cur = nxt;
      done += k;
    }
    if (t == 0) final_cur = cur;
  };
  if (n == 1) {
    work(0);
  } else {
    std::vector<std::jthread> pool;
    pool.reserve(std::size_t(n - 1));
    for (int t = 1; t < n; ++t) pool.emplace_back(work, t);
    work(0);
  }
  cur_ = final_cur;
  wrap_periodic(a_[cur_]);
  wrap_periodic(b_[cur_]);
}

}  // namespace ardcell
