#include "kernels/surface_laplacian.h"

#include <algorithm>
#include <cmath>

namespace ardcell {

void surface_face_fluxes(View<const double> phi, const PatchStencil& s, View<double> f1,
                         View<double> f2, int n) {
  for (int j = 0; j < n; ++j) {
    const double* up = phi.row(j + 1);
    const double* mid = phi.row(j);
    const double* down = phi.row(j - 1);
    const double* ax = s.ax.row(j);
    const double* bx = s.bx.row(j);
    double* out = f1.row(j);
    for (int i = 0; i <= n; ++i)
      out[i] = ax[i] * (mid[i] - mid[i - 1]) +
               bx[i] * (up[i] - down[i] + up[i - 1] - down[i - 1]) * 0.25;
  }
  for (int j = 0; j <= n; ++j) {
    const double* mid = phi.row(j);
    const double* down = phi.row(j - 1);
    const double* ay = s.ay.row(j);
    const double* by = s.by.row(j);
    double* out = f2.row(j);
    for (int i = 0; i < n; ++i)
      out[i] = ay[i] * (mid[i] - down[i]) +
               by[i] * (mid[i + 1] - mid[i - 1] + down[i + 1] - down[i - 1]) * 0.25;
  }
}

void surface_flux_divergence(View<const double> f1, View<const double> f2, View<const double> area,
                             View<double> out, int n) {
  for (int j = 0; j < n; ++j) {
    const double* a = f1.row(j);
    const double* b0 = f2.row(j);
    const double* b1 = f2.row(j + 1);
    const double* w = area.row(j);
    double* o = out.row(j);
    for (int i = 0; i < n; ++i) o[i] = (a[i + 1] - a[i] + b1[i] - b0[i]) / w[i];
  }
}

void surface_laplacian_diagonal(const PatchStencil& s, View<double> diag, int n) {
  for (int j = 0; j < n; ++j) {
    const double* ax = s.ax.row(j);
    const double* ay0 = s.ay.row(j);
    const double* ay1 = s.ay.row(j + 1);
    const double* w = s.area.row(j);
    double* d = diag.row(j);
    for (int i = 0; i < n; ++i) d[i] = -(ax[i] + ax[i + 1] + ay0[i] + ay1[i]) / w[i];
  }
}

double surface_jacobi_update(View<const double> b, View<const double> lap_x,
                             View<const double> diag, View<const double> x, View<double> x_out,
                             double c, int n) {
  double largest = 0;
  for (int j = 0; j < n; ++j) {
    const double* bb = b.row(j);
    const double* l = lap_x.row(j);
    const double* d = diag.row(j);
    const double* xx = x.row(j);
    double* xo = x_out.row(j);
    for (int i = 0; i < n; ++i) {
      const double r = bb[i] - xx[i] + c * l[i];
      largest = std::max(largest, std::abs(r));
      xo[i] = xx[i] + r / (1.0 - c * d[i]);
    }
  }
  return largest;
}

}  // namespace ardcell
