#include "host/surface/surface_laplacian.h"

#include <algorithm>
#include <cmath>

namespace ardcell {

SurfaceLaplacian::SurfaceLaplacian(const PatchTopology& topo, const PatchMetric& metric,
                                   CornerGhosts corners)
    : grid_(topo, metric.n(), corners) {
  const int n = metric.n(), patches = topo.patches;
  const double h = 1.0 / n;
  const std::size_t faces = std::size_t(n + 1) * n;
  ax_.resize(faces * patches), bx_.resize(faces * patches);
  ay_.resize(faces * patches), by_.resize(faces * patches);
  area_.resize(std::size_t(n) * n * patches), diag_.resize(area_.size());
  f1_.resize(ax_.size()), f2_.resize(ay_.size()), lap_.resize(area_.size());
  for (int p = 0; p < patches; ++p) {
    for (int j = 0; j < n; ++j)
      for (int i = 0; i <= n; ++i) {
        const MetricSample& m = metric.at(p, 2 * i + 1, 2 * j + 2);  // x1-face (i - 1/2, j)
        const std::size_t k = p * faces + std::size_t(j) * (n + 1) + i;
        ax_[k] = m.sqrt_g * m.gi11;
        bx_[k] = m.sqrt_g * m.gi12;
      }
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i < n; ++i) {
        const MetricSample& m = metric.at(p, 2 * i + 2, 2 * j + 1);  // x2-face (i, j - 1/2)
        const std::size_t k = p * faces + std::size_t(j) * n + i;
        ay_[k] = m.sqrt_g * m.gi22;
        by_[k] = m.sqrt_g * m.gi12;
      }
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        area_[(std::size_t(p) * n + j) * n + i] = metric.at(p, 2 * i + 2, 2 * j + 2).sqrt_g * h * h;
    surface_laplacian_diagonal(stencil(p), cells(diag_, p), n);
  }
  // Row sums of |coefficient| of lap (kernels/surface_laplacian.h): the four faces' a terms twice
  // (the cell and its neighbour), each face's cross term b / 4 on four cells.
  l1_diag_.resize(area_.size());
  for (int p = 0; p < patches; ++p)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const std::size_t x0 = p * faces + std::size_t(j) * (n + 1) + i, x1 = x0 + 1;
        const std::size_t y0 = p * faces + std::size_t(j) * n + i, y1 = y0 + n;
        const double a = ax_[x0] + ax_[x1] + ay_[y0] + ay_[y1];
        const double b =
            std::abs(bx_[x0]) + std::abs(bx_[x1]) + std::abs(by_[y0]) + std::abs(by_[y1]);
        const std::size_t k = (std::size_t(p) * n + j) * n + i;
        l1_diag_[k] = -(2 * a + b) / area_[k];
      }
}

PatchStencil SurfaceLaplacian::stencil(int p) const {
  const int n = grid_.n();
  const std::size_t faces = std::size_t(n + 1) * n;
  const Box2 xfaces{{0, 0}, {n + 1, n}}, yfaces{{0, 0}, {n, n + 1}};
  return PatchStencil{View<const double>(ax_.data() + p * faces, n + 1, xfaces),
                      View<const double>(bx_.data() + p * faces, n + 1, xfaces),
                      View<const double>(ay_.data() + p * faces, n, yfaces),
                      View<const double>(by_.data() + p * faces, n, yfaces), cells(area_, p)};
}

View<const double> SurfaceLaplacian::cells(const std::vector<double>& v, int p) const {
  const int n = grid_.n();
  return View<const double>(v.data() + std::size_t(p) * n * n, n, Box2{{0, 0}, {n, n}});
}

View<double> SurfaceLaplacian::cells(std::vector<double>& v, int p) const {
  const int n = grid_.n();
  return View<double>(v.data() + std::size_t(p) * n * n, n, Box2{{0, 0}, {n, n}});
}

void SurfaceLaplacian::stitch_fluxes() const {
  const int n = grid_.n();
  const std::size_t faces = std::size_t(n + 1) * n;
  // The flux array element and the sign that makes it outward, for face m of edge e.
  auto outward = [&](int p, int e, int m, double*& at) -> double {
    double* f1 = f1_.data() + p * faces;  // (i, j) at j * (n + 1) + i
    double* f2 = f2_.data() + p * faces;  // (i, j) at j * n + i
    switch (e) {
      case 0:
        at = f2 + m;
        return -1;  // (m, 0)
      case 1:
        at = f1 + std::size_t(m) * (n + 1) + n;
        return 1;  // (n, m)
      case 2:
        at = f2 + std::size_t(n) * n + (n - 1 - m);
        return 1;  // (n-1-m, n)
      default:
        at = f1 + std::size_t(n - 1 - m) * (n + 1);
        return -1;  // (0, n-1-m)
    }
  };
  // Each shared edge writes its own faces only: the edges run side by side.
  const auto& shared = grid_.shared_edges();
  executor_->for_rows(int(shared.size()), n, [&](int e0, int e1) {
    for (int e = e0; e < e1; ++e) {
      const auto& s = shared[std::size_t(e)];
      for (int m = 0; m < n; ++m) {
        double *a, *b;
        const double sa = outward(s.p, s.e, m, a), sb = outward(s.q, s.f, n - 1 - m, b);
        const double mean = 0.5 * (sa * *a - sb * *b);  // outward from p
        *a = sa * mean;
        *b = -sb * mean;
      }
    }
  });
  for (const auto& [p, e] : grid_.boundary_edges())
    for (int m = 0; m < n; ++m) {
      double* a;
      outward(p, e, m, a);
      *a = 0;
    }
}

void SurfaceLaplacian::fluxes(PatchField& phi) const {
  const int n = grid_.n();
  const std::size_t faces = std::size_t(n + 1) * n;
  const Box2 xfaces{{0, 0}, {n + 1, n}}, yfaces{{0, 0}, {n, n + 1}};
  // Per patch: its ghosts from the neighbours' interiors (which no one writes in this pass),
  // then its face fluxes from its own cells and ghosts.
  executor_->for_rows(grid_.patches(), n * n, [&](int p0, int p1) {
    for (int p = p0; p < p1; ++p) grid_.exchange(phi, p);
    for (int p = p0; p < p1; ++p)
      surface_face_fluxes(grid_.view(std::as_const(phi), p), stencil(p),
                          View<double>(f1_.data() + p * faces, n + 1, xfaces),
                          View<double>(f2_.data() + p * faces, n, yfaces), n);
  });
  stitch_fluxes();
}

void SurfaceLaplacian::divergence(int p, PatchField& out) const {
  const int n = grid_.n();
  const std::size_t faces = std::size_t(n + 1) * n;
  const Box2 xfaces{{0, 0}, {n + 1, n}}, yfaces{{0, 0}, {n, n + 1}};
  surface_flux_divergence(View<const double>(f1_.data() + p * faces, n + 1, xfaces),
                          View<const double>(f2_.data() + p * faces, n, yfaces), cells(area_, p),
                          grid_.view(out, p).crop(Box2{{0, 0}, {n, n}}), n);
}

void SurfaceLaplacian::apply(PatchField& phi, PatchField& out) const {
  fluxes(phi);
  executor_->for_rows(grid_.patches(), grid_.n() * grid_.n(), [&](int p0, int p1) {
    for (int p = p0; p < p1; ++p) divergence(p, out);
  });
}

double SurfaceLaplacian::total(const PatchField& phi) const {
  const int n = grid_.n();
  return executor_->sum_rows(grid_.patches(), n * n, [&](int p0, int p1, double* partial) {
    for (int p = p0; p < p1; ++p) {
      double sum = 0;
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) sum += cell_area(p, i, j) * phi[grid_.index(p, i, j)];
      partial[p] = sum;
    }
  });
}

double SurfaceLaplacian::area() const {
  double sum = 0;
  for (double a : area_) sum += a;
  return sum;
}

double SurfaceLaplacian::max_abs(const PatchField& f) const {
  // Per patch on the executor (a maximum is the same in any order).
  const int n = grid_.n(), patches = grid_.patches();
  if (patch_max_.size() != std::size_t(patches)) patch_max_.assign(std::size_t(patches), 0.0);
  executor_->for_rows(patches, n * n, [&](int p0, int p1) {
    for (int p = p0; p < p1; ++p) {
      double m = 0;
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) m = std::max(m, std::abs(f[grid_.index(p, i, j)]));
      patch_max_[std::size_t(p)] = m;
    }
  });
  return *std::max_element(patch_max_.begin(), patch_max_.end());
}

void SurfaceLaplacian::add(PatchField& x, double s) const {
  const int n = grid_.n();
  executor_->for_rows(grid_.patches(), n * n, [&](int p0, int p1) {
    for (int p = p0; p < p1; ++p)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) x[grid_.index(p, i, j)] += s;
  });
}

double SurfaceLaplacian::sweep_into_next(PatchField& x, const PatchField& b, double c,
                                         const std::vector<double>& diag) const {
  const int n = grid_.n(), patches = grid_.patches();
  if (lap_interior_.size() != x.size()) lap_interior_.assign(x.size(), 0.0);
  if (next_.size() != x.size()) next_.assign(x.size(), 0.0);
  if (patch_max_.size() != std::size_t(patches)) patch_max_.assign(std::size_t(patches), 0.0);
  PatchField& lap = lap_interior_;
  // Two passes: the fluxes of x (stitched across the edges), then per patch lap x, the residual
  // of x and the swept iterate into next_.
  fluxes(x);
  executor_->for_rows(patches, n * n, [&](int p0, int p1) {
    const Box2 inner{{0, 0}, {n, n}};
    for (int p = p0; p < p1; ++p) {
      divergence(p, lap);
      patch_max_[std::size_t(p)] = surface_jacobi_update(
          grid_.view(b, p).crop(inner), grid_.view(std::as_const(lap), p).crop(inner),
          cells(diag, p), grid_.view(std::as_const(x), p).crop(inner),
          grid_.view(next_, p).crop(inner), c, n);
    }
  });
  return *std::max_element(patch_max_.begin(), patch_max_.end());
}

void SurfaceLaplacian::smoothing_sweeps(PatchField& x, const PatchField& b, double c,
                                        int sweeps) const {
  for (int s = 0; s < sweeps; ++s) {
    sweep_into_next(x, b, c, l1_diag_);
    std::swap(x, next_);  // buffers only: x's ghosts are filled by the next exchange
  }
}

void SurfaceLaplacian::poisson_sweeps(PatchField& x, const PatchField& b, int sweeps) const {
  const int n = grid_.n(), patches = grid_.patches();
  if (lap_interior_.size() != x.size()) lap_interior_.assign(x.size(), 0.0);
  if (next_.size() != x.size()) next_.assign(x.size(), 0.0);
  PatchField& lap = lap_interior_;
  for (int s = 0; s < sweeps; ++s) {
    fluxes(x);
    executor_->for_rows(patches, n * n, [&](int p0, int p1) {
      for (int p = p0; p < p1; ++p) {
        divergence(p, lap);
        for (int j = 0; j < n; ++j)
          for (int i = 0; i < n; ++i) {
            const std::size_t k = grid_.index(p, i, j);
            next_[k] = x[k] + (b[k] - lap[k]) / l1_diag_[(std::size_t(p) * n + j) * n + i];
          }
      }
    });
    std::swap(x, next_);  // buffers only: x's ghosts are filled by the next exchange
  }
}

double SurfaceLaplacian::residual(PatchField& x, const PatchField& b, double c,
                                  PatchField& r) const {
  return residual_of(x, b, 1, c, r);
}

double SurfaceLaplacian::poisson_residual(PatchField& x, const PatchField& b, PatchField& r) const {
  return residual_of(x, b, 0, -1, r);
}

double SurfaceLaplacian::residual_of(PatchField& x, const PatchField& b, double x_weight,
                                     double lap_weight, PatchField& r) const {
  const int n = grid_.n(), patches = grid_.patches();
  if (patch_max_.size() != std::size_t(patches)) patch_max_.assign(std::size_t(patches), 0.0);
  fluxes(x);
  executor_->for_rows(patches, n * n, [&](int p0, int p1) {
    for (int p = p0; p < p1; ++p) {
      divergence(p, r);  // r holds lap x, then the residual
      double m = 0;
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          const std::size_t k = grid_.index(p, i, j);
          // x_weight 0 skips x (not 0 * x: an inf or NaN there stays out of the residual).
          r[k] = (x_weight != 0 ? b[k] - x_weight * x[k] : b[k]) + lap_weight * r[k];
          m = std::max(m, std::abs(r[k]));
        }
      patch_max_[std::size_t(p)] = m;
    }
  });
  return *std::max_element(patch_max_.begin(), patch_max_.end());
}

DiffusionReport SurfaceLaplacian::implicit_diffusion(PatchField& x, const PatchField& b, double c,
                                                     const DiffusionSolve& solve) const {
  double bmax = max_abs(b);
  if (bmax == 0) bmax = 1;
  DiffusionReport report;
  for (;;) {
    // The swept iterate replaces x unless x is the answer.
    report.residual = sweep_into_next(x, b, c, diag_) / bmax;
    if (report.residual <= solve.tolerance || report.sweeps >= solve.max_sweeps) break;
    std::swap(x, next_);  // buffers only: x's ghosts are filled by the next exchange
    ++report.sweeps;
  }
  // The exact solution has total(x) = total(b) (lap is conservative); a Jacobi iterate has it
  // only to its residual. A constant is in lap's null space: shift by the difference.
  add(x, (total(b) - total(x)) / area());
  return report;
}

}  // namespace ardcell
