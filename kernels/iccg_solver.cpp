// Conjugate gradients preconditioned by an incomplete Cholesky factorisation IC(0) of the
// 5-point operator (seed 000's choice for the implicit diffusion). The factor keeps A's sparsity:
// with natural ordering, M = (P - L) P^-1 (P - L^T), where -L holds A's lower neighbour weights
// and the pivots are p(i,j) = diag - wx(i,j)^2 / p(i-1,j) - wy(i,j)^2 / p(i,j-1).
//
// Block IC(0): the grid's rows are cut into blocks of kBlockRows rows, fixed by the grid (not by
// the workers), and M leaves out the couplings between blocks (the wy term of a block's first
// row). The triangular solves, sequential within a block, then run on all blocks at once, and
// the preconditioner - hence every iterate - is the same for any number of workers. The price
// is a few more iterations than whole-grid IC(0) (tests/kernels/linear_solver_test.cpp bounds
// it). Periodic wrap couplings stay in A but not in M (M only has to be symmetric positive
// definite). The vectors are kept in double so the iteration converges to float32 round-off of
// x; dot products add per-row partials in row order (runtime/row_executor.h).
//
// Rounding: the file is compiled without fma contraction, and the recurrences of the triangular
// solves fuse their multiply-adds explicitly where the CPU has FMA (kernels/iccg_solver.h), so
// the OpenCL twin (kernels/cl/iccg.cl), which makes the same choice, computes the same bits.
#include <vector>

#include "kernels/iccg_solver.h"
#include "kernels/solver_common.h"

namespace ardcell::solver_detail {
namespace {

using iccg::kBlockRows;

// a * b + c, fused where the recurrences fuse (iccg::kFusedRecurrences).
inline double multiply_add(double a, double b, double c) {
  if constexpr (iccg::kFusedRecurrences)
    return std::fma(a, b, c);
  else
    return a * b + c;
}

class IccgSolver final : public LinearSolver {
 public:
  IccgSolver(const SolverSettings& s, Int2 size, RowExecutor& ex)
      : LinearSolver(s, ex),
        size_(size),
        n_(std::size_t(size.x) * size.y),
        blocks_((size.y + kBlockRows - 1) / kBlockRows),
        pivot_(n_),
        inv_pivot_(n_),
        x_(n_),
        r_(n_),
        z_(n_),
        p_(n_),
        q_(n_),
        wx_(std::size_t(size.x + 1) * size.y),
        wy_(std::size_t(size.x) * (size.y + 1)),
        diag_(n_),
        scratch_rows_(std::size_t(size.x) * std::size_t(blocks_)),
        rf_(size, 1),
        null_space_(size) {
    ex.reserve_rows(size.y);
  }

  void prepare(const StencilOperator& op) override {
    ARDCELL_CHECK(op.size == size_, "iccg: size mismatch");
    null_space_.analyse(op, *ex_);
    const int nx = size_.x, ny = size_.y;
    periodic_x_ = op.boundary_x == BoundaryKind::kPeriodic;
    periodic_y_ = op.boundary_y == BoundaryKind::kPeriodic;
    rows([&](int y0, int y1) {
      for (int j = y0; j < y1; ++j) {
        for (int i = 0; i <= nx; ++i) wx_[std::size_t(j) * (nx + 1) + i] = op.wx(i, j);
        for (int i = 0; i < nx; ++i) diag_[idx(i, j)] = op.diag(i, j);
      }
    });
    ex_->for_rows(ny + 1, nx, [&](int y0, int y1) {
      for (int j = y0; j < y1; ++j)
        for (int i = 0; i < nx; ++i) wy_[std::size_t(j) * nx + i] = op.wy(i, j);
    });
    each_block([&](int j0, int j1) {
      for (int j = j0; j < j1; ++j)
        for (int i = 0; i < nx; ++i) {
          double d = diag_[idx(i, j)];
          if (i > 0) d -= sq(wxf(i, j)) / pivot_[idx(i - 1, j)];
          if (j > j0) d -= sq(wyf(i, j)) / pivot_[idx(i, j - 1)];
          // Guard against breakdown (the singular Neumann Poisson matrix drives the last pivot
          // to 0).
          const double floor = 1e-3 * diag_[idx(i, j)];
          if (!(d > floor)) d = diag_[idx(i, j)] > 0.0 ? diag_[idx(i, j)] : 1.0;
          pivot_[idx(i, j)] = d;
          inv_pivot_[idx(i, j)] = 1.0 / d;
        }
    });
  }

  SolveReport solve(const StencilOperator& op, const FieldF& b, FieldF& x) override {
    ARDCELL_CHECK(op.size == size_ && b.size() == size_ && x.size() == size_,
                  "iccg: size mismatch");
    const int nx = size_.x;
    rows([&](int y0, int y1) {
      for (int j = y0; j < y1; ++j)
        for (int i = 0; i < nx; ++i) x_[idx(i, j)] = x(i, j);
    });
    multiply(x_, q_);
    double bb = ex_->sum_rows(size_.y, nx, [&](int y0, int y1, double* partials) {
      for (int j = y0; j < y1; ++j) {
        double row = 0.0;
        for (int i = 0; i < nx; ++i) {
          r_[idx(i, j)] = double(b(i, j)) - q_[idx(i, j)];
          row += double(b(i, j)) * b(i, j);
        }
        partials[j] = row;
      }
    });
    if (null_space_.singular()) {
      project(r_);
      bb = null_space_.consistent_norm2(b, *ex_);
    }
    const double b_norm = std::sqrt(bb);
    SolveReport report;
    precondition(r_, z_);
    double rz = dot(r_, z_);
    cells([&](std::size_t m) { p_[m] = z_[m]; });
    const double target = settings_.tolerance * (b_norm > 0.0 ? b_norm : 1.0);
    for (int k = 0; k < settings_.max_iterations; ++k) {
      if (std::sqrt(dot(r_, r_)) <= target || rz <= 0.0) break;
      multiply(p_, q_);
      const double pq = dot(p_, q_);
      if (!(pq > 0.0)) break;
      const double alpha = rz / pq;
      cells([&](std::size_t m) {
        x_[m] += alpha * p_[m];
        r_[m] -= alpha * q_[m];
      });
      ++report.iterations;
      precondition(r_, z_);
      const double rz_next = dot(r_, z_);
      const double beta = rz_next / rz;
      rz = rz_next;
      cells([&](std::size_t m) { p_[m] = z_[m] + beta * p_[m]; });
    }
    rows([&](int y0, int y1) {
      for (int j = y0; j < y1; ++j)
        for (int i = 0; i < nx; ++i) x(i, j) = float(x_[idx(i, j)]);
    });
    null_space_.remove_mean(x, *ex_);
    report.relative_residual =
        relative_residual(op, b, x, rf_, null_space_, *ex_, null_space_.consistent_norm2(b, *ex_));
    return report;
  }

 private:
  static double sq(double v) { return v * v; }
  std::size_t idx(int i, int j) const { return std::size_t(j) * size_.x + i; }
  double wxf(int i, int j) const { return wx_[std::size_t(j) * (size_.x + 1) + i]; }
  double wyf(int i, int j) const { return wy_[std::size_t(j) * size_.x + i]; }

  // f(y0, y1) over the grid's rows, in bands on the executor.
  template <class F>
  void rows(const F& f) const {
    ex_->for_rows(size_.y, size_.x, f);
  }
  // f(m) for every cell index m, in bands of rows.
  template <class F>
  void cells(const F& f) const {
    rows([&](int y0, int y1) {
      for (std::size_t m = idx(0, y0), end = idx(0, y1); m < end; ++m) f(m);
    });
  }
  // f(j0, j1) for every block of rows [j0, j1), blocks side by side on the workers.
  template <class F>
  void each_block(const F& f) const {
    ex_->for_tasks(blocks_,
                   [&](int b) { f(b * kBlockRows, std::min(size_.y, (b + 1) * kBlockRows)); });
  }

  double dot(const std::vector<double>& a, const std::vector<double>& c) const {
    return ex_->sum_rows(size_.y, size_.x, [&](int y0, int y1, double* partials) {
      for (int j = y0; j < y1; ++j) {
        double s = 0.0;
        for (std::size_t m = idx(0, j), end = idx(0, j + 1); m < end; ++m) s += a[m] * c[m];
        partials[j] = s;
      }
    });
  }

  // out = A in (wrap couplings included). Row pointers; the edge cells take the wrap.
  void multiply(const std::vector<double>& in, std::vector<double>& out) const {
    const int nx = size_.x, ny = size_.y;
    rows([&](int y0, int y1) {
      for (int j = y0; j < y1; ++j) {
        const int jb = j > 0 ? j - 1 : (periodic_y_ ? ny - 1 : j);
        const int ja = j < ny - 1 ? j + 1 : (periodic_y_ ? 0 : j);
        const double* x0 = &in[idx(0, j)];
        const double* xb = &in[idx(0, jb)];
        const double* xa = &in[idx(0, ja)];
        const double* d = &diag_[idx(0, j)];
        const double* wx = &wx_[std::size_t(j) * (nx + 1)];
        const double* wyb = &wy_[std::size_t(j) * nx];
        const double* wya = &wy_[std::size_t(j + 1) * nx];
        double* y = &out[idx(0, j)];
        for (int i = 1; i < nx - 1; ++i)
          y[i] = d[i] * x0[i] -
                 (wx[i] * x0[i - 1] + wx[i + 1] * x0[i + 1] + wyb[i] * xb[i] + wya[i] * xa[i]);
        for (int i : {0, nx - 1}) {
          const int il = i > 0 ? i - 1 : (periodic_x_ ? nx - 1 : i);
          const int ir = i < nx - 1 ? i + 1 : (periodic_x_ ? 0 : i);
          y[i] = d[i] * x0[i] -
                 (wx[i] * x0[il] + wx[i + 1] * x0[ir] + wyb[i] * xb[i] + wya[i] * xa[i]);
        }
      }
    });
  }

  // z = M^-1 r: in each block, forward then backward substitution, row by row.
  void precondition(const std::vector<double>& r, std::vector<double>& z) const {
    const int nx = size_.x;
    each_block([&](int j0, int j1) {
      for (int j = j0; j < j1; ++j) {
        const double* rj = &r[idx(0, j)];
        const double* inv = &inv_pivot_[idx(0, j)];
        const double* wx = &wx_[std::size_t(j) * (nx + 1)];
        const double* wyb = &wy_[std::size_t(j) * nx];
        double* zj = &z[idx(0, j)];
        if (j > j0) {
          const double* zb = &z[idx(0, j - 1)];
          for (int i = 0; i < nx; ++i) zj[i] = rj[i] + wyb[i] * zb[i];  // vectorises
        } else {
          for (int i = 0; i < nx; ++i) zj[i] = rj[i];
        }
        zj[0] *= inv[0];
        for (int i = 1; i < nx; ++i) zj[i] = multiply_add(wx[i], zj[i - 1], zj[i]) * inv[i];
      }
      // t = wy(i, j+1) z(i, j+1) (vectorises), then the recurrence along the row.
      double* t = &scratch_rows_[std::size_t(j0 / kBlockRows) * std::size_t(nx)];
      for (int j = j1 - 1; j >= j0; --j) {
        const double* inv = &inv_pivot_[idx(0, j)];
        const double* wx = &wx_[std::size_t(j) * (nx + 1)];
        double* zj = &z[idx(0, j)];
        if (j < j1 - 1) {
          const double* wya = &wy_[std::size_t(j + 1) * nx];
          const double* za = &z[idx(0, j + 1)];
          for (int i = 0; i < nx; ++i) t[i] = wya[i] * za[i];
        } else {
          for (int i = 0; i < nx; ++i) t[i] = 0.0;
        }
        zj[nx - 1] += t[nx - 1] * inv[nx - 1];
        for (int i = nx - 2; i >= 0; --i)
          zj[i] = multiply_add(multiply_add(wx[i + 1], zj[i + 1], t[i]), inv[i], zj[i]);
      }
    });
    if (null_space_.singular()) project(z);
  }

  // Removes the null-space component (the mean over Z) from a vector.
  void project(std::vector<double>& v) const {
    const Field<uint8_t>& z = null_space_.mask();
    const int nx = size_.x;
    const double sum = ex_->sum_rows(size_.y, nx, [&](int y0, int y1, double* partials) {
      for (int j = y0; j < y1; ++j) {
        double s = 0.0;
        for (int i = 0; i < nx; ++i)
          if (z(i, j)) s += v[idx(i, j)];
        partials[j] = s;
      }
    });
    const double mean = sum / double(null_space_.count());
    rows([&](int y0, int y1) {
      for (int j = y0; j < y1; ++j)
        for (int i = 0; i < nx; ++i)
          if (z(i, j)) v[idx(i, j)] -= mean;
    });
  }

  Int2 size_;
  std::size_t n_;
  int blocks_;
  std::vector<double> pivot_, inv_pivot_, x_, r_, z_, p_, q_, wx_, wy_, diag_;
  mutable std::vector<double> scratch_rows_;  // one row per block (backward substitution)
  FieldF rf_;
  stencil::NullSpace null_space_;
  bool periodic_x_ = false, periodic_y_ = false;
};

}  // namespace

std::unique_ptr<LinearSolver> make_iccg_solver(const SolverSettings& s, Int2 size,
                                               RowExecutor& ex) {
  return std::make_unique<IccgSolver>(s, size, ex);
}

}  // namespace ardcell::solver_detail
