#pragma once
// OpenClIccg: the OpenCL twin of kernels/iccg_solver.cpp (ICCG: conjugate gradients
// preconditioned by block IC(0), blocks of 32 rows), on a ClStencilOperator in device memory.
// factor() computes the pivots where the operator is (on the device: the implicit diffusion
// assembles its operator there every step); iterate() runs IccgSolver::solve's loop step for
// step: the same initial residual, preconditioner, stopping rule and null-space projection, the
// vectors in double (kernels/cl/iccg.cl), each dot product's per-row partials read back and
// added in row order. On PoCL the iterates have the C++ bits, so it stops after the same
// iteration.
//
// The caller does what the C++ solve does after its loop on the float x (NullSpace::remove_mean,
// the relative residual): OpenClDevice::solve, OpenClDiffusion::step.
//
// Needs doubles on the device (OpenClKernels::has_fp64). Every buffer is allocated by the
// constructor: a solve only enqueues kernels and reads partials.
#if defined(ARDCELL_WITH_OPENCL)
#include <cstdint>

#include "kernels/cl/opencl_kernels.h"
#include "kernels/linear_solver.h"

namespace ardcell {

// A singular operator's null space (stencil::NullSpace) for OpenClIccg::iterate: the mask
// uploaded (upload_mask of NullSpace::mask()), its cell count, and |b|^2 without b's null-space
// component (NullSpace::consistent_norm2, which the C++ solve measures b by then).
struct ClNullSpace {
  const DeviceField* mask = nullptr;
  std::int64_t count = 0;
  double b_consistent_norm2 = 0.0;
};

class OpenClIccg {
 public:
  // How a block's factorisation and triangular solves are walked (kernels/cl/iccg.cl): one
  // work-item per block in the C++ order (a CPU's best: the blocks spread over its cores), or as
  // wavefronts, one work-group per block and one work-item per row (a GPU's: its cores wait on
  // memory, and the sequential walk has 32 N dependent steps where the wavefront has N + 31). The
  // same bits either way.
  enum class BlockWalk : uint8_t { kSequential, kWavefront };

  // Throws when the device has no doubles. The walk: wavefronts on a GPU, else sequential.
  OpenClIccg(OpenClKernels& cl, Int2 size);

  BlockWalk block_walk() const { return walk_; }
  void set_block_walk(BlockWalk walk) { walk_ = walk; }

  // IccgSolver::prepare: the block IC(0) pivots of op (op.size must be the solver's). Call it
  // after every change of op's coefficients, before iterate().
  void factor(const ClStencilOperator& op);
  // IccgSolver::solve up to its loop's end: improves x (the initial guess, written back as
  // float) towards op x = b, stopping as the C++ stops (settings.max_iterations, the
  // tolerance). null: op's null space when op is singular. Returns the iterations taken.
  int iterate(const ClStencilOperator& op, const DeviceField& b, DeviceField& x,
              const SolverSettings& settings, const ClNullSpace* null = nullptr);

 private:
  // z = M^-1 r (IccgSolver::precondition), projected when singular; then rz = dot(r, z) and
  // rr = dot(r, r) (one read).
  void precondition(const ClStencilOperator& op, const ClNullSpace* null, double& rz, double& rr);
  // Removes v's mean over the null space (IccgSolver::project).
  void project(OpenClBuffer& v, const ClNullSpace& null);
  // A kernel over the n cells (1D), the cells of the grid (2D), the rows or the blocks.
  void enqueue_blocks(cl_kernel k);

  OpenClKernels& cl_;
  Int2 size_;
  int n_;
  BlockWalk walk_ = BlockWalk::kSequential;
  OpenClBuffer pivot_, inv_pivot_, x_, r_, z_, p_, q_;
  ClRowPartials partials_;  // 2 ny rows: iccg_dots writes two reductions side by side
};

}  // namespace ardcell
#endif
