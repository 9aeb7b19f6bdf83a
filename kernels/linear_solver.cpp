#include "kernels/linear_solver.h"

#include "kernels/solver_common.h"

namespace ardcell {

bool parse_solver_kind(std::string_view name, SolverKind& out) {
  if (name == "jacobi") {
    out = SolverKind::kJacobi;
  } else if (name == "rbgs") {
    out = SolverKind::kRedBlackGaussSeidel;
  } else if (name == "iccg") {
    out = SolverKind::kIccg;
  } else if (name == "mg") {
    out = SolverKind::kMultigrid;
  } else {
    return false;
  }
  return true;
}

std::string_view solver_kind_name(SolverKind kind) {
  switch (kind) {
    case SolverKind::kJacobi:
      return "jacobi";
    case SolverKind::kRedBlackGaussSeidel:
      return "rbgs";
    case SolverKind::kIccg:
      return "iccg";
    case SolverKind::kMultigrid:
      return "mg";
  }
  return "jacobi";
}

const StencilOperator& LinearSolver::coarse_operator(int) const {
  detail::check_failed("coarse_levels() > 0", __FILE__, __LINE__,
                       "coarse_operator: this solver has no coarse levels");
}

std::unique_ptr<LinearSolver> LinearSolver::make(const SolverSettings& settings, Int2 size,
                                                 RowExecutor& ex) {
  ARDCELL_CHECK(size.x > 0 && size.y > 0, "solver size must be positive");
  switch (settings.kind) {
    case SolverKind::kJacobi:
      return solver_detail::make_jacobi_solver(settings, size, ex,
                                               solver_detail::jacobi_blocking_pays(size));
    case SolverKind::kRedBlackGaussSeidel:
      return solver_detail::make_rbgs_solver(settings, size, ex);
    case SolverKind::kIccg:
      return solver_detail::make_iccg_solver(settings, size, ex);
    case SolverKind::kMultigrid:
      return solver_detail::make_multigrid_solver(settings, size, ex);
  }
  return solver_detail::make_jacobi_solver(settings, size, ex,
                                           solver_detail::jacobi_blocking_pays(size));
}

}  // namespace ardcell
