// The device FFT (kernels/cl/opencl_fft.h, fft.cl; PoCL in CI) against the DFT by definition in
// double, and the periodic FFT steps on the device against their CPU kernels (FFTW), per field,
// relative error in the max norm, max |device - cpu| / max |cpu|, within 1e-5:
//   - OpenClPeriodicSolve vs PeriodicStencilSolve::solve (seed 003, Eqn 28) for Table 2's
//     sequences (a)-(f) on a grid of factors 2 and 3 and an odd one of 3, 5 and 7;
//   - OpenClEtdrk4 vs PeriodicEtdrk4::step over 10 steps of Pearson's Gray-Scott.
// The transforms round differently (fft.cl's radix passes, FFTW's codelets), so the results agree
// to a few float ulps of max |x|, not to the bit. device_fft_size_problem names the sizes the
// device FFT lacks (the engine runs those on the CPU: engine_opencl_parity_test). A steady
// transform, solve or step allocates nothing on the host.
#if defined(ARDCELL_WITH_OPENCL)
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <numbers>
#include <random>
#include <stdexcept>
#include <vector>

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

TEST(ClFft, SizeProblemNamesThePrimeFactorTheDeviceFftLacks) {
  EXPECT_EQ(device_fft_size_problem({64, 48}), "");
  EXPECT_EQ(device_fft_size_problem({60, 42}), "");
  EXPECT_EQ(device_fft_size_problem({49, 35}), "");
  EXPECT_EQ(device_fft_size_problem({1, 7}), "");
  EXPECT_EQ(device_fft_size_problem({34, 17}), "34 has a prime factor the device FFT lacks (17)");
  EXPECT_EQ(device_fft_size_problem({22, 26}), "22 has a prime factor the device FFT lacks (11)");
  EXPECT_EQ(device_fft_size_problem({64, 26}), "26 has a prime factor the device FFT lacks (13)");
  EXPECT_EQ(device_fft_size_problem({127, 93}),
            "127 has a prime factor the device FFT lacks (127)");
  EXPECT_EQ(device_fft_size_problem({64, 93}), "93 has a prime factor the device FFT lacks (31)");
}

// exp(-2 pi i k / n), k < n, in double.
std::vector<std::complex<double>> roots_of_unity(int n) {
  std::vector<std::complex<double>> roots(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k)
    roots[std::size_t(k)] = std::polar(1.0, -2.0 * std::numbers::pi * double(k) / double(n));
  return roots;
}

// The half spectra of `batch` packed real fields [f][y][x] by the definition, in double: each
// row's DFT (its first nx / 2 + 1 outputs), then each spectral column's; [f][my][mx].
std::vector<std::complex<double>> reference_spectra(const std::vector<float>& real, Int2 n,
                                                    int batch) {
  const int w = n.x / 2 + 1;
  const std::vector<std::complex<double>> wx = roots_of_unity(n.x), wy = roots_of_unity(n.y);
  std::vector<std::complex<double>> rows(std::size_t(batch * n.y * w)), out(rows.size());
  for (int f = 0; f < batch; ++f)
    for (int y = 0; y < n.y; ++y)
      for (int mx = 0; mx < w; ++mx) {
        std::complex<double> sum = 0;
        for (int x = 0; x < n.x; ++x)
          sum += double(real[std::size_t((f * n.y + y) * n.x + x)]) * wx[std::size_t(mx * x % n.x)];
        rows[std::size_t((f * n.y + y) * w + mx)] = sum;
      }
  for (int f = 0; f < batch; ++f)
    for (int my = 0; my < n.y; ++my)
      for (int mx = 0; mx < w; ++mx) {
        std::complex<double> sum = 0;
        for (int y = 0; y < n.y; ++y)
          sum += rows[std::size_t((f * n.y + y) * w + mx)] * wy[std::size_t(my * y % n.y)];
        out[std::size_t((f * n.y + my) * w + mx)] = sum;
      }
  return out;
}

// The transforms themselves, at sizes whose passes cover every radix (16, 8, 4, 2, 3, 5, 7), even
// and odd nx (an even one's rows transform as complex rows of nx / 2) and one pass per dimension
// (4 x 7, 6 x 5, 1 x 3), batches of 1 and 2, and a size of the presets' (256 x 128): forward
// against the DFT by definition in double, max |device - reference| / max |reference|; forward then
// backward against nx ny times the input (the backward transform does not scale). Both within 1e-5;
// forward leaves its input as it was.
TEST(ClFft, TransformsAgreeWithTheDftInDoubleAndInvert) {
  TestOpenClDevice* device = test_opencl_device();
  if (!device) GTEST_SKIP() << "no OpenCL device (no ICD or no platform)";
  OpenClContext& ctx = *device->ctx;
  double worst_forward = 0, worst_round_trip = 0;
  struct Case {
    Int2 n;
    int batch;
  };
  for (const Case c : {Case{{64, 48}, 1}, Case{{60, 42}, 1}, Case{{49, 35}, 1}, Case{{27, 20}, 1},
                       Case{{6, 5}, 1}, Case{{4, 7}, 1}, Case{{60, 42}, 2}, Case{{49, 35}, 2},
                       Case{{4, 7}, 2}, Case{{1, 3}, 2}, Case{{16, 40}, 2}, Case{{256, 128}, 1},
                       // Radix 16 after 16, and 4 and 2 after 16, in rows and in columns
                       // (pearson's 256^2 runs its columns as 16, 16).
                       Case{{128, 64}, 1}, Case{{64, 256}, 1}, Case{{1024, 8}, 1}}) {
    const Int2 n = c.n;
    ClFft2d fft(ctx, n, c.batch);
    const std::size_t cells = std::size_t(c.batch * fft.cells());
    std::vector<float> input(cells), kept(cells), back(cells);
    std::mt19937 rng(5u + unsigned(n.x * n.y * c.batch));
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (float& v : input) v = u(rng);
    OpenClBuffer real = fft.allocate_real(), spectrum = fft.allocate_spectrum();
    OpenClBuffer real_back = fft.allocate_real();
    ctx.write(real, input.data(), cells * sizeof(float));
    fft.forward(real, spectrum);
    std::vector<std::complex<float>> spectra(std::size_t(c.batch * fft.modes()));
    ctx.read(spectrum, spectra.data(), spectra.size() * sizeof(spectra[0]));
    ctx.read(real, kept.data(), cells * sizeof(float));
    EXPECT_EQ(kept, input) << n.x << "x" << n.y;
    const std::vector<std::complex<double>> reference = reference_spectra(input, n, c.batch);
    double diff = 0, scale = 0;
    for (std::size_t i = 0; i < reference.size(); ++i) {
      diff = std::max(diff, std::abs(std::complex<double>(spectra[i]) - reference[i]));
      scale = std::max(scale, std::abs(reference[i]));
    }
    const double forward_error = diff / scale;
    fft.backward(spectrum, real_back);
    ctx.read(real_back, back.data(), cells * sizeof(float));
    diff = 0, scale = 0;
    for (std::size_t i = 0; i < cells; ++i) {
      const double expected = double(input[i]) * fft.cells();
      diff = std::max(diff, std::abs(double(back[i]) - expected));
      scale = std::max(scale, std::abs(expected));
    }
    const double round_trip_error = diff / scale;
    EXPECT_LE(forward_error, kTolerance) << n.x << "x" << n.y << " batch " << c.batch;
    EXPECT_LE(round_trip_error, kTolerance) << n.x << "x" << n.y << " batch " << c.batch;
    worst_forward = std::max(worst_forward, forward_error);
    worst_round_trip = std::max(worst_round_trip, round_trip_error);
  }
  std::printf(
      "device FFT: max relative error %.3g forward (vs the DFT in double), %.3g forward "
      "then backward (vs nx ny x)\n",
      worst_forward, worst_round_trip);
}

// The backward transform ignores the imaginary parts a real field's spectrum cannot have: after
// the column passes, each row's X_0 and (nx even) X_(nx/2) must be real, and whatever imaginary
// part they carry is dropped, as FFTW's complex-to-real transform does. Adding i DFT_y(r) (r real)
// to the spectrum's column 0 and column nx / 2 adds i ny r(y) to exactly those values: the field
// that comes back is the same to rounding (and not, were the imaginary parts used).
TEST(ClFft, BackwardIgnoresTheImaginaryPartsOfEachRowsRealModes) {
  TestOpenClDevice* device = test_opencl_device();
  if (!device) GTEST_SKIP() << "no OpenCL device (no ICD or no platform)";
  OpenClContext& ctx = *device->ctx;
  for (const Int2 n : {Int2{64, 48}, Int2{49, 35}, Int2{128, 64}, Int2{6, 5}}) {
    ClFft2d fft(ctx, n, 1);
    const int w = fft.width();
    const FieldF field = random_field(n, 17u + unsigned(n.x));
    std::vector<float> packed(std::size_t(fft.cells()));
    for (int y = 0; y < n.y; ++y)
      for (int x = 0; x < n.x; ++x) packed[std::size_t(y) * n.x + x] = field(x, y);
    OpenClBuffer real = fft.allocate_real(), spectrum = fft.allocate_spectrum();
    ctx.write(real, packed.data(), packed.size() * sizeof(float));
    fft.forward(real, spectrum);
    std::vector<std::complex<float>> clean(std::size_t(fft.modes()));
    ctx.read(spectrum, clean.data(), clean.size() * sizeof(clean[0]));
    std::vector<std::complex<float>> perturbed = clean;
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int mx : {0, n.x % 2 == 0 ? n.x / 2 : -1}) {
      if (mx < 0) continue;
      std::vector<double> r(std::size_t(n.y));
      for (double& v : r) v = u(rng);
      for (int my = 0; my < n.y; ++my) {
        std::complex<double> dft = 0;
        for (int y = 0; y < n.y; ++y)
          dft += r[std::size_t(y)] * std::polar(1.0, -2 * std::numbers::pi * my * y / n.y);
        perturbed[std::size_t(my) * w + mx] +=
            std::complex<float>(std::complex<double>(0, 1) * dft);
      }
    }
    const auto back = [&](const std::vector<std::complex<float>>& s) {
      ctx.write(spectrum, s.data(), s.size() * sizeof(s[0]));
      fft.backward(spectrum, real);
      std::vector<float> out(packed.size());
      ctx.read(real, out.data(), out.size() * sizeof(float));
      return out;
    };
    const std::vector<float> a = back(clean), b = back(perturbed);
    double diff = 0, scale = 0;
    for (std::size_t i = 0; i < a.size(); ++i)
      diff = std::max(diff, double(std::abs(a[i] - b[i]))),
      scale = std::max(scale, double(std::abs(a[i])));
    EXPECT_LE(diff / scale, kTolerance) << n.x << "x" << n.y;
  }
}

// A size the device FFT lacks throws one line naming the factor (the engine falls back).
TEST(ClFft, ASizeTheDeviceFftLacksThrowsOneLine) {
  TestOpenClDevice* device = test_opencl_device();
  if (!device) GTEST_SKIP() << "no OpenCL device (no ICD or no platform)";
  try {
    ClFft2d fft(*device->ctx, {34, 17}, 1);
    ADD_FAILURE() << "34 x 17 made a transform";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "device FFT: 34 has a prime factor the device FFT lacks (17)");
  }
}

// Each grid's transforms are set up once, then every sequence and delta runs on them: a grid of
// factors 2 and 3, and an odd one of 3, 5 and 7.
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

// A steady transform, solve or step allocates nothing on the host: it sets kernel arguments
// and enqueues (the rule of a steady frame: tests/host/engine/frame_alloc_test.cpp).
TEST(ClFft, SteadyTransformsSolvesAndStepsAllocateNothing) {
  TestOpenClDevice* device = test_opencl_device();
  if (!device) GTEST_SKIP() << "no OpenCL device (no ICD or no platform)";
  OpenClContext& ctx = *device->ctx;
  const Int2 n{60, 42};
  ClFft2d fft(ctx, n, 1);
  OpenClBuffer real = fft.allocate_real(), spectrum = fft.allocate_spectrum();
  fft.forward(real, spectrum);
  fft.backward(spectrum, real);
  ctx.finish();
  long before = g_allocations.load();
  for (int i = 0; i < 3; ++i) {
    fft.forward(real, spectrum);
    fft.backward(spectrum, real);
  }
  EXPECT_EQ(g_allocations.load() - before, 0) << "transforms";
  ctx.finish();

  OpenClPeriodicSolve twin(*device->cl, fft);
  PeriodicStencilSolve solve(n, assemble_generalized_stencil(kTable2A));
  solve.set_delta(1.0);
  FieldF f = random_field(n, 3);
  DeviceField x = ctx.allocate_like(f);
  ctx.upload(f, x);
  twin.solve(solve, x);  // uploads the multipliers
  ctx.finish();
  before = g_allocations.load();
  for (int i = 0; i < 3; ++i) twin.solve(solve, x);
  EXPECT_EQ(g_allocations.load() - before, 0) << "periodic solves";
  ctx.finish();

  ClFft2d fft2(ctx, n, 2);
  OpenClEtdrk4 etd(*device->cl, fft2);
  PeriodicEtdrk4 cpu_step(n);
  cpu_step.set_step(1.0, 0.2, 0.1);
  ReactionParams p;
  DeviceField y = ctx.allocate_like(f);
  ctx.upload(f, y);
  etd.step(cpu_step, x, y, &p);  // uploads the coefficients
  ctx.finish();
  before = g_allocations.load();
  for (int i = 0; i < 3; ++i) etd.step(cpu_step, x, y, &p);
  EXPECT_EQ(g_allocations.load() - before, 0) << "ETDRK4 steps";
  ctx.finish();
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
