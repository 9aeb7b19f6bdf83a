#if defined(ARDCELL_WITH_OPENCL)
#include "kernels/cl/opencl_tensor_field_solve.h"

#include <cmath>
#include <stdexcept>

namespace ardcell {

OpenClTensorFieldSolve::OpenClTensorFieldSolve(OpenClKernels& cl, Int2 size)
    : cl_(cl), size_(size), n_(size.x * size.y) {
  ARDCELL_CHECK(size.x >= 2 && size.y >= 2, "OpenCL tensor-field solve needs at least 2 x 2 cells");
  if (!cl.has_fp64())
    throw std::runtime_error("OpenCL tensor-field solve: the device has no doubles (cl_khr_fp64)");
  OpenClContext& ctx = cl.context();
  const std::size_t bytes = std::size_t(n_) * sizeof(double);
  for (OpenClBuffer* b : {&b_, &x_, &r_, &shadow_, &p_, &v_, &y_, &z_, &t_})
    *b = ctx.allocate(bytes);
  partials_ = cl.row_partials(2 * size.y);
  apply_ = cl.kernel("tfs_apply");
  precondition_ = cl.kernel("tfs_precondition");
  dots_ = cl.kernel("tfs_dots");
  load_ = cl.kernel("load_doubles");
  store_ = cl.kernel("store_doubles");
  zero_ = cl.kernel("tfs_zero");
  direction_ = cl.kernel("tfs_direction");
  step_ = cl.kernel("tfs_step");
  add_ = cl.kernel("tfs_add");
}

void OpenClTensorFieldSolve::apply(const OpenClBuffer& in, const OpenClBuffer& out, bool with_b) {
  set_kernel_args(apply_, in, b_, int(with_b), out, d_.x_xx->buffer, d_.x_xy->buffer,
                  d_.y_xy->buffer, d_.y_yy->buffer, d_.x_xx->stride, size_.x, size_.y, s_);
  cl_.enqueue_cells(apply_, box_of_size(size_));
}

void OpenClTensorFieldSolve::precondition(const OpenClBuffer& in, const OpenClBuffer& out) {
  set_kernel_args(precondition_, in, out, d_.x_xx->buffer, d_.y_yy->buffer, d_.x_xx->stride,
                  size_.x, size_.y, s_);
  cl_.enqueue_cells(precondition_, box_of_size(size_));
}

double OpenClTensorFieldSolve::dot(const OpenClBuffer& a, const OpenClBuffer& b) {
  set_kernel_args(dots_, a, b, a, b, 0, size_.x, size_.y, partials_.data);
  cl_.enqueue_rows(dots_, 0, size_.y);
  return partials_.sum(cl_.context(), 0, size_.y);
}

void OpenClTensorFieldSolve::dots(const OpenClBuffer& a, const OpenClBuffer& b,
                                  const OpenClBuffer& c, const OpenClBuffer& d, double& ab,
                                  double& cd) {
  set_kernel_args(dots_, a, b, c, d, 1, size_.x, size_.y, partials_.data);
  cl_.enqueue_rows(dots_, 0, size_.y);
  const auto [first, second] = partials_.sum_pair(cl_.context(), size_.y);
  ab = first, cd = second;
}

double OpenClTensorFieldSolve::step(const OpenClBuffer& y, const OpenClBuffer& av, double w,
                                    const OpenClBuffer* z, double* shadow_r) {
  set_kernel_args(step_, x_, r_, y, av, w, shadow_, int(shadow_r != nullptr), z ? *z : z_,
                  int(z != nullptr), d_.x_xx->buffer, d_.y_yy->buffer, d_.x_xx->stride, size_.x,
                  size_.y, s_, partials_.data);
  cl_.enqueue_rows(step_, 0, size_.y);
  if (!shadow_r) return partials_.sum(cl_.context(), 0, size_.y);
  const auto [rr, sr] = partials_.sum_pair(cl_.context(), size_.y);
  *shadow_r = sr;
  return rr;
}

// bicgstab() (kernels/bicgstab.h) with TensorFieldSolve::solve's space, residual, operator and
// preconditioner, step for step: the same values in the same order, fewer launches and reads
// (the direction is preconditioned where it is made, each half step computes |r|^2 of its r and
// the first the next direction from it, the second shadow . r, the next step's rho, with it).
SolveReport OpenClTensorFieldSolve::solve(const ClRank2Faces& d, DeviceField& x, double s,
                                          int max_iterations, double tolerance) {
  ARDCELL_CHECK(x.size == size_, "OpenCL tensor-field solve: a field of another size");
  ARDCELL_CHECK(s >= 0 && std::isfinite(s),
                "OpenCL tensor-field solve: the step must be finite and >= 0");
  ARDCELL_CHECK(d.x_xx && d.x_xy && d.y_xy && d.y_yy, "OpenCL tensor-field solve: four faces");
  for (const DeviceField* f : {d.x_xx, d.x_xy, d.y_xy, d.y_yy})
    ARDCELL_CHECK(f->size == size_ && f->halo == 0 && f->stride == d.x_xx->stride,
                  "OpenCL tensor-field solve: the faces are the grid's size, halo 0, one layout");
  d_ = d;
  s_ = s;
  const int nx = size_.x, ny = size_.y;
  for (const OpenClBuffer* v : {&x_, &b_}) {
    set_kernel_args(load_, x, *v, nx, ny);
    cl_.enqueue_cells(load_, box_of_size(size_));
  }
  double bnorm = std::sqrt(dot(b_, b_));
  if (bnorm == 0) bnorm = 1;

  const int max_applications = 2 * max_iterations;
  int applications = 0;
  double report_residual = 0;
  const auto done = [&](double norm_r) {
    report_residual = norm_r / bnorm;
    return report_residual <= tolerance || applications >= max_applications;
  };
  // r = b - (I - s L) x; returns |r|, and rr = |r|^2.
  double rr = 0;
  const auto residual = [&] {
    apply(x_, r_, true);
    rr = dot(r_, r_);
    return std::sqrt(rr);
  };
  while (!done(residual())) {
    const int applications_before = applications;
    opencl_check(clEnqueueCopyBuffer(cl_.context().queue(), r_.get(), shadow_.get(), 0, 0,
                                     r_.bytes(), 0, nullptr, nullptr),
                 "clEnqueueCopyBuffer(shadow = r)");
    double rho = 1, alpha = 1, omega = 1;
    set_kernel_args(zero_, p_, v_, n_);
    cl_.enqueue_items(zero_, n_);
    // dot(shadow, r), which the loop's first step takes: shadow = r, so |r|^2 (the same products
    // in the same order); then the one each second half step reads with |r|^2.
    double shadow_r = rr;
    for (;;) {
      const double rho_next = shadow_r;
      if (rho_next == 0 || omega == 0) break;
      const double beta = (rho_next / rho) * (alpha / omega);
      rho = rho_next;
      // p = r + beta (p - omega v), y = M^-1 p.
      set_kernel_args(direction_, p_, r_, v_, y_, d_.x_xx->buffer, d_.y_yy->buffer, d_.x_xx->stride,
                      nx, ny, beta, omega, s_);
      cl_.enqueue_cells(direction_, box_of_size(size_));
      apply(y_, v_, false);
      ++applications;
      const double shadow_v = dot(shadow_, v_);
      if (shadow_v == 0) break;
      alpha = rho / shadow_v;
      // r becomes s = r - alpha v, x takes the half step; z = M^-1 s.
      if (done(std::sqrt(step(y_, v_, alpha, &z_, nullptr)))) break;
      apply(z_, t_, false);
      ++applications;
      double tt = 0, tr = 0;
      dots(t_, t_, t_, r_, tt, tr);
      omega = tt == 0 ? 0 : tr / tt;
      if (done(std::sqrt(step(z_, t_, omega, nullptr, &shadow_r)))) break;
    }
    // A pass that broke down before its first application takes one plain preconditioned step.
    if (applications == applications_before) {
      precondition(r_, y_);
      set_kernel_args(add_, x_, y_, n_);
      cl_.enqueue_items(add_, n_);
      ++applications;
    }
    if (applications >= max_applications) {
      report_residual = residual() / bnorm;
      break;
    }
  }
  set_kernel_args(store_, x_, x, nx, ny);
  cl_.enqueue_cells(store_, box_of_size(size_));
  d_ = {};  // the faces are the caller's: none kept past the solve
  return {(applications + 1) / 2, report_residual};
}

}  // namespace ardcell
#endif
