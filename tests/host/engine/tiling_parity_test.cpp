// Tiling parity: the stream and blocked schedules of a scene of tile passes (table1-ard on
// the Engine) run the same kernels on tiles copied into local stores; serial runs them on whole
// fields. Every field must agree bit for bit, on a grid
// no tile divides (127 x 93), with tiles touching every domain edge and corner, for any number
// of workers.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include <memory>

#include "host/engine/engine.h"
#include "host/engine/frame_plan.h"
#include "host/engine/table1_plan.h"
#include "host/scenes/scene_registry.h"
#include "kernels/stam_sweeps.h"
#include "runtime/thread/thread_backend.h"
#include "tests/support/field_compare.h"

namespace ardcell {
namespace {

std::unique_ptr<Engine> awkward(PlanSchedule s, int workers, int k = 0) {
  SceneConfig scene = builtin_scenes().find("table1-ard")->make();
  scene.size = {127, 93};
  EngineOptions o;
  o.backend = s == PlanSchedule::kSerial ? EngineOptions::Backend::kSerial
                                         : EngineOptions::Backend::kThreads;
  o.workers = workers;
  o.plan.schedule = s;
  o.plan.sweeps_per_residency = k;
  o.plan.local_store_bytes = 1024 * 1024;
  o.plan.max_tile_width = 32;  // many tiles: 32 wide, at most 24 tall, none dividing the grid
  o.plan.max_tile_height = 24;
  return std::make_unique<Engine>(scene, o);
}

void expect_same_state(Engine& a, Engine& b, const char* what) {
  const SimState &x = a.state(), &y = b.state();
  EXPECT_TRUE(same_cells(x.u, y.u)) << what << ": u";
  EXPECT_TRUE(same_cells(x.v, y.v)) << what << ": v";
  EXPECT_TRUE(same_cells(x.dye, y.dye)) << what << ": dye";
  EXPECT_TRUE(same_cells(x.A, y.A)) << what << ": A";
  EXPECT_TRUE(same_cells(x.B, y.B)) << what << ": B";
}

constexpr int kFrames = 6;

TEST(TilingParity, StreamAndBlockedEqualSerialBitwiseOnAnAwkwardGrid) {
  auto serial = awkward(PlanSchedule::kSerial, 1);
  for (int i = 0; i < kFrames; ++i) serial->step();
  // The run is not trivial: the fluid moved and the chemicals reacted.
  const SimState& ref = serial->state();
  EXPECT_NE(ref.u(31, 23), 0.0f);
  EXPECT_GT(ref.dye(31, 23), 0.0f);
  EXPECT_GT(ref.B(47, 35), 0.0f);
  for (PlanSchedule s : {PlanSchedule::kStream, PlanSchedule::kBlocked}) {
    auto w = awkward(s, 2);
    const FramePlan& plan = w->plan();
    for (int p = 0; p < plan.pass_count(); ++p)
      ASSERT_GT(plan.tiles(p).tiles().size(), 8u) << plan.pass_name(p);
    for (int i = 0; i < kFrames; ++i) w->step();
    expect_same_state(*w, *serial, std::string(plan_schedule_name(s)).c_str());
  }
}

TEST(TilingParity, BlockedWithSeveralResidenciesPerSolveEqualsSerial) {
  auto serial = awkward(PlanSchedule::kSerial, 1);
  for (int i = 0; i < 3; ++i) serial->step();
  for (int k : {1, 3, 7, 19}) {
    auto w = awkward(PlanSchedule::kBlocked, 2, k);
    for (int i = 0; i < 3; ++i) w->step();
    expect_same_state(*w, *serial, ("blocked k=" + std::to_string(k)).c_str());
  }
}

TEST(TilingParity, ResultsDoNotDependOnTheNumberOfWorkers) {
  for (PlanSchedule s : {PlanSchedule::kStream, PlanSchedule::kBlocked}) {
    auto one = awkward(s, 1);
    for (int i = 0; i < 3; ++i) one->step();
    for (int workers : {2, 4}) {
      auto w = awkward(s, workers);
      EXPECT_EQ(w->workers(), workers);
      for (int i = 0; i < 3; ++i) w->step();
      expect_same_state(*w, *one, "workers");
    }
  }
}

// Every boundary kind a tile can refill locally, under temporal blocking: Stam's copy and
// mirror (b = 0, 1, 2), a fixed value, and a moving lid. k sweeps in store == k global sweeps.
struct SweepCase {
  BoundaryFill fill;
  const char* name;
};

void jacobi(const void* params, View<const float> x, View<const float> rhs, View<float> out,
            Box2 region) {
  stam_jacobi_sweep(rhs, x, out, region, *static_cast<const StamSweepParams*>(params));
}

TEST(TilingParity, TemporalBlockingEqualsGlobalSweepsForEveryBoundaryKind) {
  const Int2 grid{127, 93};
  FieldF x(grid, 1), rhs(grid, 1);
  for (int y = -1; y <= grid.y; ++y)
    for (int i = -1; i <= grid.x; ++i) {
      x(i, y) = std::sin(0.1f * float(i)) * std::cos(0.07f * float(y));
      rhs(i, y) = 0.01f * float((i * 13 + y * 7) % 23);
    }
  const StamSweepParams params{0.9f, 1.0f / (1.0f + 4 * 0.9f)};
  const SweepCase cases[] = {{BoundaryFill::stam(0), "copy"},
                             {BoundaryFill::stam(1), "mirror x"},
                             {BoundaryFill::stam(2), "mirror y"},
                             {BoundaryFill::fixed(0.5f), "fixed"},
                             {BoundaryFill::no_slip(1.0f), "lid"}};
  ThreadBackend threads({2, 1024 * 1024, false});
  SerialBackend serial;
  for (const SweepCase& c : cases) {
    for (int k : {1, 2, 5, 20}) {
      auto solve = [&](Backend& be, FieldF& out) {
        FramePlanOptions o;
        o.grid = grid;
        o.workers = 2;
        o.local_store_bytes = 1024 * 1024;
        o.max_tile_width = 32;
        o.max_tile_height = 17;
        FramePlan plan(o);
        PassDesc d;
        d.name = "solve";
        d.buffers = {{&x, k % 2 == 0 ? &out : nullptr, k, false},
                     {nullptr, k % 2 == 1 ? &out : nullptr, k, false},
                     {&rhs, nullptr, k - 1, false}};
        PassOpDesc op;
        op.kind = PassOpDesc::Kind::kJacobi;
        op.sweep = jacobi;
        op.params = &params;
        op.a = 0;
        op.b = 1;
        op.rhs = 2;
        op.sweeps = k;
        op.fill = c.fill;
        d.ops.push_back(op);
        plan.add_pass(d);
        plan.run(be);
      };
      FieldF ref(grid, 1), tiled(grid, 1);
      solve(serial, ref);
      solve(threads, tiled);
      EXPECT_TRUE(same_cells(ref, tiled)) << c.name << " k=" << k;
    }
  }
}

}  // namespace
}  // namespace ardcell
