// The periodic FFT steps on the OpenCL device (kernels/cl/opencl_fft.h, clFFT on PoCL in CI)
// against their CPU kernels (FFTW), per field, relative error in the max norm,
//   max |device - cpu| / max |cpu|, within 1e-5:
//   - OpenClPeriodicSolve vs PeriodicStencilSolve::solve (seed 003, Eqn 28) for Table 2's
//     sequences (a)-(f) on a grid of factors 2 and 3 and an odd one of 3, 5 and 7;
//   - OpenClEtdrk4 vs PeriodicEtdrk4::step over 10 steps of Pearson's Gray-Scott.
// The transforms round differently (clFFT's radix passes, FFTW's codelets), so the results agree
// to a few float ulps of max |x|, not to the bit. clfft_size_problem names the sizes clFFT lacks
// (the engine runs those on the CPU: engine_opencl_parity_test).
#if defined(ARDCELL_WITH_OPENCL)
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "kernels/cl/opencl_fft.h"
#include "kernels/generalized_diffusion.h"
#include "kernels/periodic_etdrk4.h"
#include "kernels/periodic_stencil_solve.h"
#include "tests/support/alloc_counter.h"
#include "tests/support/opencl_test_device.h"

namespace ardcell {
namespace {

constexpr double kTolerance = 1e-5;

double relative_error(const FieldF& cpu, const FieldF& device) {
  double diff = 0, scale = 0;
  for (int y = 0; y < cpu.ny(); ++y)
    for (int x = 0; x < cpu.nx(); ++x) {
      const double d = std::abs(double(cpu(x, y)) - double(device(x, y)));
      diff = std::isnan(d) ? INFINITY : std::max(diff, d);
      scale = std::max(scale, std::abs(double(cpu(x, y))));
    }
  return scale > 0 ? diff / scale : diff;
}

FieldF random_field(Int2 n, unsigned seed) {
  FieldF f(n, 2);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  for (int y = 0; y < n.y; ++y)
    for (int x = 0; x < n.x; ++x) f(x, y) = u(rng);
  return f;
}

TEST(ClFft, SizeProblemNamesThePrimeFactorClFftLacks) {
  EXPECT_EQ(clfft_size_problem({64, 48}), "");
  EXPECT_EQ(clfft_size_problem({60, 42}), "");
  EXPECT_EQ(clfft_size_problem({45, 27}), "");
  EXPECT_EQ(clfft_size_problem({22, 26}), "");  // 11 and 13: clFFT 2.12's largest radices
  EXPECT_EQ(clfft_size_problem({34, 16}), "34 has a prime factor clFFT lacks (17)");
  EXPECT_EQ(clfft_size_problem({127, 93}), "127 has a prime factor clFFT lacks (127)");
  EXPECT_EQ(clfft_size_problem({64, 93}), "93 has a prime factor clFFT lacks (31)");
}

// Each grid's plans are baked once, then every sequence and delta runs on them. On a fresh
// machine PoCL compiles each size's clFFT kernels (5-10 s; cached after), hence two grids, the
// ones the other tests here use.
TEST(ClFft, PeriodicSolveAgreesWithTheCpuOnTable2) {
  TestOpenClDevice* device = test_opencl_device();
  if (!device) GTEST_SKIP() << "no OpenCL device (no ICD or no platform)";
  OpenClContext& ctx = *device->ctx;
  double worst = 0;
  for (Int2 n : {Int2{64, 48}, Int2{63, 45}}) {
    ClFft2d fft(ctx, n, 1);
    OpenClPeriodicSolve twin(*device->cl, fft);
    for (const NamedTensorSequence& seq : kTable2) {
      const Stencil5x5 k = assemble_generalized_stencil(seq.tensors);
      PeriodicStencilSolve solve(n, k);
      for (double delta : {0.1, 5.0}) {
        ASSERT_EQ(solve.problem(delta), "") << seq.name << " on " << n.x << "x" << n.y;
        solve.set_delta(delta);
        FieldF cpu = random_field(n, 7u + unsigned(n.x));
        FieldF on_device = cpu;
        DeviceField x = ctx.allocate_like(on_device);
        ctx.upload(on_device, x);
        twin.solve(solve, x);
        ctx.download(x, on_device);
        solve.solve(cpu);
        const double error = relative_error(cpu, on_device);
        EXPECT_LE(error, kTolerance)
            << seq.name << " delta " << delta << " on " << n.x << "x" << n.y;
        worst = std::max(worst, error);
      }
    }
  }
  std::printf("periodic solve, Table 2 (a)-(f), 64x48 and 63x45: max relative error %.3g\n", worst);
}

// A steady solve or step enqueues the same work each time: clFFT's own heap allocations per
// transform (vectors and a lock's name inside clfftEnqueueTransform, freed before it returns) are
// counted and reported; they do not grow. Nothing else in a steady step allocates.
TEST(ClFft, SteadySolvesAllocateOnlyInsideClFftEnqueues) {
  TestOpenClDevice* device = test_opencl_device();
  if (!device) GTEST_SKIP() << "no OpenCL device (no ICD or no platform)";
  OpenClContext& ctx = *device->ctx;
  const Int2 n{64, 48};
  ClFft2d fft(ctx, n, 1);
  OpenClPeriodicSolve twin(*device->cl, fft);
  PeriodicStencilSolve solve(n, assemble_generalized_stencil(kTable2A));
  solve.set_delta(1.0);
  FieldF f = random_field(n, 3);
  DeviceField x = ctx.allocate_like(f);
  ctx.upload(f, x);
  twin.solve(solve, x);  // uploads the multipliers
  ctx.finish();
  long counts[3];
  for (long& c : counts) {
    const long before = g_allocations.load();
    twin.solve(solve, x);
    c = g_allocations.load() - before;
  }
  ctx.finish();
  std::printf("periodic solve: %ld heap allocations a solve (two clfftEnqueueTransform calls)\n",
              counts[0]);
  EXPECT_EQ(counts[1], counts[0]);
  EXPECT_EQ(counts[2], counts[0]);

  ClFft2d fft2(ctx, n, 2);
  OpenClEtdrk4 etd(*device->cl, fft2);
  PeriodicEtdrk4 cpu_step(n);
  cpu_step.set_step(1.0, 0.2, 0.1);
  ReactionParams p;
  DeviceField y = ctx.allocate_like(f);
  ctx.upload(f, y);
  etd.step(cpu_step, x, y, &p);  // uploads the coefficients
  ctx.finish();
  for (long& c : counts) {
    const long before = g_allocations.load();
    etd.step(cpu_step, x, y, &p);
    c = g_allocations.load() - before;
  }
  ctx.finish();
  std::printf("ETDRK4: %ld heap allocations a step (nine clfftEnqueueTransform calls)\n",
              counts[0]);
  EXPECT_EQ(counts[1], counts[0]);
  EXPECT_EQ(counts[2], counts[0]);
}

// Pearson's Gray-Scott (the preset's F, k, dt and rates D / h^2 at 256 x 256 on 2.5 x 2.5) from
// its central square with noise, 10 steps.
TEST(ClFft, Etdrk4AgreesWithTheCpuOverTenSteps) {
  TestOpenClDevice* device = test_opencl_device();
  if (!device) GTEST_SKIP() << "no OpenCL device (no ICD or no platform)";
  OpenClContext& ctx = *device->ctx;
  const Int2 n{64, 48};
  ReactionParams p;
  p.model = ReactionModel::kGrayScott;
  p.F = 0.04f;
  p.k = 0.06f;
  const double h = 2.5 / 256, dt = 2.0;
  PeriodicEtdrk4 cpu_step(n);
  cpu_step.set_step(dt, 2e-5 / (h * h), 1e-5 / (h * h));
  FieldF a(n, 1), b(n, 1);
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> noise(-0.01f, 0.01f);
  for (int y = 0; y < n.y; ++y)
    for (int x = 0; x < n.x; ++x) {
      const bool inside = std::abs(x - n.x / 2) < 8 && std::abs(y - n.y / 2) < 8;
      a(x, y) = (inside ? 0.5f : 1.0f) + noise(rng);
      b(x, y) = (inside ? 0.25f : 0.0f) + noise(rng);
    }
  ClFft2d fft(ctx, n, 2);
  OpenClEtdrk4 twin(*device->cl, fft);
  DeviceField da = ctx.allocate_like(a), db = ctx.allocate_like(b);
  ctx.upload(a, da);
  ctx.upload(b, db);
  FieldF device_a = a, device_b = b;
  double worst = 0;
  for (int s = 1; s <= 10; ++s) {
    cpu_step.step(a, b, &p);
    twin.step(cpu_step, da, db, &p);
    ctx.download(da, device_a);
    ctx.download(db, device_b);
    const double error = std::max(relative_error(a, device_a), relative_error(b, device_b));
    EXPECT_LE(error, kTolerance) << "step " << s;
    worst = std::max(worst, error);
  }
  std::printf("ETDRK4, Pearson's Gray-Scott 64x48, 10 steps: max relative error %.3g\n", worst);
  // Without a reaction: the exact diffusion of each mode.
  for (int s = 0; s < 3; ++s) {
    cpu_step.step(a, b, nullptr);
    twin.step(cpu_step, da, db, nullptr);
  }
  ctx.download(da, device_a);
  ctx.download(db, device_b);
  EXPECT_LE(std::max(relative_error(a, device_a), relative_error(b, device_b)), kTolerance);
}

}  // namespace
}  // namespace ardcell
#endif
