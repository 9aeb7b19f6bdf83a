// Geometric multigrid V-cycles for the 5-point operator with per-face weights. Cell-centred
// coarsening by 2x2 aggregation (odd sizes keep a 1-wide last aggregate): restriction sums the
// residual of the aggregate, prolongation injects the coarse correction into its cells, and the
// coarse operator is the Galerkin product for those transfers with its face weights halved
// (piecewise-constant Galerkin over-weights the coupling by 2 in 2D; halving gives the
// rediscretised Laplacian). Red-black Gauss-Seidel smooths (2 before, 2 after); the coarsest
// grid is relaxed to convergence. All levels are allocated when the solver is made.
// With a tolerance, the cycles stop at the tolerance or when one cycle no longer halves the
// residual (the float32 round-off floor of x, which relative to a tiny b can exceed 1e-6).
#include <vector>

#include "kernels/solver_common.h"

namespace ardcell::solver_detail {
namespace {

using multigrid::kCoarsestSweeps;
using multigrid::kPostSmooth;
using multigrid::kPreSmooth;
using multigrid::kStagnation;

struct Level {
  StencilOperator op;
  FieldF x, b, r;
};

StencilOperator empty_operator(Int2 size) {
  return StencilOperator{size,
                         FieldF(size, 1),
                         FieldF(Int2{size.x + 1, size.y}, 1),
                         FieldF(Int2{size.x, size.y + 1}, 1),
                         BoundaryKind::kNeumann,
                         BoundaryKind::kNeumann};
}

// Coarse operator from the fine one (see the file comment).
void coarsen(const StencilOperator& fine, StencilOperator& coarse) {
  const int fx = fine.size.x, fy = fine.size.y;
  const int cx = coarse.size.x, cy = coarse.size.y;
  coarse.boundary_x = fine.boundary_x;
  coarse.boundary_y = fine.boundary_y;
  for (int J = 0; J < cy; ++J)
    for (int I = 0; I <= cx; ++I) {
      const int i = std::min(2 * I, fx);
      double w = fine.wx(i, 2 * J);
      if (2 * J + 1 < fy) w += fine.wx(i, 2 * J + 1);
      coarse.wx(I, J) = float(0.5 * w);
    }
  for (int J = 0; J <= cy; ++J)
    for (int I = 0; I < cx; ++I) {
      const int j = std::min(2 * J, fy);
      double w = fine.wy(2 * I, j);
      if (2 * I + 1 < fx) w += fine.wy(2 * I + 1, j);
      coarse.wy(I, J) = float(0.5 * w);
    }
  for (int J = 0; J < cy; ++J)
    for (int I = 0; I < cx; ++I) {
      // What the fine rows hold beyond their face weights: identity and Dirichlet boundaries.
      // A row with no face (an isolated solid cell, whose equation is x = b) is no part of the
      // PDE: where the aggregate also holds coupled cells, its identity would pin the coarse
      // correction towards 0 beside the obstacle, so only the coupled rows count there.
      double rest = 0.0, rest_coupled = 0.0;
      bool coupled = false;
      for (int j = 2 * J; j < std::min(2 * J + 2, fy); ++j)
        for (int i = 2 * I; i < std::min(2 * I + 2, fx); ++i) {
          const double faces =
              double(fine.wx(i, j)) + fine.wx(i + 1, j) + fine.wy(i, j) + fine.wy(i, j + 1);
          const double row_rest = double(fine.diag(i, j)) - fine.wx(i, j) - fine.wx(i + 1, j) -
                                  fine.wy(i, j) - fine.wy(i, j + 1);
          rest += row_rest;
          if (faces != 0.0) {
            rest_coupled += row_rest;
            coupled = true;
          }
        }
      coarse.diag(I, J) = float((coupled ? rest_coupled : rest) + coarse.wx(I, J) +
                                coarse.wx(I + 1, J) + coarse.wy(I, J) + coarse.wy(I, J + 1));
    }
}

class MultigridSolver final : public LinearSolver {
 public:
  MultigridSolver(const SolverSettings& s, Int2 size, RowExecutor& ex)
      : LinearSolver(s, ex), size_(size), b0_(size, 1), r0_(size, 1), null_space_(size) {
    ex.reserve_rows(size.y);
    Int2 n = size;
    while (n.x >= 4 && n.y >= 4) {
      n = Int2{(n.x + 1) / 2, (n.y + 1) / 2};
      levels_.push_back(Level{empty_operator(n), FieldF(n, 1), FieldF(n, 1), FieldF(n, 1)});
    }
  }

  void prepare(const StencilOperator& op) override {
    ARDCELL_CHECK(op.size == size_, "multigrid: size mismatch");
    null_space_.analyse(op, *ex_);
    const StencilOperator* fine = &op;
    for (Level& level : levels_) {
      coarsen(*fine, level.op);
      fine = &level.op;
    }
  }

  int coarse_levels() const override { return int(levels_.size()); }
  const StencilOperator& coarse_operator(int level) const override {
    ARDCELL_CHECK(level >= 0 && level < int(levels_.size()), "multigrid: no such level");
    return levels_[std::size_t(level)].op;
  }

  SolveReport solve(const StencilOperator& op, const FieldF& b, FieldF& x) override {
    ARDCELL_CHECK(op.size == size_ && b.size() == size_ && x.size() == size_,
                  "multigrid: size mismatch");
    // A singular system is solvable only for b in the range: drop b's null-space component.
    const FieldF* rhs = &b;
    if (null_space_.singular()) {
      copy_box(b.view(), b0_.view(), b.interior());
      null_space_.remove_mean(b0_, *ex_);
      rhs = &b0_;
    }
    SolveReport report;
    const double bb = null_space_.consistent_norm2(*rhs, *ex_);
    report.relative_residual = relative_residual(op, *rhs, x, r0_, null_space_, *ex_, bb);
    for (int k = 0; k < settings_.max_iterations; ++k) {
      if (settings_.tolerance > 0.0 && report.relative_residual <= settings_.tolerance) break;
      cycle(op, *rhs, x, 0);
      null_space_.remove_mean(x, *ex_);
      ++report.iterations;
      const double before = report.relative_residual;
      report.relative_residual = relative_residual(op, *rhs, x, r0_, null_space_, *ex_, bb);
      // A healthy V-cycle divides the residual by ~10; when a cycle barely helps, x has reached
      // float32 round-off and further cycles are wasted.
      if (settings_.tolerance > 0.0 && report.relative_residual > kStagnation * before) break;
    }
    return report;
  }

 private:
  // One V-cycle on level `depth` (0 = the caller's grid).
  void cycle(const StencilOperator& op, const FieldF& b, FieldF& x, std::size_t depth) {
    if (depth == levels_.size()) {
      for (int k = 0; k < kCoarsestSweeps; ++k) stencil::rbgs_sweep(op, b, x, *ex_);
      return;
    }
    for (int k = 0; k < kPreSmooth; ++k) stencil::rbgs_sweep(op, b, x, *ex_);
    FieldF& r = depth == 0 ? r0_ : levels_[depth - 1].r;
    stencil::residual_field(op, b, x, r, *ex_);
    Level& coarse = levels_[depth];
    restrict_sum(r, coarse.b, *ex_);
    coarse.x.fill(0.0f);
    cycle(coarse.op, coarse.b, coarse.x, depth + 1);
    prolong_add(coarse.x, x, *ex_);
    for (int k = 0; k < kPostSmooth; ++k) stencil::rbgs_sweep(op, b, x, *ex_);
  }

  static void restrict_sum(const FieldF& fine, FieldF& coarse, RowExecutor& ex) {
    const int fx = fine.nx(), fy = fine.ny();
    ex.for_rows(coarse.ny(), fx, [&](int y0, int y1) {
      for (int J = y0; J < y1; ++J) {
        float* c = coarse.row(J);
        const float* f0 = fine.row(2 * J);
        const float* f1 = 2 * J + 1 < fy ? fine.row(2 * J + 1) : nullptr;
        for (int I = 0; I < coarse.nx(); ++I) {
          const int i = 2 * I;
          float s = f0[i];
          if (i + 1 < fx) s += f0[i + 1];
          if (f1) {
            s += f1[i];
            if (i + 1 < fx) s += f1[i + 1];
          }
          c[I] = s;
        }
      }
    });
  }

  static void prolong_add(const FieldF& coarse, FieldF& fine, RowExecutor& ex) {
    ex.for_rows(fine.ny(), fine.nx(), [&](int y0, int y1) {
      for (int j = y0; j < y1; ++j) {
        const float* c = coarse.row(j / 2);
        float* f = fine.row(j);
        for (int i = 0; i < fine.nx(); ++i) f[i] += c[i / 2];
      }
    });
  }

  Int2 size_;
  std::vector<Level> levels_;
  FieldF b0_, r0_;
  stencil::NullSpace null_space_;
};

}  // namespace

std::unique_ptr<LinearSolver> make_multigrid_solver(const SolverSettings& s, Int2 size,
                                                    RowExecutor& ex) {
  return std::make_unique<MultigridSolver>(s, size, ex);
}

}  // namespace ardcell::solver_detail
