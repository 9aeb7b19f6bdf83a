// Jacobi iteration x <- D^-1 (b + (D - A) x), a fixed number of sweeps (or until the relative
// residual falls below the tolerance). For the model Poisson problem its error shrinks by the
// spectral radius cos(pi / (n + 1)) per sweep: slow, but every cell is independent, which is
// why it is the real-time default. With a fixed number of sweeps (no tolerance to check between
// them) on a grid whose sweep streams more than the last-level cache holds, the sweeps run
// temporally blocked, up to JacobiBlocking::kMaxSweeps per pass over the grid, with the same
// bits as sweep by sweep: 1.9x faster at 2048^2 on the 2-core EPYC (32 MiB L3), while up to
// 1024^2, where the fields stay in cache, sweeping the whole grid is 5-20% faster
// (bench/fluid_kernels_bench.cpp BM_JacobiSweeps20, bench/RESULTS_KERNELS.md).
#include <algorithm>
#include <cstring>

#include "kernels/solver_common.h"
#include "runtime/local_store.h"

namespace ardcell::solver_detail {
namespace {

class JacobiSolver final : public LinearSolver {
 public:
  JacobiSolver(const SolverSettings& s, Int2 size, RowExecutor& ex, bool blocked)
      : LinearSolver(s, ex),
        blocked_(blocked),
        other_(size, 1),
        r_(size, 1),
        null_space_(size),
        uniform_(size.y),
        blocking_(size, ex.workers()) {
    ex.reserve_rows(size.y);
  }

  void prepare(const StencilOperator& op) override {
    null_space_.analyse(op, *ex_);
    uniform_.analyse(op, *ex_);
  }

  SolveReport solve(const StencilOperator& op, const FieldF& b, FieldF& x) override {
    ARDCELL_CHECK(b.size() == op.size && x.size() == op.size && other_.size() == op.size,
                  "jacobi: size mismatch");
    if (blocked_ && settings_.tolerance <= 0.0 && settings_.max_iterations > 0)
      return solve_blocked(op, b, x);
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
    if (from != &x) copy(*from, x);
    null_space_.remove_mean(x, *ex_);
    report.relative_residual = relative_residual(op, b, x, r_, null_space_, *ex_, bb);
    return report;
  }

 private:
  // A fixed number of sweeps, temporally blocked: up to kMaxSweeps per pass over the grid. The
  // last pass also reports the residual, unless the operator is singular: then the null-space
  // mean comes out of x first and the residual takes a pass of its own, as with a tolerance.
  SolveReport solve_blocked(const StencilOperator& op, const FieldF& b, FieldF& x) {
    SolveReport report;
    const bool fused = !null_space_.singular();
    stencil::JacobiBlocking::Norms norms;
    FieldF* from = &x;
    FieldF* to = &other_;
    for (int left = settings_.max_iterations; left > 0;) {
      const int n = std::min(left, stencil::JacobiBlocking::kMaxSweeps);
      left -= n;
      blocking_.sweeps(op, b, *from, *to, n, *ex_, &uniform_,
                       fused && left == 0 ? &norms : nullptr);
      std::swap(from, to);
      report.iterations += n;
    }
    if (from != &x) copy(*from, x);
    if (fused) {
      // relative_residual() for a non-singular operator: consistent parts are the norms.
      report.relative_residual =
          norms.rhs2 > 0.0 ? std::sqrt(norms.residual2 / norms.rhs2) : std::sqrt(norms.residual2);
    } else {
      const double bb = null_space_.consistent_norm2(b, *ex_);
      null_space_.remove_mean(x, *ex_);
      report.relative_residual = relative_residual(op, b, x, r_, null_space_, *ex_, bb);
    }
    return report;
  }

  // to = from, whole allocations (halo included), in bands of rows.
  void copy(const FieldF& from, FieldF& to) {
    const std::ptrdiff_t stride = to.stride();
    const int rows = int(to.raw_size() / std::size_t(stride));
    ex_->for_rows(rows, int(stride), [&](int y0, int y1) {
      std::memcpy(to.raw() + std::ptrdiff_t(y0) * stride, from.raw() + std::ptrdiff_t(y0) * stride,
                  std::size_t(y1 - y0) * std::size_t(stride) * sizeof(float));
    });
  }

  bool blocked_;
  FieldF other_, r_;
  stencil::NullSpace null_space_;
  stencil::UniformRows uniform_;
  stencil::JacobiBlocking blocking_;
};

}  // namespace

bool jacobi_blocking_pays(Int2 size) {
  // A sweep streams x_in, x_out and b (the coefficients too on rows that are not uniform).
  return 3.0 * sizeof(float) * double(size.x) * double(size.y) >
         double(machine_last_level_cache_bytes());
}

std::unique_ptr<LinearSolver> make_jacobi_solver(const SolverSettings& s, Int2 size,
                                                 RowExecutor& ex, bool blocked) {
  return std::make_unique<JacobiSolver>(s, size, ex, blocked);
}

}  // namespace ardcell::solver_detail
