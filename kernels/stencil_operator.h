#pragma once
// The linear systems every implicit step of ardcell solves: a symmetric 5-point operator with
// one coefficient per cell face (seed 000, Eqn 13 isotropic, Eqn 17 and Eqn 19 anisotropic; Stam's
// implicit viscosity and pressure projection).
//
// Eqn 4 (the 5-point Laplacian: assemble_stencil_operator with no conductivity, k = 1; h the
// cell's length):
//   div(a grad A) ~ a (A(i-1,j) + A(i,j-1) - 4 A(i,j) + A(i+1,j) + A(i,j+1)) / h^2
//
//   (A x)(i,j) = diag(i,j) x(i,j) - wx(i,j) x(i-1,j) - wx(i+1,j) x(i+1,j)
//                                 - wy(i,j) x(i,j-1) - wy(i,j+1) x(i,j+1)
//
// wx(i,j) is the coefficient of the face between cells (i-1,j) and (i,j), for 0 <= i <= nx;
// wy(i,j) that of the face between (i,j-1) and (i,j), for 0 <= j <= ny. Because each face has
// one coefficient shared by both cells, A is symmetric (the face average of Eqn 17 gives this).
// Domain boundaries are folded in when the operator is assembled:
//   periodic  - faces at i = 0 and i = nx are the same face and couple cell 0 to cell nx-1;
//   neumann   - boundary faces carry weight 0 (no flux);
//   dirichlet - ghost value fixed: the boundary face weight moves to diag, the fixed value to b.
#include <cstdint>

#include "runtime/boundary.h"
#include "runtime/field.h"
#include "runtime/row_executor.h"

namespace ardcell {

enum class BoundaryKind : uint8_t {
  kPeriodic,   // wrap around
  kNeumann,    // zero normal derivative (copy)
  kDirichlet,  // fixed value (zero unless a value is given)
};

// The operator of a grid of `size` cells, over the cells diag covers: the whole grid, or a block
// of it (assemble_block_operator: the same coefficients on the block's cells and faces, for
// sweeps that read the neighbouring blocks' cells from x's halo).
struct StencilOperator {
  Int2 size;
  FieldF diag;  // [0,nx) x [0,ny), halo 1 (on a block: the block's cells)
  FieldF wx;    // [0,nx] x [0,ny), halo 1 (field of size nx+1 by ny; on a block its faces)
  FieldF wy;    // [0,nx) x [0,ny], halo 1 (field of size nx by ny+1; on a block its faces)
  BoundaryKind boundary_x = BoundaryKind::kNeumann;
  BoundaryKind boundary_y = BoundaryKind::kNeumann;
  // The identity term it was (re)assembled with. Boundary folds and solid cells only add to the
  // diagonal, so identity > 0 means every row sums to at least it: no null space
  // (stencil::NullSpace skips its analysis, which per-frame reassembly would pay every step).
  double identity = 0.0;
};

// Builds identity*I - scale * div(k grad .) on a grid of `size` cells, with per-cell
// conductivity k averaged onto faces ((k_a + k_b) / 2, Eqn 17). A null conductivity means k = 1.
// identity = 1, scale = dt*nu/h^2 gives implicit diffusion (Eqn 13);
// identity = 0, scale = 1 gives the (negated) Poisson operator of the pressure projection.
StencilOperator assemble_stencil_operator(Int2 size, double identity, double scale,
                                          const FieldF* conductivity, BoundaryKind boundary_x,
                                          BoundaryKind boundary_y);

// The operator of a grid of `grid` cells on the cells of `cells` (a block of it) and their faces,
// assembled as identity 1, scale 0 until reassembled. Its sweeps (stencil_sweeps.h) read x's halo
// where a neighbour lies in another block, or across a periodic edge.
StencilOperator assemble_block_operator(Int2 grid, Box2 cells, BoundaryKind boundary_x,
                                        BoundaryKind boundary_y);
inline bool on_block(const StencilOperator& op) {
  return op.diag.interior() != box_of_size(op.size);
}
// Where a cell on a periodic domain edge finds its neighbour across it: on the whole grid the
// far side's column (nx - 1, 0) or row (ny - 1, 0); on a block x's halo (-1, nx; -1, ny),
// exchanged from the block that owns those cells.
struct EdgeWraps {
  int left, right, below, above;
};
inline EdgeWraps edge_wraps(const StencilOperator& op) {
  return on_block(op) ? EdgeWraps{-1, op.size.x, -1, op.size.y}
                      : EdgeWraps{op.size.x - 1, 0, op.size.y - 1, 0};
}

// Re-assembles in place (same size and boundaries) without allocating: for operators whose
// coefficients change every frame (anisotropic diffusion). On a block, the conductivity covers
// the block with its halo exchanged (the faces on the block's edges read it).
void reassemble_stencil_operator(StencilOperator& op, double identity, double scale,
                                 const FieldF* conductivity,
                                 RowExecutor& ex = RowExecutor::serial());

// y = A x over the interior (x's halo is not read on the whole grid: boundaries are in A; on a
// block, the neighbouring blocks' cells are x's halo).
void apply_stencil_operator(const StencilOperator& op, const FieldF& x, FieldF& y);

// Adds `weight` to the diagonal of the cells along one side. Folds a per-side ghost rule into an
// operator assembled with Neumann on that axis: weight = scale * k gives a fixed ghost value
// (Dirichlet at the ghost centre), weight = 2 * scale * k a value fixed on the wall face (the
// ghost mirrored, as Stam's negated normal velocity and no-slip walls). The boundary value
// itself goes into b (weight * value) by the caller.
void add_boundary_diagonal(StencilOperator& op, BoundarySide side, double weight);

// The right-hand side's share of those folded ghost rules: b += the boundary values' share
// (factor * scale * value) on the boundary cells of a domain of `size` cells, for each side
// whose rule is kFixed (factor 1: the ghost sits one cell away), kMirror (factor 2: the value
// sits on the face half a cell away) or kParabolic (as kMirror, times parabolic_profile of the
// cell's place along the side, in float); other rules add nothing. Sides in the order left,
// right, bottom, top, so a corner cell gets both of its sides' shares, in that order. The amount
// is rounded to float once per side. (host/engine/fluid_step.cpp's diffuse_velocity.)
void add_boundary_values(View<float> b, Int2 size, const BoundaryFill& fill, double scale);
// Weight of a ghost rule on the boundary cell's diagonal, per unit face weight: the fixed ghost
// sits one cell away (1), the mirrored one puts the value on the face half a cell away (2);
// copied and periodic ghosts add nothing (0).
double boundary_rule_factor(const EdgeFill& e);

// Cuts the faces of the solid cells (solid(i, j) != 0) out of the operator: a fluid neighbour
// keeps wall_factor times the cut face weight on its diagonal (0: Neumann, zero flux through the
// obstacle, for pressure; 2: the mirrored no-slip wall, for viscosity), and a solid cell's row
// becomes the identity (so with b = 0 there, x = 0 in solids).
void isolate_solid_cells(StencilOperator& op, const Field<uint8_t>& solid, double wall_factor);

// Multiplies every face weight by that face's open fraction (open_x: (nx + 1) x ny, open_y:
// nx x (ny + 1), values in [0, 1]) and re-sums the diagonals as identity + the four faces: the
// cut-cell (variational) weights of a pressure equation whose cells are partly solid (Batty et
// al. 2007). For an operator with Neumann or periodic axes, before boundary folds.
void weigh_faces(StencilOperator& op, const FieldF& open_x, const FieldF& open_y);

}  // namespace ardcell
