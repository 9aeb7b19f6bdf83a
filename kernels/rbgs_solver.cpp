// Red-black Gauss-Seidel: the cells of one colour depend only on the other colour, so each half
// sweep is as parallel as Jacobi, and a full sweep contracts the model problem's error by the
// square of Jacobi's spectral radius (cos^2(pi / (n + 1))).
#include "kernels/solver_common.h"

namespace ardcell::solver_detail {
namespace {

class RbgsSolver final : public LinearSolver {
 public:
  RbgsSolver(const SolverSettings& s, Int2 size, RowExecutor& ex)
      : LinearSolver(s, ex), r_(size, 1), null_space_(size) {
    ex.reserve_rows(size.y);
  }

  void prepare(const StencilOperator& op) override { null_space_.analyse(op, *ex_); }

  SolveReport solve(const StencilOperator& op, const FieldF& b, FieldF& x) override {
    ARDCELL_CHECK(b.size() == op.size && x.size() == op.size && r_.size() == op.size,
                  "rbgs: size mismatch");
    SolveReport report;
    const double bb = null_space_.consistent_norm2(b, *ex_);
    const bool check = settings_.tolerance > 0.0;
    for (int k = 0; k < settings_.max_iterations; ++k) {
      stencil::rbgs_sweep(op, b, x, *ex_);
      ++report.iterations;
      if (check && relative_residual(op, b, x, r_, null_space_, *ex_, bb) <= settings_.tolerance)
        break;
    }
    null_space_.remove_mean(x, *ex_);
    report.relative_residual = relative_residual(op, b, x, r_, null_space_, *ex_, bb);
    return report;
  }

 private:
  FieldF r_;
  stencil::NullSpace null_space_;
};

}  // namespace

std::unique_ptr<LinearSolver> make_rbgs_solver(const SolverSettings& s, Int2 size,
                                               RowExecutor& ex) {
  return std::make_unique<RbgsSolver>(s, size, ex);
}

}  // namespace ardcell::solver_detail
