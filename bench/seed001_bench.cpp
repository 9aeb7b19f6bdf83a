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
constexpr int SCREEN_WIDTH = 400;
constexpr int SCREEN_HEIGHT = 400;

double table[2][2][SCREEN_HEIGHT + 2][SCREEN_WIDTH + 2];
double prod1Table[2][SCREEN_HEIGHT + 2][SCREEN_WIDTH + 2];
double prod2Table[2][SCREEN_HEIGHT + 2][SCREEN_WIDTH + 2];
int curT = 0;

double DA = 1.0;
double DB = 0.5;
double f = 0.055;
double k = 0.062;

void product() {
  for (int t = 0; t < 2; t++) {
    for (int y = 0; y < SCREEN_HEIGHT + 2; ++y)
      for (int x = 1; x < SCREEN_WIDTH + 1; ++x)
        prod1Table[t][y][x] =
            table[curT][t][y][x - 1] + 4.0f * table[curT][t][y][x] + table[curT][t][y][x + 1];

    for (int y = 1; y < SCREEN_HEIGHT + 1; ++y)
      for (int x = 1; x < SCREEN_WIDTH + 1; ++x)
        prod2Table[t][y][x] =
            prod1Table[t][y - 1][x] + 4.0f * prod1Table[t][y][x] + prod1Table[t][y + 1][x];
  }
}

void update() {
  double ca = 1.0 - f - 1.8 * DA;
  double cb = 1.0 - f - 1.8 * DB - k;

  for (int t = 0; t < 2; ++t) {
    for (int x = 0; x < SCREEN_WIDTH + 2; ++x) {
      table[curT][t][SCREEN_HEIGHT + 1][x] = table[curT][t][1][x];
      table[curT][t][0][x] = table[curT][t][SCREEN_HEIGHT][x];
    }
    for (int y = 0; y < SCREEN_HEIGHT + 2; ++y) {
      table[curT][t][y][SCREEN_WIDTH + 1] = table[curT][t][y][1];
      table[curT][t][y][0] = table[curT][t][y][SCREEN_WIDTH];
    }
  }

  product();

  for (int y = 1; y < SCREEN_HEIGHT + 1; ++y)
    for (int x = 1; x < SCREEN_WIDTH + 1; ++x) {
      double A = table[curT][0][y][x];
      double B = table[curT][1][y][x];

      table[1 - curT][0][y][x] = 0.05 * DA * prod2Table[0][y][x] - A * B * B + ca * A + f;
      table[1 - curT][1][y][x] = 0.05 * DB * prod2Table[1][y][x] + A * B * B + cb * B;
    }

  curT = 1 - curT;
}

void init() {
  curT = 0;
  for (int c = 0; c < 2; ++c)
    for (int y = 0; y < SCREEN_HEIGHT + 2; ++y)
      for (int x = 0; x < SCREEN_WIDTH + 2; ++x) {
        table[c][0][y][x] = 1.0;
        table[c][1][y][x] = 0.0;
      }
  for (int y = 0; y < 10; ++y)
    for (int x = 0; x < 10; ++x)
      table[0][1][SCREEN_HEIGHT / 2 + y - 5 + 1][SCREEN_WIDTH / 2 + x - 5 + 1] = 1.0;
}
}  // namespace article

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
