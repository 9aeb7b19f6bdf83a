// The DFG benchmark "flow around a cylinder" (Schaefer & Turek 1996) through the engine: the
// dfg-2d1 and dfg-2d2 presets, measured by the obstacle probes (host/engine/fluid_probes.h) as
// `ardcell run --probe-csv` measures them, against the published ranges
// (tests/support/dfg_reference.h). Small grids, so the tolerances are the coarse grids'; the
// convergence towards the references at finer grids is bench/dfg_bench.cpp's
// (bench/RESULTS_KERNELS.md).
#include <gtest/gtest.h>

#include <cstdio>
#include <vector>

#include "host/engine/engine.h"
#include "host/engine/fluid_probes.h"
#include "host/scenes/scene_registry.h"
#include "tests/support/dfg_reference.h"

namespace ardcell {
namespace {

std::vector<FluidProbeSample> run(const SceneConfig& scene, int frames) {
  Engine engine(scene);
  ObstacleProbes probes(engine);
  std::vector<FluidProbeSample> out;
  for (int i = 0; i < frames; ++i) {
    engine.step();
    out.push_back(probes.sample(engine));
  }
  return out;
}

SceneConfig preset(const char* name, Int2 size, double dt) {
  SceneConfig s = builtin_scenes().find(name)->make();
  s.size = size;
  s.dt = dt;
  return s;
}

// Re 20, steady by t = 3: the drag comes closer to the reference on the finer grid, and both
// grids are within a few percent of every published figure.
TEST(Dfg, Steady2D1ApproachesTheReferenceAsTheGridIsRefined) {
  double previous_miss = 1.0;
  for (const Int2 size : {Int2{220, 41}, Int2{440, 82}}) {
    const auto s = run(preset("dfg-2d1", size, 0.01), 300);
    const FluidProbeSample& last = s.back();
    const double drag_miss = dfg::relative_miss(last.drag_coefficient, dfg::kDrag2D1);
    std::printf("2D-1 %dx%d: drag %.4f lift %.5f pressure difference %.4f\n", size.x, size.y,
                last.drag_coefficient, last.lift_coefficient, last.pressure_difference);
    EXPECT_LT(drag_miss, size.x == 220 ? 0.06 : 0.03) << size;
    EXPECT_LT(drag_miss, previous_miss) << size;
    previous_miss = drag_miss;
    EXPECT_LT(dfg::relative_miss(last.pressure_difference, dfg::kPressureDifference2D1), 0.05);
    EXPECT_LT(dfg::relative_miss(last.lift_coefficient, dfg::kLift2D1), 0.4);
    // Nearly steady: the last 50 frames change the drag by less than 0.2%.
    EXPECT_NEAR(s[s.size() - 50].drag_coefficient, last.drag_coefficient, 2e-3 * 5.6);
  }
}

// Re 100: the cylinder sheds vortices; on 220 x 41 (10 cells across the cylinder) the Strouhal
// number, the lift's amplitude and the pressure difference are already near the reference.
TEST(Dfg, Periodic2D2ShedsAtTheReferenceFrequency) {
  const SceneConfig scene = preset("dfg-2d2", {220, 41}, 0.005);
  const auto s = run(scene, 1200);
  const ProbeSeriesSummary r =
      summarize_probe_series(s, 3.0, scene.fluid.inflow_speed, 2.0 * scene.fluid.obstacle_radius);
  std::printf(
      "2D-2 220x41: drag max %.4f lift max %.4f St %.4f pressure difference %.4f (%d "
      "periods)\n",
      r.drag_max, r.lift_max, r.strouhal, r.pressure_difference, r.periods);
  EXPECT_GE(r.periods, 5);
  EXPECT_LT(dfg::relative_miss(r.strouhal, dfg::kStrouhal2D2), 0.15);
  EXPECT_LT(dfg::relative_miss(r.drag_max, dfg::kDragMax2D2), 0.25);
  EXPECT_LT(dfg::relative_miss(r.lift_max, dfg::kLiftMax2D2), 0.15);
  EXPECT_LT(dfg::relative_miss(r.pressure_difference, dfg::kPressureDifference2D2), 0.08);
}

}  // namespace
}  // namespace ardcell
