// What a mirrored video wall (host/live/live_wall.h) adds to a screen's frames: every
// LiveWall::kCheckFrames frames each screen fingerprints its whole state (state_fingerprint) and
// the screens compare the fingerprints (an all-gather of 8 bytes).
//   WallFingerprint/<preset>/<N>   one iteration = one fingerprint of the preset's state at N
//                                  cells wide (after 3 frames); counters cells (of all its
//                                  fields), per_frame_us (the check's cost spread over
//                                  kCheckFrames frames)
// The preset's own fields: cavity-gray-scott holds u, v, p, dye, A, B and theta0.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "host/engine/engine.h"
#include "host/live/live_wall.h"
#include "host/scenes/preset.h"

namespace ardcell {
namespace {

void fingerprint(benchmark::State& state, const std::string& name, int n) {
  Preset preset;
  if (Status s = load_preset(name, preset); !s) {
    std::fprintf(stderr, "live_wall_bench: %s\n", s.message().c_str());
    std::exit(2);
  }
  SceneConfig scene = preset.scene;
  scene.size = Int2{n, int(std::lround(double(n) * scene.size.y / scene.size.x))};
  Engine engine(scene, EngineOptions{EngineOptions::Backend::kThreads, 0});
  for (int f = 0; f < 3; ++f) engine.step();
  const SimState& s = std::as_const(engine).state();
  long long cells = 0;
  s.for_each_field([&](std::string_view, const FieldF& f) { cells += f.size().x * f.size().y; });
  const auto t0 = std::chrono::steady_clock::now();
  for (auto _ : state) benchmark::DoNotOptimize(state_fingerprint(s));
  const double us =
      std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count();
  state.counters["cells"] = double(cells);
  state.counters["per_frame_us"] =
      us / double(std::max<benchmark::IterationCount>(state.iterations(), 1)) /
      LiveWall::kCheckFrames;
}

const bool registered = [] {
  for (int n : {256, 512, 1024})
    benchmark::RegisterBenchmark(
        ("WallFingerprint/cavity-gray-scott/" + std::to_string(n)).c_str(),
        [n](benchmark::State& s) { fingerprint(s, "cavity-gray-scott", n); })
        ->Unit(benchmark::kMillisecond);
  return true;
}();

}  // namespace
}  // namespace ardcell

BENCHMARK_MAIN();
