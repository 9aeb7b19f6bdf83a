// Table 1 of seed 000 (section 7.2): frames per second of the fluid alone and of the fluid with
// Gray-Scott RD, per grid size and schedule: Table1/<serial|stream|blocked>/<fluid|ard>/<N>, the
// built-in scenes table1 and table1-ard on the Engine, as `ardcell run` runs them (serial: the
// serial back end; stream, blocked: threads, workers pinned). One iteration is one whole frame.
// Counters: fps, cells_per_s, bytes_per_s (the sweep-by-sweep traffic of bench/README.md, per
// second). STREAM/triad measures the machine's sustainable bandwidth in the same run, with as many
// threads as the threads back end has workers.
//
// Environment: ARDCELL_BENCH_SIZES (e.g. "128,256") restricts the sizes; ARDCELL_BENCH_SERIAL_MAX
// (default 1024) is the largest size run on the slow serial schedule;
// ARDCELL_BENCH_STORE_KIB sets the local store per worker of the stream and blocked schedules
// (default: one L2 of this machine per double-buffer slot, runtime/local_store.h; 256 is the
// Cell SPE's);
// ARDCELL_BENCH_SWEEPS the blocked schedule's sweeps per residency (default 0: one load per
// solve). Counter store_kib reports the local store used.
#include <benchmark/benchmark.h>
#include <sys/resource.h>

#include <cstdlib>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "bench/bench_env.h"
#include "host/engine/engine.h"
#include "host/engine/table1_plan.h"
#include "host/scenes/scene_registry.h"
#include "runtime/backend.h"
#include "runtime/field.h"

namespace ardcell {
namespace {

// CPU seconds used by every thread of this process so far.
double process_cpu_seconds() {
  rusage r{};
  getrusage(RUSAGE_SELF, &r);
  return double(r.ru_utime.tv_sec + r.ru_stime.tv_sec) +
         1e-6 * double(r.ru_utime.tv_usec + r.ru_stime.tv_usec);
}

void run_table1(benchmark::State& state, PlanSchedule schedule, bool rd, int n) {
  SceneConfig scene = builtin_scenes().find(rd ? "table1-ard" : "table1")->make();
  scene.size = {n, n};
  EngineOptions o;
  o.backend = schedule == PlanSchedule::kSerial ? EngineOptions::Backend::kSerial
                                                : EngineOptions::Backend::kThreads;
  o.pin_workers = true;
  o.plan.schedule = schedule;
  o.plan.local_store_bytes = std::size_t(bench_env_int("ARDCELL_BENCH_STORE_KIB",
                                                       int(machine_local_store_bytes() / 1024))) *
                             1024;
  if (schedule == PlanSchedule::kBlocked)
    o.plan.sweeps_per_residency = bench_env_int("ARDCELL_BENCH_SWEEPS", 0);
  Engine engine(scene, o);
  Table1Plan& w = *engine.table1_plan();
  engine.step();  // warm: first touch of every field and store
  engine.plan().reset_stats();
  const double cpu0 = process_cpu_seconds();
  for (auto _ : state) engine.step();
  const double cpu = process_cpu_seconds() - cpu0;
  const double frames = double(state.iterations());
  // On a shared machine the wall clock counts time the workers spent descheduled; the CPU
  // seconds they consumed per frame give the rate the same cores reach when they are not
  // shared (an upper bound that assumes perfect overlap of the workers).
  state.counters["cpu_ms_per_frame"] = 1e3 * cpu / frames;
  state.counters["fps_if_unshared"] = frames * engine.workers() / std::max(cpu, 1e-9);
  state.counters["fps"] = benchmark::Counter(frames, benchmark::Counter::kIsRate);
  state.counters["cells_per_s"] =
      benchmark::Counter(frames * double(n) * n, benchmark::Counter::kIsRate);
  state.counters["bytes_per_s"] =
      benchmark::Counter(frames * w.bytes_per_frame(), benchmark::Counter::kIsRate);
  state.counters["workers"] = engine.workers();
  state.counters["store_kib"] = double(o.plan.local_store_bytes / 1024);
  if (std::getenv("ARDCELL_BENCH_STATS")) engine.plan().print_stats(stderr);
}

// STREAM triad a = b + s c over arrays far larger than the caches, split over `threads`.
void stream_triad(benchmark::State& state) {
  const int threads = int(std::max(1u, std::thread::hardware_concurrency()));
  const std::size_t n = std::size_t(1) << 24;  // 16 Mi floats = 64 MiB per array
  std::vector<float> a(n, 0.0f), b(n, 1.0f), c(n, 2.0f);
  const float s = 3.0f;
  for (auto _ : state) {
    std::vector<std::thread> pool;
    for (int t = 0; t < threads; ++t)
      pool.emplace_back([&, t] {
        const std::size_t lo = n * std::size_t(t) / std::size_t(threads);
        const std::size_t hi = n * std::size_t(t + 1) / std::size_t(threads);
        float* __restrict pa = a.data();
        const float* __restrict pb = b.data();
        const float* __restrict pc = c.data();
        for (std::size_t i = lo; i < hi; ++i) pa[i] = pb[i] + s * pc[i];
      });
    for (auto& th : pool) th.join();
    benchmark::DoNotOptimize(a.data());
    benchmark::ClobberMemory();
  }
  state.counters["bytes_per_s"] = benchmark::Counter(
      double(state.iterations()) * 3.0 * double(n) * sizeof(float), benchmark::Counter::kIsRate);
  state.counters["threads"] = threads;
}

void register_all() {
  benchmark::RegisterBenchmark("STREAM/triad", stream_triad)
      ->UseRealTime()
      ->Unit(benchmark::kMillisecond);
  const int serial_max = bench_env_int("ARDCELL_BENCH_SERIAL_MAX", 1024);
  for (PlanSchedule s : {PlanSchedule::kSerial, PlanSchedule::kStream, PlanSchedule::kBlocked})
    for (bool rd : {false, true})
      for (int n : bench_sizes_from_env({128, 256, 512, 1024, 2048})) {
        if (s == PlanSchedule::kSerial && n > serial_max) continue;
        const std::string name = "Table1/" + std::string(plan_schedule_name(s)) + "/" +
                                 (rd ? "ard" : "fluid") + "/" + std::to_string(n);
        benchmark::RegisterBenchmark(name.c_str(),
                                     [s, rd, n](benchmark::State& st) { run_table1(st, s, rd, n); })
            ->UseRealTime()
            ->Unit(benchmark::kMillisecond);
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
