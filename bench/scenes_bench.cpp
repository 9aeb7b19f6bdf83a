// Every embedded preset through the engine users run (host/engine/engine.h, the path of `ardcell
// run` and `ardcell live`), per back end and grid size:
//   Scenes/<preset>/<serial|threads>/<N>   one iteration = one frame; counters fps, cells_per_s
//   SceneSpeedup/<preset>/<N>             serial and threads frames alternating in the same
//                                          iteration; counters serial_ms, threads_ms, speedup
// (the ratio from one run, so a slow spell of the machine hits both back ends alike).
//
// Environment: ARDCELL_BENCH_SIZES (default "256,512,1024") restricts the sizes;
// ARDCELL_BENCH_PRESETS (comma-separated names) restricts the presets.
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "bench/bench_env.h"
#include "host/engine/engine.h"
#include "host/scenes/preset.h"

namespace ardcell {
namespace {

std::vector<std::string> bench_presets() {
  const char* s = std::getenv("ARDCELL_BENCH_PRESETS");
  return s ? split_commas(s) : preset_names();
}

SceneConfig scene_at(const std::string& name, int n) {
  Preset preset;
  if (Status s = load_preset(name, preset); !s) {
    std::fprintf(stderr, "scenes_bench: %s\n", s.message().c_str());
    std::exit(2);
  }
  SceneConfig scene = preset.scene;
  // The preset's domain and cell size stay as printed; only the number of cells changes.
  scene.size = Int2{n, int(std::lround(double(n) * scene.size.y / scene.size.x))};
  return scene;
}

void run_scene(benchmark::State& state, const std::string& name, EngineOptions::Backend backend,
               int n) {
  const SceneConfig scene = scene_at(name, n);
  Engine engine(scene, {backend, 0});
  engine.step();  // warm: first touch of every field
  for (auto _ : state) engine.step();
  const double frames = double(state.iterations());
  state.counters["fps"] = benchmark::Counter(frames, benchmark::Counter::kIsRate);
  state.counters["cells_per_s"] =
      benchmark::Counter(frames * double(scene.size.x) * scene.size.y, benchmark::Counter::kIsRate);
  state.counters["workers"] = engine.workers();
}

void run_speedup(benchmark::State& state, const std::string& name, int n) {
  using Clock = std::chrono::steady_clock;
  const SceneConfig scene = scene_at(name, n);
  Engine serial(scene, {EngineOptions::Backend::kSerial, 1});
  Engine threads(scene, {EngineOptions::Backend::kThreads, 0});
  serial.step();
  threads.step();
  double serial_s = 0, threads_s = 0;
  bool serial_first = true;
  for (auto _ : state) {
    for (int k = 0; k < 2; ++k) {
      const bool run_serial = (k == 0) == serial_first;
      const auto t0 = Clock::now();
      (run_serial ? serial : threads).step();
      const double s = std::chrono::duration<double>(Clock::now() - t0).count();
      (run_serial ? serial_s : threads_s) += s;
    }
    serial_first = !serial_first;
  }
  const double frames = double(state.iterations());
  state.counters["serial_ms"] = 1e3 * serial_s / frames;
  state.counters["threads_ms"] = 1e3 * threads_s / frames;
  state.counters["speedup"] = serial_s / threads_s;
  state.counters["workers"] = threads.workers();
}

}  // namespace
}  // namespace ardcell

int main(int argc, char** argv) {
  using namespace ardcell;
  const std::vector<int> sizes = bench_sizes_from_env({256, 512, 1024});
  for (const std::string& name : bench_presets())
    for (int n : sizes) {
      for (auto [label, backend] : {std::pair{"serial", EngineOptions::Backend::kSerial},
                                    std::pair{"threads", EngineOptions::Backend::kThreads}})
        benchmark::RegisterBenchmark(
            ("Scenes/" + name + "/" + label + "/" + std::to_string(n)).c_str(),
            [name, backend = backend, n](benchmark::State& s) { run_scene(s, name, backend, n); })
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime();
      benchmark::RegisterBenchmark(("SceneSpeedup/" + name + "/" + std::to_string(n)).c_str(),
                                   [name, n](benchmark::State& s) { run_speedup(s, name, n); })
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
    }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
