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
  // Sweeps (Jacobi, RBGS), CG iterations (ICCG), V-cycles (MG); kernels/tensor_field_solve.h
  // reads it as BiCGSTAB steps.
  int max_iterations = 20;
  double tolerance = 0.0;  // relative residual |b - A x| / |b| to stop at; 0 = run them all
};

// The multigrid V-cycle's schedule (kernels/multigrid_solver.cpp); OpenClDevice runs the same
// cycle on the device.
namespace multigrid {
inline constexpr int kPreSmooth = 2;         // red-black Gauss-Seidel sweeps before restricting
inline constexpr int kPostSmooth = 2;        // and after correcting
inline constexpr int kCoarsestSweeps = 100;  // on the coarsest grid, relaxed to convergence
// With a tolerance, stop when a cycle reduces the residual by less than this factor.
inline constexpr double kStagnation = 0.5;
}  // namespace multigrid

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
  // Multigrid's coarse operators as prepare() built them: level 0 is half the caller's grid,
  // the last one the coarsest. The other solvers have none. (OpenClDevice uploads them, so the
  // device cycles on the operators the CPU solver would.)
  virtual int coarse_levels() const { return 0; }
  virtual const StencilOperator& coarse_operator(int level) const;
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
