#pragma once
// One interface over the solvers of A x = b for a StencilOperator (kernels/stencil_operator.h):
// fixed-sweep Jacobi and red-black Gauss-Seidel (the real-time default), ICCG (seed 000's
// choice), and geometric multigrid V-cycles. A solver is made once for a grid size and owns its
// scratch space: solve() never allocates. Its sweeps, residuals and norms run on the RowExecutor
// it is made with (the back end's workers, same bits for any worker count); ICCG's triangular
// solves are sequential and run on the calling thread.
#include <memory>
#include <string_view>

#include "kernels/stencil_operator.h"
#include "runtime/row_executor.h"

namespace ardcell {

enum class SolverKind : uint8_t { kJacobi, kRedBlackGaussSeidel, kIccg, kMultigrid };

// "jacobi", "rbgs", "iccg", "mg"; false when the name is unknown.
bool parse_solver_kind(std::string_view name, SolverKind& out);
std::string_view solver_kind_name(SolverKind kind);

struct SolverSettings {
  SolverKind kind = SolverKind::kJacobi;
  int max_iterations = 20;  // sweeps (Jacobi, RBGS), CG iterations (ICCG), V-cycles (MG)
  double tolerance = 0.0;   // relative residual |b - A x| / |b| to stop at; 0 = run them all
};

struct SolveReport {
  int iterations = 0;        // sweeps / iterations / cycles actually taken
  double relative_residual;  // |b - A x|_2 / |b|_2 after the solve (0 when b = 0 and x = 0)
};

class LinearSolver {
 public:
  virtual ~LinearSolver() = default;
  static std::unique_ptr<LinearSolver> make(const SolverSettings& settings, Int2 size,
                                            RowExecutor& ex = RowExecutor::serial());

  // Called whenever the operator's coefficients change (factorisation, coarse operators).
  virtual void prepare(const StencilOperator& op) = 0;
  // Improves x (used as the initial guess) towards A x = b.
  virtual SolveReport solve(const StencilOperator& op, const FieldF& b, FieldF& x) = 0;
  const SolverSettings& settings() const { return settings_; }
  // Live parameter changes (Engine::update_parameters): the stopping rule only, the kind stays.
  void set_limits(int max_iterations, double tolerance) {
    settings_.max_iterations = max_iterations;
    settings_.tolerance = tolerance;
  }

 protected:
  LinearSolver(const SolverSettings& s, RowExecutor& ex) : settings_(s), ex_(&ex) {}
  SolverSettings settings_;
  RowExecutor* ex_;
};

}  // namespace ardcell
