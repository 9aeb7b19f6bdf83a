// The tensor field's semi-implicit solve on the OpenCL device (kernels/cl/
// opencl_tensor_field_solve.h, tensor_field_solve.cl; PoCL in CI) against TensorFieldSolve
// (kernels/tensor_field_solve.h, BiCGSTAB with the Jacobi diagonal) on the same faces and
// right-hand side: the same report (BiCGSTAB steps equal; the relative residual within 1e-6 of
// the CPU's, relatively) and the solution within 1e-6 relative (max norm, max |cl - cpu| /
// max |cpu|). The twin repeats the C++ arithmetic operation for operation, neither side fusing a
// multiply-add (kernels/tensor_field_solve.cpp is compiled with -ffp-contract=off), and adds
// each dot product's row partials in row order, so on PoCL the two give the same bits (printed:
// "bit-identical"); the bounds leave room for a device whose double division rounds otherwise,
// where a step's dot products move by an ulp: the iterations still agree and the fields by far
// better than float's rounding of the result.
//
// Fields: the vortex and the radial tensor (rank2_tensor_field, d_along 2, d_across 0.5: the
// presets' anisotropy) at 37 x 29 (rows of 4k + 1 cells, an odd row count), the radial one at
// 127 x 93 (4k + 3) and 6 x 4 (4k + 2), s = 1.6 (the
// presets' step) and s = 4; the presets' limits (40 steps, 1e-6), a tight tolerance that runs
// many steps, and a budget of 2 steps that stops on applications. The halo of x is not written.
#if defined(ARDCELL_WITH_OPENCL)
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>

#include "kernels/cl/opencl_tensor_field_solve.h"
#include "kernels/generalized_rd.h"
#include "kernels/tensor_field_solve.h"
#include "tests/support/cl_parity.h"

namespace ardcell {
namespace {

using namespace cl_parity;  // NOLINT: the shared helpers of every parity test

constexpr double kFieldBound = 1e-6;
constexpr double kResidualBound = 1e-6;

struct Case {
  const char* field;
  TensorFieldKind kind;
  Int2 size;
  double s;
  int max_iterations;
  double tolerance;
};

// Bit for bit the same interiors.
bool same_interior(const FieldF& a, const FieldF& b) {
  for (int y = 0; y < a.ny(); ++y)
    if (std::memcmp(a.row(y), b.row(y), std::size_t(a.nx()) * sizeof(float)) != 0) return false;
  return true;
}

struct Tally {
  int cases = 0, identical = 0;
};

void expect_twin_matches(const Case& c, Tally& tally) {
  Fixture& d = device();
  Dev dev{*d.ctx};
  const Rank2FaceField faces = rank2_tensor_field(c.size, c.kind, 2.0, 0.5);
  FieldF b(c.size, 1);
  fill_smooth(b, 2.0f, 1.0f, 0.3f);
  // Noise on top, so that every mode is in the right-hand side; the halo stays the smooth one's.
  FieldF noise(c.size, 1);
  fill_random(noise, -0.5f, 0.5f, 11);
  for (int y = 0; y < c.size.y; ++y)
    for (int x = 0; x < c.size.x; ++x) b(x, y) += noise(x, y);

  TensorFieldSolve cpu_solve(faces);
  cpu_solve.set_limits(c.max_iterations, c.tolerance);
  FieldF x_cpu = b;
  const SolveReport cpu = cpu_solve.solve(x_cpu, c.s);

  const DeviceField x_xx = dev.up(faces.x_xx), x_xy = dev.up(faces.x_xy), y_xy = dev.up(faces.y_xy),
                    y_yy = dev.up(faces.y_yy);
  DeviceField dx = dev.up(b);
  OpenClTensorFieldSolve twin(*d.cl, c.size);
  const SolveReport cl =
      twin.solve({&x_xx, &x_xy, &y_xy, &y_yy}, dx, c.s, c.max_iterations, c.tolerance);
  const FieldF x_cl = dev.down(dx);

  const double field = region_error(x_cl, x_cpu, x_cl.interior());
  const bool identical =
      cl.relative_residual == cpu.relative_residual && same_interior(x_cl, x_cpu);
  ++tally.cases;
  tally.identical += identical;
  std::printf(
      "%s %dx%d, s = %.1f (%d steps, tol %.0e): cpu %d steps, residual %.6g; device %d steps, "
      "residual %.6g; max relative difference %.3g%s\n",
      c.field, c.size.x, c.size.y, c.s, c.max_iterations, c.tolerance, cpu.iterations,
      cpu.relative_residual, cl.iterations, cl.relative_residual, field,
      identical ? " (bit-identical)" : "");
  const std::string what = std::string(c.field) + " " + std::to_string(c.size.x) + "x" +
                           std::to_string(c.size.y) + ", s = " + std::to_string(c.s);
  EXPECT_EQ(cl.iterations, cpu.iterations) << what;
  EXPECT_NEAR(cl.relative_residual, cpu.relative_residual,
              kResidualBound * cpu.relative_residual + 1e-15)
      << what;
  EXPECT_LE(field, kFieldBound) << what;
  // The solve did something: the field moved from b, and (the limits allowing) to the tolerance.
  EXPECT_GT(region_error(x_cl, b, x_cl.interior()), 1e-4) << what;
  if (cpu.iterations < c.max_iterations) {
    EXPECT_LE(cl.relative_residual, c.tolerance) << what;
  }
  // The halo of x is not written.
  for (int y = -1; y <= c.size.y; ++y)
    for (int x = -1; x <= c.size.x; ++x)
      if (!box_of_size(c.size).contains(Int2{x, y})) {
        ASSERT_EQ(x_cl(x, y), b(x, y)) << what << " halo (" << x << ", " << y << ")";
      }
}

TEST(ClTensorFieldSolveParity, MatchesTheCppBicgstab) {
  Fixture& d = device();
  ASSERT_TRUE(d.cl);
  if (!d.cl->has_fp64()) GTEST_SKIP() << "the device has no doubles: the solve stays on the CPU";
  const TensorFieldKind vortex = TensorFieldKind::kVortex, radial = TensorFieldKind::kRadial;
  const Case cases[] = {
      {"vortex", vortex, {37, 29}, 1.6, 40, 1e-6},   {"vortex", vortex, {37, 29}, 4.0, 40, 1e-6},
      {"radial", radial, {37, 29}, 1.6, 40, 1e-6},   {"radial", radial, {37, 29}, 4.0, 40, 1e-6},
      {"vortex", vortex, {37, 29}, 4.0, 200, 1e-12}, {"radial", radial, {37, 29}, 4.0, 2, 1e-12},
      {"radial", radial, {127, 93}, 4.0, 40, 1e-6},  {"radial", radial, {6, 4}, 1.6, 40, 1e-6},
  };
  Tally tally;
  for (const Case& c : cases) expect_twin_matches(c, tally);
  std::printf("%d of %d solves bit-identical to the C++\n", tally.identical, tally.cases);
  if (is_pocl(*d.ctx)) {
    EXPECT_EQ(tally.identical, tally.cases) << "PoCL rounds doubles as the C++ does";
  }
}

// A second solve on the same twin (the engine's: every step, A then B) starts afresh: it equals
// a solve on a new twin, whatever the first left in the vectors.
TEST(ClTensorFieldSolveParity, SolvesAgainWithTheSameVectors) {
  Fixture& d = device();
  ASSERT_TRUE(d.cl);
  if (!d.cl->has_fp64()) GTEST_SKIP() << "the device has no doubles: the solve stays on the CPU";
  Dev dev{*d.ctx};
  const Int2 size{37, 29};
  const Rank2FaceField faces = rank2_tensor_field(size, TensorFieldKind::kRadial, 2.0, 0.5);
  const DeviceField x_xx = dev.up(faces.x_xx), x_xy = dev.up(faces.x_xy), y_xy = dev.up(faces.y_xy),
                    y_yy = dev.up(faces.y_yy);
  const ClRank2Faces f{&x_xx, &x_xy, &y_xy, &y_yy};
  FieldF a(size, 1), b(size, 1);
  fill_random(a, 0.0f, 4.0f, 3);
  fill_random(b, 1.0f, 2.0f, 4);
  OpenClTensorFieldSolve reused(*d.cl, size), fresh(*d.cl, size);
  DeviceField da = dev.up(a), db = dev.up(b), db_fresh = dev.up(b);
  reused.solve(f, da, 4.0, 40, 1e-6);
  const SolveReport again = reused.solve(f, db, 1.6, 40, 1e-6);
  const SolveReport first = fresh.solve(f, db_fresh, 1.6, 40, 1e-6);
  EXPECT_EQ(again.iterations, first.iterations);
  EXPECT_EQ(again.relative_residual, first.relative_residual);
  EXPECT_TRUE(same_interior(dev.down(db), dev.down(db_fresh)));
}

}  // namespace
}  // namespace ardcell
#endif
