#if defined(ARDCELL_WITH_OPENCL)
#include "kernels/cl/opencl_kernels.h"

#include <algorithm>
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
  return ctx.program(OpenClKernels::kProgramKey, sources, "-cl-std=CL1.2", error);
}

int tiles_of(Box2 region, int tw, int th) {
  return ((region.width() + tw - 1) / tw) * ((region.height() + th - 1) / th);
}

}  // namespace

std::unique_ptr<OpenClKernels> OpenClKernels::create(OpenClContext& ctx, std::string* error) {
  cl_program program = build_program(ctx, error);
  if (!program) return nullptr;
  return std::unique_ptr<OpenClKernels>(new OpenClKernels(ctx, program));
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
  check_same_layout(a, b);
  check_same_layout(a, a_out);
  check_same_layout(a, b_out);
  if (region.empty()) return;
  float q[5] = {0, 0, 0, 0, 0};
  switch (p.model) {
    case ReactionModel::kGrayScott:
      q[0] = p.F, q[1] = p.k;
      break;
    case ReactionModel::kTuring:
      q[0] = p.turing_s, q[1] = p.turing_beta;
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
  const ConcentrationBox box = invariant_box(p);
  const cl_float4 clamp_box = {
      {float(box.a_lo), float(box.a_hi), float(box.b_lo), float(box.b_hi)}};
  const int tw = tiling_.tile_w, th = tiling_.tile_h;
  cl_kernel k = kernel("reaction_implicit");
  set_kernel_args(k, a.buffer, b.buffer, a_out.buffer, b_out.buffer, a.stride, a.origin,
                  region.min.x, region.min.y, region.max.x, region.max.y, tw, th, int(p.model),
                  q[0], q[1], q[2], q[3], q[4], clamp_box, dt,
                  LocalBytes{std::size_t(4 * tw * th) * sizeof(float)});
  const std::size_t groups = groups_for(tiles_of(region, tw, th));
  ctx_.enqueue(k, groups * std::size_t(tiling_.work_group), std::size_t(tiling_.work_group));
}

}  // namespace ardcell
#endif
