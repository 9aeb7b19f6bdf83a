#include "runtime/row_executor.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cstring>
#include <memory>
#include <random>
#include <vector>

#include "runtime/thread/thread_backend.h"

namespace ardcell {
namespace {

std::unique_ptr<Backend> make_backend(int workers) {
  if (workers == 0) return std::make_unique<SerialBackend>();
  ThreadBackendOptions o;
  o.workers = workers;
  return std::make_unique<ThreadBackend>(o);
}

// Values of very different magnitudes, so that any change of the summation order shows in the
// last bits of a double sum.
std::vector<double> ill_conditioned(int n) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> mantissa(-1.0, 1.0);
  std::uniform_int_distribution<int> exponent(-30, 30);
  std::vector<double> v(static_cast<std::size_t>(n));
  for (double& x : v) x = std::ldexp(mantissa(rng), exponent(rng));
  return v;
}

TEST(RowExecutor, EveryRowRunsOnceOnAnyWorkerCount) {
  for (int workers : {0, 1, 2, 3, 4}) {
    auto backend = make_backend(workers);
    RowExecutor ex(*backend);
    for (int rows : {1, 7, 93, 1000}) {
      std::vector<std::atomic<int>> visits(static_cast<std::size_t>(rows));
      ex.for_rows(rows, 4096, [&](int y0, int y1) {
        ASSERT_LT(y0, y1);
        for (int y = y0; y < y1; ++y) visits[std::size_t(y)].fetch_add(1);
      });
      for (int y = 0; y < rows; ++y) EXPECT_EQ(visits[std::size_t(y)].load(), 1) << y;
    }
  }
}

TEST(RowExecutor, SumsAreTheSameBitsForAnyWorkerCount) {
  const int rows = 997;
  const std::vector<double> values = ill_conditioned(rows * 64);
  auto row_sum = [&](RowExecutor& ex) {
    return ex.sum_rows(rows, 64 * 1024, [&](int y0, int y1, double* partials) {
      for (int y = y0; y < y1; ++y) {
        double s = 0;
        for (int x = 0; x < 64; ++x) s += values[std::size_t(y) * 64 + std::size_t(x)];
        partials[y] = s;
      }
    });
  };
  SerialBackend serial;
  RowExecutor reference(serial);
  const double expected = row_sum(reference);
  // The executor's order is rows in order: a different grouping would give other bits.
  double flat = 0;
  for (double v : values) flat += v;
  ASSERT_NE(std::memcmp(&flat, &expected, sizeof flat), 0)
      << "the data must be ill-conditioned enough to tell summation orders apart";
  for (int workers : {1, 2, 3, 4}) {
    auto backend = make_backend(workers);
    RowExecutor ex(*backend);
    const double got = row_sum(ex);
    EXPECT_EQ(std::memcmp(&got, &expected, sizeof got), 0) << workers << " workers";
  }
}

TEST(RowExecutor, TasksRunOnceEach) {
  auto backend = make_backend(2);
  RowExecutor ex(*backend);
  std::atomic<int> mask{0};
  ex.for_tasks(2, [&](int i) { mask.fetch_or(1 << i); });
  EXPECT_EQ(mask.load(), 3);
}

TEST(RowExecutor, SmallGridsRunOnTheCallingThread) {
  auto backend = make_backend(2);
  RowExecutor ex(*backend);
  int calls = 0;
  ex.for_rows(16, 16, [&](int y0, int y1) {
    ++calls;
    EXPECT_EQ(y0, 0);
    EXPECT_EQ(y1, 16);
  });
  EXPECT_EQ(calls, 1);
}

}  // namespace
}  // namespace ardcell
