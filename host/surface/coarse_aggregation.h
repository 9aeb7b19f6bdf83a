#pragma once
// The levels of SurfaceMultigrid below one cell a patch (host/surface/surface_multigrid.h): the
// Laplace-Beltrami operator as a sparse matrix, then unsmoothed aggregation (Vanek, Mandel and
// Brezina 1996, without the smoothing of the prolongation) until a dense solve can take it.
//
// Why: the patch levels coarsen every patch alike and stop at one cell a patch, so a mesh of P
// patches leaves P cells at the bottom. Up to SurfaceMultigrid::kMaxDirectCells a dense LU
// solves them; beyond (a sculpture's 16674 patches) point sweeps there cannot reach the global
// modes, and every V-cycle of the projection cost hundreds of sweeps for little.
//
// The first sparse level is that grid's lap, read off the operator by probing: lap of one cell
// reads the cells of the patches that share a corner vertex with its patch (edge ghosts,
// corner ghosts and the stitched fluxes of the edge neighbours all come from there), so lap
// applied to the indicator of a set of patches no two of which are both that close to any
// third patch gives, at each cell, the one coefficient of its row that the set holds (a
// distance-2 colouring of the vertex-sharing graph; tens of applications of the operator).
// Each further level groups cells into aggregates greedily (a free cell and its free
// neighbours; the cells left join the neighbour they are most strongly coupled to) and takes
// the Galerkin operator of piecewise-constant prolongation P and area-weighted restriction R:
//   lap_c = R lap P,   (lap_c y)_I = (1 / A_I) sum_{i in I} A_i (lap P y)_i,   A_I = sum A_i,
// which keeps lap's null space (constants on each piece) and its conservation (the area-weighted
// total of lap_c y is 0), so the bordered Poisson solve of the bottom level stays valid.
// A piecewise-constant correction is too small for smooth modes (an aggregate k cells wide sees
// the jump to its neighbour over one cell's width, not k), so the V-cycle prolongs it scaled by
// kProlongationScale, a fixed factor (the preconditioner stays linear for BiCGSTAB).
#include <vector>

#include "host/surface/patch_topology.h"
#include "host/surface/surface_laplacian.h"

namespace ardcell {

struct SparseLevel {
  int cells = 0;
  std::vector<int> start, col;  // compressed rows of lap, columns ascending
  std::vector<double> lap;      // lap's coefficients
  std::vector<double> area;     // each cell's area
  std::vector<int> piece;       // each cell's connected piece
  std::vector<int> coarse;      // each cell's aggregate on the next level (empty on the last)
  mutable std::vector<double> b, x, r;
};

inline constexpr double kProlongationScale = 1.8;

// lap of `op`, a grid of one cell a patch, as a sparse level (pieces: patch_pieces(topo)).
SparseLevel probe_patch_level(const SurfaceLaplacian& op, const PatchTopology& topo,
                              const std::vector<int>& pieces);
// Groups `fine`'s cells into aggregates (sets fine.coarse) and returns the Galerkin level.
SparseLevel aggregate_level(SparseLevel& fine);

// `sweeps` l1-Jacobi sweeps of (a I + s lap) x = b (a = 1, s = -c: implicit diffusion; a = 0,
// s = 1: the Poisson problem), as SurfaceLaplacian's smoothers: each update divided by the row's
// diagonal, its sign kept, grown by the magnitudes of the off-diagonal coefficients.
void sparse_sweeps(const SparseLevel& level, double a, double s, int sweeps);
// level.r = level.b - (a I + s lap) level.x.
void sparse_residual(const SparseLevel& level, double a, double s);

}  // namespace ardcell
