#pragma once
// OpenClTensorFieldSolve: the OpenCL twin of TensorFieldSolve (kernels/tensor_field_solve.h),
// seed 003, Eqn 28's linear part with a per-cell tensor, x <- (I - s L)^{-1} x on a periodic grid
// (reads no halo), L = div(D(x) grad) in flux form on the face field (Rank2FaceField's four
// fields on the device, halo 0). solve() runs bicgstab()'s loop (kernels/bicgstab.h) step for
// step: right-preconditioned BiCGSTAB with the Jacobi diagonal from x as the first guess, the
// Krylov vectors and the operator in double (kernels/cl/tensor_field_solve.cl), x in float in and
// out, each dot product's per-row partials read back (four reads a BiCGSTAB step) and added in
// row order, the same stopping rule and report (iterations: BiCGSTAB steps, started ones; the
// residual: the double iterate's |b - (I - s L) x|_2 / |b|_2). Neither side fuses a multiply-add
// (the C++ is compiled with -ffp-contract=off), so on PoCL the iterates have the C++ bits and it
// stops after the same step with the same residual
// (tests/kernels/cl_tensor_field_solve_parity_test.cpp).
//
// Needs doubles on the device (OpenClKernels::has_fp64). Every buffer is allocated by the
// constructor and the kernels are looked up there: a solve only sets arguments, enqueues and
// reads partials.
#if defined(ARDCELL_WITH_OPENCL)
#include "kernels/cl/opencl_kernels.h"
#include "kernels/linear_solver.h"

namespace ardcell {

// A Rank2FaceField's four fields on the device (one layout: the grid's size, halo 0).
struct ClRank2Faces {
  const DeviceField* x_xx = nullptr;
  const DeviceField* x_xy = nullptr;
  const DeviceField* y_xy = nullptr;
  const DeviceField* y_yy = nullptr;
};

class OpenClTensorFieldSolve {
 public:
  // Throws when the device has no doubles.
  OpenClTensorFieldSolve(OpenClKernels& cl, Int2 size);

  Int2 size() const { return size_; }
  // TensorFieldSolve::solve on the device: x (its interior, x.size == size()) <- (I - s L)^{-1} x,
  // s >= 0, to at most max_iterations BiCGSTAB steps or the relative residual `tolerance`.
  SolveReport solve(const ClRank2Faces& d, DeviceField& x, double s, int max_iterations,
                    double tolerance);

 private:
  // out = (I - s L) in, or b - (I - s L) in when with_b.
  void apply(const OpenClBuffer& in, const OpenClBuffer& out, bool with_b);
  // out = in / (1 + s diag).
  void precondition(const OpenClBuffer& in, const OpenClBuffer& out);
  // a . b, added in row order.
  double dot(const OpenClBuffer& a, const OpenClBuffer& b);
  // a . b and c . d from one launch and one read.
  void dots(const OpenClBuffer& a, const OpenClBuffer& b, const OpenClBuffer& c,
            const OpenClBuffer& d, double& ab, double& cd);
  // r -= w av, x += w y; returns |r|^2 of the new r. z: also z = M^-1 r. shadow_r: also
  // *shadow_r = shadow . r (one read for both).
  double step(const OpenClBuffer& y, const OpenClBuffer& av, double w, const OpenClBuffer* z,
              double* shadow_r);

  OpenClKernels& cl_;
  Int2 size_;
  int n_;
  // The solve's faces and step, set by solve() for its helpers.
  ClRank2Faces d_;
  double s_ = 0;
  OpenClBuffer b_, x_, r_, shadow_, p_, v_, y_, z_, t_;
  ClRowPartials partials_;  // 2 ny rows: tfs_dots writes two reductions side by side
  cl_kernel apply_, precondition_, dots_, load_, store_, zero_, direction_, step_, add_;
};

}  // namespace ardcell
#endif
