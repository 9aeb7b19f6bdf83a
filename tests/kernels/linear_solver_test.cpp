#include "kernels/linear_solver.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <numbers>
#include <random>
#include <string>

#include "kernels/solver_common.h"
#include "kernels/stencil_sweeps.h"
#include "runtime/thread/thread_backend.h"

namespace ardcell {
namespace {

FieldF random_field(Int2 size, unsigned seed, float lo = -1.0f, float hi = 1.0f) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> dist(lo, hi);
  FieldF f(size, 1);
  for (int j = 0; j < size.y; ++j)
    for (int i = 0; i < size.x; ++i) f(i, j) = dist(rng);
  return f;
}

double dot(const FieldF& a, const FieldF& b) {
  double s = 0.0;
  for (int j = 0; j < a.ny(); ++j)
    for (int i = 0; i < a.nx(); ++i) s += double(a(i, j)) * b(i, j);
  return s;
}

// Reference y = A x straight from the definition in stencil_operator.h, in double.
double reference_apply(const StencilOperator& op, const FieldF& x, int i, int j) {
  const int nx = op.size.x, ny = op.size.y;
  auto at = [&](int a, int c) -> double {
    if (op.boundary_x == BoundaryKind::kPeriodic) a = (a + nx) % nx;
    if (op.boundary_y == BoundaryKind::kPeriodic) c = (c + ny) % ny;
    if (a < 0 || a >= nx || c < 0 || c >= ny) return 0.0;  // weight is 0 there anyway
    return x(a, c);
  };
  return double(op.diag(i, j)) * x(i, j) - op.wx(i, j) * at(i - 1, j) -
         op.wx(i + 1, j) * at(i + 1, j) - op.wy(i, j) * at(i, j - 1) -
         op.wy(i, j + 1) * at(i, j + 1);
}

TEST(StencilOperator, ApplyMatchesDefinitionAndIsSymmetric) {
  const Int2 size{13, 9};
  const FieldF k = random_field(size, 1, 0.5f, 2.0f);
  for (BoundaryKind bx :
       {BoundaryKind::kPeriodic, BoundaryKind::kNeumann, BoundaryKind::kDirichlet})
    for (BoundaryKind by :
         {BoundaryKind::kPeriodic, BoundaryKind::kNeumann, BoundaryKind::kDirichlet}) {
      const StencilOperator op = assemble_stencil_operator(size, 0.5, 3.0, &k, bx, by);
      const FieldF x = random_field(size, 2), z = random_field(size, 3);
      FieldF ax(size, 1), az(size, 1);
      apply_stencil_operator(op, x, ax);
      apply_stencil_operator(op, z, az);
      for (int j = 0; j < size.y; ++j)
        for (int i = 0; i < size.x; ++i)
          ASSERT_NEAR(ax(i, j), reference_apply(op, x, i, j), 1e-4) << i << "," << j;
      EXPECT_NEAR(dot(z, ax), dot(x, az), 1e-4 * std::abs(dot(x, ax)));
    }
}

TEST(StencilOperator, FaceWeightsAverageConductivity) {
  const Int2 size{4, 3};
  FieldF k(size, 1);
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 4; ++i) k(i, j) = float(1 + i + 10 * j);
  const StencilOperator op = assemble_stencil_operator(size, 1.0, 2.0, &k, BoundaryKind::kNeumann,
                                                       BoundaryKind::kDirichlet);
  EXPECT_FLOAT_EQ(op.wx(2, 1), 2.0f * 0.5f * (k(1, 1) + k(2, 1)));
  EXPECT_FLOAT_EQ(op.wy(3, 2), 2.0f * 0.5f * (k(3, 1) + k(3, 2)));
  EXPECT_EQ(op.wx(0, 1), 0.0f);  // Neumann: no flux
  EXPECT_EQ(op.wy(1, 0), 0.0f);  // Dirichlet: no coupling, weight on the diagonal
  // Cell (0, 0): identity + right face + top face + Dirichlet bottom face (scale * k).
  EXPECT_FLOAT_EQ(op.diag(0, 0), 1.0f + op.wx(1, 0) + op.wy(0, 1) + 2.0f * k(0, 0));
}

// Geometric-mean residual reduction per sweep between sweeps `from` and `to`.
template <class Sweep>
double measured_rate(const StencilOperator& op, FieldF x, int from, int to, Sweep sweep) {
  const FieldF b(op.size, 1);
  double r_from = 0.0;
  for (int k = 1; k <= to; ++k) {
    sweep(op, b, x);
    if (k == from) r_from = std::sqrt(stencil::residual(op, b, x, nullptr));
  }
  const double r_to = std::sqrt(stencil::residual(op, b, x, nullptr));
  return std::pow(r_to / r_from, 1.0 / (to - from));
}

// Model problem: Dirichlet Poisson (and implicit diffusion) on n x m cells. The Jacobi iteration
// matrix I - D^-1 A has spectral radius rho_J = 2s (cos(pi/(n+1)) + cos(pi/(m+1))) / (c + 4s);
// red-black Gauss-Seidel (consistently ordered) has rho_J^2 per full sweep.
TEST(LinearSolver, JacobiAndRedBlackContractAtTheSpectralRadius) {
  const Int2 size{16, 12};
  for (double identity : {0.0, 1.0}) {
    const double s = 1.0;
    const StencilOperator op = assemble_stencil_operator(
        size, identity, s, nullptr, BoundaryKind::kDirichlet, BoundaryKind::kDirichlet);
    const double rho_j =
        2.0 * s *
        (std::cos(std::numbers::pi / (size.x + 1)) + std::cos(std::numbers::pi / (size.y + 1))) /
        (identity + 4.0 * s);
    const FieldF x0 = random_field(size, 7);
    FieldF scratch(size, 1);
    const double jacobi = measured_rate(op, x0, 200, 300, [&](auto& o, auto& b, FieldF& x) {
      stencil::jacobi_sweep(o, b, x, scratch);
      std::swap(x, scratch);
    });
    const double rbgs = measured_rate(
        op, x0, 80, 130, [](auto& o, auto& b, FieldF& x) { stencil::rbgs_sweep(o, b, x); });
    EXPECT_NEAR(jacobi, rho_j, 2e-3) << "identity " << identity;
    EXPECT_NEAR(rbgs, rho_j * rho_j, 2e-3) << "identity " << identity;
    std::printf("identity %.0f: Jacobi %.5f (theory %.5f), RBGS %.5f (theory %.5f)\n", identity,
                jacobi, rho_j, rbgs, rho_j * rho_j);
  }
}

TEST(LinearSolver, FixedSweepsReportIterationsAndReduceResidual) {
  const Int2 size{24, 24};
  const StencilOperator op = assemble_stencil_operator(
      size, 1.0, 2.0, nullptr, BoundaryKind::kNeumann, BoundaryKind::kNeumann);
  const FieldF b = random_field(size, 11);
  for (SolverKind kind : {SolverKind::kJacobi, SolverKind::kRedBlackGaussSeidel}) {
    auto solver = LinearSolver::make({kind, 20, 0.0}, size);
    solver->prepare(op);
    FieldF x(size, 1);
    const SolveReport report = solver->solve(op, b, x);
    EXPECT_EQ(report.iterations, 20);
    EXPECT_LT(report.relative_residual, 0.1);
    FieldF r(size, 1);
    const double rr = std::sqrt(stencil::residual(op, b, x, &r) / stencil::norm2_squared(b));
    EXPECT_NEAR(report.relative_residual, rr, 1e-6);
  }
}

struct Case {
  const char* name;
  BoundaryKind bx, by;
  double identity;
  bool conductivity;
};

class AccurateSolvers : public ::testing::TestWithParam<Case> {};

// ICCG and multigrid both reach the tolerance and agree with each other (and with A x = b).
TEST_P(AccurateSolvers, IccgAndMultigridConvergeAndAgree) {
  const Case c = GetParam();
  const Int2 size{40, 28};
  const FieldF k = random_field(size, 5, 0.2f, 3.0f);
  const StencilOperator op =
      assemble_stencil_operator(size, c.identity, 1.0, c.conductivity ? &k : nullptr, c.bx, c.by);
  FieldF b = random_field(size, 9);
  FieldF x_cg(size, 1), x_mg(size, 1);
  auto cg = LinearSolver::make({SolverKind::kIccg, 500, 1e-6}, size);
  auto mg = LinearSolver::make({SolverKind::kMultigrid, 60, 1e-6}, size);
  cg->prepare(op);
  mg->prepare(op);
  const SolveReport rc = cg->solve(op, b, x_cg);
  const SolveReport rm = mg->solve(op, b, x_mg);
  std::printf("%s: ICCG %d iterations, residual %.2e; MG %d cycles, residual %.2e\n", c.name,
              rc.iterations, rc.relative_residual, rm.iterations, rm.relative_residual);
  EXPECT_LE(rc.relative_residual, 2e-6);
  EXPECT_LE(rm.relative_residual, 2e-6);
  EXPECT_LT(rm.iterations, 25);
  double diff = 0.0, scale = 0.0;
  for (int j = 0; j < size.y; ++j)
    for (int i = 0; i < size.x; ++i) {
      diff = std::max(diff, double(std::abs(x_cg(i, j) - x_mg(i, j))));
      scale = std::max(scale, double(std::abs(x_cg(i, j))));
    }
  EXPECT_LT(diff, 1e-4 * scale) << c.name;
}

INSTANTIATE_TEST_SUITE_P(
    Boundaries, AccurateSolvers,
    ::testing::Values(
        Case{"NeumannPoisson", BoundaryKind::kNeumann, BoundaryKind::kNeumann, 0.0, false},
        Case{"PeriodicPoisson", BoundaryKind::kPeriodic, BoundaryKind::kPeriodic, 0.0, false},
        Case{"DirichletPoisson", BoundaryKind::kDirichlet, BoundaryKind::kDirichlet, 0.0, false},
        Case{"MixedDiffusion", BoundaryKind::kPeriodic, BoundaryKind::kDirichlet, 0.1, true},
        Case{"NeumannConductivity", BoundaryKind::kNeumann, BoundaryKind::kNeumann, 0.0, true}),
    [](const auto& info) { return std::string(info.param.name); });

TEST(LinearSolver, ParsesSolverNames) {
  SolverKind kind{};
  for (SolverKind k : {SolverKind::kJacobi, SolverKind::kRedBlackGaussSeidel, SolverKind::kIccg,
                       SolverKind::kMultigrid}) {
    ASSERT_TRUE(parse_solver_kind(solver_kind_name(k), kind));
    EXPECT_EQ(kind, k);
  }
  EXPECT_FALSE(parse_solver_kind("sor", kind));
}

}  // namespace
}  // namespace ardcell

namespace ardcell {
namespace {

// Every solver, with a tolerance (so its residual reductions steer the iteration count), gives
// the same bits on the serial back end and on 1 to 4 threads-back-end workers.
TEST(LinearSolver, SameBitsOnAnyWorkerCount) {
  const Int2 size{131, 97};
  StencilOperator op = assemble_stencil_operator(size, 0.0, 1.0, nullptr, BoundaryKind::kNeumann,
                                                 BoundaryKind::kPeriodic);
  FieldF b = random_field(size, 11);
  for (SolverKind kind : {SolverKind::kJacobi, SolverKind::kRedBlackGaussSeidel, SolverKind::kIccg,
                          SolverKind::kMultigrid}) {
    const SolverSettings settings{kind, kind == SolverKind::kMultigrid ? 10 : 60, 1e-7};
    FieldF reference(size, 1);
    SolveReport expected{};
    {
      auto solver = LinearSolver::make(settings, size);
      solver->prepare(op);
      expected = solver->solve(op, b, reference);
    }
    for (int workers : {1, 2, 3, 4}) {
      ThreadBackendOptions o;
      o.workers = workers;
      ThreadBackend backend(o);
      RowExecutor ex(backend);
      auto solver = LinearSolver::make(settings, size, ex);
      solver->prepare(op);
      FieldF x(size, 1);
      const SolveReport got = solver->solve(op, b, x);
      EXPECT_EQ(got.iterations, expected.iterations) << solver_kind_name(kind) << " " << workers;
      EXPECT_EQ(std::memcmp(&got.relative_residual, &expected.relative_residual, sizeof(double)), 0)
          << solver_kind_name(kind) << " " << workers;
      EXPECT_EQ(std::memcmp(x.raw(), reference.raw(), x.raw_size() * sizeof(float)), 0)
          << solver_kind_name(kind) << " " << workers;
    }
  }
}

// Rows whose middle cells share one diagonal and one face weight sweep without reading the
// coefficient arrays, with the same bits: isotropic operators of every boundary kind, with solid
// cells (their rows are not uniform) and a scaled patch of conductivity (nor are those).
TEST(UniformRows, JacobiSweepGivesTheSameBitsWithAndWithout) {
  const Int2 size{131, 97};
  for (BoundaryKind bx :
       {BoundaryKind::kPeriodic, BoundaryKind::kNeumann, BoundaryKind::kDirichlet})
    for (BoundaryKind by :
         {BoundaryKind::kPeriodic, BoundaryKind::kNeumann, BoundaryKind::kDirichlet}) {
      FieldF k(size, 1);
      k.fill(1.0f);
      for (int j = 60; j < 70; ++j)
        for (int i = 10; i < 20; ++i) k(i, j) = 1.5f;
      StencilOperator op = assemble_stencil_operator(size, 1.0, 3.7, &k, bx, by);
      Field<uint8_t> solid(size, 1);
      for (int j = 20; j < 30; ++j)
        for (int i = 40; i < 50; ++i) solid(i, j) = 1;
      isolate_solid_cells(op, solid, 2.0);
      stencil::UniformRows rows(size.y);
      rows.analyse(op);
      int uniform = 0;
      for (int j = 0; j < size.y; ++j) uniform += rows.uniform(j) ? 1 : 0;
      // Rows 19..30 touch the solid block, 59..70 the conductivity patch; the edge rows of a
      // non-periodic y have boundary faces of weight 0 (or moved to the diagonal).
      const int edge_rows = by == BoundaryKind::kPeriodic ? 0 : 2;
      EXPECT_EQ(uniform, size.y - 12 - 12 - edge_rows) << int(bx) << int(by);
      const FieldF b = random_field(size, 31), x = random_field(size, 32);
      FieldF plain(size, 1), fast(size, 1);
      stencil::jacobi_sweep(op, b, x, plain);
      stencil::jacobi_sweep(op, b, x, fast, RowExecutor::serial(), &rows);
      EXPECT_EQ(std::memcmp(plain.raw(), fast.raw(), plain.raw_size() * sizeof(float)), 0)
          << int(bx) << int(by);
    }
}

// Temporally blocked Jacobi gives the bits of sweep-by-sweep Jacobi: every boundary kind, with
// solid cells and a conductivity patch (rows that are not uniform), on grids whose bands are
// thinner than the sweeps' cones (two bands of 4 or 5 rows, wrapping or not), for 1 to kMaxSweeps
// sweeps, serial and on 2 to 4 workers; and the residual and right-hand side norms the same pass
// returns, with the bits of the passes of their own.
TEST(JacobiBlocking, SameBitsAsSweepBySweep) {
  std::vector<std::unique_ptr<ThreadBackend>> backends;
  std::vector<std::unique_ptr<RowExecutor>> executors;
  for (int workers : {2, 3, 4}) {
    ThreadBackendOptions o;
    o.workers = workers;
    backends.push_back(std::make_unique<ThreadBackend>(o));
    executors.push_back(std::make_unique<RowExecutor>(*backends.back()));
  }
  for (Int2 size : {Int2{131, 97}, Int2{1024, 9}, Int2{2048, 8}, Int2{3, 40}})
    for (BoundaryKind bx : {BoundaryKind::kPeriodic, BoundaryKind::kNeumann})
      for (BoundaryKind by :
           {BoundaryKind::kPeriodic, BoundaryKind::kNeumann, BoundaryKind::kDirichlet}) {
        FieldF k(size, 1);
        k.fill(1.0f);
        for (int j = size.y / 3; j < size.y / 2; ++j)
          for (int i = 0; i < size.x / 4; ++i) k(i, j) = 1.5f;
        StencilOperator op = assemble_stencil_operator(size, 1.0, 2.3, &k, bx, by);
        Field<uint8_t> solid(size, 1);
        solid(size.x / 2, size.y - 2) = 1;
        isolate_solid_cells(op, solid, 2.0);
        stencil::UniformRows rows(size.y);
        rows.analyse(op);
        const FieldF b = random_field(size, 41), x = random_field(size, 42);
        for (int sweeps : {1, 2, 7, stencil::JacobiBlocking::kMaxSweeps}) {
          FieldF ping = x, pong(size, 1);
          for (int s = 0; s < sweeps; ++s) {
            stencil::jacobi_sweep(op, b, ping, pong, RowExecutor::serial(), &rows);
            std::swap(ping, pong);
          }
          std::vector<RowExecutor*> all{&RowExecutor::serial()};
          for (auto& e : executors) all.push_back(e.get());
          for (RowExecutor* ex : all) {
            stencil::JacobiBlocking blocking(size, ex->workers());
            FieldF out(size, 1);
            stencil::JacobiBlocking::Norms norms;
            blocking.sweeps(op, b, x, out, sweeps, *ex, &rows,
                            ex->workers() > 2 ? &norms : nullptr);
            const std::string where = std::to_string(size.x) + "x" + std::to_string(size.y) +
                                      " bx " + std::to_string(int(bx)) + " by " +
                                      std::to_string(int(by)) + " " + std::to_string(sweeps) +
                                      " sweeps, " + std::to_string(ex->workers()) + " workers";
            for (int j = 0; j < size.y; ++j)
              ASSERT_EQ(std::memcmp(out.row(j), ping.row(j), sizeof(float) * size_t(size.x)), 0)
                  << where << ", row " << j;
            if (ex->workers() > 2) {
              // The fused norms: residual()'s and norm2_squared()'s bits.
              const double residual2 = stencil::residual(op, b, ping, nullptr);
              const double rhs2 = stencil::norm2_squared(b);
              EXPECT_EQ(std::memcmp(&norms.residual2, &residual2, sizeof(double)), 0) << where;
              EXPECT_EQ(std::memcmp(&norms.rhs2, &rhs2, sizeof(double)), 0) << where;
            }
          }
        }
      }
}

// A fixed-sweep Jacobi solve, sweep by sweep or temporally blocked (32 + 13 sweeps, the residual
// report fused into the last pass for a non-singular operator), gives the solution and the
// report of sweeping one sweep at a time and taking the residual afterwards, on 1 to 4 workers;
// also for the singular pure-Neumann Poisson operator (null-space mean removed before the
// residual).
TEST(LinearSolver, FixedSweepJacobiMatchesSweepBySweep) {
  const Int2 size{131, 97};
  for (double alpha : {0.0, 1.0}) {
    const StencilOperator op = assemble_stencil_operator(
        size, alpha, 2.5, nullptr, BoundaryKind::kNeumann, BoundaryKind::kNeumann);
    FieldF b = random_field(size, 51);
    const FieldF x0 = random_field(size, 52);
    stencil::NullSpace null_space(size);
    null_space.analyse(op);
    ASSERT_EQ(null_space.singular(), alpha == 0.0);
    FieldF ping = x0, pong(size, 1);
    for (int s = 0; s < 45; ++s) {
      stencil::jacobi_sweep(op, b, ping, pong);
      std::swap(ping, pong);
    }
    null_space.remove_mean(ping);
    const double bb = null_space.consistent_norm2(b);
    const double rr = null_space.consistent_part(stencil::residual(op, b, ping, &pong), pong,
                                                 RowExecutor::serial());
    const double expected = bb > 0.0 ? std::sqrt(rr / bb) : std::sqrt(rr);
    for (int workers : {1, 2, 3, 4})
      for (bool blocked : {false, true}) {
        ThreadBackendOptions o;
        o.workers = workers;
        ThreadBackend backend(o);
        RowExecutor ex(backend);
        auto solver =
            solver_detail::make_jacobi_solver({SolverKind::kJacobi, 45, 0.0}, size, ex, blocked);
        solver->prepare(op);
        FieldF x = x0;
        const SolveReport got = solver->solve(op, b, x);
        const std::string where = std::to_string(alpha) + ", " + std::to_string(workers) +
                                  " workers, " + (blocked ? "blocked" : "sweep by sweep");
        EXPECT_EQ(got.iterations, 45);
        EXPECT_EQ(std::memcmp(&got.relative_residual, &expected, sizeof(double)), 0)
            << where << ": " << got.relative_residual << " vs " << expected;
        for (int j = 0; j < size.y; ++j)
          ASSERT_EQ(std::memcmp(x.row(j), ping.row(j), sizeof(float) * std::size_t(size.x)), 0)
              << where << ", row " << j;
      }
  }
}

// Multigrid around an obstacle: the pressure operator (Neumann walls and disc) converges to its
// tolerance. The solid cells' identity rows are decoupled: a coarse cell that aggregates fluid
// and solid cells must not take their identity into its diagonal (that pinned the coarse
// correction near the disc, and the cycles stalled at a relative residual of ~1e-2).
TEST(LinearSolver, MultigridConvergesAroundSolidCells) {
  for (Int2 size : {Int2{127, 93}, Int2{128, 256}}) {
    StencilOperator op = assemble_stencil_operator(size, 0.0, 1.0, nullptr, BoundaryKind::kNeumann,
                                                   BoundaryKind::kNeumann);
    Field<uint8_t> solid(size, 1);
    const double cx = size.x * 0.5, cy = size.y * 0.4, r = size.x * 0.12;
    for (int j = 0; j < size.y; ++j)
      for (int i = 0; i < size.x; ++i)
        solid(i, j) = (i + 0.5 - cx) * (i + 0.5 - cx) + (j + 0.5 - cy) * (j + 0.5 - cy) <= r * r;
    isolate_solid_cells(op, solid, 0.0);
    FieldF b = random_field(size, 41);
    double sum = 0.0;
    int64_t fluid = 0;
    for (int j = 0; j < size.y; ++j)
      for (int i = 0; i < size.x; ++i)
        if (solid(i, j)) {
          b(i, j) = 0.0f;
        } else {
          sum += b(i, j);
          ++fluid;
        }
    for (int j = 0; j < size.y; ++j)
      for (int i = 0; i < size.x; ++i)
        if (!solid(i, j)) b(i, j) -= float(sum / double(fluid));
    auto solver = LinearSolver::make({SolverKind::kMultigrid, 30, 1e-6}, size);
    solver->prepare(op);
    FieldF x(size, 1);
    const SolveReport report = solver->solve(op, b, x);
    EXPECT_LE(report.relative_residual, 1e-5) << size << " after " << report.iterations;
    EXPECT_LE(report.iterations, 15) << size;
  }
}

}  // namespace
}  // namespace ardcell
