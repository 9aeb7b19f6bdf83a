// Seed 001's workload: explicit Gray-Scott, 9-point Laplacian, 400x400, 2000 steps, wrap.
//
// Baseline: the article's best loop, transcribed faithfully (doubles, padded tables, the
// separable (1 4 1) x (1 4 1) product into two temporary tables, constants folded, the curT
// flip instead of memcpy, and the wrap of "Putting back the wrapping"), single thread, as in
// the article. The one change: the article's wrap writes rows SCREEN_HEIGHT-1 / SCREEN_HEIGHT-2
// of a table that has SCREEN_HEIGHT+2 rows (it overwrites interior cells); here the ghosts
// are rows 0 and H+1, which is what the text describes. It is built twice: with the
// project's flags (-O3 -march=native in Release, so the compiler may vectorise it: the honest
// baseline) and as the article built it (-O2, generic x86-64).
//
// Ours: ParallelGrayScott9 (host/engine/rd_parallel_gray_scott.h): float, SIMD row kernel with
// register-shifted separable sums, one band of rows per hardware thread updated in place,
// temporally blocked (block_steps steps per barrier), band boundaries moved by measured busy
// time (balancing, see the header), and skipping the quiescent background
// bit for bit (skip = 1; skip = 0 computes every cell). computed_fraction: the cell updates
// a run computed over 400 * 400 * 2000.
//
// The machine is shared: quote medians of --benchmark_repetitions and `uptime`. The
// baselines are single-threaded, so their CPU time is their idle-machine time.
#include <benchmark/benchmark.h>

#include <time.h>

#include <chrono>
#include <cmath>
#include <thread>
#include <vector>

#include "host/engine/rd_parallel_gray_scott.h"

namespace {

// Cell updates in seed 001's workload.
constexpr double kSeed001Updates = 400.0 * 400.0 * 2000.0;

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
  state.counters["cells_per_s"] =
      benchmark::Counter(kSeed001Updates * double(state.iterations()), benchmark::Counter::kIsRate);
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
  state.counters["cells_per_s"] =
      benchmark::Counter(kSeed001Updates * double(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_Seed001_ArticleBaselineGenericX86_2000Steps)
    ->Unit(benchmark::kMillisecond)
    ->MinTime(2.0);

double thread_cpu_s() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}
double process_cpu_s() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}
double wall_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// Time column: wall clock. cpu_per_thread_ms: the process's CPU time over the run divided by
// the thread count, i.e. what the wall time would be on otherwise idle cores with perfect
// overlap (the machine is shared, so the wall clock of 2 threads includes time spent
// descheduled).
void BM_Seed001_Ours_2000Steps(benchmark::State& state) {
  const int threads = int(state.range(0));
  ardcell::ParallelGrayScott9 sim({400, 400}, {}, threads, int(state.range(1)));
  sim.set_skip_quiescent(state.range(2) != 0);
  double cpu = 0;
  for (auto _ : state) {
    state.PauseTiming();
    sim.seed_square();
    state.ResumeTiming();
    const double c0 = process_cpu_s();
    sim.run(2000);
    cpu += process_cpu_s() - c0;
    benchmark::DoNotOptimize(sim.b()(200, 200));
  }
  state.counters["threads"] = sim.threads();
  state.counters["block_steps"] = sim.block_steps();
  state.counters["cpu_per_thread_ms"] =
      1e3 * cpu / double(sim.threads()) / double(state.iterations());
  state.counters["computed_fraction"] = double(sim.last_run_cell_updates()) / kSeed001Updates;
  state.counters["cells_per_s"] =
      benchmark::Counter(kSeed001Updates * double(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_Seed001_Ours_2000Steps)
    ->ArgNames({"threads", "block_steps", "skip"})  // threads 0 = every hardware thread
    ->Args({1, 4, 0})
    ->Args({1, 4, 1})
    ->Args({0, 4, 0})
    ->Args({0, 2, 1})
    ->Args({0, 4, 1})
    ->Args({0, 8, 1})
    ->Args({0, 16, 1})
    ->Unit(benchmark::kMillisecond)
    ->MinTime(2.0)
    ->UseRealTime();

// The ratio in one place: each iteration runs the article's loop (both builds, thread CPU
// time, single-threaded) and ours on every core back to back, so that all see the same
// machine load. ratio_cpu: baseline (-O3 -march=native) / ours' CPU per thread;
// ratio_generic_cpu: the same against the article's own build; ratio_wall: baseline / ours'
// wall clock (inflated by other processes on a shared machine). ours_fixed_wall_ms: the same
// run with the band boundaries held fixed (no balancing), in the same iteration, first on
// alternate iterations; band1_start: where balancing left the second band (200 = even).
void BM_Seed001_Ratio(benchmark::State& state) {
  ardcell::ParallelGrayScott9 sim({400, 400}, {}, 0);
  ardcell::ParallelGrayScott9 fixed_bands({400, 400}, {}, 0);
  sim.set_skip_quiescent(state.range(0) != 0);
  fixed_bands.set_skip_quiescent(state.range(0) != 0);
  fixed_bands.set_balancing(false);
  double base = 0, generic = 0, ours_cpu = 0, ours_wall = 0, fixed_wall = 0;
  int64_t iteration = 0;
  for (auto _ : state) {
    article::init();
    const double b0 = thread_cpu_s();
    for (int i = 0; i < 2000; ++i) article::update();
    base += thread_cpu_s() - b0;
    benchmark::DoNotOptimize(article::table[article::curT][1][200][200]);
    article_generic::init();
    const double g0 = thread_cpu_s();
    for (int i = 0; i < 2000; ++i) article_generic::update();
    generic += thread_cpu_s() - g0;
    benchmark::DoNotOptimize(article_generic::table[article_generic::curT][1][200][200]);
    auto run_fixed = [&] {
      fixed_bands.seed_square();
      const double f0 = wall_s();
      fixed_bands.run(2000);
      fixed_wall += wall_s() - f0;
      benchmark::DoNotOptimize(fixed_bands.b()(200, 200));
    };
    if (iteration % 2 == 1) run_fixed();
    sim.seed_square();
    const double c0 = process_cpu_s(), w0 = wall_s();
    sim.run(2000);
    ours_cpu += (process_cpu_s() - c0) / double(sim.threads());
    ours_wall += wall_s() - w0;
    benchmark::DoNotOptimize(sim.b()(200, 200));
    if (iteration % 2 == 0) run_fixed();
    ++iteration;
  }
  const double n = double(state.iterations());
  state.counters["baseline_ms"] = 1e3 * base / n;
  state.counters["baseline_generic_ms"] = 1e3 * generic / n;
  state.counters["ours_cpu_per_thread_ms"] = 1e3 * ours_cpu / n;
  state.counters["ours_wall_ms"] = 1e3 * ours_wall / n;
  state.counters["ours_fixed_wall_ms"] = 1e3 * fixed_wall / n;
  const std::vector<int> starts = sim.band_starts();
  state.counters["band1_start"] = starts.size() > 1 ? starts[1] : 0;
  state.counters["ratio_cpu"] = base / ours_cpu;
  state.counters["ratio_generic_cpu"] = generic / ours_cpu;
  state.counters["ratio_wall"] = base / ours_wall;
  state.counters["threads"] = sim.threads();
  state.counters["computed_fraction"] = double(sim.last_run_cell_updates()) / kSeed001Updates;
}
BENCHMARK(BM_Seed001_Ratio)
    ->ArgName("skip")
    ->Arg(1)
    ->Arg(0)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(5);

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
