#pragma once
// Pieces shared by the LinearSolver implementations (kernels/*_solver.cpp).
#include <cmath>
#include <memory>

#include "kernels/linear_solver.h"
#include "kernels/stencil_sweeps.h"

namespace ardcell::solver_detail {

// |b - A x| / |b| over the consistent part (see NullSpace); |b - A x| when b is zero.
// r is scratch of the operator's size; bb = null_space.consistent_norm2(b), computed once per
// solve (b does not change during it).
inline double relative_residual(const StencilOperator& op, const FieldF& b, const FieldF& x,
                                FieldF& r, const stencil::NullSpace& null_space, RowExecutor& ex,
                                double bb) {
  // The residual field is needed only to take out its null-space component.
  const double rr = null_space.consistent_part(
      stencil::residual(op, b, x, null_space.singular() ? &r : nullptr, ex), r, ex);
  return bb > 0.0 ? std::sqrt(rr / bb) : std::sqrt(rr);
}

// Whether fixed Jacobi sweeps on this grid run temporally blocked (stencil::JacobiBlocking):
// when a sweep's fields outgrow the machine's last-level cache.
bool jacobi_blocking_pays(Int2 size);
std::unique_ptr<LinearSolver> make_jacobi_solver(const SolverSettings& s, Int2 size,
                                                 RowExecutor& ex, bool blocked);
std::unique_ptr<LinearSolver> make_rbgs_solver(const SolverSettings& s, Int2 size, RowExecutor& ex);
std::unique_ptr<LinearSolver> make_iccg_solver(const SolverSettings& s, Int2 size, RowExecutor& ex);
std::unique_ptr<LinearSolver> make_multigrid_solver(const SolverSettings& s, Int2 size,
                                                    RowExecutor& ex);

}  // namespace ardcell::solver_detail
