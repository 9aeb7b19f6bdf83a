// Every built-in preset on the OpenCL device (PoCL in CI) against the serial reference, through
// the one Engine: the same stages, each op the OpenCL twin of the CPU kernel
// (host/engine/opencl_device.h). At an awkward size (127 x 93), after kFrames frames, per field,
// the normwise relative error in the max norm over the interior,
//   max |cl - cpu| / max(max |cpu|, 1),
// must be <= 1e-5. kFrames is small because several presets amplify an ulp: theta = atan2(grad A)
// of the anisotropic ones and the Gray-Scott / Barkley fronts turn the device's atan2, cos and
// exp (not glibc's) into differences that grow frame after frame, as the CPU's own fields do
// under an ulp of perturbation. So:
//   - isotropic reaction-diffusion (Newton or table reaction, every boundary kind, Jacobi /
//     RBGS, Crank-Nicolson) stays within 1e-5 for 100 frames;
//   - the anisotropic space cookies stay within 1e-5 for 2 frames, and within 4x the CPU's own
//     drift under an ulp of perturbation (an ulp moved in 40% of the initial cells) for 60;
//   - the FFT presets (mcgraw-* but the two tensor fields, pearson) run their FFT steps on the
//     CPU at 127 x 93 (127 and 31 are prime factors the device FFT lacks) and on the device at
//     64 x 48, within 1e-5 after a frame (the Turing textures after 3 within 4x the CPU's own
//     drift under an ulp);
//   - mcgraw-turing-radial's BiCGSTAB solve runs on the device (no line), within 1e-5.
// Also: after the first frame a frame moves no field between host and device, and fluid scenes
// with the real-time solvers, or with the presets' multigrid solvers, and the presets' ICCG
// diffusion run every op on the device (no fallback line).
#if defined(ARDCELL_WITH_OPENCL)
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "host/engine/engine.h"
#include "host/engine/opencl_device.h"
#include "host/engine/rd_step.h"
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

// PoCL rounds doubles and the basic operations as the CPU does: the twins that repeat a C++
// solver operation for operation give its bits there.
bool is_pocl_device(OpenClDevice& device) {
  return device.kernels().context().device().platform_name.find("Portable Computing Language") !=
         std::string::npos;
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

// The worst error over `frames` frames (checked every 10), each check <= 1e-5.
double long_parity(const SceneConfig& scene, int frames, const char* what) {
  Engine serial(scene, {EngineOptions::Backend::kSerial, 1});
  Engine cl(scene, on_device());
  double worst = 0;
  for (int f = 1; f <= frames; ++f) {
    serial.step();
    cl.step();
    if (f % 10 != 0 && f != frames) continue;
    // Read through the const state(): the non-const one restarts sbdf2's history.
    const auto [error, field] =
        worst_error(std::as_const(serial).state(), std::as_const(cl).state());
    EXPECT_LE(error, kTolerance) << what << ": " << field << ", frame " << f;
    EXPECT_EQ(std::as_const(cl).state().step, std::as_const(serial).state().step);
    worst = std::max(worst, error);
    if (error > kTolerance) break;
  }
  std::printf("%s: %d frames, max relative error %.3g\n", what, frames, worst);
  return worst;
}

// Seed 001: the device steps the 9-point twin one step at a time, the CPU the temporally
// blocked kernel (kernels/gray_scott9.h); both fuse the same multiply-adds (kernels/explicit_rd.h),
// so on PoCL the frames are the CPU's bits.
TEST(EngineOpenCl, Seed001IsTheCpusBitsOnPocl) {
  if (!test_opencl_device()) GTEST_SKIP() << "no OpenCL device (no ICD or no platform)";
  const SceneConfig scene = awkward_preset_scene("seed001");
  const double error = long_parity(scene, 20, "seed001 (the 9-point twin)");
  Engine probe(scene, on_device());
  if (is_pocl_device(static_cast<OpenClDevice&>(probe.device()))) {
    EXPECT_EQ(error, 0.0);
  }
}

// Seed 003's explicit step (Eqn 27), 10 steps a frame through Device::generalized_rd_steps
// (4 + 4 + 2; on the device and, at this size, the CPU one step at a time, the results swapped
// into place): 20 frames within 1e-5.
TEST(EngineOpenCl, ExplicitGeneralizedStepsStayWithinOneInTenToTheFive) {
  if (!test_opencl_device()) GTEST_SKIP() << "no OpenCL device (no ICD or no platform)";
  SceneConfig scene = awkward_preset_scene("mcgraw-turing-a");
  scene.rd.scheme = RdScheme::kExplicit;
  scene.rd.dt = 0.05;  // stable: the explicit update's spectral radius stays <= 1
  scene.rd.steps_per_frame = 10;
  EXPECT_LE(long_parity(scene, 20, "mcgraw-turing-a explicit"), kTolerance);
}

// A preset at a small awkward grid (long runs), its diffusion set to fixed sweeps.
SceneConfig fixed_sweeps(const char* preset, SolverKind solver, int sweeps) {
  SceneConfig s = awkward_preset_scene(preset);
  s.size = {53, 37};
  s.rd.diffusion_solver = {solver, sweeps, 0.0};
  return s;
}

TEST(EngineOpenCl, IsotropicReactionDiffusionStaysWithinOneInTenToTheFiveFor100Frames) {
  if (!test_opencl_device()) GTEST_SKIP() << "no OpenCL device (no ICD or no platform)";
  SceneConfig dirichlet = fixed_sweeps("space-cookie-4", SolverKind::kJacobi, 20);
  dirichlet.rd.anisotropy.kind = AnisotropyKind::kIsotropic;
  long_parity(dirichlet, 100, "space-cookie-4 isotropic, Dirichlet, jacobi");
  long_parity(fixed_sweeps("turing-spots", SolverKind::kRedBlackGaussSeidel, 8), 100,
              "turing-spots, periodic, rbgs");
  // Pearson with the paper's scheme (its own, ETDRK4: FftPresetsStayOnTheDevice... above).
  SceneConfig table = fixed_sweeps("pearson", SolverKind::kRedBlackGaussSeidel, 10);
  table.rd.scheme = RdScheme::kImplicit;
  table.rd.use_table = true;
  table.rd.boundary = BoundaryKind::kNeumann;
  long_parity(table, 100, "pearson, table, Neumann, rbgs");
  SceneConfig crank = fixed_sweeps("pearson", SolverKind::kJacobi, 10);
  crank.rd.scheme = RdScheme::kImplicit;
  crank.rd.crank_nicolson = true;
  long_parity(crank, 60, "pearson, Crank-Nicolson, jacobi");
  // The second-order schemes with device twins: SBDF2 and Crank-Nicolson-AM2.
  for (RdScheme scheme : {RdScheme::kSbdf2, RdScheme::kCrankNicolsonAm2}) {
    SceneConfig second = fixed_sweeps("pearson", SolverKind::kJacobi, 10);
    second.rd.scheme = scheme;
    second.rd.dt = 1.0;
    long_parity(second, 60,
                scheme == RdScheme::kSbdf2 ? "pearson, sbdf2, jacobi"
                                           : "pearson, crank-nicolson-am2, jacobi");
  }
}

TEST(EngineOpenCl, AnisotropicCookiesDriftNoMoreThanTheCpuUnderAnUlp) {
  if (!test_opencl_device()) GTEST_SKIP() << "no OpenCL device (no ICD or no platform)";
  for (const char* name : {"space-cookie-3", "space-cookie-4"}) {
    const SceneConfig s = fixed_sweeps(name, SolverKind::kJacobi, 20);
    Engine cpu(s, {EngineOptions::Backend::kSerial, 1}),
        nudged(s, {EngineOptions::Backend::kSerial, 1});
    Engine cl(s, on_device());
    for (int y = 0; y < s.size.y; ++y)
      for (int x = 0; x < s.size.x; ++x)
        if ((7 * x + 3 * y) % 5 < 2)
          nudged.state().A(x, y) =
              std::nextafter(nudged.state().A(x, y), (x + y) % 2 ? 2.0f : -1.0f);
    double self = 0, device = 0;
    for (int f = 1; f <= 60; ++f) {
      cpu.step();
      nudged.step();
      cl.step();
      self = std::max(self, worst_error(cpu.state(), nudged.state()).first);
      device = std::max(device, worst_error(cpu.state(), std::as_const(cl).state()).first);
      if (f <= 2) {
        EXPECT_LE(device, kTolerance) << name << " frame " << f;
      }
    }
    std::printf("%s: 60 frames, device drift %.3g, CPU ulp-perturbed drift %.3g\n", name, device,
                self);
    EXPECT_LE(device, 4.0 * self) << name;
  }
}

TEST(EngineOpenCl, FramesStayOnTheDeviceAndNoOpFallsBack) {
  if (!test_opencl_device()) GTEST_SKIP() << "no OpenCL device (no ICD or no platform)";
  for (const char* name : {"cavity-gray-scott", "obstacle", "ink", "seed001"}) {
    SceneConfig scene = awkward_preset_scene(name);
    // The real-time solvers (the presets' own ICCG diffusion: IccgDiffusionPresets... below).
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

// The presets whose RD steps by FFT (seed 003's semi-implicit solve, Eqn 28: the mcgraw-*
// textures; ETDRK4: pearson) at a size the device FFT transforms (factors 2 and 3; the awkward
// size above has 127 and 31, which it lacks, so there they run on the CPU): on the device by its
// own FFT kernels (kernels/cl/fft.cl), frame after frame without a transfer or a fallback line,
// within 1e-5 of serial (FFTW) after the first frame (10 steps) and, but for the Turing
// textures, after kFrames. The device's float transforms round differently from FFTW's (a few
// 1e-7 of max |x| a solve), and the Turing model amplifies that as it does an ulp: on the CPU,
// an ulp moved in 40% of A's cells grows to 1.1e-5 .. 5.3e-5 in 3 frames, the device FFT's
// rounding to 1.1e-5 .. 4.1e-5; so there the device may drift no more than 4x the CPU's own drift
// under that ulp.
TEST(EngineOpenCl, FftPresetsStayOnTheDeviceWithinOneInTenToTheFive) {
  if (!test_opencl_device()) GTEST_SKIP() << "no OpenCL device (no ICD or no platform)";
  int presets = 0;
  for (const std::string& name : preset_names()) {
    SceneConfig scene = awkward_preset_scene(name);
    const RdConfig& rd = scene.rd;
    const bool fft = rd.enabled && (rd.scheme == RdScheme::kEtdrk4 ||
                                    (rd.diffusion_operator == RdOperator::kGeneralized &&
                                     rd.generalized.field == TensorFieldKind::kUniform &&
                                     rd.diffuse && rd.scheme != RdScheme::kExplicit));
    if (!fft) continue;
    ++presets;
    scene.size = {64, 48};  // cl_fft_parity_test's size
    testing::internal::CaptureStderr();
    Engine serial(scene, {EngineOptions::Backend::kSerial, 1});
    Engine cl(scene, on_device());
    auto& device = static_cast<OpenClDevice&>(cl.device());
    serial.step();
    cl.step();
    cl.finish();
    const auto [first, first_field] = worst_error(serial.state(), std::as_const(cl).state());
    EXPECT_LE(first, kTolerance) << name << ": field " << first_field << ", frame 1";
    const std::int64_t up = device.uploaded_bytes(), down = device.downloaded_bytes();
    for (int k = 0; k < kFrames - 1; ++k) {
      serial.step();
      cl.step();
    }
    cl.finish();
    EXPECT_EQ(device.uploaded_bytes(), up) << name;
    EXPECT_EQ(device.downloaded_bytes(), down) << name;
    EXPECT_EQ(testing::internal::GetCapturedStderr(), "") << name;
    const auto [error, field] = worst_error(serial.state(), std::as_const(cl).state());
    std::printf("%s (FFT) 64x48: max relative error %.3g after 1 frame, %.3g after %d\n",
                name.c_str(), first, error, kFrames);
    if (rd.reaction.model != ReactionModel::kTuring) {
      EXPECT_LE(error, kTolerance) << name << ": field " << field;
      continue;
    }
    Engine nudged(scene, {EngineOptions::Backend::kSerial, 1});
    for (int y = 0; y < scene.size.y; ++y)
      for (int x = 0; x < scene.size.x; ++x)
        if ((7 * x + 3 * y) % 5 < 2)
          nudged.state().A(x, y) =
              std::nextafter(nudged.state().A(x, y), (x + y) % 2 ? 2.0f : -1.0f);
    for (int k = 0; k < kFrames; ++k) nudged.step();
    const double self = worst_error(serial.state(), nudged.state()).first;
    std::printf("%s: CPU ulp-perturbed drift %.3g\n", name.c_str(), self);
    EXPECT_LE(error, 4.0 * self) << name << ": field " << field;
  }
  EXPECT_EQ(presets, 14);  // the 13 mcgraw-* presets and pearson
}

// The tensor field's semi-implicit solve (BiCGSTAB, kernels/tensor_field_solve.h) runs on the
// device (kernels/cl/opencl_tensor_field_solve.h, on a device with doubles: the iterates have the
// CPU's bits on PoCL, tests/kernels/cl_tensor_field_solve_parity_test.cpp): no fallback line,
// after the first frame no field moves between host and device, and the frames (the explicit
// part, the reaction and the clamp in float on the device) stay within 1e-5 of serial.
TEST(EngineOpenCl, TensorFieldSolveRunsOnTheDeviceWithoutALine) {
  if (!test_opencl_device()) GTEST_SKIP() << "no OpenCL device (no ICD or no platform)";
  const SceneConfig scene = awkward_preset_scene("mcgraw-turing-radial");
  ASSERT_EQ(scene.rd.scheme, RdScheme::kSemiImplicit);
  ASSERT_NE(scene.rd.generalized.field, TensorFieldKind::kUniform);
  testing::internal::CaptureStderr();
  Engine serial(scene, {EngineOptions::Backend::kSerial, 1});
  Engine cl(scene, on_device());
  auto& device = static_cast<OpenClDevice&>(cl.device());
  if (!device.kernels().has_fp64()) {
    testing::internal::GetCapturedStderr();
    GTEST_SKIP() << "the device has no doubles: the solve stays on the CPU";
  }
  serial.step();
  cl.step();
  cl.finish();
  const double first = worst_error(serial.state(), std::as_const(cl).state()).first;
  const std::int64_t up = device.uploaded_bytes(), down = device.downloaded_bytes();
  for (int k = 0; k < kFrames - 1; ++k) {
    serial.step();
    cl.step();
  }
  cl.finish();
  EXPECT_EQ(device.uploaded_bytes(), up);
  EXPECT_EQ(device.downloaded_bytes(), down);
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
  const auto [error, field] = worst_error(serial.state(), std::as_const(cl).state());
  std::printf(
      "mcgraw-turing-radial (BiCGSTAB on the device) %dx%d: max relative error %.3g after 1 "
      "frame, %.3g after %d\n",
      scene.size.x, scene.size.y, first, error, kFrames);
  EXPECT_LE(first, kTolerance) << "field " << field << ", frame 1";
  EXPECT_LE(error, kTolerance) << "field " << field;
  if (is_pocl_device(device)) {
    EXPECT_EQ(error, 0.0) << "on PoCL every op of the frame gives the CPU's bits";
  }
}

// The fluid presets' own settings: multigrid V-cycles to a tolerance for viscosity and pressure
// (the reaction-diffusion is off in these three) run on the device, frame after frame without a
// transfer or a fallback line, within 1e-5 of serial.
TEST(EngineOpenCl, MultigridPresetsStayOnTheDeviceWithinOneInTenToTheFive) {
  if (!test_opencl_device()) GTEST_SKIP() << "no OpenCL device (no ICD or no platform)";
  for (const char* name : {"cavity", "ink", "obstacle"}) {
    const SceneConfig scene = awkward_preset_scene(name);
    ASSERT_EQ(scene.fluid.pressure_solver.kind, SolverKind::kMultigrid) << name;
    ASSERT_EQ(scene.fluid.viscosity_solver.kind, SolverKind::kMultigrid) << name;
    testing::internal::CaptureStderr();
    Engine serial(scene, {EngineOptions::Backend::kSerial, 1});
    Engine cl(scene, on_device());
    auto& device = static_cast<OpenClDevice&>(cl.device());
    serial.step();
    cl.step();
    cl.finish();
    const std::int64_t up = device.uploaded_bytes(), down = device.downloaded_bytes();
    for (int k = 0; k < 9; ++k) {
      serial.step();
      cl.step();
    }
    cl.finish();
    EXPECT_EQ(device.uploaded_bytes(), up) << name;
    EXPECT_EQ(device.downloaded_bytes(), down) << name;
    EXPECT_EQ(testing::internal::GetCapturedStderr(), "") << name;
    const auto [error, field] = worst_error(serial.state(), std::as_const(cl).state());
    std::printf("%s (multigrid): 10 frames, max relative error %.3g\n", name, error);
    EXPECT_LE(error, kTolerance) << name << ": field " << field;
  }
}

// The device's solves report what the CPU's do: the same sweep count and the relative residual
// of the same system. Six sweeps bring it near float rounding (~6e-8), where the two fields'
// last-bit differences move it by a few percent: a wrong system would be orders away.
TEST(EngineOpenCl, DiffusionReportsTheCpusResidual) {
  if (!test_opencl_device()) GTEST_SKIP() << "no OpenCL device (no ICD or no platform)";
  for (SolverKind kind :
       {SolverKind::kJacobi, SolverKind::kRedBlackGaussSeidel, SolverKind::kIccg}) {
    SceneConfig scene = fixed_sweeps("pearson", kind, 6);
    scene.rd.scheme = RdScheme::kImplicit;
    Engine serial(scene, {EngineOptions::Backend::kSerial, 1});
    Engine cl(scene, on_device());
    for (int k = 0; k < 3; ++k) {
      serial.step();
      cl.step();
    }
    const RdStepStats& a = *serial.rd_stats();
    const RdStepStats& b = *cl.rd_stats();
    EXPECT_EQ(b.diffusion_iterations_a, a.diffusion_iterations_a);
    EXPECT_GT(a.diffusion_residual_a, 0.0);
    EXPECT_NEAR(b.diffusion_residual_a, a.diffusion_residual_a, 0.05 * a.diffusion_residual_a);
    EXPECT_NEAR(b.diffusion_residual_b, a.diffusion_residual_b, 0.05 * a.diffusion_residual_b);
  }
}

// The presets' own diffusion solver, ICCG to a tolerance (kernels/cl/opencl_iccg.h; the
// anisotropic cookie's operator assembled and factored on the device every step, the obstacle's
// solid cells isolated there): frame after frame on the device without a transfer or a
// fallback line, each solve taking the CPU's iterations, within 1e-5 of serial.
TEST(EngineOpenCl, IccgDiffusionPresetsStayOnTheDeviceWithinOneInTenToTheFive) {
  if (!test_opencl_device()) GTEST_SKIP() << "no OpenCL device (no ICD or no platform)";
  for (const char* name :
       {"turing-spots", "obstacle-rd-gray-scott", "cavity-gray-scott", "space-cookie-3"}) {
    const SceneConfig scene = awkward_preset_scene(name);
    ASSERT_EQ(scene.rd.diffusion_solver.kind, SolverKind::kIccg) << name;
    ASSERT_GT(scene.rd.diffusion_solver.tolerance, 0.0) << name;
    testing::internal::CaptureStderr();
    Engine serial(scene, {EngineOptions::Backend::kSerial, 1});
    Engine cl(scene, on_device());
    auto& device = static_cast<OpenClDevice&>(cl.device());
    std::int64_t up = 0, down = 0;
    for (int k = 0; k < kFrames; ++k) {
      serial.step();
      cl.step();
      const RdStepStats& a = *serial.rd_stats();
      const RdStepStats& b = *cl.rd_stats();
      EXPECT_EQ(b.diffusion_iterations_a, a.diffusion_iterations_a) << name << " frame " << k;
      EXPECT_EQ(b.diffusion_iterations_b, a.diffusion_iterations_b) << name << " frame " << k;
      EXPECT_NEAR(b.diffusion_residual_a, a.diffusion_residual_a, 0.05 * a.diffusion_residual_a)
          << name << " frame " << k;
      if (k == 0) {
        cl.finish();
        up = device.uploaded_bytes();
        down = device.downloaded_bytes();
      }
    }
    cl.finish();
    EXPECT_EQ(device.uploaded_bytes(), up) << name;
    EXPECT_EQ(device.downloaded_bytes(), down) << name;
    EXPECT_EQ(testing::internal::GetCapturedStderr(), "") << name;
    const auto [error, field] = worst_error(serial.state(), std::as_const(cl).state());
    const RdStepStats& last = *serial.rd_stats();
    std::printf("%s (iccg diffusion): %d frames, last %d + %d iterations, max error %.3g\n", name,
                kFrames, last.diffusion_iterations_a, last.diffusion_iterations_b, error);
    EXPECT_LE(error, kTolerance) << name << ": field " << field;
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
