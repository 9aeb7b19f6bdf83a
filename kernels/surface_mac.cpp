#include "kernels/surface_mac.h"

#include <algorithm>
#include <cmath>

namespace ardcell {

void mac_divergence(View<const double> u1, View<const double> u2, const MacStencil& s,
                    View<double> out, int n) {
  const double h = 1.0 / n;
  for (int j = 0; j < n; ++j) {
    const double* a = u1.row(j);
    const double* s1 = s.s1.row(j);
    const double* b0 = u2.row(j);
    const double* b1 = u2.row(j + 1);
    const double* t0 = s.s2.row(j);
    const double* t1 = s.s2.row(j + 1);
    const double* w = s.area.row(j);
    double* o = out.row(j);
    for (int i = 0; i < n; ++i)
      o[i] = h * (s1[i + 1] * a[i + 1] - s1[i] * a[i] + t1[i] * b1[i] - t0[i] * b0[i]) / w[i];
  }
}

void mac_subtract_gradient(View<const double> phi, const MacStencil& s, View<double> u1,
                           View<double> u2, int n) {
  const double h = 1.0 / n;
  // The same expressions as kernels/surface_laplacian.cpp's fluxes, over h sqrt(G).
  for (int j = 0; j < n; ++j) {
    const double* up = phi.row(j + 1);
    const double* mid = phi.row(j);
    const double* down = phi.row(j - 1);
    const double* ax = s.a1.row(j);
    const double* bx = s.b1.row(j);
    const double* sg = s.s1.row(j);
    double* u = u1.row(j);
    for (int i = 0; i <= n; ++i)
      u[i] -= (ax[i] * (mid[i] - mid[i - 1]) +
               bx[i] * (up[i] - down[i] + up[i - 1] - down[i - 1]) * 0.25) /
              (h * sg[i]);
  }
  for (int j = 0; j <= n; ++j) {
    const double* mid = phi.row(j);
    const double* down = phi.row(j - 1);
    const double* ay = s.a2.row(j);
    const double* by = s.b2.row(j);
    const double* sg = s.s2.row(j);
    double* u = u2.row(j);
    for (int i = 0; i < n; ++i)
      u[i] -= (ay[i] * (mid[i] - down[i]) +
               by[i] * (mid[i + 1] - mid[i - 1] + down[i + 1] - down[i - 1]) * 0.25) /
              (h * sg[i]);
  }
}

double mac_viscosity_sweep(View<const double> u1, View<const double> u2, View<const double> b1,
                           View<const double> b2, const MacStencil& s, double c, View<double> out1,
                           View<double> out2, int n) {
  const double k = c * n * n;  // c / h^2
  double largest = 0;
  const auto sweep = [&](View<const double> u, View<const double> b, View<const double> gii,
                         View<const double> gjj, View<double> out, int ni, int nj) {
    for (int j = 0; j < nj; ++j) {
      const double* up = u.row(j + 1);
      const double* mid = u.row(j);
      const double* down = u.row(j - 1);
      const double* rhs = b.row(j);
      const double* g1 = gii.row(j);
      const double* g2 = gjj.row(j);
      double* o = out.row(j);
      for (int i = 0; i < ni; ++i) {
        const double off = k * (g1[i] * (mid[i + 1] + mid[i - 1]) + g2[i] * (up[i] + down[i]));
        const double diag = 1 + 2 * k * (g1[i] + g2[i]);
        largest = std::max(largest, std::abs(rhs[i] - diag * mid[i] + off));
        o[i] = (rhs[i] + off) / diag;
      }
    }
  };
  sweep(u1, b1, s.gii1, s.gjj1, out1, n + 1, n);
  sweep(u2, b2, s.gii2, s.gjj2, out2, n, n + 1);
  return largest;
}

namespace {

double bilinear(View<const double> f, double fx, double fy) {
  const Box2& b = f.box();
  // A coordinate outside the grid (or not a number) is held at its edge.
  const double hx = b.max.x - 1, hy = b.max.y - 1;
  if (!(fx >= b.min.x)) fx = b.min.x;
  if (!(fx <= hx)) fx = hx;
  if (!(fy >= b.min.y)) fy = b.min.y;
  if (!(fy <= hy)) fy = hy;
  const int i0 = std::min(int(std::floor(fx)), b.max.x - 2);
  const int j0 = std::min(int(std::floor(fy)), b.max.y - 2);
  const double wx = fx - i0, wy = fy - j0;
  const double* r0 = f.row(j0);
  const double* r1 = f.row(j0 + 1);
  return (1 - wy) * ((1 - wx) * r0[i0] + wx * r0[i0 + 1]) +
         wy * ((1 - wx) * r1[i0] + wx * r1[i0 + 1]);
}

}  // namespace

double sample_cells(View<const double> f, double x1, double x2, int n) {
  return bilinear(f, x1 * n - 0.5, x2 * n - 0.5);
}

double sample_u1(View<const double> u1, double x1, double x2, int n) {
  return bilinear(u1, x1 * n, x2 * n - 0.5);
}

double sample_u2(View<const double> u2, double x1, double x2, int n) {
  return bilinear(u2, x1 * n - 0.5, x2 * n);
}

}  // namespace ardcell
