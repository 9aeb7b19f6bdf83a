// Multigrid V-cycles on the OpenCL device (OpenClDevice::solve, PoCL in CI) against
// kernels/multigrid_solver.cpp on the CPU: the same cycle on the same coarse operators. On PoCL
// the two give the same bits (the C++ sweeps are compiled without fma contraction, as the .cl
// files are); the bounds leave room for a device that rounds a division differently: the
// solution within 1e-5 relative (max norm, max |cl - cpu| / max |cpu|), the same cycle count,
// and the reported relative residual within a few per cent (near float round-off the solutions'
// last bits move it that much; a wrong cycle would be orders away). Operators: the pressure Poisson
// operator (singular, Neumann, with a right-hand side outside the range), a viscosity operator
// (identity + diffusion, Dirichlet walls), periodic on odd sizes (red-black order across the seam),
// and both around solid cells, at 127 x 93 and 45 x 31. The same for ICCG solves (OpenClIccg on
// the uploaded operator, its pivots factored on the device after each upload): the same
// iteration count, the null-space projection of the singular ones included.
#if defined(ARDCELL_WITH_OPENCL)
#include <gtest/gtest.h>

#include <cstdio>
#include <random>
#include <string>

#include "host/engine/opencl_device.h"
#include "kernels/linear_solver.h"
#include "tests/support/field_compare.h"
#include "tests/support/opencl_test_device.h"
#include "tests/support/solid_disc.h"

namespace ardcell {
namespace {

constexpr double kTolerance = 1e-5;
constexpr double kResidualAgreement = 0.05;

FieldF random_field(Int2 size, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> dist(-1.0f, 1.0f);
  FieldF f(size, 1);
  for (int j = 0; j < size.y; ++j)
    for (int i = 0; i < size.x; ++i) f(i, j) = dist(rng) + 0.25f;  // a mean: not in the range
  return f;
}

struct Case {
  std::string name;
  Int2 size;
  double identity, scale;
  BoundaryKind boundary;
  double solid_wall_factor;  // < 0: no solid cells
  SolverSettings settings;
};

StencilOperator operator_of(const Case& c) {
  StencilOperator op =
      assemble_stencil_operator(c.size, c.identity, c.scale, nullptr, c.boundary, c.boundary);
  if (c.solid_wall_factor >= 0) isolate_solid_cells(op, solid_disc(c.size), c.solid_wall_factor);
  return op;
}

// Solves op x = b from x = x0 on the CPU and on the device (one solver, prepared on op) and
// compares the solutions and reports.
void expect_device_matches_cpu(OpenClDevice& device, LinearSolver& solver,
                               const StencilOperator& op, const FieldF& b, const FieldF& x0,
                               const std::string& what) {
  FieldF x_cpu = x0, x_cl = x0;
  const SolveReport cpu = solver.solve(op, b, x_cpu);
  device.host_wrote(x_cl);
  device.host_wrote(b);
  const SolveReport cl = device.solve(solver, op, b, x_cl);
  device.sync_to_host(x_cl);
  const double error = max_relative_error(x_cl, x_cpu);
  std::printf("%s: %d iterations, residual cpu %.3g device %.3g, max relative difference %.3g\n",
              what.c_str(), cpu.iterations, cpu.relative_residual, cl.relative_residual, error);
  EXPECT_LE(error, kTolerance) << what;
  EXPECT_EQ(cl.iterations, cpu.iterations) << what;
  EXPECT_NEAR(cl.relative_residual, cpu.relative_residual,
              kResidualAgreement * cpu.relative_residual)
      << what;
}

// The cases' boundaries, and no solid cells (Case::solid_wall_factor).
constexpr BoundaryKind neumann = BoundaryKind::kNeumann, dirichlet = BoundaryKind::kDirichlet,
                       periodic = BoundaryKind::kPeriodic;
constexpr double fluid = -1.0;

// A case from x = 0 and from a non-zero guess (the frame's warm start), on one device (the
// second solve on what the first uploaded: levels, pivots).
void expect_case_matches_cpu(const Case& c) {
  OpenClDevice device(*test_opencl_device()->ctx, RowExecutor::serial());
  device.reserve(c.size);
  const StencilOperator op = operator_of(c);
  auto solver = LinearSolver::make(c.settings, c.size);
  solver->prepare(op);
  if (c.settings.kind == SolverKind::kMultigrid) {
    ASSERT_GT(solver->coarse_levels(), 0) << c.name;
  }
  FieldF b = random_field(c.size, 7);
  if (c.solid_wall_factor >= 0) {
    const Field<uint8_t> solid = solid_disc(c.size);
    for (int j = 0; j < c.size.y; ++j)
      for (int i = 0; i < c.size.x; ++i)
        if (solid(i, j)) b(i, j) = 0.0f;
  }
  testing::internal::CaptureStderr();
  expect_device_matches_cpu(device, *solver, op, b, FieldF(c.size, 1), c.name + ", x0 = 0");
  expect_device_matches_cpu(device, *solver, op, b, random_field(c.size, 11),
                            c.name + ", warm start");
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "") << c.name << ": no fallback line";
}

// After the host re-assembles an operator (a new dt or viscosity), prepare() and host_wrote(op)
// bring the new operator to the device (multigrid: its coarse operators; ICCG: factored anew).
void expect_rewritten_operator_followed(const SolverSettings& settings) {
  const Int2 size{45, 31};
  OpenClDevice device(*test_opencl_device()->ctx, RowExecutor::serial());
  device.reserve(size);
  StencilOperator op = assemble_stencil_operator(size, 1.0, 0.5, nullptr, BoundaryKind::kNeumann,
                                                 BoundaryKind::kDirichlet);
  auto solver = LinearSolver::make(settings, size);
  solver->prepare(op);
  const FieldF b = random_field(size, 3);
  const std::string kind(solver_kind_name(settings.kind));
  expect_device_matches_cpu(device, *solver, op, b, FieldF(size, 1), kind + ", scale 0.5");
  reassemble_stencil_operator(op, 1.0, 40.0, nullptr);
  solver->prepare(op);
  device.host_wrote(op);
  expect_device_matches_cpu(device, *solver, op, b, FieldF(size, 1),
                            kind + ", scale 40, rewritten");
}

TEST(OpenClMultigrid, MatchesTheCpuSolver) {
  if (!test_opencl_device()) GTEST_SKIP() << "no OpenCL device (no ICD or no platform)";
  const SolverSettings to_tolerance{SolverKind::kMultigrid, 20, 1e-6};
  const SolverSettings viscous{SolverKind::kMultigrid, 8, 1e-6};
  const SolverSettings three_cycles{SolverKind::kMultigrid, 3, 0.0};
  const Case cases[] = {
      {"pressure, Neumann, 127x93", {127, 93}, 0.0, 1.0, neumann, fluid, to_tolerance},
      {"pressure, Neumann, 45x31", {45, 31}, 0.0, 1.0, neumann, fluid, to_tolerance},
      {"pressure, Neumann, 3 cycles", {127, 93}, 0.0, 1.0, neumann, fluid, three_cycles},
      {"viscosity, Dirichlet, 127x93", {127, 93}, 1.0, 2.5, dirichlet, fluid, viscous},
      {"viscosity, Dirichlet, 45x31", {45, 31}, 1.0, 2.5, dirichlet, fluid, viscous},
      {"pressure, periodic, 45x31", {45, 31}, 0.0, 1.0, periodic, fluid, to_tolerance},
      {"viscosity, periodic, 127x93", {127, 93}, 1.0, 2.5, periodic, fluid, viscous},
      {"pressure, obstacle, 127x93", {127, 93}, 0.0, 1.0, neumann, 0.0, to_tolerance},
      {"viscosity, obstacle, 45x31", {45, 31}, 1.0, 2.5, neumann, 2.0, viscous},
  };
  for (const Case& c : cases) expect_case_matches_cpu(c);
}

TEST(OpenClIccgSolve, MatchesTheCpuSolver) {
  if (!test_opencl_device()) GTEST_SKIP() << "no OpenCL device (no ICD or no platform)";
  if (!test_opencl_device()->cl->has_fp64()) GTEST_SKIP() << "no doubles: ICCG on the CPU";
  const SolverSettings to_tolerance{SolverKind::kIccg, 300, 1e-6};
  const SolverSettings viscous{SolverKind::kIccg, 40, 1e-6};
  const SolverSettings five{SolverKind::kIccg, 5, 0.0};
  const Case cases[] = {
      {"iccg pressure, Neumann, 127x93", {127, 93}, 0.0, 1.0, neumann, fluid, to_tolerance},
      {"iccg pressure, Neumann, 5 iterations", {45, 31}, 0.0, 1.0, neumann, fluid, five},
      {"iccg viscosity, Dirichlet, 127x93", {127, 93}, 1.0, 2.5, dirichlet, fluid, viscous},
      {"iccg pressure, periodic, 45x31", {45, 31}, 0.0, 1.0, periodic, fluid, to_tolerance},
      {"iccg pressure, obstacle, 127x93", {127, 93}, 0.0, 1.0, neumann, 0.0, to_tolerance},
      {"iccg viscosity, obstacle, 45x31", {45, 31}, 1.0, 2.5, neumann, 2.0, viscous},
  };
  for (const Case& c : cases) expect_case_matches_cpu(c);
}

// After the host re-assembles an operator (a new dt or viscosity), prepare() and host_wrote(op)
// bring the new fine and coarse operators to the device.
TEST(OpenClMultigrid, FollowsAnOperatorTheHostRewrote) {
  if (!test_opencl_device()) GTEST_SKIP() << "no OpenCL device (no ICD or no platform)";
  expect_rewritten_operator_followed({SolverKind::kMultigrid, 8, 1e-6});
}

// The same for ICCG: host_wrote(op) uploads the new operator, whose pivots are factored anew.
TEST(OpenClIccgSolve, FollowsAnOperatorTheHostRewrote) {
  if (!test_opencl_device()) GTEST_SKIP() << "no OpenCL device (no ICD or no platform)";
  if (!test_opencl_device()->cl->has_fp64()) GTEST_SKIP() << "no doubles: ICCG on the CPU";
  expect_rewritten_operator_followed({SolverKind::kIccg, 40, 1e-6});
}

}  // namespace
}  // namespace ardcell
#endif
