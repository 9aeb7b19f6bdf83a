#pragma once
// Implicit (anisotropic) diffusion of one chemical, seed 000:
//   Eqn 13 (isotropic):   (1 - s lap) A~ = A^,                 s = D dt / h^2
//   Eqn 17, Eqn 19:       A~ - s sum_faces (k_f (A~_nb - A~)) = A^,  k_f = (k_c + k_nb) / 2
// k = a(theta) per cell (kernels/anisotropy.h); averaging it onto faces keeps the matrix
// symmetric, so the StencilOperator solvers (Jacobi, RBGS, ICCG, multigrid) apply.
// Crank-Nicolson option: (1 - s/2 L) A~ = (1 + s/2 L) A^.
// Boundaries: Dirichlet (the paper's: ghost = boundary_value), periodic (tileable), Neumann.
// Optional solid mask: solid cells are cut out (no flux through their faces) and keep their
// value. The solve is a global one: it is not a tile kernel (its tiles are the solvers'). On a
// block of a decomposed grid its Jacobi or red-black Gauss-Seidel sweeps run on the block's
// cells, exchanging the iterate's halo between sweeps (runtime/block_layout.h HaloChannel).
#include <memory>

#include "kernels/linear_solver.h"
#include "kernels/stencil_operator.h"

namespace ardcell {

class HaloChannel;

struct DiffusionStep {
  double rate_dt_over_h2 = 1.0;  // D dt / h^2
  float boundary_value = 0.0f;   // Dirichlet ghost value
  bool crank_nicolson = false;
};

class ImplicitDiffusion {
 public:
  ImplicitDiffusion(Int2 size, BoundaryKind boundary, const SolverSettings& solver,
                    RowExecutor& ex = RowExecutor::serial());
  // On the block `cells` (not the whole grid) of a decomposed grid of `grid` cells: the operator,
  // right-hand side and iterate cover the block, and step() runs the solver's sweeps there,
  // exchanging the iterate's halo through the block's channel after each one: each cell gets the
  // whole grid's bits. The residual report adds the blocks' norms (HaloChannel::sum: one process's
  // to rounding), and so does the stopping rule of a tolerance, which then may stop a sweep earlier
  // or later than one process would. Only the solvers runs_on_block() accepts; no solid cells.
  ImplicitDiffusion(Int2 grid, Box2 cells, BoundaryKind boundary, const SolverSettings& solver,
                    RowExecutor& ex = RowExecutor::serial());
  // Jacobi, whose sweeps read only the last iterate, and red-black Gauss-Seidel, whose half
  // sweeps read only the other colour - unless the grid wraps an odd number of cells, where a
  // colour meets itself across the wrap (ICCG's triangular solves and multigrid's levels are
  // global).
  static bool runs_on_block(const SolverSettings& s, Int2 grid, BoundaryKind boundary) {
    const bool odd_wrap = boundary == BoundaryKind::kPeriodic && (grid.x % 2 || grid.y % 2);
    return s.kind == SolverKind::kJacobi ||
           (s.kind == SolverKind::kRedBlackGaussSeidel && !odd_wrap);
  }
  bool on_block() const { return ardcell::on_block(op_); }
  ~ImplicitDiffusion();

  // Optional obstacle: cells with solid != 0 are held fixed and isolated (Neumann walls).
  void set_solid(const Field<uint8_t>* solid) { solid_ = solid; }

  // One step in place on `field` (interior). conductivity: per-cell k (nullptr: k = 1).
  // Re-assembles the operator only when the coefficients may have changed. On a block, `halo`
  // is the block's channel (collective: every block steps), field and conductivity cover the
  // block with a halo, and the conductivity's holds its neighbours' values (exchanged).
  SolveReport step(FieldF& field, const FieldF* conductivity, const DiffusionStep& s,
                   HaloChannel* halo = nullptr);

  const StencilOperator& op() const { return op_; }
  // The solver's iterations and tolerance (live parameter changes); allocates nothing.
  void set_solver_limits(int max_iterations, double tolerance) {
    if (solver_) solver_->set_limits(max_iterations, tolerance);
    settings_.max_iterations = max_iterations;
    settings_.tolerance = tolerance;
  }
  BoundaryKind boundary() const { return boundary_; }
  Int2 size() const { return size_; }
  const SolverSettings& solver_settings() const { return settings_; }
  const Field<uint8_t>* solid() const { return solid_; }

 private:
  void copy_rows(const FieldF& from, FieldF& to) const;  // interiors, in bands of rows
  // The right-hand side: the field (Crank-Nicolson: (1 + s/2 L) field), plus the fixed ghosts'
  // flux on the domain's edges.
  void make_rhs(FieldF& field, const FieldF* conductivity, const DiffusionStep& s,
                HaloChannel* halo);
  // The block's sweeps from x_ (the step's start), exchanging after each (RBGS: each half).
  SolveReport sweep_block(HaloChannel& halo);
  Int2 size_;
  RowExecutor* ex_;
  BoundaryKind boundary_;
  StencilOperator op_;
  SolverSettings settings_;
  std::unique_ptr<LinearSolver> solver_;  // null on a block (sweep_block)
  FieldF rhs_, x_, tmp_;
  const Field<uint8_t>* solid_ = nullptr;
  // The last operator assembled (isotropic operators are reused frame to frame).
  double last_scale_ = -1;
  bool last_isotropic_ = false;
};

}  // namespace ardcell
