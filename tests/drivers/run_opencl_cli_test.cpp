// `ardcell run NAME --backend opencl` for the general scenes, through the real binary
// (ARDCELL_BINARY):
//   - a scene set to the fixed-sweep solvers runs on the device (PoCL in CI; --stats names it)
//     with no fallback line, writes PNG frames, and saves fields that agree with the CPU
//     engine's within 1e-5 relative in the max norm (max |cl - cpu| / max |cpu|, per field);
//     resuming a saved state on the device agrees the same way;
//   - the scene's own ICCG solves (--solver iccg) run on the device too, with no fallback line
//     and the same agreement;
//   - the FFT steps (mcgraw-turing-d's semi-implicit solve, pearson's ETDRK4) run on the device
//     (its own FFT kernels) with no fallback line;
//   - a setting the device does not run (multigrid implicit diffusion, an FFT of a size with a
//     prime factor the device FFT lacks) runs that op on the CPU with ONE line naming the setting
//     and why; an invalid --cl-device prints ONE line and runs on the threads back end;
//   - --cl-device with --backend threads is a usage error (exit 2, one line).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "host/io/npy.h"
#include "tests/drivers/binary_run_fixture.h"
#if defined(ARDCELL_WITH_OPENCL)
#include "runtime/opencl/opencl_context.h"
#endif

namespace ardcell {
namespace {

namespace fs = std::filesystem;

using Result = BinaryRunResult;

bool have_opencl_device() {
#if defined(ARDCELL_WITH_OPENCL)
  std::string error;
  return !list_opencl_devices(&error).empty();
#else
  return false;
#endif
}

class RunOpenClCliTest : public BinaryRunTest {
 protected:
  // Worst relative max-norm error of A and B between two saved states.
  double state_error(const char* got, const char* ref) {
    double worst = 0;
    for (const char* field : {"A.npy", "B.npy", "u.npy", "v.npy", "dye.npy"}) {
      if (!fs::exists(work() / ref / field)) continue;  // a field the scene does not have
      NpyArray g, r;
      EXPECT_TRUE(read_npy(work() / got / field, g)) << got << "/" << field;
      EXPECT_TRUE(read_npy(work() / ref / field, r)) << ref << "/" << field;
      EXPECT_EQ(g.data.size(), r.data.size());
      if (g.data.size() != r.data.size() || r.data.empty()) return 1.0;
      double diff = 0, mag = 0;
      for (std::size_t i = 0; i < r.data.size(); ++i) {
        diff = std::max(diff, std::abs(double(g.data[i]) - double(r.data[i])));
        mag = std::max(mag, std::abs(double(r.data[i])));
      }
      worst = std::max(worst, diff / std::max(mag, 1e-30));
    }
    return worst;
  }
};

// Pearson's Gray-Scott at an awkward size with SBDF2 (its default, ETDRK4, runs its FFTs on the
// CPU) and fixed Jacobi sweeps (its default is ICCG): every op on the device.
constexpr const char* kPearson =
    "run pearson --size 41x29 --quiet --set rd.scheme=sbdf2 --set rd.dt=1 "
    "--set rd.steps_per_frame=10 --set rd.diffusion_solver.kind=jacobi "
    "--set rd.diffusion_solver.tolerance=0 --set rd.diffusion_solver.iterations=12 ";

TEST_F(RunOpenClCliTest, RdSceneRunsOnTheDeviceAndAgreesWithTheCpu) {
  if (!have_opencl_device()) GTEST_SKIP() << "no OpenCL device (or built without OpenCL)";
  const Result cl = run(std::string(kPearson) +
                        "--steps 40 --every 20 --out frames --backend opencl --stats "
                        "--save-state on_cl");
  ASSERT_EQ(cl.code, 0) << cl.err;
  EXPECT_EQ(cl.err, "");
  EXPECT_NE(cl.out.find("scene=pearson size=41x29 backend=opencl workers="), std::string::npos)
      << cl.out;
  EXPECT_NE(cl.out.find("frames=40 "), std::string::npos) << cl.out;
  EXPECT_TRUE(fs::exists(work() / "frames" / "B_00000040.png") ||
              fs::exists(work() / "frames" / "A_00000040.png"))
      << "no PNG of frame 40";
  const Result cpu =
      run(std::string(kPearson) + "--steps 40 --every 0 --backend threads --save-state on_cpu");
  ASSERT_EQ(cpu.code, 0) << cpu.err;
  const double error = state_error("on_cl", "on_cpu");
  std::printf("pearson 41x29, 40 frames: OpenCL vs CPU engine max relative error %.3g\n", error);
  EXPECT_LE(error, 1e-5);

  // Resume both for 20 more frames.
  ASSERT_EQ(run(std::string(kPearson) + "--load-state on_cl --steps 20 --every 0 --backend "
                                        "opencl --save-state cl2")
                .code,
            0);
  ASSERT_EQ(run(std::string(kPearson) + "--load-state on_cpu --steps 20 --every 0 --backend "
                                        "threads --save-state cpu2")
                .code,
            0);
  EXPECT_LE(state_error("cl2", "cpu2"), 1e-5);
  EXPECT_NE(slurp(work() / "cl2" / "meta.json"), slurp(work() / "on_cl" / "meta.json"));
}

TEST_F(RunOpenClCliTest, FluidSceneRunsOnTheDeviceAndAgreesWithTheCpu) {
  if (!have_opencl_device()) GTEST_SKIP() << "no OpenCL device (or built without OpenCL)";
  const std::string scene =
      "run cavity-gray-scott --size 45x31 --quiet --steps 10 --every 0 "
      "--set fluid.pressure_solver.kind=jacobi --set fluid.pressure_solver.tolerance=0 "
      "--set fluid.viscosity_solver.kind=rbgs --set fluid.viscosity_solver.tolerance=0 "
      "--set rd.diffusion_solver.kind=rbgs --set rd.diffusion_solver.tolerance=0 ";
  const Result cl = run(scene + "--backend opencl --save-state on_cl");
  ASSERT_EQ(cl.code, 0) << cl.err;
  EXPECT_EQ(cl.err, "") << "no op may fall back";
  ASSERT_EQ(run(scene + "--backend serial --save-state on_cpu").code, 0);
  const double error = state_error("on_cl", "on_cpu");
  std::printf("cavity-gray-scott 45x31, 10 frames: OpenCL vs CPU max relative error %.3g\n", error);
  EXPECT_LE(error, 1e-5);
}

// Every solve and the implicit diffusion with ICCG (kernels/cl/iccg.cl): no fallback line.
TEST_F(RunOpenClCliTest, IccgSolvesRunOnTheDeviceAndAgreeWithTheCpu) {
  if (!have_opencl_device()) GTEST_SKIP() << "no OpenCL device (or built without OpenCL)";
  const std::string scene =
      "run cavity-gray-scott --size 45x31 --quiet --steps 5 --every 0 --solver iccg ";
  const Result cl = run(scene + "--backend opencl --save-state on_cl");
  ASSERT_EQ(cl.code, 0) << cl.err;
  EXPECT_EQ(cl.err, "") << "no op may fall back";
  ASSERT_EQ(run(scene + "--backend serial --save-state on_cpu").code, 0);
  const double error = state_error("on_cl", "on_cpu");
  std::printf("cavity-gray-scott 45x31 iccg, 5 frames: OpenCL vs CPU max relative error %.3g\n",
              error);
  EXPECT_LE(error, 1e-5);
}

TEST_F(RunOpenClCliTest, WhatTheDeviceCannotRunFallsBackWithOneLine) {
  struct Case {
    std::string args, expected;
  };
  const bool device = have_opencl_device();
  const Case cases[] = {
      {"run pearson --size 34 --steps 2 --every 0 --backend opencl",
       device ? "ETDRK4 step (FFT) runs on the CPU (rd.scheme etdrk4: 34 has a prime factor the "
                "device FFT lacks (17))"
              : "OpenCL"},
      {"run pearson --size 24 --steps 2 --every 0 --backend opencl --set rd.scheme=implicit "
       "--set rd.diffusion_solver.kind=mg",
       device ? "implicit diffusion runs on the CPU (mg: " : "OpenCL"},
      {std::string(kPearson) + "--steps 2 --every 0 --backend opencl --cl-device 99",
       device ? "--cl-device 99" : "OpenCL"},
  };
  for (const Case& c : cases) {
    const Result r = run(c.args);
    ASSERT_EQ(r.code, 0) << c.args << "\n" << r.err;
    EXPECT_EQ(count_lines(r.err), 1) << c.args << "\n" << r.err;
    EXPECT_NE(r.err.find(c.expected), std::string::npos) << c.args << "\n" << r.err;
    EXPECT_NE(r.out.find("frames=2 "), std::string::npos) << c.args << "\n" << r.out;
  }
}

// The FFT steps (seed 003's semi-implicit solve, ETDRK4) run on the device by its own FFT at a
// size whose prime factors it has: no fallback line.
TEST_F(RunOpenClCliTest, FftScenesRunOnTheDevice) {
  if (!have_opencl_device()) GTEST_SKIP() << "no OpenCL device (or built without OpenCL)";
  for (const char* args : {"run mcgraw-turing-d --size 64x48 --steps 2 --every 0 --backend opencl",
                           "run pearson --size 64x48 --steps 2 --every 0 --backend opencl"}) {
    const Result r = run(args);
    ASSERT_EQ(r.code, 0) << args << "\n" << r.err;
    EXPECT_EQ(r.err.find("runs on the CPU"), std::string::npos) << args << "\n" << r.err;
    EXPECT_NE(r.out.find("frames=2 "), std::string::npos) << args << "\n" << r.out;
  }
}

TEST_F(RunOpenClCliTest, ClDeviceWithThreadsIsAUsageError) {
  const Result r = run("run pearson --size 16 --steps 1 --backend threads --cl-device 0");
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("--cl-device"), std::string::npos) << r.err;
  EXPECT_EQ(r.out, "");
}

}  // namespace
}  // namespace ardcell
