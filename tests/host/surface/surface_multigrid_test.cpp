// Multigrid V-cycles for implicit diffusion on patched surfaces (host/surface/surface_multigrid.h):
// the same solution as Jacobi sweeps to the tolerance, in a few cycles where Jacobi stalls (a step
// much longer than the grid's diffusion time), the total conserved, the same bits on any number
// of workers; on the torus (regular) and the cube-sphere (extraordinary vertices of valence 3);
// the Poisson problem on stretched patches in few cycles (BiCGSTAB over them).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "host/surface/procedural_mesh.h"
#include "host/surface/surface_multigrid.h"
#include "runtime/row_executor.h"
#include "runtime/thread/thread_backend.h"
#include "tests/host/surface/surface_test_util.h"

namespace ardcell {
namespace {

using surface_test::random_field;

double max_diff(const PatchGrid& g, const PatchField& a, const PatchField& b) {
  double m = 0;
  for (int p = 0; p < g.patches(); ++p)
    for (int j = 0; j < g.n(); ++j)
      for (int i = 0; i < g.n(); ++i)
        m = std::max(m, std::abs(a[g.index(p, i, j)] - b[g.index(p, i, j)]));
  return m;
}

struct Surfaces {
  LimitSurface torus, cube;
  Surfaces() {
    EXPECT_TRUE(LimitSurface::build(torus_mesh(8, 4, 2, 1), {}, torus).is_ok());
    EXPECT_TRUE(LimitSurface::build(rotate_faces(cube_mesh(1), 3), {}, cube).is_ok());
  }
};

// c in units of a cell's area: c / h^2 of a typical cell.
double stiffness(const SurfaceLaplacian& op, double c) {
  return c / (op.area() / (op.patches() * op.n() * op.n()));
}

TEST(SurfaceMultigrid, AgreesWithJacobiAndConservesTheTotal) {
  Surfaces s;
  for (const LimitSurface* surface : {&s.torus, &s.cube}) {
    const SurfaceLaplacian op(surface->topology(), sample_limit_metric(*surface, 32));
    const SurfaceMultigrid mg(*surface, op);
    EXPECT_EQ(mg.levels(), 6);  // 32, 16, 8, 4, 2, 1 cells a side
    const PatchField b = random_field(op.grid(), 7);
    const double c = 20 * op.area() / (op.patches() * 32 * 32);  // 20 cells^2: Jacobi converges
    DiffusionSolve solve{1e-10, 5000};
    PatchField by_jacobi = b, by_mg = b;
    const DiffusionReport rj = op.implicit_diffusion(by_jacobi, b, c, solve);
    const DiffusionReport rm = mg.implicit_diffusion(by_mg, b, c, solve);
    EXPECT_LE(rj.residual, 1e-10);
    EXPECT_LE(rm.residual, 1e-10);
    // BiCGSTAB over the V-cycles: 22 cycles on the torus (cells up to 3:1), 13 on the cube-sphere
    // (plain V-cycles: 45 and 23).
    EXPECT_LE(rm.cycles, 30) << "stiffness " << stiffness(op, c);
    EXPECT_GT(rj.sweeps, rm.sweeps);
    std::printf("stiffness %.0f: jacobi %d sweeps, multigrid %d cycles (%d sweeps)\n",
                stiffness(op, c), rj.sweeps, rm.cycles, rm.sweeps);
    // Both to 1e-10 of max |b|: the solutions agree to a few times that over (I - c lap)^-1.
    EXPECT_LT(max_diff(op.grid(), by_jacobi, by_mg), 1e-8);
    EXPECT_NEAR(op.total(by_mg), op.total(b), 1e-12 * op.total(b));
  }
}

// A step 10^4 times the cells' diffusion time: plain Jacobi diverges (the metric's cross terms
// outweigh the diagonal), the cycles' l1 smoother does not, and the coarsest grid's exact solve
// takes the global modes: 1e-8 in tens of cycles.
TEST(SurfaceMultigrid, ConvergesWhereJacobiStalls) {
  Surfaces s;
  for (const LimitSurface* surface : {&s.torus, &s.cube}) {
    const SurfaceLaplacian op(surface->topology(), sample_limit_metric(*surface, 32));
    const SurfaceMultigrid mg(*surface, op);
    const PatchField b = random_field(op.grid(), 11);
    const double c = 1e4 * op.area() / (op.patches() * 32 * 32);
    PatchField by_jacobi = b, by_mg = b;
    const DiffusionReport rj = op.implicit_diffusion(by_jacobi, b, c, DiffusionSolve{1e-8, 500});
    const DiffusionReport rm = mg.implicit_diffusion(by_mg, b, c, DiffusionSolve{1e-8, 100});
    EXPECT_GT(rj.residual, 1.0);
    EXPECT_LE(rm.residual, 1e-8);
    EXPECT_LE(rm.cycles, 40);  // 25 on the torus, 15 on the cube-sphere (plain: 51, 25)
    EXPECT_NEAR(op.total(by_mg), op.total(b), 1e-12 * op.total(b));
    std::printf("stiffness %.0f: jacobi 500 sweeps -> %.1e; multigrid %d cycles -> %.1e\n",
                stiffness(op, c), rj.residual, rm.cycles, rm.residual);
  }
}

// The Poisson problem of the fluid's projection on a torus of 19 x 17 quads (R = 2, r = 0.8: cells
// stretched 3:1 along the tube on its outside, as on seed 004's 1292-patch mesh), 323 patches of
// 8 x 8 cells. Point smoothing damps the modes along the stretched cells poorly: plain V-cycles
// take 80 to 1e-8, BiCGSTAB over them 29.
TEST(SurfaceMultigrid, StretchedPatchesSolveInFewCycles) {
  LimitSurface torus;
  ASSERT_TRUE(LimitSurface::build(torus_mesh(19, 17, 2, 0.8), {}, torus).is_ok());
  SurfaceLaplacian op(torus.topology(), sample_limit_metric(torus, 8));
  const SurfaceMultigrid mg(torus, op);
  PatchField b = random_field(op.grid(), 5);
  op.add(b, -op.total(b) / op.area());
  PatchField x = op.grid().make_field();
  const DiffusionReport report = mg.solve_poisson(x, b, DiffusionSolve{1e-8, 100});
  std::printf("stretched torus: %d cycles -> %.1e\n", report.cycles, report.residual);
  EXPECT_LE(report.residual, 1e-8);
  EXPECT_LE(report.cycles, 40);
  PatchField r = op.grid().make_field();
  EXPECT_LE(op.poisson_residual(x, b, r), 1e-8 * op.max_abs(b));
  EXPECT_NEAR(op.total(x), 0.0, 1e-12 * op.area() * op.max_abs(x));
}

// A budget of V-cycles is kept (an odd one included: BiCGSTAB runs two a step), and the residual
// reported when it runs out is the true one of the answer returned.
TEST(SurfaceMultigrid, StopsAtItsBudgetWithTheTrueResidual) {
  LimitSurface torus;
  ASSERT_TRUE(LimitSurface::build(torus_mesh(19, 17, 2, 0.8), {}, torus).is_ok());
  SurfaceLaplacian op(torus.topology(), sample_limit_metric(torus, 8));
  const SurfaceMultigrid mg(torus, op);
  PatchField b = random_field(op.grid(), 9);
  op.add(b, -op.total(b) / op.area());
  for (int budget : {1, 3, 4}) {
    PatchField x = op.grid().make_field();
    const DiffusionReport report = mg.solve_poisson(x, b, DiffusionSolve{1e-12, budget});
    EXPECT_EQ(report.cycles, budget);
    PatchField r = op.grid().make_field();
    const double residual = op.poisson_residual(x, b, r) / op.max_abs(b);
    EXPECT_GT(report.residual, 1e-12) << budget;
    EXPECT_NEAR(report.residual, residual, 1e-9 * residual) << budget;
  }
}

// The 32-patch torus at N = 32 (32 rows of 1024 cells: enough to run on the workers) on 1 and 3
// workers.
TEST(SurfaceMultigrid, SameBitsOnAnyNumberOfWorkers) {
  Surfaces s;
  SurfaceLaplacian op(s.torus.topology(), sample_limit_metric(s.torus, 32));
  const PatchField b = random_field(op.grid(), 3);
  const double c = 100 * op.area() / (op.patches() * 32 * 32);
  PatchField serial = b;
  {
    const SurfaceMultigrid mg(s.torus, op);
    mg.implicit_diffusion(serial, b, c, DiffusionSolve{1e-9, 50});
  }
  ThreadBackendOptions t;
  t.workers = 3;
  ThreadBackend backend(t);
  RowExecutor ex(backend);
  op.set_executor(ex);
  const SurfaceMultigrid mg(s.torus, op);
  PatchField threads = b;
  mg.implicit_diffusion(threads, b, c, DiffusionSolve{1e-9, 50});
  for (int p = 0; p < op.patches(); ++p)
    for (int j = 0; j < op.n(); ++j)
      for (int i = 0; i < op.n(); ++i) {
        const std::size_t k = op.grid().index(p, i, j);
        ASSERT_EQ(serial[k], threads[k]) << p << " " << i << " " << j;
      }
}

}  // namespace
}  // namespace ardcell
