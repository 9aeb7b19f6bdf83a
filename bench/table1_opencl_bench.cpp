// Table 1 (seed 000, section 7.2) on the OpenCL back end: Table1/opencl-stream/... and
// Table1/opencl-blocked/..., beside the CPU rows of bench/table1_bench.cpp, with the same
// naming: Table1/<backend>-<schedule>/<fluid|ard>/<N>. One iteration is one whole frame, enqueued
// and finished (as a frame must be before it is shown). Counters: fps, bytes_per_s (the
// sweep-by-sweep minimum traffic of host/engine/table1.h, so GPU figures compare with the device's
// bandwidth).
//
// Table1Ratio/opencl-<schedule>/<fluid|ard>/<N>: the threads back end (Table1Workload, same
// schedule) and the OpenCL frame ALTERNATELY, one frame each per iteration, in this one process,
// so both see the same machine load (the machine running the bench may be shared). Counters:
// threads_ms, opencl_ms (mean per frame), ratio = opencl_ms / threads_ms, and u_rel_diff (the
// two velocity fields' relative max-norm difference after the run).
//
// The device: ARDCELL_CL_DEVICE=N (as `--cl-device N`, see `ardcell devices`), else the first
// GPU, else the first device; ARDCELL_CL_TILING overrides its tiling. Without OpenCL the rows
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
#include "host/engine/table1_opencl.h"

namespace ardcell {
namespace {

struct Device {
  std::unique_ptr<OpenClContext> ctx;
  std::unique_ptr<OpenClKernels> cl;
  std::string error;
};

Device& device() {
  static Device d = [] {
    Device dev;
    const char* env = std::getenv("ARDCELL_CL_DEVICE");
    const int index = env ? std::atoi(env) : -1;
    dev.ctx = OpenClContext::open(index, &dev.error);
    if (dev.ctx) dev.cl = OpenClKernels::create(*dev.ctx, &dev.error);
    // Tuning: ARDCELL_CL_TILING="tile_w,tile_h,work_group,groups_per_unit" replaces the
    // device's default_tiling (e.g. "64,16,128,16", the GPU choice, to compare on a CPU).
    if (const char* t = std::getenv("ARDCELL_CL_TILING"); t && dev.cl) {
      ClTiling& tiling = dev.cl->tiling();
      if (std::sscanf(t, "%d,%d,%d,%d", &tiling.tile_w, &tiling.tile_h, &tiling.work_group,
                      &tiling.groups_per_unit) != 4 ||
          tiling.tile_w < 1 || tiling.tile_h < 1 || tiling.work_group < 1 ||
          tiling.groups_per_unit < 1) {
        std::fprintf(stderr,
                     "ARDCELL_CL_TILING: expected four positive integers "
                     "tile_w,tile_h,work_group,groups_per_unit, got '%s'\n",
                     t);
        std::exit(2);
      }
    }
    return dev;
  }();
  return d;
}

// The device, or null after marking the row skipped.
Device* device_or_skip(benchmark::State& state) {
  Device& d = device();
  if (d.cl) return &d;
  state.SkipWithError(("no OpenCL: " + d.error).c_str());
  return nullptr;
}

Table1Options table1_options(int n, bool rd, Table1Schedule schedule) {
  Table1Options o;
  o.n = n;
  o.rd = rd;
  o.schedule = schedule;
  return o;
}

void run_table1(benchmark::State& state, ClSchedule schedule, bool rd, int n) {
  Device* dp = device_or_skip(state);
  if (!dp) return;
  Device& d = *dp;
  const Table1Workload initial(
      table1_options(n, rd, Table1Schedule::kSerial));  // initial conditions only; never stepped
  OpenClStamFrame frame(*d.cl, table1_cl_params({n, n}, rd), schedule);
  table1_cl_upload(initial, frame);
  frame.step();  // warm-up: first launches compile the work-group functions on some drivers
  frame.finish();
  for (auto _ : state) {
    frame.step();
    frame.finish();
  }
  const double frames = double(state.iterations());
  state.counters["fps"] = benchmark::Counter(frames, benchmark::Counter::kIsRate);
  state.counters["bytes_per_s"] =
      benchmark::Counter(frames * initial.bytes_per_frame(), benchmark::Counter::kIsRate);
  state.SetLabel(d.ctx->device().device_name);
}

void run_ratio(benchmark::State& state, ClSchedule schedule, bool rd, int n) {
  Device* dp = device_or_skip(state);
  if (!dp) return;
  Device& d = *dp;
  Table1Workload threads(table1_options(
      n, rd, schedule == ClSchedule::kStream ? Table1Schedule::kStream : Table1Schedule::kBlocked));
  OpenClStamFrame frame(*d.cl, table1_cl_params({n, n}, rd), schedule);
  table1_cl_upload(threads, frame);
  threads.step();  // warm-up of both
  frame.step();
  frame.finish();
  using Clock = std::chrono::steady_clock;
  double threads_s = 0, opencl_s = 0;
  for (auto _ : state) {
    const auto t0 = Clock::now();
    threads.step();
    const auto t1 = Clock::now();
    frame.step();
    frame.finish();
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
  FieldF u(threads.u().size(), threads.u().halo());
  frame.download(ClField::kU, u);
  double diff = 0, ref = 0;
  for (int y = 0; y < u.ny(); ++y)
    for (int x = 0; x < u.nx(); ++x) {
      diff = std::max(diff, std::abs(double(u(x, y)) - double(threads.u()(x, y))));
      ref = std::max(ref, std::abs(double(threads.u()(x, y))));
    }
  state.counters["u_rel_diff"] = diff / std::max(ref, 1e-30);
  state.SetLabel(d.ctx->device().device_name);
}

// Names exactly as bench/table1_bench.cpp's: Table1/<schedule>/<fluid|ard>/<N>, the schedule
// being opencl-stream or opencl-blocked, so `ardcell bench table1` can merge the rows.
void register_all() {
  for (const auto& entry :
       {std::pair{"stream", ClSchedule::kStream}, std::pair{"blocked", ClSchedule::kBlocked}})
    for (bool rd : {false, true})
      for (int n : bench_sizes_from_env({256, 512, 1024})) {
        // A plain variable: lambdas may not capture structured bindings before clang 16.
        const ClSchedule schedule = entry.second;
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
