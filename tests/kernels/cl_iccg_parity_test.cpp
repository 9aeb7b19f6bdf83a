// ICCG on the OpenCL device (kernels/cl/opencl_iccg.h, iccg.cl; PoCL in CI) against the C++
// ICCG (kernels/iccg_solver.cpp) on the same operators: the same iteration count, the solution
// within 1e-5 relative (max norm, max |cl - cpu| / max |cpu|) and the reported relative residual
// within a few per cent (near float round-off the solutions' last bits move it that much; a
// wrong system would be orders away). Both are compiled without fma contraction, so on PoCL the
// two give the same bits (printed: "bit-identical"); the bounds leave room for a device that
// rounds a division differently.
//
// Operators: isotropic diffusion, anisotropic (per-face weights from a random conductivity),
// periodic, mixed axes, the singular Neumann Poisson operator (null-space projection, a
// right-hand side outside the range), Dirichlet, and solid cells (isolate_solid_cells, both
// wall factors), at awkward sizes: rows not a multiple of the 32-row blocks, a last block of one
// row, a single short block, one cell. Then the whole implicit diffusion step with ICCG
// (OpenClDiffusion: the operator assembled and factored on the device, solid cells isolated
// there) against ImplicitDiffusion, reports included.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>

#include "kernels/aniso_diffusion.h"
#include "kernels/cl/opencl_diffusion.h"
#include "kernels/cl/opencl_iccg.h"
#include "kernels/linear_solver.h"
#include "kernels/solver_common.h"
#include "kernels/stencil_operator.h"
#include "kernels/stencil_sweeps.h"
#include "tests/support/cl_parity.h"
#include "tests/support/solid_disc.h"

namespace ardcell {
namespace {

using namespace cl_parity;  // NOLINT: the shared helpers of every parity test

constexpr double kResidualAgreement = 0.05;

// max |cl - cpu| / max |cpu| over the interior, and whether every cell has the same bits.
struct Difference {
  double relative = 0.0;
  bool identical = true;
};
Difference difference(const FieldF& cl, const FieldF& cpu) {
  Difference d;
  d.relative = region_error(cl, cpu, cl.interior());
  for (int y = 0; y < cl.ny(); ++y)
    for (int x = 0; x < cl.nx(); ++x) {
      const float a = cl(x, y), b = cpu(x, y);
      d.identical = d.identical && std::memcmp(&a, &b, sizeof(float)) == 0;
    }
  return d;
}

struct OperatorCase {
  std::string name;
  Int2 size;
  double identity, scale;
  BoundaryKind bx, by;
  bool conductivity;         // per-face weights from a random per-cell k
  double solid_wall_factor;  // < 0: no solid cells
};

StencilOperator operator_of(const OperatorCase& c) {
  FieldF k(c.size, 1);
  fill_random(k, 0.05f, 2.0f, 17);
  StencilOperator op = assemble_stencil_operator(c.size, c.identity, c.scale,
                                                 c.conductivity ? &k : nullptr, c.bx, c.by);
  if (c.solid_wall_factor >= 0) isolate_solid_cells(op, solid_disc(c.size), c.solid_wall_factor);
  return op;
}

// The reports and the solutions of `iterations` cases, for the summary line.
struct Tally {
  int cases = 0, identical = 0;
  double worst = 0.0;
  void add(const Difference& d) {
    ++cases;
    identical += d.identical;
    worst = std::max(worst, d.relative);
  }
};

// Solves op x = b from x0 with the C++ ICCG and with OpenClIccg (the device's report: its
// iterations, and the relative residual the C++ solve computes after its loop, on the device's
// x) and compares them.
void expect_iccg_matches(const OperatorCase& c, const SolverSettings& settings, const FieldF& b,
                         const FieldF& x0, Tally& tally) {
  Fixture& d = device();
  Dev dev{*d.ctx};
  const StencilOperator op = operator_of(c);
  auto cpu_solver = LinearSolver::make(settings, c.size);
  cpu_solver->prepare(op);
  FieldF x_cpu = x0;
  const SolveReport cpu = cpu_solver->solve(op, b, x_cpu);

  ClStencilOperator cl_op = ClStencilOperator::allocate(*d.ctx, c.size, c.bx, c.by);
  cl_op.upload(*d.ctx, op);
  stencil::NullSpace null_space(c.size);
  null_space.analyse(op);
  const DeviceField mask = upload_mask(*d.ctx, null_space.mask());
  const double bb = null_space.consistent_norm2(b);
  const ClNullSpace null{&mask, null_space.count(), bb};
  OpenClIccg iccg(*d.cl, c.size);
  iccg.factor(cl_op);
  DeviceField db = dev.up(b), dx = dev.up(x0);
  SolveReport cl{};
  cl.iterations = iccg.iterate(cl_op, db, dx, settings, null_space.singular() ? &null : nullptr);
  FieldF x_cl = dev.down(dx);
  null_space.remove_mean(x_cl);
  FieldF r(c.size, 1);
  cl.relative_residual =
      solver_detail::relative_residual(op, b, x_cl, r, null_space, RowExecutor::serial(), bb);

  const Difference diff = difference(x_cl, x_cpu);
  tally.add(diff);
  std::printf(
      "%s (%d its, tol %.0e): cpu %d its, residual %.3g; device %d its, residual %.3g; "
      "max relative difference %.3g%s\n",
      c.name.c_str(), settings.max_iterations, settings.tolerance, cpu.iterations,
      cpu.relative_residual, cl.iterations, cl.relative_residual, diff.relative,
      diff.identical ? " (bit-identical)" : "");
  EXPECT_EQ(cl.iterations, cpu.iterations) << c.name;
  EXPECT_LE(diff.relative, kTolerance) << c.name;
  EXPECT_NEAR(cl.relative_residual, cpu.relative_residual,
              kResidualAgreement * cpu.relative_residual + 1e-12)
      << c.name;
  // The halo of x is not written.
  for (int y = -1; y <= c.size.y; ++y)
    for (int x = -1; x <= c.size.x; ++x)
      if (!box_of_size(c.size).contains(Int2{x, y})) {
        ASSERT_EQ(x_cl(x, y), x0(x, y)) << c.name << " halo (" << x << ", " << y << ")";
      }
}

TEST(ClIccgParity, MatchesTheCppSolverOnEveryOperator) {
  Fixture& d = device();
  ASSERT_TRUE(d.cl);
  if (!d.cl->has_fp64()) GTEST_SKIP() << "the device has no doubles: ICCG stays on the CPU";
  const BoundaryKind neumann = BoundaryKind::kNeumann, dirichlet = BoundaryKind::kDirichlet,
                     periodic = BoundaryKind::kPeriodic;
  const double fluid = -1.0;  // no solid cells
  // The pressure operators (identity 0, Neumann or periodic) are singular.
  const OperatorCase cases[] = {
      {"isotropic, Neumann, 37x23", {37, 23}, 1.0, 2.5, neumann, neumann, false, fluid},
      {"per-face, Dirichlet, 129x65", {129, 65}, 1.0, 3.7, dirichlet, dirichlet, true, fluid},
      {"per-face, periodic, 37x23", {37, 23}, 1.0, 3.7, periodic, periodic, true, fluid},
      {"periodic x Dirichlet y, 127x93", {127, 93}, 1.0, 8.0, periodic, dirichlet, false, fluid},
      {"pressure, Neumann, 129x65", {129, 65}, 0.0, 1.0, neumann, neumann, false, fluid},
      {"pressure, periodic, 37x23", {37, 23}, 0.0, 1.0, periodic, periodic, true, fluid},
      {"Poisson, Dirichlet, 50x97", {50, 97}, 0.0, 1.0, dirichlet, dirichlet, false, fluid},
      {"pressure, obstacle, 127x93", {127, 93}, 0.0, 1.0, neumann, neumann, false, 0.0},
      {"viscosity, obstacle, 37x23", {37, 23}, 1.0, 2.5, neumann, neumann, false, 2.0},
      {"per-face, obstacle, periodic, 129x65", {129, 65}, 1.0, 3.7, periodic, periodic, true, 0.0},
      {"one row of blocks, 200x7", {200, 7}, 1.0, 5.0, dirichlet, dirichlet, true, fluid},
      {"one column, 1x70", {1, 70}, 1.0, 5.0, neumann, dirichlet, false, fluid},
      {"one cell", {1, 1}, 1.0, 5.0, dirichlet, dirichlet, false, fluid},
  };
  const SolverSettings to_tolerance{SolverKind::kIccg, 200, 1e-6};
  const SolverSettings presets{SolverKind::kIccg, 40, 1e-5};
  const SolverSettings five{SolverKind::kIccg, 5, 0.0};
  Tally tally;
  for (const OperatorCase& c : cases) {
    FieldF b(c.size, 1), x0(c.size, 1), warm(c.size, 1);
    fill_random(b, -1.0f, 1.5f, 7);  // a mean: not in the range of the singular ones
    fill_random(warm, -0.5f, 0.5f, 11);
    if (c.solid_wall_factor >= 0) {
      const Field<uint8_t> solid = solid_disc(c.size);
      for (int j = 0; j < c.size.y; ++j)
        for (int i = 0; i < c.size.x; ++i)
          if (solid(i, j)) b(i, j) = 0.0f;
    }
    for (const SolverSettings& s : {to_tolerance, presets, five}) {
      expect_iccg_matches(c, s, b, x0, tally);
      expect_iccg_matches(c, s, b, warm, tally);  // a warm start (the frame's)
    }
  }
  // b = 0 from x = 0: nothing to do (the C++ stops before its first iteration).
  const OperatorCase zero{"b = 0", {37, 23}, 1.0, 2.5, neumann, neumann, false, fluid};
  expect_iccg_matches(zero, to_tolerance, FieldF(zero.size, 1), FieldF(zero.size, 1), tally);
  std::printf("ICCG: %d solves, %d bit-identical to the C++, worst max relative difference %.3g\n",
              tally.cases, tally.identical, tally.worst);
}

// A factor follows the operator: a second operator factored on the same solver solves as a
// fresh C++ solver prepared on it.
TEST(ClIccgParity, RefactorsAfterTheOperatorChanges) {
  Fixture& d = device();
  ASSERT_TRUE(d.cl);
  if (!d.cl->has_fp64()) GTEST_SKIP() << "the device has no doubles: ICCG stays on the CPU";
  const Int2 size{45, 40};
  const SolverSettings settings{SolverKind::kIccg, 100, 1e-6};
  Dev dev{*d.ctx};
  OpenClIccg iccg(*d.cl, size);
  ClStencilOperator cl_op =
      ClStencilOperator::allocate(*d.ctx, size, BoundaryKind::kNeumann, BoundaryKind::kNeumann);
  FieldF b(size, 1);
  fill_random(b, -1.0f, 1.0f, 5);
  for (double scale : {0.5, 40.0}) {
    const StencilOperator op = assemble_stencil_operator(
        size, 1.0, scale, nullptr, BoundaryKind::kNeumann, BoundaryKind::kNeumann);
    auto cpu = LinearSolver::make(settings, size);
    cpu->prepare(op);
    FieldF x_cpu(size, 1);
    const SolveReport r = cpu->solve(op, b, x_cpu);
    cl_op.upload(*d.ctx, op);
    iccg.factor(cl_op);
    DeviceField db = dev.up(b), dx = dev.up(FieldF(size, 1));
    EXPECT_EQ(iccg.iterate(cl_op, db, dx, settings), r.iterations) << scale;
    EXPECT_LE(region_error(dev.down(dx), x_cpu, box_of_size(size)), kTolerance) << scale;
  }
}

// The wavefront walk (a GPU's) gives the sequential walk's bits (a CPU's, the C++ order), on
// every block shape: rows not a multiple of the 32-row blocks, a last block of one row, a lone
// block of 23 or 7 rows, one column, one cell, solid cells and a singular operator, from a cold and
// a warm start.
TEST(ClIccgParity, WavefrontWalkGivesTheSequentialBits) {
  Fixture& d = device();
  ASSERT_TRUE(d.cl);
  if (!d.cl->has_fp64()) GTEST_SKIP() << "the device has no doubles: ICCG stays on the CPU";
  const BoundaryKind neumann = BoundaryKind::kNeumann, dirichlet = BoundaryKind::kDirichlet,
                     periodic = BoundaryKind::kPeriodic;
  const OperatorCase cases[] = {
      {"per-face, Dirichlet, 129x65", {129, 65}, 1.0, 3.7, dirichlet, dirichlet, true, -1.0},
      {"per-face, obstacle, periodic, 77x33", {77, 33}, 1.0, 3.7, periodic, periodic, true, 0.0},
      {"pressure, Neumann, 40x97", {40, 97}, 0.0, 1.0, neumann, neumann, false, -1.0},
      {"a partial block of 23 rows, 37x23", {37, 23}, 1.0, 2.5, neumann, neumann, true, -1.0},
      {"a partial block of 7 rows, 200x7", {200, 7}, 1.0, 5.0, dirichlet, periodic, true, -1.0},
      {"one column, 1x70", {1, 70}, 1.0, 5.0, neumann, dirichlet, false, -1.0},
      {"one row, 90x1", {90, 1}, 1.0, 5.0, dirichlet, dirichlet, true, -1.0},
      {"one cell", {1, 1}, 1.0, 5.0, dirichlet, dirichlet, false, -1.0},
  };
  const SolverSettings settings{SolverKind::kIccg, 40, 1e-6};
  Dev dev{*d.ctx};
  for (const OperatorCase& c : cases) {
    const StencilOperator op = operator_of(c);
    ClStencilOperator cl_op = ClStencilOperator::allocate(*d.ctx, c.size, c.bx, c.by);
    cl_op.upload(*d.ctx, op);
    stencil::NullSpace null_space(c.size);
    null_space.analyse(op);
    FieldF b(c.size, 1), warm(c.size, 1);
    fill_random(b, -1.0f, 1.5f, 7);
    fill_random(warm, -0.5f, 0.5f, 11);
    const DeviceField mask = upload_mask(*d.ctx, null_space.mask());
    const ClNullSpace null{&mask, null_space.count(), null_space.consistent_norm2(b)};
    for (const FieldF& x0 : {FieldF(c.size, 1), warm}) {
      FieldF x[2];
      int iterations[2];
      for (auto walk : {OpenClIccg::BlockWalk::kSequential, OpenClIccg::BlockWalk::kWavefront}) {
        OpenClIccg iccg(*d.cl, c.size);
        iccg.set_block_walk(walk);
        iccg.factor(cl_op);
        DeviceField db = dev.up(b), dx = dev.up(x0);
        const int k = int(walk == OpenClIccg::BlockWalk::kWavefront);
        iterations[k] =
            iccg.iterate(cl_op, db, dx, settings, null_space.singular() ? &null : nullptr);
        x[k] = dev.down(dx);
      }
      EXPECT_EQ(iterations[1], iterations[0]) << c.name;
      EXPECT_GT(iterations[0], 0) << c.name;
      EXPECT_TRUE(difference(x[1], x[0]).identical) << c.name;
    }
  }
}

// The whole implicit step with ICCG: ImplicitDiffusion against OpenClDiffusion (its operator
// assembled and factored on the device, from the conductivity kernel's k), isotropic and
// anisotropic, Crank-Nicolson, every boundary kind with a Dirichlet value, around solid cells.
// Three steps each, so the isotropic operator is reused (its pivots too).
TEST(ClIccgParity, ImplicitDiffusionStepWithIccg) {
  Fixture& d = device();
  ASSERT_TRUE(d.cl);
  if (!d.cl->has_fp64()) GTEST_SKIP() << "the device has no doubles: ICCG stays on the CPU";
  Dev dev{*d.ctx};
  AnisotropyParams wk;
  wk.kind = AnisotropyKind::kWitkinKass;
  wk.a1 = 1.0f;
  wk.a2 = 0.1f;
  Tally tally;
  for (Int2 size : {Int2{129, 65}, Int2{37, 23}})
    for (BoundaryKind boundary :
         {BoundaryKind::kPeriodic, BoundaryKind::kNeumann, BoundaryKind::kDirichlet})
      for (bool crank : {false, true})
        for (bool anisotropic : {false, true})
          for (bool solid : {false, true}) {
            const std::string what =
                (std::to_string(size.x) + "x" + std::to_string(size.y) + " boundary " +
                 std::to_string(int(boundary)) + (crank ? " CN" : "") +
                 (anisotropic ? " witkin-kass" : " isotropic") + (solid ? " solid" : ""));
            SCOPED_TRACE(what);
            FieldF a(size, 1);
            fill_smooth(a, 0.5f, 0.4f, 0.7f);
            FieldF k(size, 1);
            conductivity_tile(a.view(), {}, k.view(), a.interior(), wk);
            const Field<uint8_t> mask = solid_disc(size);
            const SolverSettings settings{SolverKind::kIccg, 40, 1e-6};
            ImplicitDiffusion cpu(size, boundary, settings);
            if (solid) cpu.set_solid(&mask);
            OpenClDiffusion gpu(*d.cl, size, boundary, settings);
            const DeviceField dmask = upload_mask(*d.ctx, mask);
            FieldF ref = a;
            DeviceField da = dev.up(a), dk = dev.up(k);
            for (int step = 0; step < 3; ++step) {
              const DiffusionStep s{2.5 + step, 0.3f, crank};
              const SolveReport r_cpu = cpu.step(ref, anisotropic ? &k : nullptr, s);
              const SolveReport r_cl =
                  gpu.step(da, anisotropic ? &dk : nullptr, s, solid ? &dmask : nullptr);
              EXPECT_EQ(r_cl.iterations, r_cpu.iterations) << "step " << step;
              EXPECT_NEAR(r_cl.relative_residual, r_cpu.relative_residual,
                          kResidualAgreement * r_cpu.relative_residual + 1e-12)
                  << "step " << step;
            }
            const FieldF out = dev.down(da);
            EXPECT_LE(relative_error(out, ref, a, a.interior()), kTolerance);
            const Difference diff = difference(out, ref);
            tally.add(diff);
            if (solid)  // solid cells keep their value
              for (int j = 0; j < size.y; ++j)
                for (int i = 0; i < size.x; ++i)
                  if (mask(i, j)) {
                    ASSERT_EQ(out(i, j), a(i, j)) << i << ", " << j;
                  }
          }
  std::printf(
      "ICCG diffusion: %d cases of 3 steps, %d bit-identical to the C++, worst max "
      "relative difference %.3g\n",
      tally.cases, tally.identical, tally.worst);
}

// Solid cells in the device's diffusion with the real-time sweeps too (the operator's
// isolation and the right-hand side are the solver's inputs, whatever the solver).
TEST(ClIccgParity, ImplicitDiffusionSweepsAroundSolidCells) {
  Fixture& d = device();
  ASSERT_TRUE(d.cl);
  Dev dev{*d.ctx};
  const Int2 size{53, 37};
  for (SolverKind kind : {SolverKind::kJacobi, SolverKind::kRedBlackGaussSeidel})
    for (BoundaryKind boundary : {BoundaryKind::kNeumann, BoundaryKind::kDirichlet}) {
      SCOPED_TRACE(std::string(solver_kind_name(kind)) + " boundary " +
                   std::to_string(int(boundary)));
      FieldF a(size, 1);
      fill_smooth(a, 0.5f, 0.4f, 0.2f);
      const Field<uint8_t> mask = solid_disc(size);
      const SolverSettings settings{kind, 12, 0.0};
      ImplicitDiffusion cpu(size, boundary, settings);
      cpu.set_solid(&mask);
      OpenClDiffusion gpu(*d.cl, size, boundary, settings);
      const DeviceField dmask = upload_mask(*d.ctx, mask);
      FieldF ref = a;
      DeviceField da = dev.up(a);
      const DiffusionStep s{2.5, 0.3f, false};
      const SolveReport r_cpu = cpu.step(ref, nullptr, s);
      const SolveReport r_cl = gpu.step(da, nullptr, s, &dmask);
      EXPECT_EQ(r_cl.iterations, r_cpu.iterations);
      EXPECT_NEAR(r_cl.relative_residual, r_cpu.relative_residual,
                  kResidualAgreement * r_cpu.relative_residual);
      EXPECT_LE(relative_error(dev.down(da), ref, a, a.interior()), kTolerance);
    }
}

}  // namespace
}  // namespace ardcell
