#if defined(ARDCELL_WITH_OPENCL)
#include "kernels/cl/opencl_kernels.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <initializer_list>
#include <stdexcept>
#include <vector>

#include "kernels/cl_sources.h"

namespace ardcell {

namespace {

cl_program build_program(OpenClContext& ctx, std::string* error) {
  std::vector<std::string_view> sources;
  const std::string_view common = cl_source("common.cl");
  if (common.empty()) {
    if (error) *error = "OpenCL: kernels/cl/common.cl is not embedded in this binary";
    return nullptr;
  }
  sources.push_back(common);
  for (const ClSource& s : cl_sources())
    if (std::string_view(s.name) != "common.cl") sources.push_back(s.text);
  // OpenCL lets a device divide and take square roots in single precision to 2.5 and 3 ulp
  // (NVIDIA's does); the C++ twins round correctly, and parity is asked in bits, so a device
  // that can round correctly is told to.
  cl_device_fp_config fp = 0;
  clGetDeviceInfo(ctx.device().device, CL_DEVICE_SINGLE_FP_CONFIG, sizeof fp, &fp, nullptr);
  const char* options = (fp & CL_FP_CORRECTLY_ROUNDED_DIVIDE_SQRT)
                            ? "-cl-std=CL1.2 -cl-fp32-correctly-rounded-divide-sqrt"
                            : "-cl-std=CL1.2";
  return ctx.program(OpenClKernels::kProgramKey, sources, options, error);
}

// Whether the device compiles common.cl's `real` as double: it reports cl_khr_fp64 (the
// extension macro common.cl tests).
bool device_has_fp64(cl_device_id device) {
  std::size_t bytes = 0;
  if (clGetDeviceInfo(device, CL_DEVICE_EXTENSIONS, 0, nullptr, &bytes) != CL_SUCCESS) return false;
  std::string extensions(bytes, '\0');
  if (clGetDeviceInfo(device, CL_DEVICE_EXTENSIONS, bytes, extensions.data(), nullptr) !=
      CL_SUCCESS)
    return false;
  return extensions.find("cl_khr_fp64") != std::string::npos;
}

// The model's invariant box (a_lo, a_hi, b_lo, b_hi), into which the implicit updates clamp
// their inputs.
cl_float4 invariant_box_arg(const ReactionParams& p) {
  const ConcentrationBox box = invariant_box(p);
  return {{float(box.a_lo), float(box.a_hi), float(box.b_lo), float(box.b_hi)}};
}

int tiles_of(Box2 region, int tw, int th) {
  return ((region.width() + tw - 1) / tw) * ((region.height() + th - 1) / th);
}

}  // namespace

void cl_reaction_args(const ReactionParams& p, float q[5]) {
  std::fill(q, q + 5, 0.0f);
  switch (p.model) {
    case ReactionModel::kGrayScott:
      q[0] = p.F, q[1] = p.k;
      break;
    case ReactionModel::kTuring:
      q[0] = p.turing_s, q[1] = p.turing_beta, q[2] = p.turing_supply;
      break;
    case ReactionModel::kMeinhardt:
      q[0] = p.meinhardt_s, q[1] = p.meinhardt_alpha, q[2] = p.meinhardt_p1;
      q[3] = p.meinhardt_p2, q[4] = p.meinhardt_p3;
      break;
    case ReactionModel::kFitzHughNagumo:
      q[0] = p.fhn_epsilon, q[1] = p.fhn_a0, q[2] = p.fhn_a1;
      q[3] = float(invariant_box(p).a_hi);  // the bracket half-width M
      break;
    case ReactionModel::kBarkley:
    case ReactionModel::kBarkleyTurbulent:
      q[0] = p.barkley_epsilon, q[1] = p.barkley_a, q[2] = p.barkley_b;
      break;
  }
}

ClTiling default_tiling(const OpenClDeviceInfo& device) {
  if (device.type == "cpu" || !device.local_mem_dedicated) return ClTiling{256, 32, 1, 4};
  return ClTiling{};
}

std::unique_ptr<OpenClKernels> OpenClKernels::create(OpenClContext& ctx, std::string* error) {
  cl_program program = build_program(ctx, error);
  if (!program) return nullptr;
  auto kernels = std::unique_ptr<OpenClKernels>(new OpenClKernels(ctx, program));
  kernels->tiling_ = default_tiling(ctx.device());
  if (const char* t = std::getenv("ARDCELL_CL_TILING")) {
    ClTiling& tiling = kernels->tiling_;
    char rest = 0;
    if (std::sscanf(t, "%d,%d,%d,%d%c", &tiling.tile_w, &tiling.tile_h, &tiling.work_group,
                    &tiling.groups_per_unit, &rest) != 4 ||
        tiling.tile_w < 1 || tiling.tile_h < 1 || tiling.work_group < 1 ||
        tiling.groups_per_unit < 1) {
      if (error)
        *error = "ARDCELL_CL_TILING '" + std::string(t).substr(0, 40) +
                 "': expected four positive integers tile_w,tile_h,work_group,groups_per_unit";
      return nullptr;
    }
  }
  kernels->real_bytes_ = device_has_fp64(ctx.device().device) ? sizeof(double) : sizeof(float);
  return kernels;
}

bool OpenClKernels::prepare(OpenClContext& ctx, std::string* error) {
  return build_program(ctx, error) != nullptr;
}

cl_kernel OpenClKernels::kernel(const char* name) {
  std::string error;
  cl_kernel k = ctx_.kernel(program_, name, &error);
  if (!k) throw std::runtime_error(error);
  return k;
}

std::size_t OpenClKernels::groups_for(int tiles) const {
  const int per_device =
      std::max(1, int(ctx_.device().compute_units) * std::max(1, tiling_.groups_per_unit));
  return std::size_t(std::clamp(tiles, 1, per_device));
}

void OpenClKernels::check_same_layout(const DeviceField& a, const DeviceField& b) const {
  ARDCELL_CHECK(a.stride == b.stride && a.origin == b.origin && a.size == b.size,
                "OpenCL launch: every field of one launch must share size, halo and stride");
}

void OpenClKernels::reaction_implicit(const DeviceField& a, const DeviceField& b,
                                      DeviceField& a_out, DeviceField& b_out, Box2 region,
                                      const ReactionParams& p, float dt) {
  check_same_layout(a, b, a_out, b_out);
  if (region.empty()) return;
  float q[5];
  cl_reaction_args(p, q);
  const cl_float4 clamp_box = invariant_box_arg(p);
  const int tw = tiling_.tile_w, th = tiling_.tile_h;
  cl_kernel k = kernel("reaction_implicit");
  set_kernel_args(k, a.buffer, b.buffer, a_out.buffer, b_out.buffer, a.stride, a.origin,
                  region.min.x, region.min.y, region.max.x, region.max.y, tw, th, int(p.model),
                  q[0], q[1], q[2], q[3], q[4], clamp_box, dt,
                  LocalBytes{std::size_t(4 * tw * th) * sizeof(float)});
  enqueue_tiled(k, region);
}

void OpenClKernels::enqueue_tiled(cl_kernel k, Box2 region) {
  const std::size_t groups = groups_for(tiles_of(region, tiling_.tile_w, tiling_.tile_h));
  ctx_.enqueue(k, groups * std::size_t(tiling_.work_group), std::size_t(tiling_.work_group));
}

void OpenClKernels::enqueue_cells(cl_kernel k, Box2 region) {
  // A fixed work-group shape: drivers that specialise code per work-group size (PoCL) compile
  // each kernel once, not once per region size. The kernels skip the cells past the region.
  const std::size_t local[2] = {32, 4};
  const std::size_t global[2] = {(std::size_t(region.width()) + 31) / 32 * 32,
                                 (std::size_t(region.height()) + 3) / 4 * 4};
  opencl_check(
      clEnqueueNDRangeKernel(ctx_.queue(), k, 2, nullptr, global, local, 0, nullptr, nullptr),
      "clEnqueueNDRangeKernel");
}

namespace {
cl_int4 box4(Box2 b) { return {{b.min.x, b.min.y, b.max.x, b.max.y}}; }
}  // namespace

ClAnisotropyArgs cl_anisotropy_args(const AnisotropyParams& p) {
  ClAnisotropyArgs a{};
  a.kind = cl_int(p.kind);
  a.isotropic_value = p.isotropic_value;
  a.a1 = p.a1;
  a.a2 = p.a2;
  a.lobes = p.lobes;
  std::copy(std::begin(p.lobe_speed), std::end(p.lobe_speed), a.lobe_speed);
  a.samples = p.samples;
  std::copy(std::begin(p.sample), std::end(p.sample), a.sample);
  a.theta0 = p.theta0;
  a.gradient_epsilon = p.gradient_epsilon;
  return a;
}
static_assert(sizeof(ClAnisotropyArgs) == 4 * (8 + kMaxLobes + kMaxPolarSamples),
              "ClAnisotropyArgs must match diffusion.cl's aniso_t");

ClStencilOperator ClStencilOperator::allocate(OpenClContext& ctx, Int2 size,
                                              BoundaryKind boundary_x, BoundaryKind boundary_y) {
  ClStencilOperator op;
  op.size = size;
  op.diag = ctx.allocate_like(FieldF(size, 1));
  op.wx = ctx.allocate_like(FieldF(Int2{size.x + 1, size.y}, 1));
  op.wy = ctx.allocate_like(FieldF(Int2{size.x, size.y + 1}, 1));
  op.boundary_x = boundary_x;
  op.boundary_y = boundary_y;
  return op;
}

void ClStencilOperator::upload(OpenClContext& ctx, const StencilOperator& op) {
  ARDCELL_CHECK(op.size == size && op.boundary_x == boundary_x && op.boundary_y == boundary_y,
                "device operator: size or boundaries differ from the host operator's");
  ctx.upload(op.diag, diag);
  ctx.upload(op.wx, wx);
  ctx.upload(op.wy, wy);
}

void ClReactionTable::upload(OpenClContext& ctx, const ReactionTableView& table) {
  ARDCELL_CHECK(table.data && table.n >= 2, "reaction table: empty table");
  const std::size_t bytes = std::size_t(table.n) * std::size_t(table.n) * 2 * sizeof(float);
  if (!data || data.bytes() != bytes) data = ctx.allocate(bytes);
  ctx.write(data, table.data, bytes);
  n = table.n;
  a_lo = table.a_lo;
  a_hi = table.a_hi;
  b_lo = table.b_lo;
  b_hi = table.b_hi;
}

void OpenClKernels::reaction_table(const DeviceField& a, const DeviceField& b, DeviceField& a_out,
                                   DeviceField& b_out, Box2 region, const ClReactionTable& table) {
  check_same_layout(a, b, a_out, b_out);
  ARDCELL_CHECK(table.data && table.n >= 2, "reaction table: not uploaded");
  if (region.empty()) return;
  const cl_float4 range = {{table.a_lo, table.a_hi, table.b_lo, table.b_hi}};
  cl_kernel k = kernel("reaction_table");
  set_kernel_args(k, a.buffer, b.buffer, a_out.buffer, b_out.buffer, a.stride, a.origin,
                  box4(region), table.data, table.n, range);
  enqueue_cells(k, region);
}

void OpenClKernels::conductivity(const DeviceField& a, const DeviceField* theta0, DeviceField& k,
                                 Box2 region, const AnisotropyParams& p) {
  check_same_layout(a, k);
  if (theta0) check_same_layout(a, *theta0);
  ARDCELL_CHECK(a.with_halo().contains(region.grown(1)), "conductivity reads halo 1 of A");
  if (region.empty()) return;
  const ClAnisotropyArgs args = cl_anisotropy_args(p);
  cl_kernel kk = kernel("conductivity");
  set_kernel_args(kk, a.buffer, theta0 ? theta0->buffer : a.buffer, int(theta0 != nullptr),
                  k.buffer, a.stride, a.origin, box4(region), ByValue<ClAnisotropyArgs>{args});
  enqueue_cells(kk, region);
}

void OpenClKernels::check_operator_layout(const ClStencilOperator& op, const DeviceField& f) const {
  check_same_layout(op.diag, f);
}

void OpenClKernels::assemble_stencil_operator(ClStencilOperator& op, float identity, float scale,
                                              const DeviceField* conductivity,
                                              const DeviceField* solid) {
  if (conductivity) check_operator_layout(op, *conductivity);
  if (solid) check_operator_layout(op, *solid);
  const DeviceField& k = conductivity ? *conductivity : op.diag;  // unread without conductivity
  const DeviceField& m = solid ? *solid : op.diag;                // unread without a mask
  cl_kernel kk = kernel("stencil_assemble");
  set_kernel_args(kk, k.buffer, int(conductivity != nullptr), k.stride, k.origin, m.buffer,
                  int(solid != nullptr), op.diag, op.wx, op.wy, op.size.x, op.size.y,
                  int(op.boundary_x), int(op.boundary_y), identity, scale);
  enqueue_cells(kk, Box2{{0, 0}, {op.size.x + 1, op.size.y + 1}});
}

namespace {
int periodic_x(const ClStencilOperator& op) {
  return int(op.boundary_x == BoundaryKind::kPeriodic);
}
int periodic_y(const ClStencilOperator& op) {
  return int(op.boundary_y == BoundaryKind::kPeriodic);
}
}  // namespace

void OpenClKernels::stencil_jacobi_sweep(const ClStencilOperator& op, const DeviceField& b,
                                         const DeviceField& x_in, DeviceField& x_out) {
  check_operator_layout(op, b);
  check_operator_layout(op, x_in);
  check_operator_layout(op, x_out);
  ARDCELL_CHECK(x_in.buffer.get() != x_out.buffer.get(), "stencil Jacobi: x_out aliases x_in");
  cl_kernel k = kernel("stencil_jacobi");
  set_kernel_args(k, op.diag, op.wx, op.wy, b.buffer, x_in.buffer, x_out.buffer, op.size.x,
                  op.size.y, periodic_x(op), periodic_y(op));
  enqueue_cells(k, box_of_size(op.size));
}

void OpenClKernels::stencil_rbgs_half_sweep(const ClStencilOperator& op, const DeviceField& b,
                                            DeviceField& x, int color) {
  check_operator_layout(op, b);
  check_operator_layout(op, x);
  // On a periodic axis of odd length the C++ order makes the last column (row) read the new
  // first one: extra phases keep that order (diffusion.cl).
  const int late_x = periodic_x(op) && op.size.x % 2 == 1 && op.size.x > 1;
  const int late_y = periodic_y(op) && op.size.y % 2 == 1 && op.size.y > 1;
  cl_kernel k = kernel("stencil_rbgs_half");
  for (int phase = 0; phase <= late_x + late_y; ++phase) {
    set_kernel_args(k, op.diag, op.wx, op.wy, b.buffer, x.buffer, op.size.x, op.size.y,
                    periodic_x(op), periodic_y(op), color, late_x, late_y, phase);
    enqueue_cells(k, box_of_size(op.size));
  }
}

void OpenClKernels::apply_stencil_operator(const ClStencilOperator& op, const DeviceField& x,
                                           DeviceField& y) {
  check_operator_layout(op, x);
  check_operator_layout(op, y);
  ARDCELL_CHECK(x.buffer.get() != y.buffer.get(), "apply: y aliases x");
  cl_kernel k = kernel("stencil_apply");
  set_kernel_args(k, op.diag, op.wx, op.wy, x.buffer, y.buffer, op.size.x, op.size.y,
                  periodic_x(op), periodic_y(op));
  enqueue_cells(k, box_of_size(op.size));
}

void OpenClKernels::stencil_rbgs_sweeps_one_group(const ClStencilOperator& op, const DeviceField& b,
                                                  DeviceField& x, int sweeps) {
  check_operator_layout(op, b);
  check_operator_layout(op, x);
  if (sweeps <= 0 || op.size.x <= 0 || op.size.y <= 0) return;
  const int late_x = periodic_x(op) && op.size.x % 2 == 1 && op.size.x > 1;
  const int late_y = periodic_y(op) && op.size.y % 2 == 1 && op.size.y > 1;
  cl_kernel k = kernel("mg_rbgs_sweeps_one_group");
  set_kernel_args(k, op.diag, op.wx, op.wy, b.buffer, x.buffer, op.size.x, op.size.y,
                  periodic_x(op), periodic_y(op), late_x, late_y, sweeps);
  // One fixed group size (PoCL compiles a kernel per size); each work-item strides over cells.
  const std::size_t group = std::min<std::size_t>(64, ctx_.device().max_work_group_size);
  ctx_.enqueue(k, group, group);
}

void OpenClKernels::restrict_sum(const DeviceField& fine, DeviceField& coarse) {
  ARDCELL_CHECK(coarse.size.x == (fine.size.x + 1) / 2 && coarse.size.y == (fine.size.y + 1) / 2,
                "restrict_sum: the coarse grid must be half the fine one, rounded up");
  if (coarse.interior().empty()) return;
  cl_kernel k = kernel("mg_restrict_sum");
  set_kernel_args(k, fine, fine.size.x, fine.size.y, coarse, coarse.size.x, coarse.size.y);
  enqueue_cells(k, coarse.interior());
}

void OpenClKernels::prolong_add(const DeviceField& coarse, DeviceField& fine) {
  ARDCELL_CHECK(coarse.size.x == (fine.size.x + 1) / 2 && coarse.size.y == (fine.size.y + 1) / 2,
                "prolong_add: the coarse grid must be half the fine one, rounded up");
  if (fine.interior().empty()) return;
  cl_kernel k = kernel("mg_prolong_add");
  set_kernel_args(k, coarse, fine, fine.size.x, fine.size.y);
  enqueue_cells(k, fine.interior());
}

void OpenClKernels::diffusion_rhs(const DeviceField& field, const DeviceField* ax, DeviceField& rhs,
                                  const DeviceField* conductivity, double g,
                                  const DeviceField* solid) {
  check_same_layout(field, rhs);
  if (ax) check_same_layout(field, *ax);
  if (conductivity) check_same_layout(field, *conductivity);
  if (solid) check_same_layout(field, *solid);
  cl_kernel k = kernel("diffusion_rhs");
  // `real g`: a double where the device has doubles (the C++ multiplies in double).
  const auto set_args = [&](auto g_real) {
    set_kernel_args(k, field.buffer, ax ? ax->buffer : field.buffer, rhs.buffer,
                    conductivity ? conductivity->buffer : field.buffer,
                    int(conductivity != nullptr), solid ? solid->buffer : field.buffer,
                    int(solid != nullptr), field.stride, field.origin, field.size.x, field.size.y,
                    int(ax != nullptr), int(g != 0.0), g_real);
  };
  if (has_fp64())
    set_args(g);
  else
    set_args(float(g));
  enqueue_cells(k, field.interior());
}

void OpenClKernels::fill_boundary(DeviceField& f, const BoundaryFill& fill) {
  const cl_int4 rules = {
      {int(fill.left.rule), int(fill.right.rule), int(fill.bottom.rule), int(fill.top.rule)}};
  const cl_float4 values = {{fill.left.value, fill.right.value, fill.bottom.value, fill.top.value}};
  const int nx = f.size.x, ny = f.size.y;
  if (nx <= 0 || ny <= 0) return;
  cl_kernel k = kernel("fill_boundary");
  set_kernel_args(k, f.buffer, f.stride, f.origin, nx, ny, rules, values);
  const std::size_t wg = std::min<std::size_t>(256, ctx_.device().max_work_group_size);
  ctx_.enqueue(k, wg, wg);
}

void OpenClKernels::stam_jacobi_sweep(const DeviceField& x0, const DeviceField& x_in,
                                      DeviceField& x_out, Box2 region, const StamSweepParams& p) {
  check_same_layout(x0, x_in);
  check_same_layout(x0, x_out);
  ARDCELL_CHECK(x_in.buffer.get() != x_out.buffer.get(), "Jacobi sweep: x_out aliases x_in");
  if (region.empty()) return;
  const int tw = tiling_.tile_w, th = tiling_.tile_h;
  cl_kernel k = kernel("stam_jacobi");
  set_kernel_args(k, x0.buffer, x_in.buffer, x_out.buffer, x0.stride, x0.origin, box4(region), tw,
                  th, box4(x0.with_halo()), p.a, p.inv_c,
                  LocalBytes{std::size_t(4 * (tw + 2) * (th + 2)) * sizeof(float)});
  enqueue_tiled(k, region);
}

void OpenClKernels::stam_jacobi_blocked(const DeviceField& rhs, const DeviceField& x_in,
                                        DeviceField& x_out, int sweeps, const StamSweepParams& p,
                                        const BoundaryFill& fill, Int2 tile) {
  check_same_layout(rhs, x_in);
  check_same_layout(rhs, x_out);
  ARDCELL_CHECK(x_in.buffer.get() != x_out.buffer.get(), "blocked Jacobi: x_out aliases x_in");
  ARDCELL_CHECK(rhs.halo == 1, "blocked Jacobi: fields must have halo 1");
  ARDCELL_CHECK(fill.left.rule != EdgeRule::kPeriodic && fill.right.rule != EdgeRule::kPeriodic &&
                    fill.bottom.rule != EdgeRule::kPeriodic && fill.top.rule != EdgeRule::kPeriodic,
                "blocked Jacobi: periodic edges run sweep by sweep");
  ARDCELL_CHECK(sweeps >= 1, "blocked Jacobi: at least one sweep");
  const cl_int4 rules = {
      {int(fill.left.rule), int(fill.right.rule), int(fill.bottom.rule), int(fill.top.rule)}};
  const cl_float4 values = {{fill.left.value, fill.right.value, fill.bottom.value, fill.top.value}};
  const int tw = tile.x, th = tile.y;
  const std::size_t floats =
      std::size_t(5) * std::size_t(tw + 2 * sweeps) * std::size_t(th + 2 * sweeps);
  cl_kernel k = kernel("stam_jacobi_blocked");
  set_kernel_args(k, rhs.buffer, x_in.buffer, x_out.buffer, rhs.stride, rhs.origin, rhs.size.x,
                  rhs.size.y, tw, th, sweeps, p.a, p.inv_c, rules, values,
                  LocalBytes{floats * sizeof(float)});
  const std::size_t groups = groups_for(tiles_of(rhs.interior(), tw, th));
  ctx_.enqueue(k, groups * std::size_t(tiling_.work_group), std::size_t(tiling_.work_group));
}

Int2 OpenClKernels::blocked_tile(int sweeps) const {
  // The largest tile (width a multiple of 16, height of 4) whose 5 buffers of (tile + 2 sweeps)
  // fit in half the device's local memory, capped at 256 x 64 (diminishing returns); {0, 0}
  // when not even 16 x 4 fits.
  const std::size_t budget = ctx_.device().local_mem_bytes / 2 / (5 * sizeof(float));
  Int2 best{0, 0};
  for (int w = 16; w <= 256; w += 16)
    for (int h = 4; h <= 64; h += 4)
      if (std::size_t(w + 2 * sweeps) * std::size_t(h + 2 * sweeps) <= budget &&
          w * h > best.x * best.y)
        best = {w, h};
  return best;
}

int OpenClKernels::blocked_sweeps(int wanted) const {
  // A residency of k sweeps recomputes a ring of width k around its tile; past the k where the
  // tile's own cells are half of what it computes, more sweeps per load cost more than the
  // loads they save. A GPU's 48 KiB of __local memory holds 4 sweeps of a 16 x 40 tile; PoCL's
  // emulated 1 MiB keeps the Cell's 20.
  for (int k = std::max(1, wanted); k > 1; --k) {
    const Int2 t = blocked_tile(k);
    if (2 * t.x * t.y >= (t.x + 2 * k) * (t.y + 2 * k) && t.x > 0) return k;
  }
  return 1;
}

void OpenClKernels::stam_rbgs_half_sweep(const DeviceField& x0, DeviceField& x, Box2 region,
                                         int color, const StamSweepParams& p) {
  check_same_layout(x0, x);
  if (region.empty()) return;
  const int tw = tiling_.tile_w, th = tiling_.tile_h;
  cl_kernel k = kernel("stam_rbgs_half");
  set_kernel_args(k, x0.buffer, x.buffer, x0.stride, x0.origin, box4(region), tw, th,
                  box4(x0.with_halo()), color, p.a, p.inv_c,
                  LocalBytes{std::size_t(4 * (tw + 2) * (th + 2)) * sizeof(float)});
  enqueue_tiled(k, region);
}

void OpenClKernels::pressure_rhs(const DeviceField& u, const DeviceField& v, DeviceField& rhs,
                                 Box2 region, const ProjectParams& p) {
  check_same_layout(u, v);
  check_same_layout(u, rhs);
  if (region.empty()) return;
  const int tw = tiling_.tile_w, th = tiling_.tile_h;
  const float k = -0.5f * p.h;
  cl_kernel kk = kernel("pressure_rhs");
  set_kernel_args(kk, u.buffer, v.buffer, rhs.buffer, u.stride, u.origin, box4(region), tw, th,
                  box4(u.with_halo()), k,
                  LocalBytes{std::size_t(4 * (tw + 2) * (th + 2)) * sizeof(float)});
  enqueue_tiled(kk, region);
}

void OpenClKernels::pressure_rhs_cut(const DeviceField& u, const DeviceField& v,
                                     const DeviceField& open_x, const DeviceField& open_y,
                                     DeviceField& rhs, Box2 region, const ProjectParams& p) {
  check_same_layout(u, v);
  check_same_layout(u, rhs);
  if (region.empty()) return;
  ARDCELL_CHECK(u.with_halo().contains(region.grown(1)), "pressure_rhs_cut reads halo 1");
  ARDCELL_CHECK(open_x.with_halo().contains(Box2{region.min, {region.max.x + 1, region.max.y}}) &&
                    open_y.with_halo().contains(Box2{region.min, {region.max.x, region.max.y + 1}}),
                "pressure_rhs_cut: open fractions too small for the region's faces");
  const float k = -0.5f * p.h;
  cl_kernel kk = kernel("pressure_rhs_cut");
  set_kernel_args(kk, u.buffer, v.buffer, rhs.buffer, u.stride, u.origin, open_x, open_y,
                  box4(region), k);
  enqueue_cells(kk, region);
}

void OpenClKernels::subtract_gradient(const DeviceField& p, DeviceField& u, DeviceField& v,
                                      Box2 region, const ProjectParams& params) {
  check_same_layout(p, u);
  check_same_layout(p, v);
  if (region.empty()) return;
  const int tw = tiling_.tile_w, th = tiling_.tile_h;
  const float k = 0.5f / params.h;
  cl_kernel kk = kernel("subtract_gradient");
  set_kernel_args(kk, p.buffer, u.buffer, v.buffer, p.stride, p.origin, box4(region), tw, th,
                  box4(p.with_halo()), k,
                  LocalBytes{std::size_t(2 * (tw + 2) * (th + 2)) * sizeof(float)});
  enqueue_tiled(kk, region);
}

void OpenClKernels::advect_scalar(const DeviceField& q0, const DeviceField& u, const DeviceField& v,
                                  DeviceField& q, Box2 region, const AdvectParams& p) {
  check_same_layout(q0, u);
  check_same_layout(q0, v);
  check_same_layout(q0, q);
  ARDCELL_CHECK(q.buffer.get() != q0.buffer.get(), "advect: q aliases q0");
  if (region.empty()) return;
  const Box2 view = q0.with_halo();
  ARDCELL_CHECK(view.width() >= 2 && view.height() >= 2, "advect: source view too small");
  cl_kernel k = kernel("advect_scalar");
  const cl_int2 domain = {{p.domain.x, p.domain.y}};
  set_kernel_args(k, q0.buffer, u.buffer, v.buffer, q.buffer, q0.stride, q0.origin, box4(region),
                  box4(view), domain, int(p.periodic), p.dt_over_h);
  enqueue_cells(k, region);
}

void OpenClKernels::advect_scalar3(const DeviceField& q0a, const DeviceField& q0b,
                                   const DeviceField& q0c, const DeviceField& u,
                                   const DeviceField& v, DeviceField& qa, DeviceField& qb,
                                   DeviceField& qc, Box2 region, const AdvectParams& p) {
  for (const DeviceField* f :
       std::initializer_list<const DeviceField*>{&q0b, &q0c, &u, &v, &qa, &qb, &qc})
    check_same_layout(q0a, *f);
  for (const DeviceField* out : std::initializer_list<const DeviceField*>{&qa, &qb, &qc})
    for (const DeviceField* in :
         std::initializer_list<const DeviceField*>{&q0a, &q0b, &q0c, &u, &v})
      ARDCELL_CHECK(out->buffer.get() != in->buffer.get(), "advect: an output aliases an input");
  if (region.empty()) return;
  const Box2 view = q0a.with_halo();
  ARDCELL_CHECK(view.width() >= 2 && view.height() >= 2, "advect: source view too small");
  cl_kernel k = kernel("advect_scalar3");
  const cl_int2 domain = {{p.domain.x, p.domain.y}};
  set_kernel_args(k, q0a.buffer, q0b.buffer, q0c.buffer, u.buffer, v.buffer, qa.buffer, qb.buffer,
                  qc.buffer, q0a.stride, q0a.origin, box4(region), box4(view), domain,
                  int(p.periodic), p.dt_over_h);
  enqueue_cells(k, region);
}

void OpenClKernels::advect_velocity(const DeviceField& u0, const DeviceField& v0, DeviceField& u,
                                    DeviceField& v, Box2 region, const AdvectParams& p) {
  check_same_layout(u0, v0);
  check_same_layout(u0, u);
  check_same_layout(u0, v);
  ARDCELL_CHECK(u.buffer.get() != u0.buffer.get() && v.buffer.get() != v0.buffer.get(),
                "advect: outputs alias inputs");
  if (region.empty()) return;
  const Box2 view = u0.with_halo();
  cl_kernel k = kernel("advect_velocity");
  const cl_int2 domain = {{p.domain.x, p.domain.y}};
  set_kernel_args(k, u0.buffer, v0.buffer, u.buffer, v.buffer, u0.stride, u0.origin, box4(region),
                  box4(view), domain, int(p.periodic), p.dt_over_h);
  enqueue_cells(k, region);
}

void OpenClKernels::add_scaled(const DeviceField& s, DeviceField& x, Box2 region, float scale) {
  check_same_layout(s, x);
  if (region.empty()) return;
  cl_kernel k = kernel("add_scaled");
  set_kernel_args(k, s.buffer, x.buffer, s.stride, s.origin, box4(region), scale);
  enqueue_cells(k, region);
}

void OpenClKernels::add_splat(DeviceField& f, Box2 region, const SplatParams& splat) {
  if (!(splat.radius > 0.0f)) return;
  const float reach = 3.0f * splat.radius;
  const Box2 near{{int(std::floor(splat.cx - reach)), int(std::floor(splat.cy - reach))},
                  {int(std::ceil(splat.cx + reach)) + 1, int(std::ceil(splat.cy + reach)) + 1}};
  const Box2 r = region.intersected(near);
  if (r.empty()) return;
  const float inv_r2 = 1.0f / (splat.radius * splat.radius);
  cl_kernel k = kernel("add_splat");
  set_kernel_args(k, f.buffer, f.stride, f.origin, box4(r), splat.cx, splat.cy, inv_r2,
                  splat.amount);
  enqueue_cells(k, r);
}

void OpenClKernels::set_inflow_stripes(DeviceField& dye, int stripes, BoundarySide side) {
  const int nx = dye.size.x, ny = dye.size.y;
  if (nx <= 0 || ny <= 0) return;
  const bool column = side == BoundarySide::kLeft || side == BoundarySide::kRight;
  cl_kernel k = kernel("set_inflow_stripes");
  set_kernel_args(k, dye.buffer, dye.stride, dye.origin, nx, ny, stripes, int(side));
  enqueue_cells(k, Box2{{0, 0}, {column ? ny : nx, 1}});
}

// ---- The frame's remaining fluid twins ---------------------------------------------------------

DeviceField upload_mask(OpenClContext& ctx, const Field<uint8_t>& mask) {
  FieldF host(mask.size(), 1);
  const Box2 b = mask.with_halo().intersected(host.with_halo());
  for (int y = b.min.y; y < b.max.y; ++y)
    for (int x = b.min.x; x < b.max.x; ++x) host(x, y) = mask(x, y) ? 1.0f : 0.0f;
  DeviceField dev = ctx.allocate_like(host);
  ctx.upload(host, dev);
  return dev;
}

void OpenClKernels::face_velocities(const DeviceField& u, const DeviceField& v,
                                    const DeviceField& p, DeviceField& uf, DeviceField& vf,
                                    Box2 region, const ProjectParams& params) {
  check_same_layout(u, v);
  check_same_layout(u, p);
  if (region.empty()) return;
  ARDCELL_CHECK(u.with_halo().contains(region.grown(1)), "face_velocities reads halo 1");
  ARDCELL_CHECK(uf.with_halo().contains(Box2{region.min, {region.max.x + 1, region.max.y}}) &&
                    vf.with_halo().contains(Box2{region.min, {region.max.x, region.max.y + 1}}),
                "face_velocities: uf or vf too small for the region's faces");
  const float inv_h = 1.0f / params.h;
  cl_kernel k = kernel("face_velocities");
  set_kernel_args(k, u.buffer, v.buffer, p.buffer, u.stride, u.origin, uf, vf, box4(region), inv_h);
  enqueue_cells(k, Box2{region.min, {region.max.x + 1, region.max.y + 1}});
}

void OpenClKernels::advect_scalar_mac(const DeviceField& q0, const DeviceField& uf,
                                      const DeviceField& vf, DeviceField& q, Box2 region,
                                      const AdvectParams& p) {
  check_same_layout(q0, q);
  ARDCELL_CHECK(q.buffer.get() != q0.buffer.get(), "advect: q aliases q0");
  if (region.empty()) return;
  const Box2 view = q0.with_halo();
  ARDCELL_CHECK(view.width() >= 2 && view.height() >= 2, "advect: source view too small");
  ARDCELL_CHECK(uf.with_halo().contains(Box2{region.min, {region.max.x + 1, region.max.y}}) &&
                    vf.with_halo().contains(Box2{region.min, {region.max.x, region.max.y + 1}}),
                "advect_scalar_mac: uf or vf do not hold the region's faces");
  cl_kernel k = kernel("advect_scalar_mac");
  const cl_int2 domain = {{p.domain.x, p.domain.y}};
  set_kernel_args(k, q0.buffer, q.buffer, q0.stride, q0.origin, uf, vf, box4(region), box4(view),
                  box4(uf.with_halo()), box4(vf.with_halo()), domain, int(p.periodic), p.dt_over_h);
  enqueue_cells(k, region);
}

void OpenClKernels::maccormack_correct(const DeviceField& q0, const DeviceField& q_hat,
                                       const DeviceField& q_back, const DeviceField& u,
                                       const DeviceField& v, DeviceField& q, Box2 region,
                                       const AdvectParams& p, bool mac) {
  check_same_layout(q0, q);
  check_same_layout(q0, q_hat);
  check_same_layout(q0, q_back);
  ARDCELL_CHECK(q.buffer.get() != q0.buffer.get() && q.buffer.get() != q_back.buffer.get(),
                "maccormack_correct: q aliases q0 or q_back");
  if (region.empty()) return;
  const Box2 view = q0.with_halo();
  ARDCELL_CHECK(view.width() >= 2 && view.height() >= 2, "advect: source view too small");
  const cl_int2 domain = {{p.domain.x, p.domain.y}};
  if (mac) {
    ARDCELL_CHECK(u.with_halo().contains(Box2{region.min, {region.max.x + 1, region.max.y}}) &&
                      v.with_halo().contains(Box2{region.min, {region.max.x, region.max.y + 1}}),
                  "maccormack_correct: uf or vf do not hold the region's faces");
    cl_kernel k = kernel("maccormack_correct_mac");
    set_kernel_args(k, q0.buffer, q_hat.buffer, q_back.buffer, q.buffer, q0.stride, q0.origin, u, v,
                    box4(region), box4(view), box4(u.with_halo()), box4(v.with_halo()), domain,
                    int(p.periodic), p.dt_over_h);
    enqueue_cells(k, region);
    return;
  }
  check_same_layout(q0, u);
  check_same_layout(q0, v);
  cl_kernel k = kernel("maccormack_correct");
  set_kernel_args(k, q0.buffer, q_hat.buffer, q_back.buffer, u.buffer, v.buffer, q.buffer,
                  q0.stride, q0.origin, box4(region), box4(view), domain, int(p.periodic),
                  p.dt_over_h);
  enqueue_cells(k, region);
}

void OpenClKernels::fill_obstacle(DeviceField& f, const DeviceField& solid, Box2 region,
                                  ObstacleRule rule) {
  check_same_layout(f, solid);
  if (region.empty()) return;
  ARDCELL_CHECK(f.with_halo().contains(region.grown(1)),
                "fill_obstacle: fields must hold the region grown by 1");
  cl_kernel k = kernel("fill_obstacle");
  set_kernel_args(k, f.buffer, solid.buffer, f.stride, f.origin, box4(region), int(rule));
  enqueue_cells(k, region);
}

void OpenClKernels::copy_field(const DeviceField& from, DeviceField& to) {
  check_same_layout(from, to);
  ARDCELL_CHECK(from.buffer.bytes() == to.buffer.bytes(), "copy_field: allocations differ");
  if (from.buffer.get() == to.buffer.get() || from.buffer.bytes() == 0) return;
  opencl_check(clEnqueueCopyBuffer(ctx_.queue(), from.buffer.get(), to.buffer.get(), 0, 0,
                                   from.buffer.bytes(), 0, nullptr, nullptr),
               "clEnqueueCopyBuffer");
}

void OpenClKernels::fill_field(DeviceField& f, float value) {
  if (f.buffer.bytes() == 0) return;
  opencl_check(clEnqueueFillBuffer(ctx_.queue(), f.buffer.get(), &value, sizeof(value), 0,
                                   f.buffer.bytes(), 0, nullptr, nullptr),
               "clEnqueueFillBuffer");
}

void OpenClKernels::add_boundary_values(DeviceField& b, const BoundaryFill& fill, double scale) {
  const int nx = b.size.x, ny = b.size.y;
  if (nx <= 0 || ny <= 0) return;
  // The amounts in double, rounded to float once per side, as the C++ does.
  const auto amount = [&](const EdgeFill& e) {
    return float(boundary_rule_factor(e) * scale * e.value);
  };
  const cl_float4 amounts = {
      {amount(fill.left), amount(fill.right), amount(fill.bottom), amount(fill.top)}};
  if (amounts.s[0] == 0.0f && amounts.s[1] == 0.0f && amounts.s[2] == 0.0f && amounts.s[3] == 0.0f)
    return;
  const auto parabolic = [](const EdgeFill& e) { return int(e.rule == EdgeRule::kParabolic); };
  const cl_int4 profiles = {
      {parabolic(fill.left), parabolic(fill.right), parabolic(fill.bottom), parabolic(fill.top)}};
  cl_kernel k = kernel("add_boundary_values");
  set_kernel_args(k, b.buffer, b.stride, b.origin, nx, ny, amounts, profiles);
  const std::size_t wg = std::min<std::size_t>(256, ctx_.device().max_work_group_size);
  ctx_.enqueue(k, wg, wg);
}

// ---- Reductions ---------------------------------------------------------------------------------

void ClRowPartials::read(OpenClContext& ctx, int y0, int y1, double* out) const {
  ARDCELL_CHECK(y0 >= 0 && y1 <= rows, "row partials: rows out of range");
  if (y1 <= y0) return;
  const std::size_t n = std::size_t(y1 - y0);
  if (real_bytes == sizeof(double)) {
    opencl_check(clEnqueueReadBuffer(ctx.queue(), data.get(), CL_TRUE, std::size_t(y0) * real_bytes,
                                     n * real_bytes, out + y0, 0, nullptr, nullptr),
                 "clEnqueueReadBuffer");
    return;
  }
  float* f = host_floats.data();
  opencl_check(clEnqueueReadBuffer(ctx.queue(), data.get(), CL_TRUE, std::size_t(y0) * real_bytes,
                                   n * real_bytes, f, 0, nullptr, nullptr),
               "clEnqueueReadBuffer");
  for (std::size_t i = 0; i < n; ++i) out[std::size_t(y0) + i] = double(f[i]);
}

double ClRowPartials::sum(OpenClContext& ctx, int y0, int y1) const {
  if (y1 <= y0) return 0.0;
  read(ctx, y0, y1, host.data());
  return added(y0, y1);
}

double ClRowPartials::added(int y0, int y1) const {
  ARDCELL_CHECK(y0 >= 0 && y1 <= rows, "row partials: rows out of range");
  double total = 0.0;
  for (int y = y0; y < y1; ++y) total += host[std::size_t(y)];
  return total;
}

std::array<double, 2> ClRowPartials::sum_pair(OpenClContext& ctx, int rows_each) const {
  read(ctx, 0, 2 * rows_each, host.data());
  return {added(0, rows_each), added(rows_each, 2 * rows_each)};
}

ClRowPartials OpenClKernels::row_partials(int rows) const {
  ClRowPartials p;
  p.rows = std::max(rows, 0);
  p.real_bytes = real_bytes_;
  p.data = ctx_.allocate(std::size_t(std::max(rows, 1)) * real_bytes_);
  p.host.assign(std::size_t(std::max(rows, 1)), 0.0);
  if (real_bytes_ != sizeof(double)) p.host_floats.assign(std::size_t(std::max(rows, 1)), 0.0f);
  return p;
}

void OpenClKernels::enqueue_rows(cl_kernel k, int y0, int y1) {
  const std::size_t local = 32;
  const std::size_t global = (std::size_t(y1 - y0) + local - 1) / local * local;
  ctx_.enqueue(k, global, local);
}

void OpenClKernels::enqueue_items(cl_kernel k, int n) {
  constexpr std::size_t kGroup = 64;
  ctx_.enqueue(k, (std::size_t(n) + kGroup - 1) / kGroup * kGroup, kGroup);
}

void OpenClKernels::check_partials(const ClRowPartials& partials, int y1) const {
  ARDCELL_CHECK(partials.data && partials.rows >= y1 && partials.real_bytes == real_bytes_,
                "row partials: too few rows, or from another device");
}

// A kernel (f, nx, y0, y1, partials) writing one partial per row of [y0, y1).
void OpenClKernels::row_reduction(const char* name, const DeviceField& f, int y0, int y1,
                                  ClRowPartials& partials) {
  check_partials(partials, y1);
  ARDCELL_CHECK(y0 >= 0 && y1 <= f.size.y, "row reduction: rows outside the field");
  if (y1 <= y0 || f.size.x <= 0) return;
  cl_kernel k = kernel(name);
  set_kernel_args(k, f, f.size.x, y0, y1, partials.data);
  enqueue_rows(k, y0, y1);
}

void OpenClKernels::row_sums(const DeviceField& f, int y0, int y1, ClRowPartials& partials) {
  row_reduction("row_sums", f, y0, y1, partials);
}

void OpenClKernels::row_ranges(const DeviceField& f, int y0, int y1, ClRowPartials& sum,
                               ClRowPartials& lo, ClRowPartials& hi) {
  check_partials(sum, y1);
  check_partials(lo, y1);
  check_partials(hi, y1);
  ARDCELL_CHECK(y0 >= 0 && y1 <= f.size.y, "row_ranges: rows outside the field");
  if (y1 <= y0 || f.size.x <= 0) return;
  cl_kernel k = kernel("row_ranges");
  set_kernel_args(k, f, f.size.x, y0, y1, sum.data, lo.data, hi.data);
  enqueue_rows(k, y0, y1);
}

void OpenClKernels::row_mass_weights(const DeviceField& f, int y0, int y1, float lo, float hi,
                                     ClRowPartials& partials) {
  check_partials(partials, y1);
  ARDCELL_CHECK(y0 >= 0 && y1 <= f.size.y, "row_mass_weights: rows outside the field");
  if (y1 <= y0 || f.size.x <= 0) return;
  cl_kernel k = kernel("row_mass_weights");
  set_kernel_args(k, f, f.size.x, y0, y1, lo, hi, partials.data);
  enqueue_rows(k, y0, y1);
}

void OpenClKernels::row_masked_sums(const DeviceField& f, const DeviceField& mask, int y0, int y1,
                                    ClRowPartials& partials) {
  check_same_layout(f, mask);
  check_partials(partials, y1);
  ARDCELL_CHECK(y0 >= 0 && y1 <= f.size.y, "row_masked_sums: rows outside the field");
  if (y1 <= y0 || f.size.x <= 0) return;
  cl_kernel k = kernel("row_masked_sums");
  set_kernel_args(k, f.buffer, mask.buffer, f.stride, f.origin, f.size.x, y0, y1, partials.data);
  enqueue_rows(k, y0, y1);
}

void OpenClKernels::restore_mass_rows(DeviceField& f, int y0, int y1, double k, float lo,
                                      float hi) {
  ARDCELL_CHECK(y0 >= 0 && y1 <= f.size.y, "restore_mass_rows: rows outside the field");
  const Box2 rows{{0, y0}, {f.size.x, y1}};
  if (rows.empty()) return;
  cl_kernel kk = kernel("restore_mass_rows");
  // `real k`: a double where the device has doubles (the C++ multiplies in double).
  if (real_bytes_ == sizeof(double))
    set_kernel_args(kk, f, box4(rows), k, lo, hi);
  else
    set_kernel_args(kk, f, box4(rows), float(k), lo, hi);
  enqueue_cells(kk, rows);
}

void OpenClKernels::residual(const ClStencilOperator& op, const DeviceField& b,
                             const DeviceField& x, DeviceField* r, ClRowPartials& partials) {
  check_operator_layout(op, b);
  check_operator_layout(op, x);
  if (r) check_operator_layout(op, *r);
  check_partials(partials, op.size.y);
  if (op.size.x <= 0 || op.size.y <= 0) return;
  cl_kernel k = kernel("stencil_residual");
  set_kernel_args(k, op.diag, op.wx, op.wy, b.buffer, x.buffer, r ? r->buffer : b.buffer,
                  int(r != nullptr), op.size.x, op.size.y, periodic_x(op), periodic_y(op), 0,
                  op.size.y, partials.data);
  enqueue_rows(k, 0, op.size.y);
}

void OpenClKernels::row_sums_of_squares(const DeviceField& f, int y0, int y1,
                                        ClRowPartials& partials) {
  row_reduction("row_sums_of_squares", f, y0, y1, partials);
}

void OpenClKernels::subtract_masked(DeviceField& f, const DeviceField& mask, float mean) {
  check_same_layout(f, mask);
  if (f.interior().empty()) return;
  cl_kernel k = kernel("subtract_masked");
  set_kernel_args(k, f.buffer, mask.buffer, f.stride, f.origin, box4(f.interior()), mean);
  enqueue_cells(k, f.interior());
}

// ---- The second-order schemes' per-cell kernels -------------------------------------------------

void OpenClKernels::reaction_trapezoidal(const DeviceField& a, const DeviceField& b,
                                         DeviceField& a_out, DeviceField& b_out, Box2 region,
                                         const ReactionParams& p, float dt) {
  check_same_layout(a, b, a_out, b_out);
  if (region.empty()) return;
  float q[5];
  cl_reaction_args(p, q);
  cl_kernel k = kernel("reaction_trapezoidal");
  set_kernel_args(k, a.buffer, b.buffer, a_out.buffer, b_out.buffer, a.stride, a.origin,
                  box4(region), int(p.model), q[0], q[1], q[2], q[3], q[4], invariant_box_arg(p),
                  dt);
  enqueue_cells(k, region);
}

void OpenClKernels::sbdf_rhs(DeviceField& a, DeviceField& b, DeviceField& a_prev,
                             DeviceField& b_prev, Box2 region, const SbdfRhsParams& p) {
  check_same_layout(a, b, a_prev, b_prev);
  if (region.empty()) return;
  float q[5];
  cl_reaction_args(p.reaction, q);
  cl_kernel k = kernel("sbdf_rhs");
  set_kernel_args(k, a.buffer, b.buffer, a_prev.buffer, b_prev.buffer, a.stride, a.origin,
                  box4(region), int(p.reaction.model), q[0], q[1], q[2], q[3], q[4], p.dt, p.order,
                  int(p.react));
  enqueue_cells(k, region);
}

// ---- Explicit reaction-diffusion ----------------------------------------------------------------

bool OpenClKernels::check_explicit_rd_args(const DeviceField& a, const DeviceField& b,
                                           const DeviceField& a_out, const DeviceField& b_out,
                                           Box2 region) const {
  check_same_layout(a, b, a_out, b_out);
  ARDCELL_CHECK(a_out.buffer.get() != a.buffer.get() && a_out.buffer.get() != b.buffer.get() &&
                    b_out.buffer.get() != a.buffer.get() && b_out.buffer.get() != b.buffer.get(),
                "explicit RD: outputs alias inputs");
  if (region.empty()) return false;
  ARDCELL_CHECK(a.with_halo().contains(region.grown(1)), "explicit RD reads halo 1");
  return true;
}

void OpenClKernels::explicit_rd(const DeviceField& a, const DeviceField& b, DeviceField& a_out,
                                DeviceField& b_out, Box2 region, const ExplicitRdParams& p,
                                bool nine_point) {
  if (!check_explicit_rd_args(a, b, a_out, b_out, region)) return;
  float q[5];
  cl_reaction_args(p.reaction, q);
  cl_kernel k = kernel("explicit_rd");
  set_kernel_args(k, a.buffer, b.buffer, a_out.buffer, b_out.buffer, a.stride, a.origin,
                  box4(region), int(p.reaction.model), q[0], q[1], q[2], q[3], q[4], p.dt,
                  p.diffusion_a, p.diffusion_b, int(nine_point));
  enqueue_cells(k, region);
}

void OpenClKernels::explicit_rd5(const DeviceField& a, const DeviceField& b, DeviceField& a_out,
                                 DeviceField& b_out, Box2 region, const ExplicitRdParams& p) {
  explicit_rd(a, b, a_out, b_out, region, p, false);
}

void OpenClKernels::explicit_rd9(const DeviceField& a, const DeviceField& b, DeviceField& a_out,
                                 DeviceField& b_out, Box2 region, const ExplicitRdParams& p) {
  explicit_rd(a, b, a_out, b_out, region, p, true);
}

void OpenClKernels::gray_scott9_explicit(const DeviceField& a, const DeviceField& b,
                                         DeviceField& a_out, DeviceField& b_out, Box2 region,
                                         const GrayScott9Params& p) {
  if (!check_explicit_rd_args(a, b, a_out, b_out, region)) return;
  // The constants the C++ row kernel folds (kernels/explicit_rd.h).
  const GrayScott9Coeffs c = gray_scott9_coeffs(p);
  cl_kernel k = kernel("gray_scott9_explicit");
  set_kernel_args(k, a.buffer, b.buffer, a_out.buffer, b_out.buffer, a.stride, a.origin,
                  box4(region), c.ca, c.cb, c.pa, c.pb, c.q, c.dt);
  enqueue_cells(k, region);
}

OpenClBuffer OpenClKernels::stencil_groups(const GeneralizedTaps& k) {
  float w[kStencilGroupFloats] = {};
  int at = 0;
  w[at++] = float(k.group_count);
  for (int g = 0; g < k.group_count; ++g) {
    const GeneralizedTaps::Group& group = k.groups[g];
    w[at++] = float(group.count);
    w[at++] = group.weight;
    for (int t = group.first; t < group.first + group.count; ++t) {
      w[at++] = float(k.taps[t].dx);
      w[at++] = float(k.taps[t].dy);
    }
  }
  OpenClBuffer buffer = ctx_.allocate(sizeof(w));
  ctx_.write(buffer, w, sizeof(w));
  return buffer;
}

void OpenClKernels::generalized_rd(const DeviceField& a, const DeviceField& b, DeviceField& a_out,
                                   DeviceField& b_out, const OpenClBuffer& weights,
                                   const GeneralizedRdParams& p) {
  // Layouts and aliasing (the kernel wraps its indices: the halo check holds trivially).
  if (!check_explicit_rd_args(a, b, a_out, b_out, a.interior())) return;
  ARDCELL_CHECK(weights.bytes() == kStencilGroupFloats * sizeof(float),
                "generalized RD: the stencil's groups (stencil_groups)");
  float q[5];
  cl_reaction_args(p.reaction, q);
  cl_kernel k = kernel("generalized_rd");
  const cl_int2 size{{a.size.x, a.size.y}};
  set_kernel_args(k, a.buffer, b.buffer, a_out.buffer, b_out.buffer, a.stride, a.origin, size,
                  weights, int(p.reaction.model), q[0], q[1], q[2], q[3], q[4], p.dt, p.scale_a,
                  p.scale_b, cl_float4{{p.a_lo, p.a_hi, p.b_lo, p.b_hi}}, p.f_step, p.k_step);
  enqueue_cells(k, a.interior());
}

void OpenClKernels::tensor_field_rd(const DeviceField& a, const DeviceField& b, DeviceField& a_out,
                                    DeviceField& b_out, const DeviceField& x_xx,
                                    const DeviceField& x_xy, const DeviceField& y_xy,
                                    const DeviceField& y_yy, const GeneralizedRdParams& p) {
  if (!check_explicit_rd_args(a, b, a_out, b_out, a.interior())) return;
  for (const DeviceField* f : {&x_xy, &y_xy, &y_yy}) check_same_layout(x_xx, *f);
  ARDCELL_CHECK(x_xx.size == a.size && x_xx.halo == 0,
                "tensor-field RD: the face fields are the grid's size, halo 0");
  float q[5];
  cl_reaction_args(p.reaction, q);
  cl_kernel k = kernel("tensor_field_rd");
  const cl_int2 size{{a.size.x, a.size.y}};
  set_kernel_args(k, a.buffer, b.buffer, a_out.buffer, b_out.buffer, a.stride, a.origin, size,
                  x_xx.buffer, x_xy.buffer, y_xy.buffer, y_yy.buffer, x_xx.stride,
                  int(p.reaction.model), q[0], q[1], q[2], q[3], q[4], p.dt, p.scale_a, p.scale_b,
                  cl_float4{{p.a_lo, p.a_hi, p.b_lo, p.b_hi}}, p.f_step, p.k_step);
  enqueue_cells(k, a.interior());
}

}  // namespace ardcell
#endif
