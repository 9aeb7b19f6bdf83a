// The sparse levels below one cell a patch (host/surface/coarse_aggregation.h): the probed
// matrix is the operator to rounding; aggregation keeps lap's null space and its conservation;
// and a mesh of more patches than a dense solve takes solves in about the V-cycles of one that
// fits it, where the bottom grid's point sweeps needed several times as many.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

#include "host/surface/coarse_aggregation.h"
#include "host/surface/procedural_mesh.h"
#include "host/surface/surface_multigrid.h"
#include "tests/host/surface/surface_fluid_test_util.h"
#include "tests/host/surface/surface_test_util.h"

namespace ardcell {
namespace {

// Values in [-1, 1): lap's range and null space both in the right-hand side.
PatchField random_field(const PatchGrid& g, unsigned seed) {
  return surface_test::random_field(g, seed, -1, 1);
}

std::vector<double> times(const SparseLevel& l, const std::vector<double>& x) {
  std::vector<double> y(std::size_t(l.cells), 0.0);
  for (int r = 0; r < l.cells; ++r)
    for (int k = l.start[std::size_t(r)]; k < l.start[std::size_t(r) + 1]; ++k)
      y[std::size_t(r)] += l.lap[std::size_t(k)] * x[std::size_t(l.col[std::size_t(k)])];
  return y;
}

// The cube-sphere with rotated parametrisations (extraordinary vertices of valence 3), the
// double torus (valence 5 and 6) and an open surface (the cube with one quad cut out).
TEST(CoarseAggregation, ProbedMatrixIsTheOperator) {
  for (const PolyMesh& mesh :
       {rotate_faces(cube_mesh(3), 5), genus2_mesh(1), surface_fluid_test::open_box()}) {
    LimitSurface s;
    ASSERT_TRUE(LimitSurface::build(mesh, {}, s).is_ok());
    SurfaceLaplacian op(s.topology(), sample_limit_metric(s, 1));
    const SparseLevel l = probe_patch_level(op, s.topology(), patch_pieces(s.topology()));
    PatchField x = random_field(op.grid(), 3), lap = op.grid().make_field();
    op.apply(x, lap);
    std::vector<double> flat(std::size_t(l.cells));
    for (int p = 0; p < l.cells; ++p) flat[std::size_t(p)] = x[op.grid().index(p, 0, 0)];
    const std::vector<double> y = times(l, flat);
    double err = 0, scale = 0;
    for (int p = 0; p < l.cells; ++p) {
      err = std::max(err, std::abs(y[std::size_t(p)] - lap[op.grid().index(p, 0, 0)]));
      scale = std::max(scale, std::abs(lap[op.grid().index(p, 0, 0)]));
    }
    std::printf("%d patches, %zu coefficients: max |A x - lap x| = %.1e of %.1e\n", l.cells,
                l.col.size(), err, scale);
    EXPECT_LE(err, 1e-13 * scale);
  }
}

TEST(CoarseAggregation, AggregatesKeepTheNullSpaceAndTheTotal) {
  LimitSurface s;
  ASSERT_TRUE(LimitSurface::build(rotate_faces(cube_mesh(8), 2), {}, s).is_ok());
  SurfaceLaplacian op(s.topology(), sample_limit_metric(s, 1));
  SparseLevel fine = probe_patch_level(op, s.topology(), patch_pieces(s.topology()));
  const SparseLevel coarse = aggregate_level(fine);
  std::printf("%d cells -> %d aggregates\n", fine.cells, coarse.cells);
  EXPECT_LE(coarse.cells * 4, fine.cells);
  ASSERT_EQ(fine.coarse.size(), std::size_t(fine.cells));
  double area = 0, coarse_area = 0;
  for (double a : fine.area) area += a;
  for (double a : coarse.area) coarse_area += a;
  EXPECT_NEAR(coarse_area, area, 1e-13 * area);
  // lap_c 1 = 0 (each row sums to 0) and sum_I A_I (lap_c y)_I = 0 (each column's area-weighted
  // sum is 0), relative to the row's largest coefficient.
  std::vector<double> column(std::size_t(coarse.cells), 0.0);
  double largest = 0;
  for (int r = 0; r < coarse.cells; ++r) {
    double row = 0, big = 0;
    for (int k = coarse.start[std::size_t(r)]; k < coarse.start[std::size_t(r) + 1]; ++k) {
      row += coarse.lap[std::size_t(k)];
      big = std::max(big, std::abs(coarse.lap[std::size_t(k)]));
      column[std::size_t(coarse.col[std::size_t(k)])] +=
          coarse.area[std::size_t(r)] * coarse.lap[std::size_t(k)];
    }
    EXPECT_LE(std::abs(row), 1e-11 * big) << "row " << r;
    largest = std::max(largest, big * coarse.area[std::size_t(r)]);
  }
  for (int c = 0; c < coarse.cells; ++c)
    EXPECT_LE(std::abs(column[std::size_t(c)]), 1e-11 * largest) << "column " << c;
}

// The projection's Poisson problem, 2 x 2 cells a patch, on a ring of 128 x 8 quads (1024
// patches: the bottom grid solved densely) and of 512 x 8 (4096: aggregated). The ring's
// longest mode spans 1024 cells; point sweeps on a bottom grid of 4096 cells leave it alone.
TEST(CoarseAggregation, ManyPatchesSolveInTheCyclesOfFew) {
  int cycles[2] = {0, 0};
  const int around[2] = {128, 512};
  for (int m = 0; m < 2; ++m) {
    LimitSurface s;
    // Square cells: the ring's circumference 2 pi R over `around` equals the tube's 2 pi r / 8.
    const double r = 0.25, big_r = r * around[m] / 8;
    ASSERT_TRUE(LimitSurface::build(torus_mesh(around[m], 8, big_r, r), {}, s).is_ok());
    SurfaceLaplacian op(s.topology(), sample_limit_metric(s, 2));
    const SurfaceMultigrid mg(s, op);
    PatchField b = random_field(op.grid(), 11);
    op.add(b, -op.total(b) / op.area());
    PatchField x = op.grid().make_field();
    const DiffusionReport report = mg.solve_poisson(x, b, DiffusionSolve{1e-8, 400});
    std::printf("%d patches: %d V-cycles -> %.1e\n", op.patches(), report.cycles, report.residual);
    EXPECT_LE(report.residual, 1e-8);
    PatchField res = op.grid().make_field();
    EXPECT_LE(op.poisson_residual(x, b, res), 1e-8 * op.max_abs(b));
    cycles[m] = report.cycles;
  }
  EXPECT_LE(cycles[1], 2 * cycles[0] + 4);
}

// (I - c lap) x = b, the reaction-diffusion's implicit step, on the 4096-patch ring at a stiff
// step (10^4 cells' areas): through the aggregates to 1e-8, the total kept.
TEST(CoarseAggregation, ImplicitDiffusionThroughTheAggregates) {
  LimitSurface s;
  ASSERT_TRUE(LimitSurface::build(torus_mesh(512, 8, 0.25 * 512 / 8, 0.25), {}, s).is_ok());
  SurfaceLaplacian op(s.topology(), sample_limit_metric(s, 2));
  const SurfaceMultigrid mg(s, op);
  const PatchField b = random_field(op.grid(), 13);
  PatchField x = b;
  const double c = 1e4 * op.area() / (op.patches() * 4);
  const DiffusionReport report = mg.implicit_diffusion(x, b, c, DiffusionSolve{1e-8, 200});
  std::printf("implicit diffusion, 4096 patches: %d V-cycles -> %.1e\n", report.cycles,
              report.residual);
  EXPECT_LE(report.residual, 1e-8);
  EXPECT_LE(report.cycles, 60);
  PatchField bb = b, r = op.grid().make_field();
  EXPECT_LE(op.residual(x, bb, c, r), 1e-8 * op.max_abs(b));
  EXPECT_NEAR(op.total(x), op.total(b), 1e-10 * std::abs(op.total(b)));
}

// Several pieces on an aggregated mesh: the ring, a cube-sphere and a lone quad (open, every edge
// a boundary: its cell at the bottom is a row of zeros, a piece of one cell). The Poisson problem
// solves with a finite answer of total 0 on every piece.
TEST(CoarseAggregation, PiecesAndALonePatch) {
  PolyMesh mesh = torus_mesh(512, 8, 0.25 * 512 / 8, 0.25);
  const auto append = [&mesh](const PolyMesh& other, std::array<double, 3> shift) {
    const int base = int(mesh.points.size());
    for (auto p : other.points)
      mesh.points.push_back({p[0] + shift[0], p[1] + shift[1], p[2] + shift[2]});
    for (int f = 0; f < other.face_count(); ++f) {
      const int* v = other.face(f);
      mesh.add_face({base + v[0], base + v[1], base + v[2], base + v[3]});
    }
  };
  append(cube_mesh(2), {0, 0, 30});
  PolyMesh quad;
  quad.points = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  quad.add_face({0, 1, 2, 3});
  append(quad, {0, 0, -30});
  LimitSurface s;
  ASSERT_TRUE(LimitSurface::build(mesh, {}, s).is_ok());
  const std::vector<int> pieces = patch_pieces(s.topology());
  ASSERT_EQ(*std::max_element(pieces.begin(), pieces.end()), 2);
  SurfaceLaplacian op(s.topology(), sample_limit_metric(s, 2));
  const SurfaceMultigrid mg(s, op);
  PatchField b = random_field(op.grid(), 17);
  PatchField x = op.grid().make_field();
  const DiffusionReport report = mg.solve_poisson(x, b, DiffusionSolve{1e-8, 200});
  std::printf("three pieces, %d patches: %d V-cycles -> %.1e\n", op.patches(), report.cycles,
              report.residual);
  EXPECT_LE(report.residual, 1e-8);
  double totals[3] = {0, 0, 0}, scale = 0;
  const PatchGrid& g = op.grid();
  for (int p = 0; p < g.patches(); ++p)
    for (int j = 0; j < g.n(); ++j)
      for (int i = 0; i < g.n(); ++i) {
        const double v = x[g.index(p, i, j)];
        ASSERT_TRUE(std::isfinite(v)) << "patch " << p;
        totals[pieces[std::size_t(p)]] += op.cell_area(p, i, j) * v;
        scale = std::max(scale, std::abs(v));
      }
  for (double t : totals) EXPECT_NEAR(t, 0.0, 1e-10 * scale * op.area());
}

}  // namespace
}  // namespace ardcell
