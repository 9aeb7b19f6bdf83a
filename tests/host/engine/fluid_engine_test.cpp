#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <new>
#include <vector>

#include "host/engine/engine.h"
#include "host/engine/fluid_step.h"
#include "host/scenes/scene_registry.h"

#include "tests/support/alloc_counter.h"

namespace ardcell {
namespace {

SceneConfig small(const char* name, Int2 size) {
  SceneConfig s = builtin_scenes().find(name)->make();
  s.size = size;
  return s;
}

bool all_finite(const SimState& s) {
  bool ok = true;
  s.for_each_field([&](std::string_view, const FieldF& f) {
    for (int j = 0; j < f.ny(); ++j)
      for (int i = 0; i < f.nx(); ++i) ok = ok && std::isfinite(f(i, j));
  });
  return ok;
}

bool same_fields(const SimState& a, const SimState& b) {
  for (const FieldF* f : {&a.u, &a.v, &a.p, &a.dye}) {
    const FieldF& g = f == &a.u ? b.u : f == &a.v ? b.v : f == &a.p ? b.p : b.dye;
    for (int j = 0; j < f->ny(); ++j)
      for (int i = 0; i < f->nx(); ++i)
        if ((*f)(i, j) != g(i, j)) return false;
  }
  return true;
}

TEST(FluidScenes, RegisteredWithTheirDefaults) {
  const SceneRegistry& r = builtin_scenes();
  for (const char* name : {"cavity", "obstacle", "ink"}) {
    const SceneEntry* e = r.find(name);
    ASSERT_NE(e, nullptr) << name;
    EXPECT_EQ(e->make().name, name);
    EXPECT_FALSE(e->description.empty());
  }
  const SceneConfig cavity = r.find("cavity")->make();
  EXPECT_EQ(cavity.size, (Int2{256, 256}));
  EXPECT_EQ(cavity.fluid.kind, FluidSceneKind::kCavity);
  EXPECT_NEAR(reynolds_number(cavity.fluid, cavity.domain_width), 1000.0, 1e-9);
  SceneConfig c = cavity;
  set_reynolds_number(c.fluid, 100.0, c.domain_width);
  EXPECT_NEAR(c.fluid.viscosity, 0.01, 1e-12);
  const SceneConfig obstacle = r.find("obstacle")->make();
  EXPECT_NEAR(reynolds_number(obstacle.fluid, obstacle.domain_width), 200.0, 1e-9);
}

TEST(FluidEngine, EveryScenePlaysFiniteAndResetRestarts) {
  for (const auto& [name, size] :
       {std::pair{"cavity", Int2{32, 32}}, std::pair{"obstacle", Int2{32, 64}},
        std::pair{"ink", Int2{32, 32}}}) {
    Engine engine(small(name, size));
    const SimState initial = engine.state();
    for (int k = 0; k < 30; ++k) engine.step();
    EXPECT_TRUE(all_finite(engine.state())) << name;
    EXPECT_EQ(engine.state().step, 30);
    EXPECT_NEAR(engine.state().time, 30 * engine.config().dt, 1e-9);
    EXPECT_FALSE(same_fields(engine.state(), initial)) << name << " did not move";
    engine.reset();
    EXPECT_EQ(engine.state().step, 0);
    EXPECT_TRUE(same_fields(engine.state(), initial)) << name;
  }
}

TEST(FluidEngine, InkBoxWithEveryWallKind) {
  for (FluidWalls walls : {FluidWalls::kFreeSlip, FluidWalls::kNoSlip, FluidWalls::kPeriodic}) {
    SceneConfig scene = small("ink", {32, 32});
    scene.fluid.walls = walls;
    Engine engine(scene);
    for (int k = 0; k < 30; ++k) engine.step();
    const SimState& s = engine.state();
    EXPECT_TRUE(all_finite(s)) << int(walls);
    if (walls == FluidWalls::kPeriodic) {
      // No walls: the ghost cells are the opposite side.
      for (int j = 0; j < 32; ++j) EXPECT_EQ(s.u(-1, j), s.u(31, j));
    } else {
      for (int j = 0; j < 32; ++j) EXPECT_EQ(s.u(-1, j), -s.u(0, j));  // no flow through walls
    }
  }
}

TEST(FluidEngine, DeterministicAcrossInstances) {
  Engine a(small("ink", {40, 40})), b(small("ink", {40, 40}));
  for (int k = 0; k < 20; ++k) {
    a.step();
    b.step();
  }
  EXPECT_TRUE(same_fields(a.state(), b.state()));
}

TEST(FluidEngine, NoHeapAllocationAfterTheFirstFrame) {
  // The counter sees allocations (control).
  const long before_probe = g_allocations.load();
  auto* probe = new std::vector<int>(100);
  const long probe_allocations = g_allocations.load() - before_probe;
  delete probe;
  ASSERT_GE(probe_allocations, 1);

  for (SolverKind kind : {SolverKind::kJacobi, SolverKind::kRedBlackGaussSeidel, SolverKind::kIccg,
                          SolverKind::kMultigrid}) {
    for (const char* name : {"cavity", "obstacle", "ink"}) {
      SceneConfig scene = small(name, {32, 48});
      set_fluid_solver(scene.fluid, kind, 10);
      scene.fluid.dye_diffusion = 1e-4;
      Engine engine(scene);
      engine.step();
      const long before = g_allocations.load();
      for (int k = 0; k < 5; ++k) engine.step();
      EXPECT_EQ(g_allocations.load() - before, 0) << name << " with " << solver_kind_name(kind);
    }
  }
}

TEST(FluidEngine, CavityLidDrivesTheFlow) {
  Engine engine(small("cavity", {32, 32}));
  for (int k = 0; k < 50; ++k) engine.step();
  const SimState& s = engine.state();
  double top = 0.0, bottom = 0.0;
  for (int i = 0; i < 32; ++i) {
    top += s.u(i, 31);
    bottom += s.u(i, 0);
  }
  EXPECT_GT(top / 32, 0.3);      // dragged along by the lid (speed 1)
  EXPECT_LT(bottom / 32, 0.05);  // the return flow runs the other way, slowly
}

TEST(FluidEngine, ObstacleChannelCarriesTheInflowOut) {
  Engine engine(small("obstacle", {32, 64}));
  for (int k = 0; k < 60; ++k) engine.step();
  const SimState& s = engine.state();
  // Mass balance: the outflow through the bottom matches the inflow (-1 per unit width).
  double outflow = 0.0;
  for (int i = 0; i < 32; ++i) outflow += s.v(i, 0);
  EXPECT_NEAR(outflow / 32, -1.0, 0.1);
  // The disc is solid: no flow through its centre cell.
  const int cx = int(0.5 / s.h), cy = int(1.5 / s.h);
  EXPECT_EQ(s.obstacle(cx, cy), 1);
  EXPECT_EQ(s.u(cx, cy), 0.0f);
  EXPECT_EQ(s.v(cx, cy), 0.0f);
}

TEST(FluidEngine, InkEmittersAddDyeAndMomentum) {
  Engine engine(small("ink", {48, 48}));
  for (int k = 0; k < 20; ++k) engine.step();
  const SimState& s = engine.state();
  double dye = 0.0, speed = 0.0;
  for (int j = 0; j < 48; ++j)
    for (int i = 0; i < 48; ++i) {
      dye += s.dye(i, j);
      speed = std::max(speed, double(std::hypot(s.u(i, j), s.v(i, j))));
    }
  EXPECT_GT(dye, 0.0);
  EXPECT_GT(speed, 0.01);
}

}  // namespace
}  // namespace ardcell
