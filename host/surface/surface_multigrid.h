#pragma once
// Implicit diffusion on a patched surface by multigrid V-cycles (seed 004, Sec. 7.3.2 solves by
// Jacobi sweeps; its fluid's projection asks for multigrid): (I - c lap) x = b as
// SurfaceLaplacian::implicit_diffusion solves it, with the same stopping rule (relative residual
// max |b - (I - c lap) x| / max |b|) and the same conservation shift at the end, in far fewer
// passes over the cells when c lap is stiff (a step dt much larger than h^2 / r).
//
// Levels: the patches of N x N cells, then N/2, ... down to 2 x 2 cells a patch (every patch
// coarsens alike, N a power of two), each with its own Laplace-Beltrami operator built from the
// limit surface's metric sampled at that resolution (rediscretisation), its ghost exchange
// across patch edges before every sweep. Cycle: two l1-Jacobi sweeps (convergent for any step,
// where plain Jacobi diverges once the metric's cross terms outweigh the diagonal:
// SurfaceLaplacian::smoothing_sweeps), the residual restricted to the coarser grid as the
// area-weighted mean of each 2 x 2 block (what leaves a fine cell's integral leaves the coarse
// cell's), the correction solved there and added back bilinearly (the coarse ghost ring
// exchanged first), two more sweeps. The coarsest patch grid has one cell a patch; below it the
// levels are sparse matrices (host/surface/coarse_aggregation.h): that grid's lap read off the
// operator, then aggregates of cells with the Galerkin operator, until at most kMaxDirectCells
// cells are left (a mesh of up to that many patches has no aggregate level). The last level is
// solved exactly: a dense LU of its matrix, kept while c stays the same. (Point sweeps on a
// bottom grid of 16674 cells, the elephant's, left the global modes of a projection for
// hundreds of sweeps a cycle; BiCGSTAB there made the preconditioner nonlinear: truncated at 60
// steps the outer iteration no longer converged, and run to 1e-4 it cost more than the cycles
// it saved.) Should aggregation stall above kMaxDirectCells, the last level takes
// kCoarseSweeps sweeps instead.
// Krylov acceleration: the V-cycle is the right preconditioner of BiCGSTAB (van der Vorst 1992;
// the operator is not symmetric: the cross terms read corner ghosts each patch fills its own
// way), not the iteration itself. Point smoothing leaves the modes along a patch's long side
// where patches are stretched (3:1 on a torus of 38 x 34 quads: 37 plain V-cycles a projection
// against 16 on 49 x 23), and the Krylov recurrence removes the few such modes the cycle damps
// poorly. Each BiCGSTAB step runs two V-cycles; DiffusionReport::cycles counts V-cycles.
// Work runs per patch on the fine operator's executor, and every dot product adds per-patch
// partials in patch order: the same bits for any number of workers.
#include <memory>
#include <vector>

#include "host/surface/coarse_aggregation.h"
#include "host/surface/limit_surface.h"
#include "host/surface/surface_laplacian.h"
#include "kernels/bicgstab.h"

namespace ardcell {

class SurfaceMultigrid {
 public:
  static constexpr int kPreSweeps = 2, kPostSweeps = 2, kCoarseSweeps = 200;
  static constexpr int kMaxDirectCells = 2048;  // a 32 MiB matrix, factored in about a second
  static constexpr int kCoarsestCells = 1;      // cells along a patch's side on the coarsest grid

  // `fine` is the operator on N x N cells a patch (kept by reference; it must outlive this);
  // the coarser operators are built from `surface`'s metric. Allocates every level's fields.
  SurfaceMultigrid(const LimitSurface& surface, const SurfaceLaplacian& fine,
                   CornerGhosts corners = CornerGhosts::kDiagonalExtrapolate);
  ~SurfaceMultigrid();

  int levels() const { return int(levels_.size()); }
  // Solves (I - c lap) x = b (x the first guess) to solve.tolerance or solve.max_sweeps V-cycles;
  // x's buffer may come back exchanged with the fine operator's scratch, as by
  // SurfaceLaplacian::implicit_diffusion.
  DiffusionReport implicit_diffusion(PatchField& x, const PatchField& b, double c,
                                     const DiffusionSolve& solve) const;
  // Solves the Poisson problem lap x = b (the fluid's projection, host/surface/surface_fluid.h)
  // by V-cycles of the same levels with SurfaceLaplacian::poisson_sweeps. lap is singular on a
  // closed surface (and with no-flux boundaries): on a surface of several connected pieces its
  // range is the fields of total 0 on every piece and its null space the fields constant on
  // each. So b's area-weighted mean on each piece is taken out first (it is rounding for a
  // divergence), the coarsest grid solves the bordered system (lap + sum over pieces of
  // 1_piece w_piece^T) x = b, w_piece the piece's cells' areas over its area (whose solution is
  // the one with total 0 on every piece), and x comes back with total 0 on every piece. Same
  // stopping rule as implicit_diffusion: max |b - lap x| / max |b| (b after the means are taken
  // out) to solve.tolerance or solve.max_sweeps V-cycles. x holds the first guess (a constant
  // per piece in it is irrelevant).
  DiffusionReport solve_poisson(PatchField& x, const PatchField& b,
                                const DiffusionSolve& solve) const;

 private:
  struct Level;
  void cycle(int level, double c) const;
  void poisson_cycle(int level) const;
  // The coarsest patch grid's correction through the sparse levels: (I - c lap) x = b, or with
  // poisson lap x = b.
  void coarse_correction(double c, bool poisson) const;
  void sparse_cycle(int level, double c, bool poisson) const;
  // The last sparse level's x from its b, exactly (false: too many cells for a dense solve).
  bool solve_coarsest(double c) const;
  bool solve_coarsest_poisson() const;

  // BiCGSTAB's vectors on the finest grid (kernels/bicgstab.h).
  using Krylov = BicgstabVectors<PatchField>;
  // kernels/bicgstab.h's BiCGSTAB on op's grid, right-preconditioned: x from its first guess to
  // max |residual| / bmax <= solve.tolerance or solve.max_sweeps preconditioner applications
  // (the report's cycles). residual(x, r) sets r = b - A x and returns max |r|; apply(y, out)
  // sets out = A y; precondition(q, y) sets y to M^-1 q.
  template <class Residual, class Apply, class Precondition>
  DiffusionReport bicgstab(const SurfaceLaplacian& op, Krylov& k, PatchField& x, double bmax,
                           const DiffusionSolve& solve, const Residual& residual,
                           const Apply& apply, const Precondition& precondition) const;
  // One V-cycle of (I - c lap) (c >= 0) or, with poisson, of lap, from 0 for the right-hand
  // side q: y = M^-1 q.
  void precondition(const PatchField& q, PatchField& y, double c, bool poisson) const;

  // The integral of f over each connected piece of the surface taken out: lap's null space is the
  // fields constant on each piece, its range the fields of total 0 on each.
  void remove_piece_means(const SurfaceLaplacian& op, PatchField& f) const;
  // The area of each piece on the finest grid, computed once.
  const std::vector<double>& piece_areas() const;

  std::vector<std::unique_ptr<Level>> levels_;  // finest first
  std::vector<SparseLevel> sparse_;             // below the coarsest patch grid, its lap first
  std::vector<int> pieces_;                     // the connected piece of each patch (patch_pieces)
  mutable std::vector<double> patch_sums_, piece_sums_, fine_piece_areas_;
  // The finest grid's right-hand side, and BiCGSTAB's vectors there.
  mutable PatchField b_;
  mutable Krylov fine_krylov_;
  // The coarsest matrix I - c lap factored (row-major LU, partial pivoting), one for each of
  // the last kFactors values of c (a reaction-diffusion step solves for two chemicals, each its
  // own c): a factorisation is built once per c, not once per solve.
  struct Factor {
    double c = -1;
    std::vector<double> lu;
    std::vector<int> pivot;
  };
  static constexpr int kFactors = 2;
  const Factor& factor_for(double c) const;
  mutable Factor factors_[kFactors];
  mutable Factor poisson_factor_;               // lap + 1 w^T, built on the first Poisson solve
  mutable std::vector<double> poisson_weight_;  // w: the last level's cells' areas over the total
  mutable int next_factor_ = 0;                 // the slot a new c replaces
  mutable std::vector<double> rhs_;
};

}  // namespace ardcell
