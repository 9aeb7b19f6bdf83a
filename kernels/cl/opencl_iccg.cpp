#if defined(ARDCELL_WITH_OPENCL)
#include "kernels/cl/opencl_iccg.h"

#include <cmath>
#include <stdexcept>

#include "kernels/iccg_solver.h"

namespace ardcell {

namespace {

int periodic_x(const ClStencilOperator& op) {
  return int(op.boundary_x == BoundaryKind::kPeriodic);
}
int periodic_y(const ClStencilOperator& op) {
  return int(op.boundary_y == BoundaryKind::kPeriodic);
}
}  // namespace

OpenClIccg::OpenClIccg(OpenClKernels& cl, Int2 size) : cl_(cl), size_(size), n_(size.x * size.y) {
  ARDCELL_CHECK(size.x > 0 && size.y > 0, "OpenCL ICCG: size must be positive");
  if (!cl.has_fp64())
    throw std::runtime_error("OpenCL ICCG: the device has no doubles (cl_khr_fp64)");
  OpenClContext& ctx = cl.context();
  const std::size_t bytes = std::size_t(n_) * sizeof(double);
  for (OpenClBuffer* b : {&pivot_, &inv_pivot_, &x_, &r_, &z_, &p_, &q_}) *b = ctx.allocate(bytes);
  partials_ = cl.row_partials(2 * size.y);
  if (ctx.device().type == "gpu") walk_ = BlockWalk::kWavefront;
}

static_assert(iccg::kBlockRows <= 64,
              "kernels/cl/iccg.cl: a wavefront work-group holds kWavefrontRows = 64 rows");

void OpenClIccg::enqueue_blocks(cl_kernel k) {
  // Sequential: one work-item per block, each its own work-group, so the blocks spread over the
  // compute units. Wavefront: one work-group of kBlockRows work-items per block.
  const std::size_t blocks = std::size_t((size_.y + iccg::kBlockRows - 1) / iccg::kBlockRows);
  const std::size_t group = walk_ == BlockWalk::kWavefront ? iccg::kBlockRows : 1;
  cl_.context().enqueue(k, blocks * group, group);
}

void OpenClIccg::factor(const ClStencilOperator& op) {
  ARDCELL_CHECK(op.size == size_, "OpenCL ICCG: size mismatch");
  cl_kernel k =
      cl_.kernel(walk_ == BlockWalk::kWavefront ? "iccg_factor_wavefront" : "iccg_factor");
  set_kernel_args(k, op.diag, op.wx, op.wy, size_.x, size_.y, iccg::kBlockRows, pivot_, inv_pivot_);
  enqueue_blocks(k);
}

void OpenClIccg::project(OpenClBuffer& v, const ClNullSpace& null) {
  OpenClContext& ctx = cl_.context();
  const DeviceField& mask = *null.mask;
  cl_kernel sums = cl_.kernel("iccg_masked_row_sums");
  set_kernel_args(sums, v, mask, size_.x, size_.y, partials_.data);
  cl_.enqueue_rows(sums, 0, size_.y);
  const double mean = partials_.sum(ctx, 0, size_.y) / double(null.count);
  cl_kernel subtract = cl_.kernel("iccg_subtract_masked");
  set_kernel_args(subtract, v, mask, size_.x, size_.y, mean);
  cl_.enqueue_cells(subtract, box_of_size(size_));
}

void OpenClIccg::precondition(const ClStencilOperator& op, const ClNullSpace* null, double& rz,
                              double& rr) {
  cl_kernel k = cl_.kernel(walk_ == BlockWalk::kWavefront ? "iccg_precondition_wavefront"
                                                          : "iccg_precondition");
  set_kernel_args(k, inv_pivot_, op.wx, op.wy, r_, z_, size_.x, size_.y, iccg::kBlockRows,
                  int(iccg::kFusedRecurrences));
  enqueue_blocks(k);
  if (null) project(z_, *null);
  cl_kernel dots = cl_.kernel("iccg_dots");
  set_kernel_args(dots, r_, z_, size_.x, size_.y, partials_.data);
  cl_.enqueue_rows(dots, 0, size_.y);
  const auto [first, second] = partials_.sum_pair(cl_.context(), size_.y);
  rz = first, rr = second;
}

int OpenClIccg::iterate(const ClStencilOperator& op, const DeviceField& b, DeviceField& x,
                        const SolverSettings& settings, const ClNullSpace* null) {
  ARDCELL_CHECK(op.size == size_ && b.size == size_ && x.size == size_,
                "OpenCL ICCG: size mismatch");
  ARDCELL_CHECK(b.stride == op.diag.stride && b.origin == op.diag.origin &&
                    x.stride == op.diag.stride && x.origin == op.diag.origin,
                "OpenCL ICCG: b and x must have the operator's layout");
  ARDCELL_CHECK(!null || (null->mask && null->count > 0), "OpenCL ICCG: empty null space");
  OpenClContext& ctx = cl_.context();
  const int nx = size_.x, ny = size_.y;
  const Box2 cells = box_of_size(size_);
  cl_kernel load = cl_.kernel("load_doubles");
  set_kernel_args(load, x, x_, nx, ny);
  cl_.enqueue_cells(load, cells);
  cl_kernel multiply = cl_.kernel("iccg_multiply");
  const int px = periodic_x(op), py = periodic_y(op);
  // q = A x (the partials, x . q, unread), then r = b - q with the rows' sums of b^2.
  set_kernel_args(multiply, op.diag, op.wx, op.wy, x_, q_, nx, ny, px, py, partials_.data);
  cl_.enqueue_rows(multiply, 0, ny);
  cl_kernel residual = cl_.kernel("iccg_residual");
  set_kernel_args(residual, b, q_, r_, nx, ny, partials_.data);
  cl_.enqueue_rows(residual, 0, ny);
  double bb = partials_.sum(ctx, 0, ny);
  if (null) {
    project(r_, *null);
    bb = null->b_consistent_norm2;
  }
  const double b_norm = std::sqrt(bb);
  double rz = 0.0, rr = 0.0;
  precondition(op, null, rz, rr);
  opencl_check(
      clEnqueueCopyBuffer(ctx.queue(), z_.get(), p_.get(), 0, 0, z_.bytes(), 0, nullptr, nullptr),
      "clEnqueueCopyBuffer(p = z)");
  const double target = settings.tolerance * (b_norm > 0.0 ? b_norm : 1.0);
  cl_kernel update = cl_.kernel("iccg_update");
  cl_kernel direction = cl_.kernel("iccg_direction");
  set_kernel_args(multiply, op.diag, op.wx, op.wy, p_, q_, nx, ny, px, py, partials_.data);
  int iterations = 0;
  for (int k = 0; k < settings.max_iterations; ++k) {
    if (std::sqrt(rr) <= target || rz <= 0.0) break;
    cl_.enqueue_rows(multiply, 0, ny);  // q = A p, the partials of p . q
    const double pq = partials_.sum(ctx, 0, ny);
    if (!(pq > 0.0)) break;
    const double alpha = rz / pq;
    set_kernel_args(update, x_, r_, p_, q_, alpha, n_);
    cl_.enqueue_items(update, n_);
    ++iterations;
    double rz_next = 0.0;
    precondition(op, null, rz_next, rr);
    const double beta = rz_next / rz;
    rz = rz_next;
    set_kernel_args(direction, p_, z_, beta, n_);
    cl_.enqueue_items(direction, n_);
  }
  cl_kernel store = cl_.kernel("store_doubles");
  set_kernel_args(store, x_, x, nx, ny);
  cl_.enqueue_cells(store, cells);
  return iterations;
}

}  // namespace ardcell
#endif
