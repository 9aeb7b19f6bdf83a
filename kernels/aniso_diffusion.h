#pragma once
// Implicit (anisotropic) diffusion of one chemical, seed 000:
//   Eqn 13 (isotropic):   (1 - s lap) A~ = A^,                 s = D dt / h^2
//   Eqn 17, Eqn 19:       A~ - s sum_faces (k_f (A~_nb - A~)) = A^,  k_f = (k_c + k_nb) / 2
// k = a(theta) per cell (kernels/anisotropy.h); averaging it onto faces keeps the matrix
// symmetric, so the StencilOperator solvers (Jacobi, RBGS, ICCG, multigrid) apply.
// Crank-Nicolson option: (1 - s/2 L) A~ = (1 + s/2 L) A^.
// Boundaries: Dirichlet (the paper's: ghost = boundary_value), periodic (tileable), Neumann.
// Optional solid mask: solid cells are cut out (no flux through their faces) and keep their
// value. The solve is a global one: it is not a tile kernel (its tiles are the solvers').
#include <memory>

#include "kernels/linear_solver.h"
#include "kernels/stencil_operator.h"

namespace ardcell {

struct DiffusionStep {
  double rate_dt_over_h2 = 1.0;  // D dt / h^2
  float boundary_value = 0.0f;   // Dirichlet ghost value
  bool crank_nicolson = false;
};

class ImplicitDiffusion {
 public:
  ImplicitDiffusion(Int2 size, BoundaryKind boundary, const SolverSettings& solver,
                    RowExecutor& ex = RowExecutor::serial());
  ~ImplicitDiffusion();

  // Optional obstacle: cells with solid != 0 are held fixed and isolated (Neumann walls).
  void set_solid(const Field<uint8_t>* solid) { solid_ = solid; }

  // One step in place on `field` (interior). conductivity: per-cell k (nullptr: k = 1).
  // Re-assembles the operator only when the coefficients may have changed.
  SolveReport step(FieldF& field, const FieldF* conductivity, const DiffusionStep& s);

  const StencilOperator& op() const { return op_; }
  // The solver's iterations and tolerance (live parameter changes); allocates nothing.
  void set_solver_limits(int max_iterations, double tolerance) {
    solver_->set_limits(max_iterations, tolerance);
  }
  BoundaryKind boundary() const { return boundary_; }
  Int2 size() const { return size_; }
  const SolverSettings& solver_settings() const { return solver_->settings(); }
  const Field<uint8_t>* solid() const { return solid_; }

 private:
  void copy_rows(const FieldF& from, FieldF& to) const;  // interiors, in bands of rows
  Int2 size_;
  RowExecutor* ex_;
  BoundaryKind boundary_;
  StencilOperator op_;
  std::unique_ptr<LinearSolver> solver_;
  FieldF rhs_, x_, tmp_;
  const Field<uint8_t>* solid_ = nullptr;
  // The last operator assembled (isotropic operators are reused frame to frame).
  double last_scale_ = -1;
  bool last_isotropic_ = false;
};

}  // namespace ardcell
