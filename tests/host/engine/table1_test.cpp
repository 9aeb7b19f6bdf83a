// The Table 1 scenes (table1, table1-ard) on the Engine as a frame plan
// (host/engine/table1_plan.h): the schedules agree, the fields stay physical, bad settings are
// refused with one line.
#include "host/engine/table1_plan.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <memory>

#include "host/engine/engine.h"
#include "host/scenes/scene_registry.h"
#include "tests/support/field_compare.h"

namespace ardcell {
namespace {

SceneConfig table1_scene(bool rd, int n = 32) {
  SceneConfig scene = builtin_scenes().find(rd ? "table1-ard" : "table1")->make();
  scene.size = {n, n};
  return scene;
}

std::unique_ptr<Engine> small(PlanSchedule s, bool rd) {
  EngineOptions o;
  o.workers = 2;
  o.plan.schedule = s;
  return std::make_unique<Engine>(table1_scene(rd), o);
}

TEST(Table1, ScheduleNamesRoundTrip) {
  for (PlanSchedule s : {PlanSchedule::kSerial, PlanSchedule::kStream, PlanSchedule::kBlocked}) {
    PlanSchedule back{};
    ASSERT_TRUE(parse_plan_schedule(plan_schedule_name(s), back));
    EXPECT_EQ(back, s);
  }
  PlanSchedule s{};
  EXPECT_FALSE(parse_plan_schedule("fast", s));
}

// 100 frames of fluid + RD: every schedule gives the same fields bit for bit, and a second run
// of one schedule repeats itself exactly.
TEST(Table1, HundredFramesAgreeBitwiseAcrossSchedules) {
  auto serial = small(PlanSchedule::kSerial, true);
  auto stream = small(PlanSchedule::kStream, true);
  auto blocked = small(PlanSchedule::kBlocked, true);
  EXPECT_STREQ(serial->backend_name(), "serial");
  EXPECT_STREQ(blocked->backend_name(), "threads");
  for (int i = 0; i < 100; ++i) {
    serial->step();
    stream->step();
    blocked->step();
  }
  const SimState& ref = serial->state();
  EXPECT_EQ(ref.step, 100);
  for (Engine* w : {stream.get(), blocked.get()}) {
    const SimState& s = w->state();
    EXPECT_TRUE(same_cells(s.u, ref.u));
    EXPECT_TRUE(same_cells(s.v, ref.v));
    EXPECT_TRUE(same_cells(s.dye, ref.dye));
    EXPECT_TRUE(same_cells(s.A, ref.A));
    EXPECT_TRUE(same_cells(s.B, ref.B));
  }
  blocked->reset();
  for (int i = 0; i < 100; ++i) blocked->step();
  EXPECT_TRUE(same_cells(blocked->state().B, ref.B));
  EXPECT_TRUE(same_cells(blocked->state().u, ref.u));
}

// Any sweep count: an odd one puts each solve's result in the other buffer of its residency.
TEST(Table1, OddSweepCountsAgreeBitwiseAcrossSchedules) {
  SceneConfig scene = table1_scene(true, 40);
  for (SolverSettings* s :
       {&scene.fluid.viscosity_solver, &scene.fluid.pressure_solver, &scene.rd.diffusion_solver})
    s->max_iterations = 7;
  std::unique_ptr<Engine> engines[3];
  const PlanSchedule schedules[] = {PlanSchedule::kSerial, PlanSchedule::kStream,
                                    PlanSchedule::kBlocked};
  for (int i = 0; i < 3; ++i) {
    EngineOptions o;
    o.workers = 2;
    o.plan.schedule = schedules[i];
    engines[i] = std::make_unique<Engine>(scene, o);
    for (int f = 0; f < 20; ++f) engines[i]->step();
  }
  const SimState& ref = engines[0]->state();
  EXPECT_GT(ref.B(20, 20) + ref.B(15, 15), 0.0f);
  for (int i = 1; i < 3; ++i) {
    const SimState& s = engines[i]->state();
    EXPECT_TRUE(same_cells(s.u, ref.u)) << plan_schedule_name(schedules[i]);
    EXPECT_TRUE(same_cells(s.dye, ref.dye)) << plan_schedule_name(schedules[i]);
    EXPECT_TRUE(same_cells(s.A, ref.A)) << plan_schedule_name(schedules[i]);
    EXPECT_TRUE(same_cells(s.B, ref.B)) << plan_schedule_name(schedules[i]);
  }
}

// Physical sanity of the workload itself: finite, dye injected and bounded, concentrations in
// [0, 1], the projected velocity nearly divergence-free, walls respected (Stam's set_bnd).
TEST(Table1, FieldsStayPhysical) {
  auto engine = small(PlanSchedule::kBlocked, true);
  for (int i = 0; i < 60; ++i) engine->step();
  const SimState& w = engine->state();
  const int n = w.size.x;
  double dye = 0, div2 = 0, vel2 = 0;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      ASSERT_TRUE(std::isfinite(w.u(x, y)) && std::isfinite(w.v(x, y)));
      ASSERT_GE(w.A(x, y), 0.0f);
      ASSERT_LE(w.A(x, y), 1.0f);
      ASSERT_GE(w.B(x, y), 0.0f);
      ASSERT_LE(w.B(x, y), 1.0f);
      dye += w.dye(x, y);
      vel2 += double(w.u(x, y)) * w.u(x, y) + double(w.v(x, y)) * w.v(x, y);
      if (x > 0 && y > 0 && x < n - 1 && y < n - 1) {
        const double d = 0.5 * (w.u(x + 1, y) - w.u(x - 1, y) + w.v(x, y + 1) - w.v(x, y - 1));
        div2 += d * d;
      }
    }
  EXPECT_GT(dye, 0.0);
  EXPECT_GT(vel2, 0.0);
  // 20 Jacobi sweeps leave some divergence, but far below the velocity's own gradients.
  EXPECT_LT(div2, 0.1 * vel2);
  for (int y = 0; y < n; ++y) {
    EXPECT_EQ(w.u(-1, y), -w.u(0, y));  // Stam b = 1: u mirrored at the side walls
    EXPECT_EQ(w.v(y, -1), -w.v(y, 0));  // b = 2: v mirrored at bottom and top
    EXPECT_EQ(w.dye(-1, y), w.dye(0, y));
  }
}

TEST(Table1, FluidAloneAllocatesNoRdFieldsAndCountsBytes) {
  auto fluid = small(PlanSchedule::kBlocked, false);
  EXPECT_TRUE(fluid->state().A.empty());
  EXPECT_DOUBLE_EQ(fluid->table1_plan()->bytes_per_frame(),
                   32.0 * 32 * Table1Constants::kFluidBytesPerCell);
  auto ard = small(PlanSchedule::kBlocked, true);
  EXPECT_DOUBLE_EQ(
      ard->table1_plan()->bytes_per_frame(),
      32.0 * 32 * (Table1Constants::kFluidBytesPerCell + Table1Constants::kRdBytesPerCell));
  fluid->step();
  EXPECT_GT(fluid->state().dye(10, 10), 0.0f);
}

// The scene's parameters reach the plan: a higher viscosity damps the velocity, more sweeps
// leave less divergence; settings the plan cannot run are refused with the key named.
TEST(Table1, ReadsTheScenesParametersAndRefusesWhatItCannotRun) {
  auto speed2 = [](const SceneConfig& scene) {
    Engine e(scene, EngineOptions{EngineOptions::Backend::kSerial, 1});
    for (int i = 0; i < 20; ++i) e.step();
    double sum = 0;
    const SimState& s = e.state();
    for (int y = 0; y < s.size.y; ++y)
      for (int x = 0; x < s.size.x; ++x) sum += double(s.u(x, y)) * s.u(x, y);
    return sum;
  };
  SceneConfig viscous = table1_scene(false);
  viscous.fluid.viscosity = 1e-2;
  EXPECT_LT(speed2(viscous), 0.9 * speed2(table1_scene(false)));

  SceneConfig bad = table1_scene(true);
  bad.fluid.pressure_solver.kind = SolverKind::kMultigrid;
  EXPECT_NE(table1_config_problem(bad).find("fluid.pressure_solver"), std::string::npos);
  EXPECT_THROW(Engine(bad, EngineOptions{}), std::invalid_argument);
  bad = table1_scene(true);
  bad.rd.reaction.model = ReactionModel::kFitzHughNagumo;
  EXPECT_NE(table1_config_problem(bad).find("rd.reaction.model"), std::string::npos);
  bad = table1_scene(true);
  bad.rd.diffusion_solver.max_iterations = 10;
  EXPECT_NE(table1_config_problem(bad).find("rd.diffusion_solver.iterations"), std::string::npos);
  EXPECT_EQ(table1_config_problem(table1_scene(true)), "");

  // Live changes of what the plan holds are refused, with no change.
  Engine e(table1_scene(true), EngineOptions{});
  SceneConfig next = table1_scene(true);
  next.fluid.viscosity = 2e-4;
  const Status st = e.update_parameters(next);
  EXPECT_FALSE(st);
  EXPECT_NE(st.message().find("fluid.scene table1"), std::string::npos);
}

}  // namespace
}  // namespace ardcell
