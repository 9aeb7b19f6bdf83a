// Engine::update_parameters: live parameter changes apply on the next frame, exactly as if the
// engine had been built with them, without a reset and without heap allocation; structural
// changes are refused. Global operator new is replaced here and counted (as frame_alloc_test).
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>

#include "host/engine/engine.h"
#include "host/scenes/scene_registry.h"

#include "tests/support/alloc_counter.h"

namespace ardcell {
namespace {

SceneConfig small(const char* name, Int2 size) {
  SceneConfig s = builtin_scenes().find(name)->make();
  s.size = size;
  return s;
}

double max_difference(const FieldF& a, const FieldF& b) {
  double d = 0;
  for (int y = 0; y < a.size().y; ++y)
    for (int x = 0; x < a.size().x; ++x) d = std::max(d, double(std::abs(a(x, y) - b(x, y))));
  return d;
}

TEST(EngineUpdate, FeedAndKillApplyNextFrameAsIfBuiltWithThem) {
  const SceneConfig base = small("pearson", {48, 48});
  SceneConfig changed = base;
  changed.rd.reaction.F = 0.03f;
  changed.rd.reaction.k = 0.055f;

  Engine updated(base), unchanged(base), rebuilt(changed);
  for (int i = 0; i < 5; ++i) {
    updated.step();
    unchanged.step();
  }
  // The rebuilt engine continues from the same state, with the new parameters from the start.
  rebuilt.state().A = updated.state().A;
  rebuilt.state().B = updated.state().B;
  rebuilt.state().time = updated.state().time;
  rebuilt.state().step = updated.state().step;

  const long before = g_allocations.load();
  const Status s = updated.update_parameters(changed);
  for (int i = 0; i < 10; ++i) updated.step();
  const long allocations = g_allocations.load() - before;
  ASSERT_TRUE(s.is_ok()) << s.message();
  EXPECT_EQ(allocations, 0);
  for (int i = 0; i < 10; ++i) {
    unchanged.step();
    rebuilt.step();
  }
  EXPECT_EQ(updated.state().step, 15);  // no reset
  EXPECT_EQ(updated.config().rd.reaction.F, 0.03f);
  EXPECT_EQ(max_difference(updated.state().B, rebuilt.state().B), 0.0);
  EXPECT_EQ(max_difference(updated.state().A, rebuilt.state().A), 0.0);
  EXPECT_GT(max_difference(updated.state().B, unchanged.state().B), 1e-4);
}

TEST(EngineUpdate, FluidAndRdParametersChangeWithoutAllocating) {
  const SceneConfig base = small("cavity-gray-scott", {32, 32});
  SceneConfig next = base;
  next.fluid.viscosity *= 3;
  next.fluid.lid_speed = 0.5;
  next.fluid.pressure_solver.max_iterations = 7;
  next.fluid.viscosity_solver.tolerance = 1e-4;
  next.rd.reaction.F = 0.05f;
  next.rd.diffusion_a = 0.8;
  next.rd.diffusion_solver.max_iterations = 12;
  next.rd.anisotropy.kind = AnisotropyKind::kWitkinKass;
  next.rd.anisotropy.theta0 = 0.5f;
  next.dt = base.dt * 0.5;

  Engine engine(base), reference(base);
  engine.step();
  reference.step();
  const long before = g_allocations.load();
  const Status s = engine.update_parameters(next);
  for (int i = 0; i < 4; ++i) engine.step();
  const long allocations = g_allocations.load() - before;
  ASSERT_TRUE(s.is_ok()) << s.message();
  EXPECT_EQ(allocations, 0);
  for (int i = 0; i < 4; ++i) reference.step();
  EXPECT_EQ(engine.config().fluid.lid_speed, 0.5);
  EXPECT_EQ(engine.state().dt, base.dt * 0.5);
  EXPECT_NEAR(engine.state().time, base.dt * 3, 1e-12);
  EXPECT_GT(max_difference(engine.state().u, reference.state().u), 1e-4);
  EXPECT_GT(max_difference(engine.state().B, reference.state().B), 1e-6);
}

TEST(EngineUpdate, StructuralChangesAreRefusedAndChangeNothing) {
  const SceneConfig base = small("cavity-gray-scott", {32, 32});
  Engine engine(base), reference(base);
  struct Case {
    void (*edit)(SceneConfig&);
    const char* key;
  };
  const Case cases[] = {
      {[](SceneConfig& s) {
         s.size = {64, 32};
       },
       "grid.size"},
      {[](SceneConfig& s) { s.fluid.kind = FluidSceneKind::kInk; }, "fluid.scene"},
      {[](SceneConfig& s) { s.rd.reaction.model = ReactionModel::kBarkley; }, "rd.reaction.model"},
      {[](SceneConfig& s) { s.rd.scheme = RdScheme::kExplicit5; }, "rd.scheme"},
      {[](SceneConfig& s) { s.rd.boundary = BoundaryKind::kPeriodic; }, "rd.boundary"},
      {[](SceneConfig& s) { s.fluid.pressure_solver.kind = SolverKind::kJacobi; },
       "fluid.pressure_solver.kind"},
  };
  for (const Case& c : cases) {
    SceneConfig next = base;
    next.rd.reaction.F = 0.01f;  // a valid change alongside: it must not be applied either
    c.edit(next);
    const Status s = engine.update_parameters(next);
    ASSERT_FALSE(s.is_ok()) << c.key;
    EXPECT_EQ(s.message(), std::string(c.key) +
                               ": changes the simulation's structure; rebuild the engine (switch "
                               "presets) to change it");
    EXPECT_EQ(engine.config().rd.reaction.F, base.rd.reaction.F);
  }
  SceneConfig bad = base;
  bad.rd.reaction.k = -0.1f;
  const Status s = engine.update_parameters(bad);
  ASSERT_FALSE(s.is_ok());
  EXPECT_EQ(s.message().find('\n'), std::string::npos);
  for (int i = 0; i < 3; ++i) {
    engine.step();
    reference.step();
  }
  EXPECT_EQ(max_difference(engine.state().B, reference.state().B), 0.0);
  EXPECT_EQ(max_difference(engine.state().u, reference.state().u), 0.0);
}

// The state keeps the RD's own time beside the scene's: rd.dt x rd.steps_per_frame per frame
// (seed 001 runs 20 unit steps a frame), and a live change of either counts from the next frame.
TEST(EngineUpdate, RdTimeCountsTheRdStepsOfEveryFrame) {
  SceneConfig config = small("pearson", {24, 24});
  config.dt = 0.5;
  config.rd.dt = 2.0;
  config.rd.steps_per_frame = 10;
  Engine engine(config);
  for (int i = 0; i < 3; ++i) engine.step();
  EXPECT_DOUBLE_EQ(engine.state().time, 1.5);
  EXPECT_DOUBLE_EQ(engine.state().rd_time, 60.0);
  config.rd.steps_per_frame = 4;
  ASSERT_TRUE(engine.update_parameters(config));
  engine.step();
  EXPECT_DOUBLE_EQ(engine.state().rd_time, 68.0);
  engine.reset();
  EXPECT_EQ(engine.state().rd_time, 0.0);
}

}  // namespace
}  // namespace ardcell
