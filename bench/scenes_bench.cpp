// Every embedded preset through the engine users run (host/engine/engine.h, the path of `ardcell
// run` and `ardcell live`), per back end and grid size:
//   Scenes/<preset>/<serial|threads|opencl>/<N>   one iteration = one frame (finished);
//                                                 counters fps, cells_per_s
//   SceneSpeedup/<preset>/<N>   serial, threads and (with a device) opencl runs of kSpeedupRun
//                               frames alternating in the same iteration; counters serial_ms,
//                               threads_ms, opencl_ms (a frame), speedup (serial / threads),
//                               opencl_speedup (serial / opencl)
// (ratios from one run, so a slow spell of the machine hits every back end alike). The presets
// run as they are: an op the device does not run (an FFT step) runs on the CPU for that op, as
// in `ardcell run`, and says so once on stderr.
//
// Environment: ARDCELL_BENCH_SIZES (default "256,512,1024") restricts the sizes;
// ARDCELL_BENCH_PRESETS (comma-separated names) restricts the presets; ARDCELL_CL_DEVICE=N picks
// the OpenCL device (as --cl-device N; default the first), ARDCELL_CL_DEVICE=none leaves it out;
// ARDCELL_BENCH_REALTIME=1 runs every preset on its real-time settings (use_realtime_solvers,
// as `--realtime-solvers`).
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <string_view>
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

OpenClContext* opencl() { return bench_opencl("scenes_bench"); }

EngineOptions options_for(EngineOptions::Backend backend) {
  EngineOptions o{backend, 0};
  if (backend == EngineOptions::Backend::kOpenCl) o.opencl = opencl();
  return o;
}

SceneConfig scene_at(const std::string& name, int n) {
  Preset preset;
  if (Status s = load_preset(name, preset); !s) {
    std::fprintf(stderr, "scenes_bench: %s\n", s.message().c_str());
    std::exit(2);
  }
  const char* realtime = std::getenv("ARDCELL_BENCH_REALTIME");
  if (realtime && std::string_view(realtime) == "1") use_realtime_solvers(preset);
  SceneConfig scene = preset.scene;
  // The preset's domain and cell size stay as printed; only the number of cells changes.
  scene.size = Int2{n, int(std::lround(double(n) * scene.size.y / scene.size.x))};
  return scene;
}

void run_scene(benchmark::State& state, const std::string& name, EngineOptions::Backend backend,
               int n) {
  const SceneConfig scene = scene_at(name, n);
  Engine engine(scene, options_for(backend));
  engine.step();  // warm: first touch of every field (and the device copies)
  engine.finish();
  for (auto _ : state) {
    engine.step();
    engine.finish();
  }
  const double frames = double(state.iterations());
  state.counters["fps"] = benchmark::Counter(frames, benchmark::Counter::kIsRate);
  state.counters["cells_per_s"] =
      benchmark::Counter(frames * double(scene.size.x) * scene.size.y, benchmark::Counter::kIsRate);
  state.counters["workers"] = engine.workers();
}

// SceneSpeedup's iteration: kSpeedupRun frames of each back end in turn. Back to back, as `ardcell
// run` steps them: a back end whose workers went to sleep while another stepped (a wake-up costs
// about 0.1 ms on a KVM guest) pays for it once a run, not once a frame.
constexpr int kSpeedupRun = 8;

void run_speedup(benchmark::State& state, const std::string& name, int n) {
  using Clock = std::chrono::steady_clock;
  const SceneConfig scene = scene_at(name, n);
  std::vector<std::unique_ptr<Engine>> engines;
  engines.push_back(std::make_unique<Engine>(scene, options_for(EngineOptions::Backend::kSerial)));
  engines.push_back(std::make_unique<Engine>(scene, options_for(EngineOptions::Backend::kThreads)));
  if (opencl())
    engines.push_back(
        std::make_unique<Engine>(scene, options_for(EngineOptions::Backend::kOpenCl)));
  for (auto& e : engines) {
    e->step();
    e->finish();
  }
  double seconds[3] = {0, 0, 0};
  std::size_t first = 0;  // the back end that goes first turns each iteration
  for (auto _ : state) {
    for (std::size_t k = 0; k < engines.size(); ++k) {
      const std::size_t i = (first + k) % engines.size();
      const auto t0 = Clock::now();
      for (int f = 0; f < kSpeedupRun; ++f) {
        engines[i]->step();
        engines[i]->finish();
      }
      seconds[i] += std::chrono::duration<double>(Clock::now() - t0).count();
    }
    first = (first + 1) % engines.size();
  }
  const double frames = double(state.iterations()) * kSpeedupRun;
  state.counters["serial_ms"] = 1e3 * seconds[0] / frames;
  state.counters["threads_ms"] = 1e3 * seconds[1] / frames;
  state.counters["speedup"] = seconds[0] / seconds[1];
  state.counters["workers"] = engines[1]->workers();
  if (engines.size() > 2) {
    state.counters["opencl_ms"] = 1e3 * seconds[2] / frames;
    state.counters["opencl_speedup"] = seconds[0] / seconds[2];
  }
}

}  // namespace
}  // namespace ardcell

int main(int argc, char** argv) {
  using namespace ardcell;
  const std::vector<int> sizes = bench_sizes_from_env({256, 512, 1024});
  for (const std::string& name : bench_presets())
    for (int n : sizes) {
      for (auto [label, backend] : {std::pair{"serial", EngineOptions::Backend::kSerial},
                                    std::pair{"threads", EngineOptions::Backend::kThreads},
                                    std::pair{"opencl", EngineOptions::Backend::kOpenCl}}) {
        if (backend == EngineOptions::Backend::kOpenCl && !opencl()) continue;
        benchmark::RegisterBenchmark(
            ("Scenes/" + name + "/" + label + "/" + std::to_string(n)).c_str(),
            [name, backend = backend, n](benchmark::State& s) { run_scene(s, name, backend, n); })
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime();
      }
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
