// The lid-driven cavity against Ghia, Ghia & Shin (1982) at Re 1000: the accuracy of the fluid
// users run (the `cavity` scene on the engine, threads back end, its multigrid solves), with
// semi-Lagrangian and MacCormack advection (fluid.advection), at two time steps.
//   Ghia/<N>/<Re>/<advection: 0 semi-Lagrangian, 1 MacCormack>/<frames per 0.01>
//   one iteration = the run to t = 60 (the cavity at Re 1000 is close to steady by then)
// Counters: u_error, v_error (the largest |ours - Ghia| over Table I's u on x = 0.5 and Table
// II's v on y = 0.5), ms_per_frame. dt = 0.01 at 256^2 (the preset's), scaled with h elsewhere,
// divided by the last argument. Environment: ARDCELL_BENCH_SIZES (default "256").
#include <benchmark/benchmark.h>

#include <chrono>
#include <string>

#include "bench/bench_env.h"
#include "host/engine/engine.h"
#include "host/scenes/scene_registry.h"
#include "tests/support/ghia_reference.h"

namespace ardcell {
namespace {

void BM_Ghia(benchmark::State& state) {
  const int n = int(state.range(0)), re = int(state.range(1));
  const bool maccormack = state.range(2) != 0;
  const int substeps = int(state.range(3));
  SceneConfig scene = builtin_scenes().find("cavity")->make();
  scene.size = {n, n};
  scene.dt = 0.01 * 256.0 / n / substeps;
  set_reynolds_number(scene.fluid, re, scene.domain_width);
  scene.fluid.advection =
      maccormack ? AdvectionScheme::kMacCormack : AdvectionScheme::kSemiLagrangian;
  constexpr double kEndTime = 60.0;
  const int frames = int(kEndTime / scene.dt + 0.5);
  ghia::Errors errors;
  double seconds = 0.0;
  for (auto _ : state) {
    Engine engine(scene);
    const auto start = std::chrono::steady_clock::now();
    for (int f = 0; f < frames; ++f) engine.step();
    engine.finish();
    seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const SimState& s = engine.state();
    errors = ghia::max_errors(s.u, s.v, s.h, re);
  }
  state.counters["u_error"] = errors.u;
  state.counters["v_error"] = errors.v;
  state.counters["ms_per_frame"] = 1e3 * seconds / frames;
  state.SetLabel(std::string(maccormack ? "maccormack" : "semi-lagrangian") +
                 ", dt = " + std::to_string(scene.dt) + ", t = 60");
}

void ghia_args(benchmark::internal::Benchmark* b) {
  for (int n : bench_sizes_from_env({256}))
    for (int substeps : {1, 2})
      for (int scheme : {0, 1}) b->Args({n, 1000, scheme, substeps});
}

BENCHMARK(BM_Ghia)->Apply(ghia_args)->Iterations(1)->Unit(benchmark::kSecond);

}  // namespace
}  // namespace ardcell

BENCHMARK_MAIN();
