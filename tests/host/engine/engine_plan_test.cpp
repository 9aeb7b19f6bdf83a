// Every scene's frame is its Engine's FramePlan: the Table 1 scenes as tile passes, the others as
// the fluid's stages and then the RD's, in the paper's order; step() runs the plan once, and
// step_without_rd() leaves the RD's stages out.
#include <gtest/gtest.h>

#include <string>
#include <string_view>
#include <vector>

#include "host/engine/engine.h"
#include "host/scenes/scene_registry.h"

namespace ardcell {
namespace {

std::vector<std::string> step_names(const FramePlan& plan) {
  std::vector<std::string> names;
  for (int i = 0; i < plan.pass_count(); ++i) names.emplace_back(plan.pass_name(i));
  return names;
}

TEST(EnginePlan, EveryBuiltInSceneIsAPlanOfItsStagesOrPasses) {
  const std::vector<std::string> fluid = {"fluid: forces, sources", "fluid: viscosity",
                                          "fluid: projection",      "fluid: self-advection",
                                          "fluid: projection 2",    "fluid: dye"};
  for (const SceneEntry& e : builtin_scenes().entries()) {
    SceneConfig s = e.make();
    s.size = {40, 32};
    Engine engine(s, {EngineOptions::Backend::kThreads, 2});
    const FramePlan& plan = engine.plan();
    const std::vector<std::string> names = step_names(plan);
    ASSERT_GT(plan.pass_count(), 0) << e.name;
    if (s.fluid.kind == FluidSceneKind::kTable1) {
      for (int i = 0; i < plan.pass_count(); ++i) EXPECT_FALSE(plan.is_stage(i)) << e.name;
    } else {
      std::vector<std::string> expected;
      if (s.fluid.kind != FluidSceneKind::kNone) expected = fluid;
      if (s.rd.enabled) {
        expected.push_back("rd: reaction-diffusion");
        if (s.fluid.kind != FluidSceneKind::kNone) expected.push_back("rd: advection");
      }
      EXPECT_EQ(names, expected) << e.name;
      for (int i = 0; i < plan.pass_count(); ++i) EXPECT_TRUE(plan.is_stage(i)) << e.name;
    }
    engine.step();
    engine.step();
    EXPECT_EQ(plan.runs(), 2) << e.name;
    EXPECT_EQ(engine.state().step, 2) << e.name;
  }
}

TEST(EnginePlan, StepWithoutRdAdvancesTheFluidAndLeavesTheChemicals) {
  SceneConfig s = builtin_scenes().find("cavity-gray-scott")->make();
  s.size = {48, 48};
  Engine engine(s, {EngineOptions::Backend::kThreads, 2});
  for (int k = 0; k < 3; ++k) engine.step();
  const SimState before = engine.state();
  engine.step_without_rd();
  const SimState& after = engine.state();
  EXPECT_EQ(after.rd_time, before.rd_time);
  EXPECT_EQ(after.step, before.step + 1);
  bool fluid_moved = false;
  for (int y = 0; y < s.size.y; ++y)
    for (int x = 0; x < s.size.x; ++x) {
      ASSERT_EQ(after.A(x, y), before.A(x, y));
      ASSERT_EQ(after.B(x, y), before.B(x, y));
      fluid_moved = fluid_moved || after.u(x, y) != before.u(x, y);
    }
  EXPECT_TRUE(fluid_moved);
  engine.step();
  EXPECT_GT(engine.state().rd_time, before.rd_time);
}

}  // namespace
}  // namespace ardcell
