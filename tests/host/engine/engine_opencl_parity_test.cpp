// Every built-in preset on the OpenCL device (PoCL in CI) against the serial reference, through
// the one Engine: the same stages, each op the OpenCL twin of the CPU kernel
// (host/engine/opencl_device.h). At an awkward size (127 x 93), after kFrames frames, per field,
// the normwise relative error in the max norm over the interior,
//   max |cl - cpu| / max(max |cpu|, 1),
// must be <= 1e-5. kFrames is small because several presets amplify an ulp: theta = atan2(grad A)
// of the anisotropic ones and the Gray-Scott / Barkley fronts turn the device's atan2, cos and
// exp (not glibc's) into differences that grow frame after frame, as the CPU's own fields do
// under an ulp of perturbation (tests/host/engine/opencl_rd_engine_test.cpp measures that
// envelope).
// Also: after the first frame a frame moves no field between host and device, and fluid scenes
// with the real-time solvers run every op on the device (no fallback line).
#if defined(ARDCELL_WITH_OPENCL)
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "host/engine/engine.h"
#include "host/engine/opencl_device.h"
#include "host/scenes/preset.h"
#include "tests/support/opencl_test_device.h"
#include "tests/support/preset_params.h"

namespace ardcell {
namespace {

constexpr int kFrames = 3;
constexpr double kTolerance = 1e-5;

// The worst field's error (see the top of the file) and its name.
std::pair<double, std::string> worst_error(const SimState& cpu, const SimState& cl) {
  std::vector<std::pair<std::string_view, const FieldF*>> a, b;
  cpu.for_each_field([&](std::string_view n, const FieldF& f) { a.emplace_back(n, &f); });
  cl.for_each_field([&](std::string_view n, const FieldF& f) { b.emplace_back(n, &f); });
  EXPECT_EQ(a.size(), b.size());
  std::pair<double, std::string> worst{0.0, ""};
  for (std::size_t k = 0; k < std::min(a.size(), b.size()); ++k) {
    const FieldF &f = *a[k].second, &g = *b[k].second;
    double diff = 0.0, scale = 1.0;
    for (int y = 0; y < f.ny(); ++y)
      for (int x = 0; x < f.nx(); ++x) {
        const double d = std::abs(double(f(x, y)) - double(g(x, y)));
        diff = std::isnan(d) ? INFINITY : std::max(diff, d);
        scale = std::max(scale, std::abs(double(f(x, y))));
      }
    if (diff / scale > worst.first || worst.second.empty())
      worst = {diff / scale, std::string(a[k].first)};
  }
  return worst;
}

EngineOptions on_device() {
  EngineOptions o;
  o.backend = EngineOptions::Backend::kOpenCl;
  o.opencl = test_opencl_device()->ctx.get();
  return o;
}

class EngineOpenClParity : public testing::TestWithParam<std::string> {};

TEST_P(EngineOpenClParity, WithinOneInTenToTheFiveOfSerial) {
  if (!test_opencl_device()) GTEST_SKIP() << "no OpenCL device (no ICD or no platform)";
  const SceneConfig scene = awkward_preset_scene(GetParam());
  Engine serial(scene, {EngineOptions::Backend::kSerial, 1});
  Engine cl(scene, on_device());
  EXPECT_STREQ(cl.backend_name(), "opencl");
  for (int k = 0; k < kFrames; ++k) {
    serial.step();
    cl.step();
  }
  const auto [error, field] = worst_error(serial.state(), std::as_const(cl).state());
  EXPECT_LE(error, kTolerance) << GetParam() << ": field " << field;
}

INSTANTIATE_TEST_SUITE_P(EveryPreset, EngineOpenClParity, testing::ValuesIn(preset_names()),
                         preset_test_name);

TEST(EngineOpenCl, FramesStayOnTheDeviceAndNoOpFallsBack) {
  if (!test_opencl_device()) GTEST_SKIP() << "no OpenCL device (no ICD or no platform)";
  for (const char* name : {"cavity-gray-scott", "obstacle", "ink", "seed001"}) {
    SceneConfig scene = awkward_preset_scene(name);
    // The real-time solvers (the presets may choose ICCG or multigrid, which run on the CPU).
    scene.fluid.pressure_solver = {SolverKind::kJacobi, 20, 0.0};
    scene.fluid.viscosity_solver = {SolverKind::kRedBlackGaussSeidel, 10, 0.0};
    scene.rd.diffusion_solver = {SolverKind::kRedBlackGaussSeidel, 10, 0.0};
    testing::internal::CaptureStderr();
    Engine cl(scene, on_device());
    auto& device = static_cast<OpenClDevice&>(cl.device());
    cl.step();
    cl.finish();
    const std::int64_t up = device.uploaded_bytes(), down = device.downloaded_bytes();
    for (int k = 0; k < 3; ++k) cl.step();
    cl.finish();
    EXPECT_EQ(device.uploaded_bytes(), up) << name;
    EXPECT_EQ(device.downloaded_bytes(), down) << name;
    EXPECT_EQ(testing::internal::GetCapturedStderr(), "") << name;
    // Looking at the state downloads it; writing into it uploads it again.
    (void)std::as_const(cl).state();
    EXPECT_GT(device.downloaded_bytes(), down) << name;
  }
}

TEST(EngineOpenCl, PaintedStateReachesTheDevice) {
  if (!test_opencl_device()) GTEST_SKIP() << "no OpenCL device (no ICD or no platform)";
  const SceneConfig scene = awkward_preset_scene("cavity-gray-scott");
  Engine serial(scene, {EngineOptions::Backend::kSerial, 1});
  Engine cl(scene, on_device());
  serial.step();
  cl.step();
  // The same stroke of B on both (the non-const state() hands the host copy to the caller).
  for (Engine* e : {&serial, &cl})
    for (int y = 40; y < 50; ++y)
      for (int x = 60; x < 70; ++x) e->state().B(x, y) = 0.25f;
  serial.step();
  cl.step();
  const auto [error, field] = worst_error(serial.state(), std::as_const(cl).state());
  EXPECT_LE(error, kTolerance) << field;
}

}  // namespace
}  // namespace ardcell
#endif
