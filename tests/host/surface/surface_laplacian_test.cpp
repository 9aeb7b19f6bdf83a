// The Laplace-Beltrami operator on patches: the flat torus against ardcell's flat periodic
// grid, and the convergence on the cube-sphere against the exact operator from the limit
// surface's second derivatives.
#include "host/surface/surface_laplacian.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "host/surface/procedural_mesh.h"
#include "kernels/stencil_operator.h"
#include "surface_test_util.h"

namespace ardcell {
namespace {

using namespace surface_test;
constexpr double kPi = std::numbers::pi;

// The unit square, periodic, as k x k patches whose parametrisations are rotated at random.
struct FlatTorus {
  int k, n;
  PatchTopology topo;
  PolyMesh mesh;
  FlatTorus(int k_, int n_) : k(k_), n(n_) {
    mesh = rotate_faces(torus_mesh(k, k, 2, 1), 17);
    EXPECT_TRUE(build_patch_topology(mesh, topo));
  }
  // Global cell (column, row) of the M x M grid, M = k n, holding cell (i, j) of patch p:
  // the patch's corners are lattice points (a, t) of its vertices, unwrapped around corner 0.
  std::array<int, 2> global_cell(int p, int i, int j) const {
    double corner[4][2];
    flat_torus_corners(mesh, k, p, corner);
    const double x = (i + 0.5) / n, y = (j + 0.5) / n;
    double g[2];
    for (int d = 0; d < 2; ++d)
      g[d] = (1 - x) * (1 - y) * corner[0][d] + x * (1 - y) * corner[1][d] + x * y * corner[2][d] +
             (1 - x) * y * corner[3][d];
    const int m = k * n;
    return {((int(std::floor(g[0] * n)) % m) + m) % m, ((int(std::floor(g[1] * n)) % m) + m) % m};
  }
};

TEST(SurfaceLaplacianFlat, RotatedPatchesGiveTheFlatPeriodicGrid) {
  const int k = 4, n = 8, m = k * n;
  FlatTorus torus(k, n);
  const SurfaceLaplacian op(torus.topo, flat_metric(torus.topo, n, 1.0 / k));
  // A field with every Fourier mode: random values on the global grid.
  FieldF global({m, m}, 1);
  unsigned state = 12345;
  for (int y = 0; y < m; ++y)
    for (int x = 0; x < m; ++x) {
      state = state * 1664525u + 1013904223u;
      global(x, y) = float(state >> 8) / float(1 << 24) - 0.5f;
    }
  PatchField phi = op.grid().make_field(), lap = op.grid().make_field();
  for (int p = 0; p < op.patches(); ++p)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const auto g = torus.global_cell(p, i, j);
        phi[op.grid().index(p, i, j)] = global(g[0], g[1]);
      }
  op.apply(phi, lap);
  // ardcell's flat periodic grid: identity 0, scale 1/h^2 is -lap.
  const double h = 1.0 / m;
  const StencilOperator flat = assemble_stencil_operator(
      {m, m}, 0.0, 1.0 / (h * h), nullptr, BoundaryKind::kPeriodic, BoundaryKind::kPeriodic);
  FieldF out({m, m}, 1);
  apply_stencil_operator(flat, global, out);
  double worst = 0, scale = 0;
  for (int p = 0; p < op.patches(); ++p)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const auto g = torus.global_cell(p, i, j);
        worst = std::max(worst, std::abs(lap[op.grid().index(p, i, j)] + out(g[0], g[1])));
        scale = std::max(scale, std::abs(double(out(g[0], g[1]))));
      }
  std::printf("flat torus %dx%d patches of %d^2: |lap - flat| / |flat| = %.2e (float grid)\n", k, k,
              n, worst / scale);
  EXPECT_LT(worst / scale, 1e-6);
}

// Every patch of the flat torus carrying the constant metric G = [[2, 0.6], [0.6, 1]] of the
// global lattice, in its own rotated frame: the 9-point operator with its cross terms is the
// global one's, term for term, so corner ghosts and the tensors' rotation are exercised.
TEST(SurfaceLaplacianFlat, ShearedMetricMatchesTheGlobalNinePointStencil) {
  const int k = 4, n = 8, m = k * n;
  FlatTorus torus(k, n);
  const double G[3] = {2.0, 0.6, 1.0};
  PatchMetric metric(n, torus.topo.patches);
  for (int p = 0; p < torus.topo.patches; ++p) {
    // The patch's axes in lattice units: from its cell (0,0) to cells (1,0) and (0,1).
    const auto c00 = torus.global_cell(p, 0, 0), c10 = torus.global_cell(p, 1, 0),
               c01 = torus.global_cell(p, 0, 1);
    auto wrap = [&](int d) { return d > 1 ? d - m : d < -1 ? d + m : d; };
    const double j[2][2] = {{double(wrap(c10[0] - c00[0])), double(wrap(c01[0] - c00[0]))},
                            {double(wrap(c10[1] - c00[1])), double(wrap(c01[1] - c00[1]))}};
    // Du = J e1 / k, Dv = J e2 / k in the plane with metric G.
    auto gdot = [&](int a, int b) {
      const double u[2] = {j[0][a], j[1][a]}, v[2] = {j[0][b], j[1][b]};
      return (G[0] * u[0] * v[0] + G[1] * (u[0] * v[1] + u[1] * v[0]) + G[2] * u[1] * v[1]) /
             (k * k);
    };
    MetricSample s;
    s.g11 = gdot(0, 0), s.g12 = gdot(0, 1), s.g22 = gdot(1, 1);
    const double det = s.g11 * s.g22 - s.g12 * s.g12;
    s.sqrt_g = std::sqrt(det), s.gi11 = s.g22 / det, s.gi12 = -s.g12 / det, s.gi22 = s.g11 / det;
    for (int b = 0; b < metric.side(); ++b)
      for (int a = 0; a < metric.side(); ++a) metric.at(p, a, b) = s;
  }
  const SurfaceLaplacian op(torus.topo, metric);
  std::vector<double> global(std::size_t(m) * m);
  unsigned state = 99;
  for (double& v : global) {
    state = state * 1664525u + 1013904223u;
    v = double(state >> 8) / double(1 << 24) - 0.5;
  }
  auto at = [&](int x, int y) { return global[std::size_t((y + m) % m) * m + (x + m) % m]; };
  PatchField phi = op.grid().make_field(), lap = op.grid().make_field();
  for (int p = 0; p < op.patches(); ++p)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const auto g = torus.global_cell(p, i, j);
        phi[op.grid().index(p, i, j)] = at(g[0], g[1]);
      }
  op.apply(phi, lap);
  const double det = G[0] * G[2] - G[1] * G[1], h = 1.0 / m;
  const double a = G[2] / det, b = -G[1] / det, c = G[0] / det;  // g^ij
  double worst = 0, scale = 0;
  for (int p = 0; p < op.patches(); ++p)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const auto g = torus.global_cell(p, i, j);
        const int x = g[0], y = g[1];
        const double want =
            (a * (at(x + 1, y) + at(x - 1, y) - 2 * at(x, y)) +
             c * (at(x, y + 1) + at(x, y - 1) - 2 * at(x, y)) +
             b * 0.5 *
                 (at(x + 1, y + 1) - at(x + 1, y - 1) - at(x - 1, y + 1) + at(x - 1, y - 1))) /
            (h * h);
        worst = std::max(worst, std::abs(lap[op.grid().index(p, i, j)] - want));
        scale = std::max(scale, std::abs(want));
      }
  std::printf("sheared flat torus: |lap - global 9-point| / |lap| = %.2e\n", worst / scale);
  EXPECT_LT(worst / scale, 1e-12);
}

TEST(SurfaceLaplacianFlat, FourierModesAreEigenvectorsConvergingAtSecondOrder) {
  const int k = 4, p1 = 1, p2 = 2;
  double previous = 0;
  for (int n : {4, 8, 16}) {
    const int m = k * n;
    const double h = 1.0 / m;
    FlatTorus torus(k, n);
    const SurfaceLaplacian op(torus.topo, flat_metric(torus.topo, n, 1.0 / k));
    PatchField phi = op.grid().make_field(), lap = op.grid().make_field();
    for (int p = 0; p < op.patches(); ++p)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          const auto g = torus.global_cell(p, i, j);
          phi[op.grid().index(p, i, j)] =
              std::cos(2 * kPi * (p1 * (g[0] + 0.5) + p2 * (g[1] + 0.5)) * h);
        }
    op.apply(phi, lap);
    const double discrete =
        -4 / (h * h) * (std::pow(std::sin(kPi * p1 * h), 2) + std::pow(std::sin(kPi * p2 * h), 2));
    const double exact = -4 * kPi * kPi * (p1 * p1 + p2 * p2);
    double worst = 0;
    for (int p = 0; p < op.patches(); ++p)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          const std::size_t c = op.grid().index(p, i, j);
          worst = std::max(worst, std::abs(lap[c] - discrete * phi[c]));
        }
    EXPECT_LT(worst, 1e-9 * std::abs(discrete));
    const double err = std::abs(discrete - exact) / std::abs(exact);
    std::printf("flat torus N=%d: mode (1,2) eigenvalue error %.3e%s\n", n, err,
                previous > 0 ? (", ratio " + std::to_string(previous / err)).c_str() : "");
    if (previous > 0) {
      EXPECT_NEAR(previous / err, 4.0, 0.1);
    }
    previous = err;
  }
}

// Relative L2 (area-weighted) and max errors of the discrete operator against the exact one,
// over the cells at Chebyshev distance >= `away` (in patch parameters) from every extraordinary
// corner, and over the rest.
struct Errors {
  double l2_far = 0, max_far = 0, l2_near = 0, max_near = 0;
};

Errors laplacian_error(const LimitSurface& s, int n, CornerGhosts corners, double away,
                       double (*f)(const Cell&), double (*lap_f)(const Cell&)) {
  const PatchMetric metric = sample_limit_metric(s, n);
  const SurfaceLaplacian op(s.topology(), metric, corners);
  PatchField phi = sample(s, op.grid(), f), want = sample(s, op.grid(), lap_f);
  PatchField lap = op.grid().make_field();
  op.apply(phi, lap);
  Errors e;
  double norm = 0;
  for (int p = 0; p < op.patches(); ++p)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const std::size_t c = op.grid().index(p, i, j);
        const double x = (i + 0.5) / n, y = (j + 0.5) / n, d = lap[c] - want[c];
        const double corner_x[4] = {0, 1, 1, 0}, corner_y[4] = {0, 0, 1, 1};
        bool near = false;
        for (int k = 0; k < 4; ++k)
          near |= !s.topology().regular_corner(p, k) &&
                  std::max(std::abs(x - corner_x[k]), std::abs(y - corner_y[k])) < away;
        (near ? e.l2_near : e.l2_far) += op.cell_area(p, i, j) * d * d;
        double& m = near ? e.max_near : e.max_far;
        m = std::max(m, std::abs(d));
        norm += op.cell_area(p, i, j) * want[c] * want[c];
      }
  e.l2_far = std::sqrt(e.l2_far / norm);
  e.l2_near = std::sqrt(e.l2_near / norm);
  return e;
}

// The cube-sphere's parametrisation is singular at its 8 extraordinary vertices (valence 3:
// |X_x| ~ r^0.29, |X_xx| ~ r^-0.71 at parameter distance r), so the stencil is not consistent
// in the cells touching them; away from them the operator converges, at first order in the
// max norm (the limit surface is C2 across patch edges, its third derivatives jump there) and
// faster in L2.
TEST(SurfaceLaplacianCubeSphere, L1AndL2FunctionsConvergeAwayFromExtraordinaryVertices) {
  LimitSurface s;
  ASSERT_TRUE(LimitSurface::build(rotate_faces(cube_mesh(1), 3), {}, s));
  struct Case {
    const char* name;
    double (*f)(const Cell&);
    double (*lap)(const Cell&);
  };
  const double away = 1.0 / 16;
  for (const Case& c : {Case{"l=1 (x)", l1, lap_l1}, Case{"l=2 (xy)", l2, lap_l2}}) {
    Errors previous;
    for (int n : {8, 16, 32, 64}) {
      const Errors e = laplacian_error(s, n, CornerGhosts::kDiagonalExtrapolate, away, c.f, c.lap);
      std::printf("cube-sphere %s N=%2d: >= 1/16 from the vertices: L2 %.3e max %.3e", c.name, n,
                  e.l2_far, e.max_far);
      if (previous.l2_far > 0)
        std::printf(" (orders %.2f, %.2f)", std::log2(previous.l2_far / e.l2_far),
                    std::log2(previous.max_far / e.max_far));
      std::printf("; within 1/16: L2 %.3e max %.3e\n", e.l2_near, e.max_near);
      if (n >= 32) {
        EXPECT_GT(std::log2(previous.l2_far / e.l2_far), 1.4) << c.name << " N=" << n;
        EXPECT_GT(std::log2(previous.max_far / e.max_far), 0.7) << c.name << " N=" << n;
      }
      previous = e;
    }
  }
}

// A cube with its vertices moved, where the cross terms do not vanish on patch edges (on the
// symmetric cube they do): the corner ghost rule at extraordinary vertices, compared.
TEST(SurfaceLaplacianCubeSphere, CornerGhostRulesOnAnIrregularCube) {
  PolyMesh mesh = rotate_faces(cube_mesh(2), 8);
  unsigned state = 5;
  for (auto& p : mesh.points)
    for (double& x : p) {
      state = state * 1664525u + 1013904223u;
      x += 0.15 * (double(state >> 8) / double(1 << 24) - 0.5);
    }
  LimitSurface s;
  ASSERT_TRUE(LimitSurface::build(mesh, {}, s));
  for (CornerGhosts corners : {CornerGhosts::kDiagonalExtrapolate, CornerGhosts::kSeedAverage}) {
    Errors previous;
    for (int n : {8, 16, 32}) {
      const Errors e = laplacian_error(s, n, corners, 1.0 / 16, l2, lap_l2);
      std::printf(
          "irregular cube, %s corner ghosts, N=%2d: l=2 L2 error %.3e away from and %.3e "
          "near the extraordinary vertices\n",
          corners == CornerGhosts::kSeedAverage ? "seed-average" : "extrapolated", n, e.l2_far,
          e.l2_near);
      if (previous.l2_far > 0) {
        EXPECT_LT(e.l2_far, previous.l2_far);
      }
      previous = e;
    }
  }
}

}  // namespace
}  // namespace ardcell
