#pragma once
// Twin of ImplicitDiffusion (kernels/aniso_diffusion.h) on an OpenCL device: one implicit step
// of seed 000's diffusion, Eqn 13 (isotropic) or Eqns 17/19 (per-cell conductivity from
// OpenClKernels::conductivity, averaged onto faces), Crank-Nicolson optional, periodic / Neumann
// / Dirichlet (with a boundary value) edges. The solver is the real-time one: a fixed number of
// Jacobi or red-black Gauss-Seidel sweeps (SolverSettings with tolerance 0); ICCG, multigrid,
// stopping on a residual and solid masks stay on the CPU. Every buffer is allocated once, here:
// a step only enqueues kernels, and its parameters (rate, boundary value, sweeps, conductivity)
// are kernel arguments.
#if defined(ARDCELL_WITH_OPENCL)
#include "kernels/aniso_diffusion.h"
#include "kernels/cl/opencl_kernels.h"

namespace ardcell {

class OpenClDiffusion {
 public:
  // solver: kind kJacobi or kRedBlackGaussSeidel, tolerance 0; max_iterations sweeps.
  OpenClDiffusion(OpenClKernels& cl, Int2 size, BoundaryKind boundary,
                  const SolverSettings& solver);

  // One step in place on field's interior (its halo is not touched). conductivity: per-cell k,
  // same layout as field (null: k = 1). Returns the relative residual |b - A x| / |b| of the
  // solve, as the CPU solvers report it (waits for the step).
  double step(DeviceField& field, const DeviceField* conductivity, const DiffusionStep& s);
  void set_sweeps(int sweeps);

  const ClStencilOperator& op() const { return op_; }

 private:
  OpenClKernels& cl_;
  SolverKind kind_;
  int sweeps_;
  ClStencilOperator op_;
  DeviceField rhs_, x_, tmp_, ax_;
  ClRowPartials partials_;
  // The last operator assembled (isotropic operators are reused from step to step).
  float last_scale_ = -1.0f;
  bool last_isotropic_ = false;
};

}  // namespace ardcell
#endif
