// Table 1 (seed 000, section 7.2) on the OpenCL back end: Table1/opencl-stream/... and
// Table1/opencl-blocked/..., beside the CPU rows of bench/table1_bench.cpp, with the same
// naming: Table1/<backend>-<schedule>/<fluid|ard>/<N>. One iteration is one whole frame, enqueued
// and finished (as a frame must be before it is shown). Counters: fps, bytes_per_s (the
// sweep-by-sweep minimum traffic of host/engine/table1_plan.h, so GPU figures compare with the
// device's bandwidth). Both run the built-in scenes table1 and table1-ard on the Engine, as
// `ardcell run --backend opencl` does.
//
// Table1Ratio/opencl-<schedule>/<fluid|ard>/<N>: the threads back end (same schedule) and the
// OpenCL engine ALTERNATELY, one frame each per iteration, in this one process,
// so both see the same machine load (the machine running the bench may be shared). Counters:
// threads_ms, opencl_ms (mean per frame), ratio = opencl_ms / threads_ms, and u_rel_diff (the
// two velocity fields' relative max-norm difference after the run).
//
// The device: ARDCELL_CL_DEVICE=N (as `--cl-device N`, see `ardcell devices`), else the first
// GPU, else the first device; ARDCELL_CL_TILING overrides its tiling
// (kernels/cl/opencl_kernels.h). Without OpenCL the rows
// report an error and the program exits 0.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "bench/bench_env.h"
#include "host/engine/engine.h"
#include "host/engine/table1_plan.h"
#include "host/scenes/scene_registry.h"
#if defined(ARDCELL_WITH_OPENCL)
#include "kernels/cl/opencl_kernels.h"
#include "runtime/opencl/opencl_context.h"
#endif

namespace ardcell {
namespace {

#if defined(ARDCELL_WITH_OPENCL)
struct Device {
  std::unique_ptr<OpenClContext> ctx;
  std::string error;
};

Device& device() {
  static Device d = [] {
    Device dev;
    const char* env = std::getenv("ARDCELL_CL_DEVICE");
    const int index = env ? std::atoi(env) : -1;
    dev.ctx = OpenClContext::open(index, &dev.error);
    // The program and the tiling (ARDCELL_CL_TILING): an error here skips every row.
    if (dev.ctx && !OpenClKernels::create(*dev.ctx, &dev.error)) dev.ctx.reset();
    return dev;
  }();
  return d;
}

// The device, or null after marking the row skipped.
Device* device_or_skip(benchmark::State& state) {
  Device& d = device();
  if (d.ctx) return &d;
  state.SkipWithError(("no OpenCL: " + d.error).c_str());
  return nullptr;
}

SceneConfig table1_scene(bool rd, int n) {
  SceneConfig scene = builtin_scenes().find(rd ? "table1-ard" : "table1")->make();
  scene.size = {n, n};
  return scene;
}

EngineOptions engine_options(PlanSchedule schedule, OpenClContext* ctx) {
  EngineOptions o;
  o.backend = ctx ? EngineOptions::Backend::kOpenCl : EngineOptions::Backend::kThreads;
  o.opencl = ctx;
  o.pin_workers = true;
  o.plan.schedule = schedule;
  return o;
}

void run_table1(benchmark::State& state, PlanSchedule schedule, bool rd, int n) {
  Device* dp = device_or_skip(state);
  if (!dp) return;
  Engine engine(table1_scene(rd, n), engine_options(schedule, dp->ctx.get()));
  engine.step();  // warm-up: first launches compile the work-group functions on some drivers
  engine.finish();
  for (auto _ : state) {
    engine.step();
    engine.finish();
  }
  const double frames = double(state.iterations());
  state.counters["fps"] = benchmark::Counter(frames, benchmark::Counter::kIsRate);
  state.counters["bytes_per_s"] = benchmark::Counter(
      frames * engine.table1_plan()->bytes_per_frame(), benchmark::Counter::kIsRate);
  state.SetLabel(dp->ctx->device().device_name);
}

void run_ratio(benchmark::State& state, PlanSchedule schedule, bool rd, int n) {
  Device* dp = device_or_skip(state);
  if (!dp) return;
  Engine threads(table1_scene(rd, n), engine_options(schedule, nullptr));
  Engine opencl(table1_scene(rd, n), engine_options(schedule, dp->ctx.get()));
  threads.step();  // warm-up of both
  opencl.step();
  opencl.finish();
  using Clock = std::chrono::steady_clock;
  double threads_s = 0, opencl_s = 0;
  for (auto _ : state) {
    const auto t0 = Clock::now();
    threads.step();
    const auto t1 = Clock::now();
    opencl.step();
    opencl.finish();
    const auto t2 = Clock::now();
    threads_s += std::chrono::duration<double>(t1 - t0).count();
    opencl_s += std::chrono::duration<double>(t2 - t1).count();
  }
  const double frames = double(state.iterations());
  state.counters["threads_ms"] = 1e3 * threads_s / frames;
  state.counters["opencl_ms"] = 1e3 * opencl_s / frames;
  state.counters["ratio"] = opencl_s / threads_s;
  // Both ran the same frames from the same state: the velocity's normwise relative max-norm
  // difference shows the OpenCL rows computed the same thing.
  const FieldF& u = opencl.state().u;
  const FieldF& ref_u = threads.state().u;
  double diff = 0, ref = 0;
  for (int y = 0; y < u.ny(); ++y)
    for (int x = 0; x < u.nx(); ++x) {
      diff = std::max(diff, std::abs(double(u(x, y)) - double(ref_u(x, y))));
      ref = std::max(ref, std::abs(double(ref_u(x, y))));
    }
  state.counters["u_rel_diff"] = diff / std::max(ref, 1e-30);
  state.SetLabel(dp->ctx->device().device_name);
}
#else
void run_table1(benchmark::State& state, PlanSchedule, bool, int) {
  state.SkipWithError("no OpenCL: this build has none");
}
void run_ratio(benchmark::State& state, PlanSchedule, bool, int) {
  state.SkipWithError("no OpenCL: this build has none");
}
#endif

// Names exactly as bench/table1_bench.cpp's: Table1/<schedule>/<fluid|ard>/<N>, the schedule
// being opencl-stream or opencl-blocked, so `ardcell bench table1` can merge the rows.
void register_all() {
  for (const auto& entry :
       {std::pair{"stream", PlanSchedule::kStream}, std::pair{"blocked", PlanSchedule::kBlocked}})
    for (bool rd : {false, true})
      for (int n : bench_sizes_from_env({256, 512, 1024})) {
        // A plain variable: lambdas may not capture structured bindings before clang 16.
        const PlanSchedule schedule = entry.second;
        const std::string suffix =
            std::string(entry.first) + (rd ? "/ard/" : "/fluid/") + std::to_string(n);
        benchmark::RegisterBenchmark(
            ("Table1/opencl-" + suffix).c_str(),
            [schedule, rd, n](benchmark::State& s) { run_table1(s, schedule, rd, n); })
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime();
        benchmark::RegisterBenchmark(
            ("Table1Ratio/opencl-" + suffix).c_str(),
            [schedule, rd, n](benchmark::State& s) { run_ratio(s, schedule, rd, n); })
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime();
      }
}

}  // namespace
}  // namespace ardcell

int main(int argc, char** argv) {
  ardcell::register_all();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
