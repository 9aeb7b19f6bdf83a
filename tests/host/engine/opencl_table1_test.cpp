// The whole Table 1 workload on OpenCL (PoCL) against the serial back end over 100 frames, at an
// awkward non-square grid, in both OpenCL schedules. Norm: per field (u, v, dye, A, B), the
// normwise relative error in the max norm over interior + halo,
//   max |cl - serial| / max |serial|  <= 1e-5.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "host/engine/table1_opencl.h"
#include "runtime/opencl/backend_choice.h"

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

struct Device {
  std::unique_ptr<OpenClContext> ctx;
  std::unique_ptr<OpenClKernels> cl;
};

Device open_device() {
  Device d;
  std::string error;
  d.ctx = OpenClContext::open(0, &error);
  if (d.ctx) d.cl = OpenClKernels::create(*d.ctx, &error);
  EXPECT_TRUE(d.cl) << error;
  return d;
}

// The serial workload's fields after kFrames (computed once per process).
const Table1Workload& serial_reference() {
  static Table1Workload* w = [] {
    Table1Options o;
    o.grid = kGrid;
    o.rd = true;
    o.schedule = Table1Schedule::kSerial;
    auto* s = new Table1Workload(o);
    for (int i = 0; i < kFrames; ++i) s->step();
    return s;
  }();
  return *w;
}

void expect_agrees(OpenClStamFrame& frame, const Table1Workload& ref, const char* what) {
  FieldF got(kGrid, 1);
  const std::pair<ClField, const FieldF*> fields[] = {{ClField::kU, &ref.u()},
                                                      {ClField::kV, &ref.v()},
                                                      {ClField::kDye, &ref.dye()},
                                                      {ClField::kA, &ref.a()},
                                                      {ClField::kB, &ref.b()}};
  const char* names[] = {"u", "v", "dye", "A", "B"};
  int i = 0;
  for (const auto& [which, field] : fields) {
    frame.download(which, got);
    const double err = relative_error(got, *field);
    std::printf("%s %s: relative max-norm error %.3g\n", what, names[i], err);
    EXPECT_LE(err, kTolerance) << what << " " << names[i];
    ++i;
  }
}

void run_schedule(ClSchedule schedule, int per_residency, const char* what) {
  Device d = open_device();
  ASSERT_TRUE(d.cl);
  Table1Options o;
  o.grid = kGrid;
  o.rd = true;
  o.schedule = Table1Schedule::kSerial;
  const Table1Workload initial(o);
  OpenClStamFrame frame(*d.cl, table1_cl_params(kGrid, true), schedule, per_residency);
  table1_cl_upload(initial, frame);
  const int builds = d.ctx->build_count();
  for (int i = 0; i < kFrames; ++i) frame.step();
  frame.finish();
  EXPECT_EQ(frame.frame(), kFrames);
  EXPECT_EQ(d.ctx->build_count(), builds);
  // The fluid must actually move for the comparison to mean anything.
  const Table1Workload& ref = serial_reference();
  double speed = 0;
  for (int y = 0; y < kGrid.y; ++y)
    for (int x = 0; x < kGrid.x; ++x) speed = std::max(speed, double(std::abs(ref.u()(x, y))));
  ASSERT_GT(speed, 1e-3);
  expect_agrees(frame, ref, what);
}

TEST(OpenClTable1, StreamAgreesWithSerialOver100Frames) {
  run_schedule(ClSchedule::kStream, 1, "stream");
}

TEST(OpenClTable1, BlockedAgreesWithSerialOver100Frames) {
  run_schedule(ClSchedule::kBlocked, 20, "blocked-20");
}

TEST(OpenClTable1, BlockedWithSeveralResidenciesPerSolve) {
  run_schedule(ClSchedule::kBlocked, 7, "blocked-7");
}

// Parameters are kernel arguments: changing them between frames of a running loop changes the
// result and builds nothing.
TEST(OpenClTable1, SwitchingParametersUnderARunningLoopRebuildsNothing) {
  Device d = open_device();
  ASSERT_TRUE(d.cl);
  Table1Options o;
  o.grid = kGrid;
  o.rd = true;
  const Table1Workload initial(o);
  OpenClStamFrame steady(*d.cl, table1_cl_params(kGrid, true), ClSchedule::kStream);
  OpenClStamFrame switched(*d.cl, table1_cl_params(kGrid, true), ClSchedule::kStream);
  table1_cl_upload(initial, steady);
  table1_cl_upload(initial, switched);
  const int builds = d.ctx->build_count();
  for (int i = 0; i < 10; ++i) {
    steady.step();
    ClStamFrameParams& p = switched.params();
    // A preset switch and slider moves every frame: feed and kill rates, viscosity, RD speed.
    p.reaction.F = i % 2 ? 0.035f : 0.055f;
    p.reaction.k = i % 2 ? 0.065f : 0.062f;
    p.viscosity.a *= 1.5f;
    p.viscosity.inv_c = 1.0f / (1.0f + 4.0f * p.viscosity.a);
    p.rd_b = StamSweepParams{0.25f, 1.0f / (1.0f + 4.0f * 0.25f)};
    switched.step();
  }
  d.ctx->finish();
  EXPECT_EQ(d.ctx->build_count(), builds);
  FieldF a1(kGrid, 1), a2(kGrid, 1);
  steady.download(ClField::kB, a1);
  switched.download(ClField::kB, a2);
  EXPECT_GT(relative_error(a2, a1), 1e-3) << "the new parameters took effect";
}

// The fallback: an invalid device index gives one line and the workload runs on threads.
TEST(OpenClTable1, InvalidDeviceRunsOnThreads) {
  const BackendChoice c = choose_backend(BackendKind::kOpenCl, 42);
  ASSERT_EQ(c.kind, BackendKind::kThreads);
  EXPECT_NE(c.message.find("--cl-device 42"), std::string::npos) << c.message;
  Table1Options o;
  o.grid = kGrid;
  o.rd = true;
  o.schedule = Table1Schedule::kStream;
  o.workers = 2;
  Table1Workload threads(o);
  EXPECT_STREQ(threads.backend().name(), "threads");
  for (int i = 0; i < 3; ++i) threads.step();
  o.schedule = Table1Schedule::kSerial;
  Table1Workload serial(o);
  for (int i = 0; i < 3; ++i) serial.step();
  EXPECT_EQ(relative_error(threads.u(), serial.u()), 0.0);
}

}  // namespace
}  // namespace ardcell
