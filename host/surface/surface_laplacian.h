#pragma once
// The Laplace-Beltrami operator on a whole patched surface and implicit diffusion with it
// (seed 004, Sec. 4.2 and 6; the per-patch stencil is kernels/surface_laplacian.h).
//
// Conservation. Each patch computes the fluxes through its own edge faces from its own ghost
// cells; across a patch edge the two sides agree to truncation error, not to rounding (the
// cross terms read corner ghosts, which each side fills its own way). Each shared edge face's
// two fluxes are therefore replaced by their mean before the divergence, so that what leaves
// one patch enters the other and sum(sqrt(G) h^2 lap phi) = 0 on a closed surface.
//
// Implicit diffusion (I - c lap) x = b, c = dt r, by Jacobi sweeps with a ghost exchange after
// each (the seed's Sec. 7.3.2), to a relative residual or a sweep count. The exact solution
// keeps the total, total(x) = total(b); a Jacobi iterate keeps it only to its residual, so the
// answer is the last iterate shifted by the constant (lap's null space on a closed surface, and
// with no-flux boundaries) that restores the total: conserved to rounding after any number of
// sweeps, the residual changed by that constant alone.
//
// Work runs per patch (per shared edge when stitching) on a RowExecutor, so the threads back end
// runs patches side by side; every per-cell result and every reduction (maxima, and totals as
// per-patch partials added in patch order) is the same bits for any number of workers.
#include <vector>

#include "runtime/row_executor.h"

#include "host/surface/patch_grid.h"
#include "host/surface/patch_metric.h"
#include "kernels/surface_laplacian.h"

namespace ardcell {

struct DiffusionSolve {
  double tolerance = 1e-8;  // max |b - (I - c lap) y| / max |b|
  int max_sweeps = 2000;
};

struct DiffusionReport {
  int sweeps = 0;       // Jacobi sweeps (multigrid: smoothing sweeps on the finest grid)
  int cycles = 0;       // multigrid V-cycles (host/surface/surface_multigrid.h); 0 for Jacobi
  double residual = 0;  // relative, of the last iterate
};

class SurfaceLaplacian {
 public:
  SurfaceLaplacian(const PatchTopology& topo, const PatchMetric& metric,
                   CornerGhosts corners = CornerGhosts::kDiagonalExtrapolate);

  // Where the patches run (the serial executor by default); `executor` must outlive the operator.
  void set_executor(RowExecutor& executor) { executor_ = &executor; }
  RowExecutor& executor() const { return *executor_; }

  const PatchGrid& grid() const { return grid_; }
  int n() const { return grid_.n(); }
  int patches() const { return grid_.patches(); }

  // out = lap phi on every interior cell (phi's ghost ring is filled first).
  void apply(PatchField& phi, PatchField& out) const;
  // sum over cells of sqrt(G) h^2 phi: the integral of phi over the surface.
  double total(const PatchField& phi) const;
  double area() const;
  // sqrt(G) h^2 of cell (i, j) of patch p.
  double cell_area(int p, int i, int j) const {
    return area_[(std::size_t(p) * n() + j) * n() + i];
  }

  // Solves (I - c lap) x = b; x holds the first guess on entry. b's ghosts are not read; x's
  // buffer may come back exchanged with the operator's scratch (same size), its ghosts stale.
  DiffusionReport implicit_diffusion(PatchField& x, const PatchField& b, double c,
                                     const DiffusionSolve& solve) const;
  // `sweeps` l1-Jacobi sweeps of (I - c lap) x = b (multigrid's smoother): each cell's update
  // divided by its row's diagonal plus the magnitudes of its off-diagonal coefficients, which
  // converges for any c, where plain Jacobi diverges once c lap's cross terms (g^12) outweigh
  // its diagonal. x's buffer exchanged as by implicit_diffusion.
  void smoothing_sweeps(PatchField& x, const PatchField& b, double c, int sweeps) const;
  // r = b - (I - c lap) x on every interior cell (x's ghost ring is filled first); returns
  // max |r|.
  double residual(PatchField& x, const PatchField& b, double c, PatchField& r) const;
  // The Poisson problem lap x = b (the fluid's projection, host/surface/surface_fluid.h; lap is
  // singular: constants are its null space, and b must have total 0): `sweeps` l1-Jacobi sweeps
  // x' = x + (b - lap x) / d, d minus the row's absolute sum (as smoothing_sweeps). x's buffer
  // exchanged as by implicit_diffusion.
  void poisson_sweeps(PatchField& x, const PatchField& b, int sweeps) const;
  // r = b - lap x on every interior cell (x's ghost ring is filled first); returns max |r|.
  double poisson_residual(PatchField& x, const PatchField& b, PatchField& r) const;
  // max |f| over the interior cells.
  double max_abs(const PatchField& f) const;
  // x += s on every interior cell.
  void add(PatchField& x, double s) const;

 private:
  PatchStencil stencil(int p) const;
  View<const double> cells(const std::vector<double>& v, int p) const;
  View<double> cells(std::vector<double>& v, int p) const;
  void stitch_fluxes() const;
  // The face fluxes of phi (its ghost ring exchanged first), stitched across patch edges.
  void fluxes(PatchField& phi) const;
  // out = the divergence of the fluxes on patch p's interior (after fluxes()).
  void divergence(int p, PatchField& out) const;
  // r = b - x_weight x + lap_weight lap x on every interior cell (x's ghost ring filled
  // first): (I - c lap) with (1, c), the Poisson problem lap x = b with (0, -1); max |r|.
  double residual_of(PatchField& x, const PatchField& b, double x_weight, double lap_weight,
                     PatchField& r) const;
  // One Jacobi sweep of x into next_ (the fluxes of x, then per patch its lap, residual and
  // update); returns x's max |r|.
  double sweep_into_next(PatchField& x, const PatchField& b, double c,
                         const std::vector<double>& diag) const;

  PatchGrid grid_;
  RowExecutor* executor_ = &RowExecutor::serial();
  std::vector<double> ax_, bx_, ay_, by_, area_, diag_;
  // -(the diagonal's and the off-diagonals' magnitudes) / area: the l1 smoother's diagonal.
  std::vector<double> l1_diag_;
  // Scratch (the operator is used from one thread at a time).
  mutable std::vector<double> f1_, f2_, lap_, lap_interior_, patch_max_, next_;
};

}  // namespace ardcell
