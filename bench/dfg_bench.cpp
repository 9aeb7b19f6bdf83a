// The DFG benchmark "flow around a cylinder" (Schaefer & Turek 1996) on the presets users run
// (dfg-2d1, dfg-2d2: the engine, threads back end, cut-cell cylinder, MacCormack advection,
// multigrid solves), at three grids, beside the published ranges (tests/support/dfg_reference.h):
//   Dfg2D1/<cells across the channel>   Re 20 to t = 6 (steady): drag, lift, pressure_difference
//   Dfg2D2/<cells across the channel>   Re 100 to t = 10: drag_max, lift_max, strouhal,
//                                       pressure_difference (over t >= 5)
// The grid is 220/41 as wide as tall (41: h = 0.01, 20 cells across the cylinder at 82); dt is
// the preset's at 82 cells, scaled with h. One iteration = one whole run. Counters also give
// ms_per_frame (stepping and probing).
#include <benchmark/benchmark.h>

#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include "host/engine/engine.h"
#include "host/engine/fluid_probes.h"
#include "host/scenes/scene_registry.h"
#include "tests/support/dfg_reference.h"

namespace ardcell {
namespace {

struct Run {
  std::vector<FluidProbeSample> samples;
  double ms_per_frame = 0.0;
};

Run run(const char* preset, int cells_across, double end_time) {
  SceneConfig scene = builtin_scenes().find(preset)->make();
  const double scale = 82.0 / cells_across;
  scene.size = {cells_across * 220 / 41, cells_across};
  scene.dt *= scale;
  const int frames = int(end_time / scene.dt + 0.5);
  Engine engine(scene);
  ObstacleProbes probes(engine);
  Run r;
  r.samples.reserve(std::size_t(frames));
  const auto start = std::chrono::steady_clock::now();
  for (int f = 0; f < frames; ++f) {
    engine.step();
    r.samples.push_back(probes.sample(engine));
  }
  r.ms_per_frame = 1e3 *
                   std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() /
                   frames;
  return r;
}

void BM_Dfg2D1(benchmark::State& state) {
  Run r;
  for (auto _ : state) r = run("dfg-2d1", int(state.range(0)), 6.0);
  const FluidProbeSample& s = r.samples.back();
  state.counters["drag"] = s.drag_coefficient;
  state.counters["lift"] = s.lift_coefficient;
  state.counters["pressure_difference"] = s.pressure_difference;
  state.counters["ms_per_frame"] = r.ms_per_frame;
  state.SetLabel(
      "reference: drag 5.57-5.59, lift 0.0104-0.0110, pressure difference "
      "0.1172-0.1176");
}

void BM_Dfg2D2(benchmark::State& state) {
  Run r;
  for (auto _ : state) r = run("dfg-2d2", int(state.range(0)), 10.0);
  const ProbeSeriesSummary s = summarize_probe_series(r.samples, 5.0, 1.0, 0.1);
  state.counters["drag_max"] = s.drag_max;
  state.counters["lift_max"] = s.lift_max;
  state.counters["strouhal"] = s.strouhal;
  state.counters["pressure_difference"] = s.pressure_difference;
  state.counters["ms_per_frame"] = r.ms_per_frame;
  state.SetLabel(
      "reference: drag max 3.22-3.24, lift max 0.99-1.01, St 0.295-0.305, pressure "
      "difference 2.46-2.50");
}

BENCHMARK(BM_Dfg2D1)->Arg(41)->Arg(82)->Arg(164)->Iterations(1)->Unit(benchmark::kSecond);
BENCHMARK(BM_Dfg2D2)->Arg(41)->Arg(82)->Arg(164)->Iterations(1)->Unit(benchmark::kSecond);

}  // namespace
}  // namespace ardcell

BENCHMARK_MAIN();
