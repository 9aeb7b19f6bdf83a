#pragma once
// Twin of ImplicitDiffusion (kernels/aniso_diffusion.h) on an OpenCL device: one implicit step
// of seed 000's diffusion, Eqn 13 (isotropic) or Eqns 17/19 (per-cell conductivity from
// OpenClKernels::conductivity, averaged onto faces), Crank-Nicolson optional, periodic / Neumann
// / Dirichlet (with a boundary value) edges, solid cells optional (isolated as
// isolate_solid_cells does). The solver: a fixed number of Jacobi or red-black Gauss-Seidel
// sweeps (SolverSettings with tolerance 0), or ICCG with its stopping rule (OpenClIccg, on a
// device with doubles), its pivots computed on the device after each assembly; multigrid and
// sweeps stopping on a residual stay on the CPU (supports()). Every buffer is allocated once,
// here: a step only enqueues kernels and reads reductions, and its parameters (rate, boundary
// value, iterations, conductivity) are kernel arguments.
#if defined(ARDCELL_WITH_OPENCL)
#include <memory>

#include "kernels/aniso_diffusion.h"
#include "kernels/cl/opencl_iccg.h"
#include "kernels/cl/opencl_kernels.h"

namespace ardcell {

class OpenClDiffusion {
 public:
  // Whether `solver` has a twin on cl's device: jacobi or rbgs with tolerance 0, or iccg on a
  // device with doubles.
  static bool supports(const OpenClKernels& cl, const SolverSettings& solver);
  // solver: one that supports() (checked); max_iterations sweeps or ICCG iterations.
  OpenClDiffusion(OpenClKernels& cl, Int2 size, BoundaryKind boundary,
                  const SolverSettings& solver);

  // One step in place on field's interior (its halo is not touched). conductivity: per-cell k,
  // same layout as field (null: k = 1). solid: a mask from upload_mask, same layout (null:
  // none); solid cells keep their value and pass no flux. Reports the iterations and the
  // relative residual |b - A x| / |b| of the solve, as the CPU solvers report them (waits for
  // the step).
  SolveReport step(DeviceField& field, const DeviceField* conductivity, const DiffusionStep& s,
                   const DeviceField* solid = nullptr);
  // The stopping rule (live parameter changes; the kind stays): sweeps, or ICCG's iterations and
  // tolerance. Sweeps keep tolerance 0.
  void set_limits(int max_iterations, double tolerance);

  const ClStencilOperator& op() const { return op_; }

 private:
  OpenClKernels& cl_;
  SolverSettings solver_;
  ClStencilOperator op_;
  DeviceField rhs_, x_, tmp_, ax_;
  ClRowPartials partials_;
  std::unique_ptr<OpenClIccg> iccg_;  // with kind iccg
  // The last operator assembled (isotropic operators without solid cells are reused from step
  // to step, their ICCG pivots too).
  float last_scale_ = -1.0f;
  bool last_reusable_ = false;
};

}  // namespace ardcell
#endif
