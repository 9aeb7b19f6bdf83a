// FramePlan::run(Device&): the plan's whole-field form on a Device, each op through its device
// twin, and an op without one on the CPU with one line. On the CPU device every field equals the
// serial back end's bit for bit; on OpenCL (PoCL) within 1e-5 relative.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include "host/engine/device.h"
#include "host/engine/frame_plan.h"
#include "runtime/backend.h"
#include "runtime/row_executor.h"
#include "tests/support/field_compare.h"
#if defined(ARDCELL_WITH_OPENCL)
#include "host/engine/opencl_device.h"
#include "tests/support/opencl_test_device.h"
#endif

namespace ardcell {
namespace {

const Int2 kGrid{37, 29};
const StamSweepParams kSweep{0.7f, 1.0f / (1.0f + 4 * 0.7f)};

void sweep_kernel(const void* params, View<const float> x, View<const float> rhs, View<float> out,
                  Box2 region) {
  stam_jacobi_sweep(rhs, x, out, region, *static_cast<const StamSweepParams*>(params));
}
void sweep_on_device(const void* params, Device& dev, const FieldF& rhs, FieldF& a, FieldF& b,
                     int sweeps, const BoundaryFill& fill) {
  dev.stam_jacobi_sweeps(rhs, a, b, sweeps, *static_cast<const StamSweepParams*>(params), fill);
}

// buffers[1] = buffers[0] (whole box), with its twin.
void copy_kernel(const void*, std::span<const View<float>> b, Box2) {
  copy_box<float>(b[0], b[1], b[1].box());
}
void copy_on_device(const void*, Device& dev, std::span<FieldF* const> f) {
  dev.copy(*f[0], *f[1]);
}

// buffers[1] *= a per-cell factor, in place: no twin.
void scale_kernel(const void*, std::span<const View<float>> b, Box2 region) {
  for (int y = region.min.y; y < region.max.y; ++y)
    for (int x = region.min.x; x < region.max.x; ++x)
      b[1](x, y) = b[1](x, y) * (1.0f + 0.01f * float((x * 7 + y * 3) % 17));
}

FieldF pattern(int seed) {
  FieldF f(kGrid, 1);
  for (int y = -1; y <= kGrid.y; ++y)
    for (int x = -1; x <= kGrid.x; ++x)
      f(x, y) = float(((x + 3) * 37 + (y + 5) * 91 + seed * 13) % 101) / 101.0f;
  return f;
}

// A two-pass plan: copy x -> y and scale y (no twin); then 6 sweeps from y with rhs into out.
struct Problem {
  FieldF x = pattern(1), rhs = pattern(2), y{kGrid, 1}, out{kGrid, 1};
  FramePlan plan{FramePlanOptions{kGrid, 1, std::size_t(1) << 20, 1, 0, 0}};
  Problem() {
    PassDesc a;
    a.name = "copy+scale";
    a.buffers = {{&x, nullptr, 0, false}, {nullptr, &y, 0, false}};
    PassOpDesc copy;
    copy.map = copy_kernel;
    copy.device = copy_on_device;
    copy.writes = {1, -1, -1, -1};
    PassOpDesc scale;
    scale.map = scale_kernel;
    scale.writes = {1, -1, -1, -1};
    scale.fill_buffers = {1, -1, -1, -1};
    scale.fills = {BoundaryFill::stam(0)};
    a.ops = {copy, scale};
    plan.add_pass(a);
    PassDesc s;
    s.name = "solve";
    s.buffers = {{&y, &out, 6, false}, {nullptr, nullptr, 6, false}, {&rhs, nullptr, 5, false}};
    PassOpDesc j;
    j.kind = PassOpDesc::Kind::kJacobi;
    j.params = &kSweep;
    j.sweep = sweep_kernel;
    j.device_sweeps = sweep_on_device;
    j.a = 0;
    j.b = 1;
    j.rhs = 2;
    j.sweeps = 6;
    j.fill = BoundaryFill::stam(1);
    s.ops = {j};
    plan.add_pass(s);
  }
};

TEST(FramePlanOnDevice, CpuDeviceEqualsTheSerialBackEndBitwise) {
  Problem ref, dev;
  SerialBackend serial;
  ref.plan.run(serial);
  testing::internal::CaptureStderr();
  dev.plan.run(CpuDevice::serial());
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_NE(err.find("frame plan pass 'copy+scale' op 1 runs on the CPU"), std::string::npos)
      << err;
  EXPECT_TRUE(same_cells(ref.y, dev.y));
  EXPECT_TRUE(same_cells(ref.out, dev.out));
  EXPECT_NE(ref.out(5, 5), ref.x(5, 5));  // the plan did something
}

#if defined(ARDCELL_WITH_OPENCL)
double relative_error(const FieldF& got, const FieldF& ref) {
  double diff = 0, mag = 0;
  for (int y = -1; y <= ref.ny(); ++y)
    for (int x = -1; x <= ref.nx(); ++x) {
      diff = std::max(diff, std::abs(double(got(x, y)) - double(ref(x, y))));
      mag = std::max(mag, std::abs(double(ref(x, y))));
    }
  return diff / std::max(mag, 1e-30);
}

TEST(FramePlanOnDevice, AnOpWithoutATwinRunsOnTheCpuAndSaysSo) {
  TestOpenClDevice* d = test_opencl_device();
  if (!d) GTEST_SKIP() << "no OpenCL device";
  OpenClDevice device(*d->ctx, RowExecutor::serial());
  Problem ref, dev;
  SerialBackend serial;
  testing::internal::CaptureStderr();
  for (int i = 0; i < 2; ++i) {  // the line comes once
    ref.plan.run(serial);
    dev.plan.run(device);
  }
  device.sync_to_host(dev.out);
  device.sync_to_host(dev.y);
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
  EXPECT_NE(err.find("ardcell: opencl: frame plan pass 'copy+scale' op 1 runs on the CPU"),
            std::string::npos)
      << err;
  EXPECT_LE(relative_error(dev.y, ref.y), 1e-6);
  EXPECT_LE(relative_error(dev.out, ref.out), 1e-5);
}
#endif

}  // namespace
}  // namespace ardcell
