// Seed 003's semi-implicit step with a per-cell tensor (kernels/tensor_field_solve.h): BiCGSTAB
// against the FFT's exact solve for a uniform tensor (Eqn 29's stencil), the residual checked
// with the explicit kernel's float operator (another code path), conservation on the periodic
// grid, the budget, and the same bits on any number of workers.
#include "kernels/tensor_field_solve.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>

#include "kernels/generalized_diffusion.h"
#include "kernels/periodic_stencil_solve.h"
#include "runtime/thread/thread_backend.h"
#include "tests/support/field_compare.h"
#include "tests/support/uniform_tensor.h"

namespace ardcell {
namespace {

double max_abs_interior(const FieldF& f) {
  double m = 0;
  for (int y = 0; y < f.size().y; ++y)
    for (int x = 0; x < f.size().x; ++x) m = std::max(m, double(std::abs(f(x, y))));
  return m;
}

// The relative 2-norm of b - (x - s L x), with the explicit kernel's float operator.
double float_residual(const Rank2FaceField& d, const FieldF& x, const FieldF& b, double s) {
  const Int2 size = x.size();
  GeneralizedRdParams p;
  p.scale_a = p.scale_b = float(-s);
  FieldF back(size, 1), unused(size, 1);
  tensor_field_rd_rows(d, x.view(), x.view(), back.view(), unused.view(), size, 0, size.y, p);
  double r2 = 0, b2 = 0;
  for (int y = 0; y < size.y; ++y)
    for (int i = 0; i < size.x; ++i) {
      r2 += std::pow(double(back(i, y)) - b(i, y), 2);
      b2 += std::pow(double(b(i, y)), 2);
    }
  return std::sqrt(r2 / b2);
}

// Seed 003's requirement: the semi-implicit FFT step equals the iterative solve of the same
// system within 1e-5. A uniform tensor makes L Eqn 29's 9-point stencil, which the FFT inverts
// exactly (in float).
TEST(TensorFieldSolve, UniformTensorEqualsTheFftSolve) {
  const Int2 size{40, 36};
  const float xx = 0.8f, xy = 0.3f, yy = 0.5f;
  const double s = 3.0;
  const Rank2FaceField d = uniform_tensor_faces(size, xx, xy, yy);
  const FieldF b = random_field(size, 1, 7, 0.0f, 4.0f);
  FieldF iterative = b, fft = b;
  TensorFieldSolve solve(d);
  solve.set_limits(200, 1e-10);
  const SolveReport r = solve.solve(iterative, s);
  PeriodicStencilSolve exact(size, gaussian_stencil(xx, xy, yy));
  exact.solve(fft, s);
  double worst = 0;
  for (int y = 0; y < size.y; ++y)
    for (int x = 0; x < size.x; ++x)
      worst = std::max(worst, double(std::abs(iterative(x, y) - fft(x, y))));
  const double relative = worst / max_abs_interior(fft);
  std::printf(
      "uniform tensor, s = %.1f: BiCGSTAB %d steps (residual %.2g), max |BiCGSTAB - FFT| "
      "/ max |x| = %.3g\n",
      s, r.iterations, r.relative_residual, relative);
  EXPECT_LE(r.relative_residual, 1e-10);
  EXPECT_LT(relative, 1e-5);
}

// The vortex field: (I - s L) x = b checked with tensor_field_rd_rows (the explicit step's float
// kernel with scale -s gives x - s L x), and the total of x is b's (the fluxes telescope).
TEST(TensorFieldSolve, SolvesTheVortexFieldAndConservesTheTotal) {
  const Int2 size{48, 40};
  const Rank2FaceField d = rank2_tensor_field(size, TensorFieldKind::kVortex, 2.0, 0.5);
  const FieldF b = random_field(size, 1, 8, 1.0f, 5.0f);
  FieldF x = b;
  TensorFieldSolve solve(d);
  solve.set_limits(100, 1e-8);
  const double s = 4.0;
  const SolveReport r = solve.solve(x, s);
  const double check = float_residual(d, x, b, s);
  const double drift = std::abs(interior_sum(x) - interior_sum(b)) / interior_sum(b);
  std::printf(
      "vortex field, s = %.1f: %d steps, residual %.2g (float check %.2g), total drift "
      "%.2g\n",
      s, r.iterations, r.relative_residual, check, drift);
  EXPECT_LE(r.relative_residual, 1e-8);
  EXPECT_LT(check, 1e-6) << "x - s L x in float is b to float rounding";
  EXPECT_LT(drift, 1e-7);
  EXPECT_LT(max_abs_interior(x), 5.0f) << "diffusion does not overshoot";
}

// One step of a stiff system: the budget stops it, and the report's residual is the true one
// (the float check agrees to float rounding); with a budget the same system is solved.
TEST(TensorFieldSolve, StopsAtItsBudgetWithTheTrueResidual) {
  const Int2 size{32, 32};
  const Rank2FaceField d = rank2_tensor_field(size, TensorFieldKind::kRadial, 3.0, 0.2);
  const FieldF b = random_field(size, 1, 9, 0.0f, 1.0f);
  const double s = 50.0;
  TensorFieldSolve solve(d);
  solve.set_limits(1, 1e-12);
  FieldF x = b;
  const SolveReport one = solve.solve(x, s);
  const double one_check = float_residual(d, x, b, s);
  EXPECT_EQ(one.iterations, 1);
  EXPECT_GT(one.relative_residual, 1e-3) << "one step does not solve a stiff system";
  EXPECT_NEAR(one_check, one.relative_residual, 1e-5 + 1e-3 * one.relative_residual);
  solve.set_limits(500, 1e-9);
  x = b;
  const SolveReport full = solve.solve(x, s);
  std::printf(
      "s = %.0f: 1 step -> %.3g (float check %.3g); %d steps -> %.2g (float check "
      "%.2g)\n",
      s, one.relative_residual, one_check, full.iterations, full.relative_residual,
      float_residual(d, x, b, s));
  EXPECT_GT(full.iterations, 1);
  EXPECT_LE(full.relative_residual, 1e-9);
  // Rounded to float: float's epsilon times the condition (about 1 + 8 s max D = 1200).
  EXPECT_LT(float_residual(d, x, b, s), 5e-5);
}

TEST(TensorFieldSolve, SameBitsOnAnyNumberOfWorkers) {
  const Int2 size{130, 97};  // past RowExecutor::kMinParallelCells, so the bands really split
  const Rank2FaceField d = rank2_tensor_field(size, TensorFieldKind::kVortex, 2.0, 0.5);
  const FieldF b = random_field(size, 1, 10, 0.0f, 3.0f);
  FieldF serial = b;
  TensorFieldSolve(d).solve(serial, 2.5);
  for (int workers : {2, 3}) {
    ThreadBackendOptions t;
    t.workers = workers;
    ThreadBackend backend(t);
    RowExecutor ex(backend);
    FieldF threads = b;
    TensorFieldSolve(d, ex).solve(threads, 2.5);
    for (int y = 0; y < size.y; ++y)
      ASSERT_EQ(std::memcmp(serial.row(y), threads.row(y), sizeof(float) * size.x), 0)
          << workers << " workers, row " << y;
  }
}

}  // namespace
}  // namespace ardcell
