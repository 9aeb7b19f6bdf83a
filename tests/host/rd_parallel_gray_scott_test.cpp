#include "host/rd_parallel_gray_scott.h"

#include <gtest/gtest.h>

#include <cmath>

namespace ardcell {
namespace {

TEST(ParallelGrayScott9, ThreadsGiveBitIdenticalResults) {
  ParallelGrayScott9 one({40, 30}, {}, 1), two({40, 30}, {}, 2), three({40, 30}, {}, 3);
  for (ParallelGrayScott9* s : {&one, &two, &three}) {
    s->seed_square();
    s->run(101);
  }
  for (int y = 0; y < 30; ++y)
    for (int x = 0; x < 40; ++x) {
      ASSERT_EQ(one.b()(x, y), two.b()(x, y));
      ASSERT_EQ(one.b()(x, y), three.b()(x, y));
      ASSERT_EQ(one.a()(x, y), three.a()(x, y));
    }
}

// Against a plain double-precision transcription of seed 001's update (with wrap).
TEST(ParallelGrayScott9, MatchesSeed001Reference) {
  const int n = 32, steps = 150;
  ParallelGrayScott9 sim({n, n}, {}, 2);
  sim.seed_square();
  std::vector<double> A(n * n, 1.0), B(n * n, 0.0), A2(n * n), B2(n * n);
  for (int y = 0; y < 10; ++y)
    for (int x = 0; x < 10; ++x) B[(n / 2 + y - 5) * n + (n / 2 + x - 5)] = 1.0;
  const double coef[3][3] = {{0.05, 0.2, 0.05}, {0.2, -1.0, 0.2}, {0.05, 0.2, 0.05}};
  for (int s = 0; s < steps; ++s) {
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        double la = 0, lb = 0;
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int i = ((y + dy + n) % n) * n + (x + dx + n) % n;
            la += coef[dy + 1][dx + 1] * A[i];
            lb += coef[dy + 1][dx + 1] * B[i];
          }
        const double a = A[y * n + x], b = B[y * n + x];
        A2[y * n + x] = a + 1.0 * la - a * b * b + 0.055 * (1.0 - a);
        B2[y * n + x] = b + 0.5 * lb + a * b * b - (0.062 + 0.055) * b;
      }
    std::swap(A, A2);
    std::swap(B, B2);
  }
  sim.run(steps);
  double worst = 0;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x)
      worst = std::max(worst, std::abs(double(sim.b()(x, y)) - B[y * n + x]));
  EXPECT_LT(worst, 1e-4);                       // float32 vs double over 150 steps
  EXPECT_GT(B[(n / 2) * n + n / 2 + 6], 1e-3);  // the pattern has spread (non-trivial)
}

}  // namespace
}  // namespace ardcell
