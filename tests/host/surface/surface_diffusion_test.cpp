// Implicit diffusion on the surface: a mode decays at its eigenvalue's rate, the eigenvalue
// converges with N, and the total is conserved to rounding on closed surfaces.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "host/surface/procedural_mesh.h"
#include "host/surface/surface_laplacian.h"
#include "surface_test_util.h"

namespace ardcell {
namespace {

using namespace surface_test;

double norm(const SurfaceLaplacian& op, const PatchField& x) { return std::sqrt(inner(op, x, x)); }

// -<x, lap x> / <x, x>, area-weighted.
double rayleigh(const SurfaceLaplacian& op, PatchField x) {
  PatchField lap = op.grid().make_field();
  op.apply(x, lap);
  return -inner(op, x, lap) / inner(op, x, x);
}

struct Decay {
  double rate;        // measured over the second half of the run
  double eigenvalue;  // Rayleigh quotient of the field at the end
};

// Diffuses f for time T in steps dt: what is left of other modes decays faster, so the second
// half of the run sees the eigenmode of f's symmetry class alone.
Decay diffuse(const LimitSurface& s, int n, double (*f)(const Cell&), double dt, int steps) {
  const SurfaceLaplacian op(s.topology(), sample_limit_metric(s, n));
  PatchField x = sample(s, op.grid(), f), b;
  DiffusionSolve solve;
  solve.tolerance = 1e-10;
  double half = 0;
  for (int k = 0; k < steps; ++k) {
    b = x;
    const DiffusionReport r = op.implicit_diffusion(x, b, dt, solve);
    EXPECT_LE(r.residual, 1e-10);
    if (k + 1 == steps / 2) half = norm(op, x);
  }
  const double t_half = dt * (steps - steps / 2);
  return {std::log(half / norm(op, x)) / t_half, rayleigh(op, x)};
}

TEST(SurfaceDiffusion, CubeSphereModesDecayAtTheirEigenvalues) {
  LimitSurface s;
  ASSERT_TRUE(LimitSurface::build(rotate_faces(cube_mesh(1), 3), {}, s));
  const SurfaceLaplacian op(s.topology(), sample_limit_metric(s, 32));
  struct Case {
    const char* name;
    double (*f)(const Cell&);
    double sphere;  // the round sphere's eigenvalue l (l + 1) / R^2 at the same area
    double dt;
  };
  const double r2 = op.area() / (4 * std::numbers::pi);
  for (const Case& c : {Case{"l=1", l1, 2 / r2, 0.002}, Case{"l=2", l2, 6 / r2, 0.0007}}) {
    double eig[3], rate[3];
    int k = 0;
    for (int n : {8, 16, 32}) {
      const Decay d = diffuse(s, n, c.f, c.dt, 120);
      // Backward Euler damps a mode of eigenvalue L by 1 / (1 + L dt) a step.
      const double euler_rate = std::log(1 + d.eigenvalue * c.dt) / c.dt;
      std::printf(
          "cube-sphere %s N=%2d: eigenvalue (Rayleigh) %.6f, decay rate %.6f (backward "
          "Euler's %.6f)\n",
          c.name, n, d.eigenvalue, d.rate, euler_rate);
      EXPECT_NEAR(d.rate / euler_rate, 1.0, 1e-4);
      eig[k] = d.eigenvalue, rate[k++] = d.rate;
    }
    const double order = std::log2((eig[1] - eig[0]) / (eig[2] - eig[1]));
    const double limit = eig[2] + (eig[2] - eig[1]) / (std::pow(2.0, order) - 1);
    std::printf(
        "cube-sphere %s eigenvalue: observed order %.2f, extrapolated %.6f; N=32's decay "
        "rate is %.3f%% from it; round sphere of the same area: %.6f\n",
        c.name, order, limit, 100 * std::abs(rate[2] / limit - 1), c.sphere);
    EXPECT_GT(order, 1.5);
    EXPECT_NEAR(rate[2] / limit, 1.0, 0.01);
  }
}

// Rates are in surface units: a blob diffused for time T spreads by <|X - X0|^2> = 4 r T
// (to the surface's curvature) whatever N is.
TEST(SurfaceDiffusion, SpreadInSurfaceUnitsDoesNotDependOnN) {
  LimitSurface s;
  ASSERT_TRUE(LimitSurface::build(rotate_faces(cube_mesh(2), 6), {}, s));
  const double r = 1e-3, dt = 2.0;
  double spread[2];
  int k = 0;
  for (int n : {16, 32}) {
    const SurfaceLaplacian op(s.topology(), sample_limit_metric(s, n));
    const auto pos = cell_positions(s, op.grid());
    // A Gaussian of width 0.05 around the centre of patch 0, then 10 steps.
    const auto centre = s.position(0, 0.5, 0.5);
    auto dist2 = [&](std::size_t c) {
      double d = 0;
      for (int a = 0; a < 3; ++a) d += (pos[a][c] - centre[a]) * (pos[a][c] - centre[a]);
      return d;
    };
    PatchField x = op.grid().make_field(), b;
    for (int p = 0; p < op.patches(); ++p)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          const std::size_t c = op.grid().index(p, i, j);
          x[c] = std::exp(-dist2(c) / (2 * 0.05 * 0.05));
        }
    auto second_moment = [&] {
      double m0 = 0, m2 = 0;
      for (int p = 0; p < op.patches(); ++p)
        for (int j = 0; j < n; ++j)
          for (int i = 0; i < n; ++i) {
            const std::size_t c = op.grid().index(p, i, j);
            m0 += op.cell_area(p, i, j) * x[c];
            m2 += op.cell_area(p, i, j) * x[c] * dist2(c);
          }
      return m2 / m0;
    };
    const double before = second_moment();
    DiffusionSolve solve;
    solve.tolerance = 1e-10;
    for (int step = 0; step < 10; ++step) {
      b = x;
      op.implicit_diffusion(x, b, dt * r, solve);
    }
    spread[k++] = second_moment() - before;
    std::printf("N=%d: second moment grew by %.6f (4 r T = %.6f)\n", n, spread[k - 1],
                4 * r * dt * 10);
  }
  EXPECT_NEAR(spread[1] / spread[0], 1.0, 0.01);
  EXPECT_NEAR(spread[1] / (4 * r * dt * 10), 1.0, 0.05);
}

void expect_conserved(const LimitSurface& s, int n, int max_sweeps, const char* name) {
  const SurfaceLaplacian op(s.topology(), sample_limit_metric(s, n));
  PatchField x = op.grid().make_field(), b;
  unsigned state = 7;
  for (double& v : x) {
    state = state * 1664525u + 1013904223u;
    v = double(state >> 8) / double(1 << 24);
  }
  const double before = op.total(x);
  DiffusionSolve solve;
  solve.max_sweeps = max_sweeps;
  double worst = 0;
  for (int k = 0; k < 20; ++k) {
    b = x;
    op.implicit_diffusion(x, b, 0.01, solve);
    worst = std::max(worst, std::abs(op.total(x) / before - 1));
  }
  std::printf("%s N=%d, %d sweeps at most: total drifts by %.2e relative over 20 steps\n", name, n,
              max_sweeps, worst);
  EXPECT_LT(worst, 1e-13);
}

TEST(SurfaceDiffusion, TotalIsConservedToRounding) {
  LimitSurface cube, torus;
  ASSERT_TRUE(LimitSurface::build(rotate_faces(cube_mesh(2), 1), {}, cube));
  ASSERT_TRUE(LimitSurface::build(rotate_faces(torus_mesh(8, 4, 2, 0.7), 1), {}, torus));
  for (int sweeps : {2, 200}) {
    expect_conserved(cube, 16, sweeps, "cube-sphere (24 patches)");
    expect_conserved(torus, 16, sweeps, "torus (32 patches)");
  }
}

}  // namespace
}  // namespace ardcell
