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
// Ours: what `ardcell run seed001` runs, the Engine on the seed001 preset (threads back end,
// 200 frames of 10 steps; RdStepper -> Device::gray_scott9_steps -> kernels/gray_scott9.h's
// GrayScott9Blocked on the back end's workers): float, SIMD row kernel with register-shifted
// separable sums, one band of rows per worker updated in place, temporally blocked (a pass of up
// to 5 steps per band), band boundaries moved by measured busy time, and skipping the quiescent
// background bit for bit. BM_Seed001_Kernel runs the kernel alone on a back end of its own, in
// frames of 10 steps as the engine does, to compare schedules (bands per worker, block steps,
// skipping, balancing). computed_fraction: the cell updates a run computed over 400 * 400 *
// 2000.
//
// The machine is shared: quote medians of --benchmark_repetitions and `uptime`. The
// baselines are single-threaded, so their CPU time is their idle-machine time.
#include <benchmark/benchmark.h>

#include <time.h>

#include <chrono>
#include <cmath>
#include <memory>
#include <thread>
#include <vector>

#include "host/engine/engine.h"
#include "host/scenes/preset.h"
#include "kernels/gray_scott9.h"
#include "runtime/check.h"
#include "runtime/row_executor.h"
#include "runtime/thread/thread_backend.h"

namespace {

// Cell updates in seed 001's workload.
constexpr double kSeed001Updates = 400.0 * 400.0 * 2000.0;
constexpr int kFrames = 200, kStepsPerFrame = 10;

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

ardcell::SceneConfig seed001_scene() {
  ardcell::Preset preset;
  ARDCELL_CHECK(bool(ardcell::load_preset("seed001", preset)), "the seed001 preset");
  ARDCELL_CHECK(preset.scene.size == (ardcell::Int2{400, 400}) &&
                    preset.scene.rd.steps_per_frame == kStepsPerFrame,
                "seed001 is 400^2 in frames of 10 steps");
  return preset.scene;
}

// The product path: the engine `ardcell run seed001` builds (its options: the threads back end on
// every core, pinned), reset to seed 001's start, 200 frames.
class EngineRun {
 public:
  EngineRun() : engine_(seed001_scene(), run_options()) {}
  ardcell::Engine& engine() { return engine_; }
  static ardcell::EngineOptions run_options() {
    ardcell::EngineOptions o;
    o.pin_workers = true;
    return o;
  }
  // Wall seconds for 200 frames from seed 001's start.
  double run() {
    engine_.reset();
    const double w0 = wall_s();
    for (int f = 0; f < kFrames; ++f) engine_.step();
    engine_.finish();
    const double seconds = wall_s() - w0;
    benchmark::DoNotOptimize(engine_.state().B(200, 200));
    return seconds;
  }

 private:
  ardcell::Engine engine_;
};

// Times run.run() (wall seconds of 200 frames) in every iteration. Time column: the wall clock.
// cpu_per_worker_ms: the process's CPU time over the run divided by the worker count, i.e. what
// the wall time would be on otherwise idle cores with perfect overlap (the machine is shared, so
// the wall clock includes time spent descheduled).
template <class Run>
void time_frames(benchmark::State& state, Run& run, int workers) {
  double cpu = 0, wall = 0;
  for (auto _ : state) {
    const double c0 = process_cpu_s();
    wall += run.run();
    cpu += process_cpu_s() - c0;
  }
  const double n = double(state.iterations());
  state.counters["workers"] = workers;
  state.counters["ms_per_frame"] = 1e3 * wall / n / kFrames;
  state.counters["cpu_per_worker_ms"] = 1e3 * cpu / double(workers) / n;
  state.counters["cells_per_s"] =
      benchmark::Counter(kSeed001Updates * n, benchmark::Counter::kIsRate);
}

void BM_Seed001_Engine_2000Steps(benchmark::State& state) {
  EngineRun run;
  time_frames(state, run, run.engine().workers());
}
BENCHMARK(BM_Seed001_Engine_2000Steps)->Unit(benchmark::kMillisecond)->MinTime(2.0)->UseRealTime();

// The kernel alone on a threads back end like the one `ardcell run` gives the engine (pinned, the
// host thread is worker 0), in frames of 10 steps.
class KernelRun {
 public:
  KernelRun(int workers, int bands_per_worker, int block_steps)
      : backend_(options(workers)),
        ex_(backend_),
        a_(ardcell::GrayScott9Blocked::make_field({400, 400})),
        b_(ardcell::GrayScott9Blocked::make_field({400, 400})),
        gs_({400, 400}, ex_, bands_per_worker * backend_.workers(), block_steps) {}
  ardcell::GrayScott9Blocked& kernel() { return gs_; }
  int workers() const { return backend_.workers(); }
  // Cell updates the last run() computed.
  int64_t cell_updates() const { return cell_updates_; }
  // Wall seconds for 200 frames from seed 001's start.
  double run() {
    a_.fill(1.0f);
    b_.fill(0.0f);
    for (int y = 195; y < 205; ++y)
      for (int x = 195; x < 205; ++x) b_(x, y) = 1.0f;
    cell_updates_ = 0;
    const double w0 = wall_s();
    for (int f = 0; f < kFrames; ++f) {
      gs_.run(a_, b_, kStepsPerFrame, {});
      cell_updates_ += gs_.last_run_cell_updates();
    }
    const double seconds = wall_s() - w0;
    benchmark::DoNotOptimize(b_(200, 200));
    return seconds;
  }

 private:
  static ardcell::ThreadBackendOptions options(int workers) {
    ardcell::ThreadBackendOptions o;
    o.workers = workers;
    o.pin = true;
    return o;
  }
  ardcell::ThreadBackend backend_;
  ardcell::RowExecutor ex_;
  ardcell::FieldF a_, b_;
  ardcell::GrayScott9Blocked gs_;
  int64_t cell_updates_ = 0;
};

void BM_Seed001_Kernel_2000Steps(benchmark::State& state) {
  KernelRun run(int(state.range(0)), int(state.range(1)), int(state.range(2)));
  run.kernel().set_skip_quiescent(state.range(3) != 0);
  run.kernel().set_balancing(state.range(4) != 0);
  time_frames(state, run, run.workers());
  state.counters["bands"] = run.kernel().bands();
  state.counters["computed_fraction"] = double(run.cell_updates()) / kSeed001Updates;
}
BENCHMARK(BM_Seed001_Kernel_2000Steps)
    // workers 0 = every hardware thread; bands per worker
    ->ArgNames({"workers", "bands", "block_steps", "skip", "balance"})
    ->Args({1, 1, 5, 0, 0})
    ->Args({1, 1, 5, 1, 0})
    ->Args({0, 1, 5, 0, 1})
    ->Args({0, 1, 2, 1, 1})
    ->Args({0, 1, 5, 1, 1})
    ->Args({0, 1, 10, 1, 1})
    ->Args({0, 1, 5, 1, 0})
    ->Args({0, 4, 5, 1, 0})
    ->Args({0, 8, 5, 1, 0})
    ->Unit(benchmark::kMillisecond)
    ->MinTime(2.0)
    ->UseRealTime();

// The ratio in one place: each iteration runs the article's loop (both builds, thread CPU
// time, single-threaded) and the product path (the Engine, 200 frames, wall clock) back to back,
// so that both see the same machine load. ratio_wall: baseline (-O3 -march=native) / the
// engine's wall clock (inflated by other processes on a shared machine); ratio_cpu: the same
// against the engine's CPU per worker; ratio_generic_wall: against the article's own build.
// The schedules that could replace balancing run in the same iterations, in alternating order
// (the kernel on a back end of its own, frames of 10): stealing_wall_ms, 4 bands per worker
// with fixed boundaries, which the workers take from each other; fixed_wall_ms, one fixed band
// per worker.
void BM_Seed001_Ratio(benchmark::State& state) {
  EngineRun engine;
  KernelRun stealing(0, 4, ardcell::GrayScott9Blocked::kBlockSteps);
  KernelRun fixed(0, 1, ardcell::GrayScott9Blocked::kBlockSteps);
  stealing.kernel().set_balancing(false);
  fixed.kernel().set_balancing(false);
  double base = 0, generic = 0, ours_cpu = 0, ours_wall = 0, stealing_wall = 0, fixed_wall = 0;
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
    auto others = [&] {
      stealing_wall += stealing.run();
      fixed_wall += fixed.run();
    };
    if (iteration % 2 == 1) others();
    const double c0 = process_cpu_s();
    ours_wall += engine.run();
    ours_cpu += (process_cpu_s() - c0) / double(engine.engine().workers());
    if (iteration % 2 == 0) others();
    ++iteration;
  }
  const double n = double(state.iterations());
  state.counters["baseline_ms"] = 1e3 * base / n;
  state.counters["baseline_generic_ms"] = 1e3 * generic / n;
  state.counters["ours_wall_ms"] = 1e3 * ours_wall / n;
  state.counters["ours_cpu_per_worker_ms"] = 1e3 * ours_cpu / n;
  state.counters["ms_per_frame"] = 1e3 * ours_wall / n / kFrames;
  state.counters["stealing_wall_ms"] = 1e3 * stealing_wall / n;
  state.counters["fixed_wall_ms"] = 1e3 * fixed_wall / n;
  state.counters["ratio_wall"] = base / ours_wall;
  state.counters["ratio_cpu"] = base / ours_cpu;
  state.counters["ratio_generic_wall"] = generic / ours_wall;
  state.counters["workers"] = engine.engine().workers();
}
BENCHMARK(BM_Seed001_Ratio)->Unit(benchmark::kMillisecond)->Iterations(5);

// Agreement of the two programs after 2000 steps (float vs double): max |B_ours - B_article|,
// ours through the engine.
void BM_Seed001_Agreement(benchmark::State& state) {
  EngineRun run;
  double worst = 0;
  for (auto _ : state) {
    article::init();
    for (int i = 0; i < 2000; ++i) article::update();
    run.run();
    const ardcell::FieldF& b = run.engine().state().B;
    worst = 0;
    for (int y = 0; y < 400; ++y)
      for (int x = 0; x < 400; ++x)
        worst = std::max(
            worst, std::abs(double(b(x, y)) - article::table[article::curT][1][y + 1][x + 1]));
  }
  state.counters["max_abs_diff_B"] = worst;
}
BENCHMARK(BM_Seed001_Agreement)->Iterations(1)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
