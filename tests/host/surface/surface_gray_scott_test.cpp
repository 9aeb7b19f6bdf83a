// Gray-Scott on the surface: a developed pattern shows no seams across patch edges, and the
// threads back end gives the serial bits.
#include "host/surface/surface_gray_scott.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "host/surface/procedural_mesh.h"
#include "runtime/row_executor.h"
#include "runtime/thread/thread_backend.h"
#include "surface_test_util.h"

namespace ardcell {
namespace {

using namespace surface_test;

struct Seams {
  double edge = 0;      // mean |db| / distance between the cells on either side of a patch edge
  double inside = 0;    // the same one cell further in, between the edge cell and the next
  double interior = 0;  // the same over all pairs of neighbouring cells inside the patches
};

// A seam is a jump at the patch edges: the differences across the edges against those of the
// pairs just inside them (which see the same pattern features one cell away) and of all pairs
// inside the patches; each difference over the distance of the cell centres on the surface.
Seams measure_seams(const LimitSurface& surface, const SurfaceLaplacian& op, PatchField f) {
  const PatchGrid& g = op.grid();
  const int n = g.n();
  std::array<PatchField, 3> pos = cell_positions(surface, g);
  for (auto& c : pos) g.exchange(c);
  g.exchange(f);
  auto slope = [&](std::size_t u, std::size_t v) {
    const double d =
        std::hypot(pos[0][u] - pos[0][v], pos[1][u] - pos[1][v], pos[2][u] - pos[2][v]);
    return std::abs(f[u] - f[v]) / d;
  };
  Seams s;
  double edges = 0, pairs = 0;
  for (int p = 0; p < g.patches(); ++p) {
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const std::size_t c = g.index(p, i, j);
        if (i + 1 < n) s.interior += slope(c, g.index(p, i + 1, j)), ++pairs;
        if (j + 1 < n) s.interior += slope(c, g.index(p, i, j + 1)), ++pairs;
      }
    for (int e = 0; e < 4; ++e)
      for (int m = 0; m < n; ++m) {
        const auto out = edge_ring_cell(e, m, -1, n);    // ghost and edge cell
        const auto in = edge_ring_cell(e, m, 0, n - 1);  // edge cell and the next one in
        s.edge += slope(g.index(p, out.out_i, out.out_j), g.index(p, out.in_i, out.in_j));
        s.inside += slope(g.index(p, in.out_i, in.out_j), g.index(p, in.in_i, in.in_j));
        ++edges;
      }
  }
  s.edge /= edges;
  s.inside /= edges;
  s.interior /= pairs;
  return s;
}

struct RdRun {
  Seams seams;
  double spread;  // max b - min b
};

RdRun run_gray_scott(const LimitSurface& s, int n, SurfaceReaction scheme, int steps) {
  const SurfaceLaplacian op(s.topology(), sample_limit_metric(s, n));
  // Cells of the classic flat model 1/12 of a patch's side, whatever N is; three discs a patch
  // of a fifth of its side.
  const double side = std::sqrt(op.area() / op.patches());
  SurfaceRdParams params = gray_scott_for_length(side / 12);
  params.scheme = scheme;
  params.solve.tolerance = 1e-5;
  SurfaceGrayScott rd(op, params);
  rd.seed_spots(cell_positions(s, op.grid()), 42, 3 * op.patches(), 0.2 * side);
  for (int k = 0; k < steps; ++k) rd.step();
  double lo = 1, hi = 0;
  for (int p = 0; p < op.patches(); ++p)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        lo = std::min(lo, rd.b()[op.grid().index(p, i, j)]);
        hi = std::max(hi, rd.b()[op.grid().index(p, i, j)]);
      }
  return {measure_seams(s, op, rd.b()), hi - lo};
}

void expect_no_seams(const RdRun& r, int n, const char* scheme) {
  const double ratio = r.seams.edge / r.seams.inside, ratio_all = r.seams.edge / r.seams.interior;
  std::printf(
      "cube-sphere (24 patches) N=%d, %s reaction, 600 steps: b spans %.3f; mean |db|/distance "
      "across patch edges %.4f, one cell in %.4f (ratio %.2f), all interior pairs %.4f "
      "(ratio %.2f)\n",
      n, scheme, r.spread, r.seams.edge, r.seams.inside, ratio, r.seams.interior, ratio_all);
  EXPECT_GT(r.spread, 0.2);  // a pattern, not the trivial state
  EXPECT_LE(ratio, 1.5);
  EXPECT_LE(ratio_all, 1.5);
}

TEST(SurfaceGrayScott, ForwardEulerPatternHasNoSeams) {
  LimitSurface s;
  ASSERT_TRUE(LimitSurface::build(rotate_faces(cube_mesh(2), 4), {}, s));
  expect_no_seams(run_gray_scott(s, 8, SurfaceReaction::kForwardEuler, 600), 8, "forward Euler");
  expect_no_seams(run_gray_scott(s, 16, SurfaceReaction::kForwardEuler, 600), 16, "forward Euler");
}

TEST(SurfaceGrayScott, ImplicitReactionPatternHasNoSeams) {
  LimitSurface s;
  ASSERT_TRUE(LimitSurface::build(rotate_faces(cube_mesh(2), 4), {}, s));
  expect_no_seams(run_gray_scott(s, 16, SurfaceReaction::kImplicit, 600), 16, "implicit");
}

// The patches run side by side on the threads back end: 1, 2 and 3 workers give the same fields
// bit for bit (per-cell work per patch, maxima, totals as per-patch partials in patch order).
// The start's discs: every cell within the radius of each random centre, in the order of a scan
// over all cells (each takes two draws from the generator), as that scan finds them. The discs
// are found through bins of the radius; here the scan itself, on the genus-2 surface, with radii
// that make the bins exactly the radius wide along an axis (the rounding a bin must not miss),
// tiny (one cell) and larger than the surface (one bin).
TEST(SurfaceGrayScott, StartDiscsAreTheCellsAFullScanFinds) {
  LimitSurface s;
  ASSERT_TRUE(LimitSurface::build(genus2_mesh(1.0), {}, s));
  const SurfaceLaplacian op(s.topology(), sample_limit_metric(s, 4));
  const PatchGrid& g = op.grid();
  const std::array<PatchField, 3> pos = cell_positions(s, g);
  double lo = INFINITY, hi = -INFINITY;
  for (int p = 0; p < g.patches(); ++p)
    for (int j = 0; j < g.n(); ++j)
      for (int i = 0; i < g.n(); ++i)
        lo = std::min(lo, pos[0][g.index(p, i, j)]), hi = std::max(hi, pos[0][g.index(p, i, j)]);
  for (double radius : {(hi - lo) / 7, (hi - lo) / 10, 1e-3, 100 * (hi - lo)}) {
    SurfaceGrayScott rd(op, gray_scott_for_length(0.1));
    const int spots = 40;
    rd.seed_spots(pos, 11, spots, radius);
    // The scan, with SurfaceGrayScott::seed_spots's draws.
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::uniform_int_distribution<int> patch(0, g.patches() - 1), cell(0, g.n() - 1);
    PatchField a = g.make_field(1.0), b = g.make_field(0.0);
    for (int k = 0; k < spots; ++k) {
      const std::size_t centre = g.index(patch(rng), cell(rng), cell(rng));
      for (int p = 0; p < g.patches(); ++p)
        for (int j = 0; j < g.n(); ++j)
          for (int i = 0; i < g.n(); ++i) {
            const std::size_t c = g.index(p, i, j);
            double d2 = 0;
            for (const PatchField& x : pos) d2 += (x[c] - x[centre]) * (x[c] - x[centre]);
            if (d2 > radius * radius) continue;
            a[c] = 0.5 * (1 + 0.02 * (unit(rng) - 0.5));
            b[c] = 0.25 * (1 + 0.02 * (unit(rng) - 0.5));
          }
    }
    int covered = 0;
    for (double v : b) covered += v != 0;
    EXPECT_GT(covered, 0) << radius;
    EXPECT_TRUE(rd.a() == a) << "radius " << radius;
    EXPECT_TRUE(rd.b() == b) << "radius " << radius;
  }
}

TEST(SurfaceGrayScott, AnyNumberOfWorkersGivesTheSameBits) {
  LimitSurface s;
  ASSERT_TRUE(LimitSurface::build(genus2_mesh(1.0), {}, s));
  const int n = 16;  // 50 patches of 16^2 cells: enough for the executor to dispatch
  ASSERT_GE(50L * n * n, RowExecutor::kMinParallelCells);
  const PatchMetric metric = sample_limit_metric(s, n);
  PatchField reference_a, reference_b;
  for (int workers : {1, 2, 3}) {
    ThreadBackendOptions options;
    options.workers = workers;
    options.pin = false;
    ThreadBackend backend(options);
    RowExecutor executor(backend);
    SurfaceLaplacian op(s.topology(), metric);
    op.set_executor(executor);
    const double side = std::sqrt(op.area() / op.patches());
    SurfaceGrayScott rd(op, gray_scott_for_length(side / 12));
    rd.seed_spots(cell_positions(s, op.grid()), 7, 2 * op.patches(), 0.2 * side);
    for (int k = 0; k < 10; ++k) rd.step();
    if (workers == 1) {
      reference_a = rd.a(), reference_b = rd.b();
      continue;
    }
    EXPECT_TRUE(rd.a() == reference_a) << workers << " workers";
    EXPECT_TRUE(rd.b() == reference_b) << workers << " workers";
  }
}

}  // namespace
}  // namespace ardcell
