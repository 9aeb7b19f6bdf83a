#pragma once
// The semi-implicit step of seed 003 with a per-cell tensor (Table 1, last row at rank 2):
//   seed 003, Eqn 28: u^{t+1} = (I - delta A)^{-1} (u^t + delta f(u^t))
// with A = L = div(D(x) grad) in flux form (kernels/tensor_field_operator.h, the operator of the
// explicit step tensor_field_rd_rows). This solves the linear part, x <- (I - s L)^{-1} x in
// place, s = delta (the tensor in cells^2, so s is the step), where the caller has already added
// delta f(u^t) to x.
// Reads NO halo: the grid is periodic and the operator wraps its indices.
//
// Why BiCGSTAB: an inhomogeneous operator is not circulant, so the FFT solve of a homogeneous
// one (kernels/periodic_stencil_solve.h) does not apply; and L is not symmetric (the cross term
// of the face between x and x + 1 couples (x, y) to (x + 1, y + 1) with that face's D_xy, while
// (x + 1, y + 1) reaches back through the face of row y + 1), so CG and ICCG do not either.
// Right-preconditioned BiCGSTAB (kernels/bicgstab.h) with the diagonal of I - s L (Jacobi), from
// x itself as the first guess (the step's u + delta f, or the implicit reaction's result: within
// a step's diffusion of the answer).
// For a uniform tensor L is Eqn 29's 9-point stencil, so the solve equals the FFT's
// (tests/kernels/tensor_field_solve_test.cpp asserts 1e-5).
//
// Stopping rule: |b - (I - s L) x|_2 / |b|_2 <= tolerance, or max_iterations BiCGSTAB steps (two
// applications of the operator each), as SolverSettings says (rd.diffusion_solver).
// Precision: the Krylov vectors and the operator in double; x in float in and out. The report's
// residual is the double iterate's; rounding it to float adds about float's epsilon times the
// operator's condition (x - s L x of the returned field is b to 5e-7 on the test's vortex field
// at s = 4, where the double iterate's residual is 2e-9).
// The same bits for any number of workers: cells in bands of rows, every dot product per-row
// partials added in row order (RowExecutor::sum_rows).
// Conservation: the fluxes telescope, so sum L x = 0 and sum x = sum b to the residual.
// Allocation: none in solve() (every vector is sized in the constructor).
// OpenCL twin: kernels/cl/opencl_tensor_field_solve.h (the same steps in double on the device;
// on PoCL the same bits and report).
#include <vector>

#include "kernels/bicgstab.h"
#include "kernels/generalized_rd.h"
#include "kernels/linear_solver.h"
#include "runtime/field.h"
#include "runtime/row_executor.h"

namespace ardcell {

class TensorFieldSolve {
 public:
  // d is kept by reference (it must outlive the solve); its size is the grid's.
  explicit TensorFieldSolve(const Rank2FaceField& d, RowExecutor& ex = RowExecutor::serial());

  Int2 size() const { return n_; }
  void set_limits(int max_iterations, double tolerance) {
    max_iterations_ = max_iterations;
    tolerance_ = tolerance;
  }
  int max_iterations() const { return max_iterations_; }
  double tolerance() const { return tolerance_; }
  // The face field (for the device twin, kernels/cl/opencl_tensor_field_solve.h).
  const Rank2FaceField& faces() const { return *d_; }
  // x <- (I - s L)^{-1} x over the interior, s >= 0; the report's iterations are BiCGSTAB steps
  // (started ones: an application of the operator counts half).
  SolveReport solve(FieldF& x, double s);

  // The grid as BiCGSTAB's space (flat row-major vectors of nx * ny doubles).
  struct Space {
    using Vector = std::vector<double>;
    RowExecutor* ex;
    Int2 n;
    double dot(const Vector& a, const Vector& b) const;
    double norm(const Vector& a) const;  // the 2-norm
    template <class F>
    void each(const F& f) const {
      const int nx = n.x;
      ex->for_rows(n.y, nx, [&](int y0, int y1) {
        for (std::size_t q = std::size_t(y0) * nx; q < std::size_t(y1) * nx; ++q) f(q);
      });
    }
  };

 private:
  // out = (I - s L) y; with b, out = b - (I - s L) y instead.
  void apply(const std::vector<double>& y, std::vector<double>& out, double s,
             const std::vector<double>* b) const;

  const Rank2FaceField* d_;
  RowExecutor* ex_;
  Int2 n_;
  int max_iterations_ = 40;
  double tolerance_ = 1e-6;
  std::vector<double> b_, x_, diagonal_;  // diagonal_: the faces' sum, minus L's diagonal
  BicgstabVectors<std::vector<double>> k_;
};

}  // namespace ardcell
