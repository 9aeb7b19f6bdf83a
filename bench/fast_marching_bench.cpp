// Fast marching and the live-pen orientation update (Kim & Lin section 6): after a stroke
// segment, theta0 over the whole grid must be ready within 8 ms at 512^2 and 30 ms at 1024^2
// on 2 cores. The update pools the stroke onto a coarse grid, marches there and upsamples
// (OrientationExtender); the upsampling runs on two threads as the painter does.
#include <benchmark/benchmark.h>

#include <cmath>
#include <thread>

#include "kernels/fast_marching.h"

namespace ardcell {
namespace {

// A three-turn spiral stroke rasterised 3 cells wide, as the painter would.
struct Stroke {
  FieldF w, c, s;
  explicit Stroke(int n) : w({n, n}, 0), c({n, n}, 0), s({n, n}, 0) {
    const double cx = n / 2.0, cy = n / 2.0;
    for (int k = 0; k < 20000; ++k) {
      const double a = 6 * 3.14159265 * k / 20000;
      const double r = n * (0.03 + 0.07 * a / 3.14159265);
      const int x = int(cx + r * std::cos(a)), y = int(cy + r * std::sin(a));
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int px = x + dx, py = y + dy;
          if (px < 0 || py < 0 || px >= n || py >= n) continue;
          w(px, py) = 1;
          c(px, py) = float(-std::sin(a));
          s(px, py) = float(std::cos(a));
        }
    }
  }
};

void BM_FastMarchingDistance(benchmark::State& state) {
  const int n = int(state.range(0));
  const int order = int(state.range(1));
  Stroke stroke(n);
  FieldF d({n, n}, 0), f({n, n}, 0);
  FastMarchingWorkspace ws({n, n});
  FastMarchingParams p;
  p.order = order;
  for (auto _ : state) {
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) d(x, y) = stroke.w(x, y) > 0 ? 0.f : kFarDistance;
    const View<float> values[1] = {f.view()};
    benchmark::DoNotOptimize(fast_marching(d.view(), values, box_of_size({n, n}), p, ws));
  }
  state.SetItemsProcessed(state.iterations() * int64_t(n) * n);
}
BENCHMARK(BM_FastMarchingDistance)
    ->Args({256, 1})
    ->Args({512, 1})
    ->Args({512, 2})
    ->Unit(benchmark::kMillisecond);

// Full-grid theta0 update as the painter runs it: coarse march + 2-thread upsample.
void BM_Theta0Update(benchmark::State& state) {
  const int n = int(state.range(0));
  const int factor = int(state.range(1));
  Stroke stroke(n);
  FieldF theta({n, n}, 0);
  OrientationExtender ext({n, n}, factor);
  for (auto _ : state) {
    ext.march(stroke.w.view(), stroke.c.view(), stroke.s.view());
    std::thread other([&] {
      ext.upsample_rows(stroke.w.view(), stroke.c.view(), stroke.s.view(), theta.view(), n / 2, n);
    });
    ext.upsample_rows(stroke.w.view(), stroke.c.view(), stroke.s.view(), theta.view(), 0, n / 2);
    other.join();
    benchmark::DoNotOptimize(theta.raw());
  }
}
BENCHMARK(BM_Theta0Update)
    ->Args({512, 1})
    ->Args({512, 4})
    ->Args({1024, 4})
    ->Args({1024, 8})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace ardcell

BENCHMARK_MAIN();
