#pragma once
// Shared by the surface tests: fields sampled from functions of the limit surface, and the
// exact Laplace-Beltrami operator of the coordinate functions and their products.
#include <array>
#include <cmath>
#include <functional>
#include <random>

#include "host/surface/limit_surface.h"
#include "host/surface/poly_mesh.h"
#include "host/surface/surface_laplacian.h"

namespace ardcell::surface_test {

struct Cell {
  std::array<double, 3> x;  // position
  double lap_x[3];          // exact lap of the coordinate functions
  std::array<double, 3> n;  // unit normal
};

// At (x1, x2) of patch p: lap_S X = (g^ij X_ij . n) n (the mean-curvature normal).
inline Cell cell_geometry(const LimitSurface& s, int p, double x1, double x2) {
  LimitSample d;
  s.evaluate(p, x1, x2, d);
  const auto& u = d.du;
  const auto& v = d.dv;
  std::array<double, 3> n{u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
                          u[0] * v[1] - u[1] * v[0]};
  const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  for (double& c : n) c /= len;
  const MetricSample m = metric_from_tangents(u, v);
  auto dotn = [&](const std::array<double, 3>& a) {
    return a[0] * n[0] + a[1] * n[1] + a[2] * n[2];
  };
  const double h = m.gi11 * dotn(d.duu) + 2 * m.gi12 * dotn(d.duv) + m.gi22 * dotn(d.dvv);
  Cell c;
  c.x = d.p;
  c.n = n;
  for (int k = 0; k < 3; ++k) c.lap_x[k] = h * n[k];
  return c;
}

// f(cell) on every interior cell of a patch field.
inline PatchField sample(const LimitSurface& s, const PatchGrid& g,
                         const std::function<double(const Cell&)>& f) {
  PatchField out = g.make_field();
  const int n = g.n();
  for (int p = 0; p < g.patches(); ++p)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        out[g.index(p, i, j)] = f(cell_geometry(s, p, (i + 0.5) / n, (j + 0.5) / n));
  return out;
}

// The l = 1 and l = 2 functions of the sphere's harmonics, x and x y, and their exact
// Laplace-Beltrami on the surface: lap(x y) = x lap y + y lap x + 2 grad x . grad y, with
// grad x . grad y = e_x . (I - n n^T) e_y = -n_x n_y.
inline double l1(const Cell& c) { return c.x[0]; }
inline double lap_l1(const Cell& c) { return c.lap_x[0]; }
inline double l2(const Cell& c) { return c.x[0] * c.x[1]; }
inline double lap_l2(const Cell& c) {
  return c.x[0] * c.lap_x[1] + c.x[1] * c.lap_x[0] - 2 * c.n[0] * c.n[1];
}

// Uniform random values in [lo, hi) on every interior cell (ghosts 0).
inline PatchField random_field(const PatchGrid& g, unsigned seed, double lo = 0, double hi = 1) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(lo, hi);
  PatchField f = g.make_field();
  for (int p = 0; p < g.patches(); ++p)
    for (int j = 0; j < g.n(); ++j)
      for (int i = 0; i < g.n(); ++i) f[g.index(p, i, j)] = u(rng);
  return f;
}

// Area-weighted <a, b> over the interior cells.
inline double inner(const SurfaceLaplacian& op, const PatchField& a, const PatchField& b) {
  const PatchGrid& g = op.grid();
  double s = 0;
  for (int p = 0; p < g.patches(); ++p)
    for (int j = 0; j < g.n(); ++j)
      for (int i = 0; i < g.n(); ++i)
        s += op.cell_area(p, i, j) * a[g.index(p, i, j)] * b[g.index(p, i, j)];
  return s;
}

// The flat torus as k x k quads (procedural_mesh.h's torus_mesh(k, k, ...), vertex a k + t at
// lattice point (a, t)): patch p's four corners as lattice points, unwrapped around its corner 0
// so that the quad does not straddle the period.
inline void flat_torus_corners(const PolyMesh& mesh, int k, int p, double corner[4][2]) {
  const int* v = mesh.face(p);
  const int a0 = v[0] / k, t0 = v[0] % k;
  for (int c = 0; c < 4; ++c) {
    int a = v[c] / k, t = v[c] % k;
    if (a - a0 > 1) a -= k;
    if (a0 - a > 1) a += k;
    if (t - t0 > 1) t -= k;
    if (t0 - t > 1) t += k;
    corner[c][0] = a, corner[c][1] = t;
  }
}

}  // namespace ardcell::surface_test
