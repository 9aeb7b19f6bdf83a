// The Table 1 scene (table1-ard) on the Engine's OpenCL back end (PoCL) against the serial back
// end over 100 frames, at an awkward non-square grid, in both OpenCL schedules. Norm: per field
// (u, v, dye, A, B), the normwise relative error in the max norm over interior + halo,
//   max |cl - serial| / max |serial|  <= 1e-5.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

#include "host/engine/engine.h"
#include "host/engine/table1_plan.h"
#include "host/scenes/scene_registry.h"
#include "runtime/opencl/backend_choice.h"
#include "tests/support/opencl_test_device.h"

namespace ardcell {
namespace {

constexpr double kTolerance = 1e-5;
constexpr int kFrames = 100;
const Int2 kGrid{61, 47};

double relative_error(const FieldF& got, const FieldF& ref) {
  double diff = 0, mag = 0;
  for (int y = -1; y < ref.ny() + 1; ++y)
    for (int x = -1; x < ref.nx() + 1; ++x) {
      diff = std::max(diff, std::abs(double(got(x, y)) - double(ref(x, y))));
      mag = std::max(mag, std::abs(double(ref(x, y))));
    }
  return diff / std::max(mag, 1e-30);
}

SceneConfig scene() {
  SceneConfig s = builtin_scenes().find("table1-ard")->make();
  s.size = kGrid;
  return s;
}

std::unique_ptr<Engine> engine(EngineOptions::Backend backend, PlanSchedule schedule, int k,
                               OpenClContext* ctx = nullptr) {
  EngineOptions o;
  o.backend = backend;
  o.workers = 2;
  o.opencl = ctx;
  o.plan.schedule = schedule;
  o.plan.sweeps_per_residency = k;
  return std::make_unique<Engine>(scene(), o);
}

// The serial engine's fields after kFrames (computed once per process).
const SimState& serial_reference() {
  static Engine* e = [] {
    Engine* s = engine(EngineOptions::Backend::kSerial, PlanSchedule::kSerial, 0).release();
    for (int i = 0; i < kFrames; ++i) s->step();
    return s;
  }();
  return e->state();
}

void run_schedule(PlanSchedule schedule, int per_residency, const char* what) {
  TestOpenClDevice* d = test_opencl_device();
  if (!d) GTEST_SKIP() << "no OpenCL device";
  auto cl = engine(EngineOptions::Backend::kOpenCl, schedule, per_residency, d->ctx.get());
  EXPECT_STREQ(cl->backend_name(), "opencl");
  const int builds = d->ctx->build_count();
  for (int i = 0; i < kFrames; ++i) cl->step();
  cl->finish();
  EXPECT_EQ(d->ctx->build_count(), builds);
  // The fluid must actually move for the comparison to mean anything.
  const SimState& ref = serial_reference();
  double speed = 0;
  for (int y = 0; y < kGrid.y; ++y)
    for (int x = 0; x < kGrid.x; ++x) speed = std::max(speed, double(std::abs(ref.u(x, y))));
  ASSERT_GT(speed, 1e-3);
  const SimState& got = cl->state();
  EXPECT_EQ(got.step, kFrames);
  const std::pair<const char*, const FieldF SimState::*> fields[] = {{"u", &SimState::u},
                                                                     {"v", &SimState::v},
                                                                     {"dye", &SimState::dye},
                                                                     {"A", &SimState::A},
                                                                     {"B", &SimState::B}};
  for (const auto& [name, field] : fields) {
    const double err = relative_error(got.*field, ref.*field);
    std::printf("%s %s: relative max-norm error %.3g\n", what, name, err);
    EXPECT_LE(err, kTolerance) << what << " " << name;
  }
}

TEST(OpenClTable1, StreamAgreesWithSerialOver100Frames) {
  run_schedule(PlanSchedule::kStream, 0, "stream");
}

TEST(OpenClTable1, BlockedAgreesWithSerialOver100Frames) {
  run_schedule(PlanSchedule::kBlocked, 0, "blocked-20");
}

TEST(OpenClTable1, BlockedWithSeveralResidenciesPerSolve) {
  run_schedule(PlanSchedule::kBlocked, 7, "blocked-7");
}

// What the host writes into the fields (a loaded state, painting) goes to the device before the
// next frame: a frame from the same fields gives the same result as on the CPU.
TEST(OpenClTable1, HostWritesReachTheDevice) {
  TestOpenClDevice* d = test_opencl_device();
  if (!d) GTEST_SKIP() << "no OpenCL device";
  auto cl = engine(EngineOptions::Backend::kOpenCl, PlanSchedule::kStream, 0, d->ctx.get());
  auto cpu = engine(EngineOptions::Backend::kSerial, PlanSchedule::kSerial, 0);
  for (Engine* e : {cl.get(), cpu.get()}) {
    SimState& s = e->state();
    for (int y = 10; y < 20; ++y)
      for (int x = 10; x < 30; ++x) {
        s.dye(x, y) = 1.0f;
        s.u(x, y) = 0.5f;
      }
    for (int i = 0; i < 5; ++i) e->step();
  }
  EXPECT_LE(relative_error(cl->state().dye, cpu->state().dye), kTolerance);
  EXPECT_LE(relative_error(cl->state().u, cpu->state().u), kTolerance);
  EXPECT_GT(cpu->state().dye(20, 15), 0.5f);
}

// The fallback: an invalid device index gives one line and the scene runs on threads.
TEST(OpenClTable1, InvalidDeviceRunsOnThreads) {
  const BackendChoice c = choose_backend(BackendKind::kOpenCl, 42);
  ASSERT_EQ(c.kind, BackendKind::kThreads);
  EXPECT_NE(c.message.find("--cl-device 42"), std::string::npos) << c.message;
  auto threads = engine(EngineOptions::Backend::kThreads, PlanSchedule::kStream, 0);
  EXPECT_STREQ(threads->backend_name(), "threads");
  for (int i = 0; i < 3; ++i) threads->step();
  auto serial = engine(EngineOptions::Backend::kSerial, PlanSchedule::kSerial, 0);
  for (int i = 0; i < 3; ++i) serial->step();
  EXPECT_EQ(relative_error(threads->state().u, serial->state().u), 0.0);
}

}  // namespace
}  // namespace ardcell
