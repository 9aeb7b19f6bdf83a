// Seed 001's workload: explicit Gray-Scott, 9-point Laplacian, 400x400, 2000 steps, wrap.
//
// Baseline: the article's best loop, transcribed faithfully (doubles, padded tables, the
// separable (1 4 1) x (1 4 1) product into two temporary tables, constants folded, the curT
// flip instead of memcpy, and the wrap of "Putting back the wrapping"), single thread, as in
// the article. The one change: the article's wrap writes rows SCREEN_HEIGHT-1 / SCREEN_HEIGHT-2
// of a table that has SCREEN_HEIGHT+2 rows (it overwrites interior cells); here the ghosts
// are rows 0 and H+1, which is what the text describes. Both are compiled with the project's
// flags (-O3 -march=native in Release), so the compiler may vectorise the baseline too.
//
// Ours: ParallelGrayScott9 (host/rd_parallel_gray_scott.h): float, fused row kernel, one band
// of rows per hardware thread, one barrier per step.
#include <benchmark/benchmark.h>

#include <cmath>
#include <thread>

#include "host/rd_parallel_gray_scott.h"

namespace {

namespace article {
#include "bench/seed001_article.inc"
}  // namespace article

// The same source compiled as the article's own build would be: -O2 for generic x86-64
// (SSE2 doubles), no -march=native.
#pragma GCC push_options
#pragma GCC target("arch=x86-64")
#pragma GCC optimize("O2")
namespace article_generic {
#include "bench/seed001_article.inc"
}  // namespace article_generic
#pragma GCC pop_options

void BM_Seed001_ArticleBaseline_2000Steps(benchmark::State& state) {
  for (auto _ : state) {
    state.PauseTiming();
    article::init();
    state.ResumeTiming();
    for (int i = 0; i < 2000; ++i) article::update();
    benchmark::DoNotOptimize(article::table[article::curT][1][200][200]);
  }
  state.counters["cells_per_s"] = benchmark::Counter(
      400.0 * 400.0 * 2000.0 * double(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_Seed001_ArticleBaseline_2000Steps)->Unit(benchmark::kMillisecond)->MinTime(2.0);

void BM_Seed001_ArticleBaselineGenericX86_2000Steps(benchmark::State& state) {
  for (auto _ : state) {
    state.PauseTiming();
    article_generic::init();
    state.ResumeTiming();
    for (int i = 0; i < 2000; ++i) article_generic::update();
    benchmark::DoNotOptimize(article_generic::table[article_generic::curT][1][200][200]);
  }
  state.counters["cells_per_s"] = benchmark::Counter(
      400.0 * 400.0 * 2000.0 * double(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_Seed001_ArticleBaselineGenericX86_2000Steps)
    ->Unit(benchmark::kMillisecond)
    ->MinTime(2.0);

void BM_Seed001_Ours_2000Steps(benchmark::State& state) {
  const int threads = int(state.range(0));
  ardcell::ParallelGrayScott9 sim({400, 400}, {}, threads);
  for (auto _ : state) {
    state.PauseTiming();
    sim.seed_square();
    state.ResumeTiming();
    sim.run(2000);
    benchmark::DoNotOptimize(sim.b()(200, 200));
  }
  state.counters["threads"] = sim.threads();
  state.counters["cells_per_s"] = benchmark::Counter(
      400.0 * 400.0 * 2000.0 * double(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_Seed001_Ours_2000Steps)
    ->Arg(1)
    ->Arg(0)  // 0 = every hardware thread
    ->Unit(benchmark::kMillisecond)
    ->MinTime(2.0)
    ->UseRealTime();

// Agreement of the two programs after 2000 steps (float vs double): max |B_ours - B_article|.
void BM_Seed001_Agreement(benchmark::State& state) {
  ardcell::ParallelGrayScott9 sim({400, 400}, {}, 0);
  double worst = 0;
  for (auto _ : state) {
    article::init();
    for (int i = 0; i < 2000; ++i) article::update();
    sim.seed_square();
    sim.run(2000);
    worst = 0;
    for (int y = 0; y < 400; ++y)
      for (int x = 0; x < 400; ++x)
        worst = std::max(worst, std::abs(double(sim.b()(x, y)) -
                                         article::table[article::curT][1][y + 1][x + 1]));
  }
  state.counters["max_abs_diff_B"] = worst;
}
BENCHMARK(BM_Seed001_Agreement)->Iterations(1)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
