// Jacobi iteration x <- D^-1 (b + (D - A) x), a fixed number of sweeps (or until the relative
// residual falls below the tolerance). For the model Poisson problem its error shrinks by the
// spectral radius cos(pi / (n + 1)) per sweep: slow, but every cell is independent, which is
// why it is the real-time default on tiles (ghost-zone temporal blocking).
#include <cstring>

#include "kernels/solver_common.h"

namespace ardcell::solver_detail {
namespace {

class JacobiSolver final : public LinearSolver {
 public:
  JacobiSolver(const SolverSettings& s, Int2 size, RowExecutor& ex)
      : LinearSolver(s, ex), other_(size, 1), r_(size, 1), null_space_(size), uniform_(size.y) {
    ex.reserve_rows(size.y);
  }

  void prepare(const StencilOperator& op) override {
    null_space_.analyse(op, *ex_);
    uniform_.analyse(op, *ex_);
  }

  SolveReport solve(const StencilOperator& op, const FieldF& b, FieldF& x) override {
    ARDCELL_CHECK(b.size() == op.size && x.size() == op.size && other_.size() == op.size,
                  "jacobi: size mismatch");
    SolveReport report;
    const double bb = null_space_.consistent_norm2(b, *ex_);
    const bool check = settings_.tolerance > 0.0;
    FieldF* from = &x;
    FieldF* to = &other_;
    for (int k = 0; k < settings_.max_iterations; ++k) {
      stencil::jacobi_sweep(op, b, *from, *to, *ex_, &uniform_);
      std::swap(from, to);
      ++report.iterations;
      if (check &&
          relative_residual(op, b, *from, r_, null_space_, *ex_, bb) <= settings_.tolerance)
        break;
    }
    if (from != &x) std::memcpy(x.raw(), from->raw(), x.raw_size() * sizeof(float));
    null_space_.remove_mean(x, *ex_);
    report.relative_residual = relative_residual(op, b, x, r_, null_space_, *ex_, bb);
    return report;
  }

 private:
  FieldF other_, r_;
  stencil::NullSpace null_space_;
  stencil::UniformRows uniform_;
};

}  // namespace

std::unique_ptr<LinearSolver> make_jacobi_solver(const SolverSettings& s, Int2 size,
                                                 RowExecutor& ex) {
  return std::make_unique<JacobiSolver>(s, size, ex);
}

}  // namespace ardcell::solver_detail
