#if defined(ARDCELL_WITH_OPENCL)
#include "kernels/cl/opencl_diffusion.h"

#include <cmath>
#include <utility>

namespace ardcell {

bool OpenClDiffusion::supports(const OpenClKernels& cl, const SolverSettings& solver) {
  switch (solver.kind) {
    case SolverKind::kJacobi:
    case SolverKind::kRedBlackGaussSeidel:
      return solver.tolerance == 0.0;
    case SolverKind::kIccg:
      return cl.has_fp64();
    case SolverKind::kMultigrid:
      return false;
  }
  return false;
}

OpenClDiffusion::OpenClDiffusion(OpenClKernels& cl, Int2 size, BoundaryKind boundary,
                                 const SolverSettings& solver)
    : cl_(cl), solver_(solver) {
  ARDCELL_CHECK(size.x > 0 && size.y > 0, "OpenCL diffusion: size must be positive");
  ARDCELL_CHECK(supports(cl, solver),
                "OpenCL diffusion: the solver must be jacobi or rbgs with fixed sweeps "
                "(tolerance 0), or iccg on a device with doubles");
  ARDCELL_CHECK(solver.max_iterations >= 0, "OpenCL diffusion: iterations must be >= 0");
  OpenClContext& ctx = cl_.context();
  op_ = ClStencilOperator::allocate(ctx, size, boundary, boundary);
  const FieldF like(size, 1);
  for (DeviceField* f : {&rhs_, &x_, &tmp_, &ax_}) *f = ctx.allocate_like(like);
  partials_ = cl_.row_partials(size.y);
  if (solver.kind == SolverKind::kIccg) iccg_ = std::make_unique<OpenClIccg>(cl_, size);
}

void OpenClDiffusion::set_limits(int max_iterations, double tolerance) {
  ARDCELL_CHECK(max_iterations >= 0, "OpenCL diffusion: iterations must be >= 0");
  SolverSettings next = solver_;
  next.max_iterations = max_iterations;
  next.tolerance = tolerance;
  ARDCELL_CHECK(supports(cl_, next), "OpenCL diffusion: sweeps take no tolerance");
  solver_ = next;
}

SolveReport OpenClDiffusion::step(DeviceField& field, const DeviceField* conductivity,
                                  const DiffusionStep& s, const DeviceField* solid) {
  ARDCELL_CHECK(field.size == op_.size && field.halo == 1,
                "OpenCL diffusion: field size differs from the solver's");
  OpenClContext& ctx = cl_.context();
  const double scale = s.crank_nicolson ? 0.5 * s.rate_dt_over_h2 : s.rate_dt_over_h2;
  // As ImplicitDiffusion::step: a conductivity or solid cells re-assemble every step.
  const bool reusable = conductivity == nullptr && solid == nullptr;
  if (!reusable || !last_reusable_ || float(scale) != last_scale_) {
    cl_.assemble_stencil_operator(op_, 1.0f, float(scale), conductivity, solid);
    if (iccg_) iccg_->factor(op_);
    last_scale_ = float(scale);
    last_reusable_ = reusable;
  }
  if (s.crank_nicolson) cl_.apply_stencil_operator(op_, field, ax_);
  const bool dirichlet_value =
      op_.boundary_x == BoundaryKind::kDirichlet && s.boundary_value != 0.0f;
  const double g = dirichlet_value ? double(s.boundary_value) * s.rate_dt_over_h2 : 0.0;
  cl_.diffusion_rhs(field, s.crank_nicolson ? &ax_ : nullptr, rhs_, conductivity, g, solid);
  SolveReport report{solver_.max_iterations, 0.0};
  if (iccg_) {
    // The initial guess is the field; ICCG writes its interior only.
    report.iterations = iccg_->iterate(op_, rhs_, field, solver_);
  } else {
    // The initial guess is the field (whole buffers: the sweeps never write a halo, so the copy
    // back leaves field's halo as it was).
    auto copy = [&](const DeviceField& from, DeviceField& to) {
      opencl_check(clEnqueueCopyBuffer(ctx.queue(), from.buffer.get(), to.buffer.get(), 0, 0,
                                       from.buffer.bytes(), 0, nullptr, nullptr),
                   "clEnqueueCopyBuffer");
    };
    copy(field, x_);
    if (solver_.kind == SolverKind::kJacobi) {
      DeviceField* from = &x_;
      DeviceField* to = &tmp_;
      for (int k = 0; k < solver_.max_iterations; ++k) {
        cl_.stencil_jacobi_sweep(op_, rhs_, *from, *to);
        std::swap(from, to);
      }
      copy(*from, field);
    } else {
      for (int k = 0; k < solver_.max_iterations; ++k) {
        cl_.stencil_rbgs_half_sweep(op_, rhs_, x_, 0);
        cl_.stencil_rbgs_half_sweep(op_, rhs_, x_, 1);
      }
      copy(x_, field);
    }
  }
  // |rhs - A x| / |rhs| (the operator is the identity plus a diffusion: never singular), as the
  // CPU solvers report it.
  const int ny = op_.size.y;
  cl_.row_sums_of_squares(rhs_, 0, ny, partials_);
  const double bb = partials_.sum(ctx, 0, ny);
  cl_.residual(op_, rhs_, field, nullptr, partials_);
  const double rr = partials_.sum(ctx, 0, ny);
  report.relative_residual = bb > 0.0 ? std::sqrt(rr / bb) : std::sqrt(rr);
  return report;
}

}  // namespace ardcell
#endif
