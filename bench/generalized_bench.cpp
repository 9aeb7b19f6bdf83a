// Seed 003's Table 3 through the engine users run (host/engine/engine.h, `ardcell run`): iterations
// per second of generalized reaction-diffusion (A and B, Turing reaction, periodic) on the
// threads back end and, with a device, OpenCL, beside the paper's GLSL figures on an 8800 GTX:
//   Generalized/<isotropic|gaussian|nongaussian>/<explicit|semi-implicit>/<threads|opencl>/<N>
// isotropic = Table 2 (a) (a 5-point stencil), gaussian = (b) (rank 2 only), nongaussian = (d)
// (rank 4: 25 points). One iteration is one RD step (Eqn 27 explicit, or Eqn 28 with its two FFT
// solves); a frame runs 10. Counters: it_per_s and the paper's table3_it_per_s at that size.
// ARDCELL_BENCH_SIZES restricts the sizes (default 256,512,1024); ARDCELL_CL_DEVICE=N|none picks
// or leaves out the OpenCL device (bench/bench_env.h). On OpenCL the semi-implicit step's FFT
// solves run on the CPU, as in `ardcell run`.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <string>
#include <utility>

#include "bench/bench_env.h"
#include "host/engine/engine.h"
#include "host/scenes/preset.h"

namespace ardcell {
namespace {

constexpr int kStepsPerFrame = 10;

struct Method {
  const char* name;
  const char* preset;
  double table3[3];  // it/s at 256, 512, 1024 (seed 003, Table 3)
};
constexpr Method kMethods[] = {{"isotropic", "mcgraw-turing-a", {6387, 6206, 1515}},
                               {"gaussian", "mcgraw-turing-b", {6245, 3740, 1210}},
                               {"nongaussian", "mcgraw-turing-d", {6204, 2031, 603}}};

double table3_at(const Method& m, int n) {
  return n == 256 ? m.table3[0] : n == 512 ? m.table3[1] : n == 1024 ? m.table3[2] : 0.0;
}

void run(benchmark::State& state, const Method& m, RdScheme scheme, EngineOptions options, int n) {
  Preset preset;
  if (Status s = load_builtin_preset(m.preset, preset); !s) {
    std::fprintf(stderr, "generalized_bench: %s\n", s.message().c_str());
    std::exit(2);
  }
  SceneConfig scene = preset.scene;
  scene.size = {n, n};
  scene.rd.scheme = scheme;
  scene.rd.steps_per_frame = kStepsPerFrame;
  Engine engine(scene, options);  // threads: every core
  engine.step();                  // the first frame sizes everything
  for (auto _ : state) {
    engine.step();
    engine.finish();
  }
  const double its = double(state.iterations()) * kStepsPerFrame;
  state.counters["it_per_s"] = benchmark::Counter(its, benchmark::Counter::kIsRate);
  const double paper = table3_at(m, n);
  state.counters["table3_it_per_s"] = paper;
  state.SetItemsProcessed(int64_t(its) * n * n);
}

const int kRegistered = [] {
  for (const Method& m : kMethods)
    for (const auto& entry : {std::pair{RdScheme::kExplicit, "explicit"},
                              std::pair{RdScheme::kSemiImplicit, "semi-implicit"}})
      for (const auto& backend : {std::pair{EngineOptions::Backend::kThreads, "threads"},
                                  std::pair{EngineOptions::Backend::kOpenCl, "opencl"}})
        for (int n : bench_sizes_from_env({256, 512, 1024})) {
          EngineOptions options{backend.first, 0};
          if (backend.first == EngineOptions::Backend::kOpenCl &&
              !(options.opencl = bench_opencl("generalized_bench")))
            continue;
          const RdScheme scheme = entry.first;
          const std::string name = std::string("Generalized/") + m.name + "/" + entry.second + "/" +
                                   backend.second + "/" + std::to_string(n);
          benchmark::RegisterBenchmark(
              name.c_str(),
              [&m, scheme, options, n](benchmark::State& s) { run(s, m, scheme, options, n); })
              ->Unit(benchmark::kMillisecond)
              ->UseRealTime();
        }
  return 0;
}();

}  // namespace
}  // namespace ardcell

BENCHMARK_MAIN();
