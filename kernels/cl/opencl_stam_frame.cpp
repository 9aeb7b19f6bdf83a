#if defined(ARDCELL_WITH_OPENCL)
#include "kernels/cl/opencl_stam_frame.h"

#include <algorithm>

namespace ardcell {

OpenClStamFrame::OpenClStamFrame(OpenClKernels& cl, const ClStamFrameParams& params,
                                 ClSchedule schedule, int sweeps_per_residency)
    : cl_(cl), p_(params), schedule_(schedule), per_residency_(sweeps_per_residency) {
  ARDCELL_CHECK(p_.grid.x >= 2 && p_.grid.y >= 2, "OpenCL frame: grid must be at least 2 x 2");
  ARDCELL_CHECK(per_residency_ >= 1, "OpenCL frame: sweeps per residency must be >= 1");
  per_residency_ = cl_.blocked_sweeps(std::min(per_residency_, std::max(1, p_.sweeps)));
  blocked_tile_ = cl_.blocked_tile(per_residency_);
  ARDCELL_CHECK(blocked_tile_.x > 0, "OpenCL frame: the device's local memory holds no tile");
  const FieldF like(p_.grid, 1);
  OpenClContext& ctx = cl_.context();
  for (DeviceField* f : {&u_, &v_, &dye_, &u0_, &v0_, &u1_, &v1_, &dye0_, &tu_, &tv_, &tdye_, &p0_,
                         &p1_, &pz_, &div_})
    *f = ctx.allocate_like(like);
  if (p_.rd)
    for (DeviceField* f : {&a_, &b_, &a0_, &b0_, &ta_, &tb_}) *f = ctx.allocate_like(like);
  // Every buffer starts at zero (the scratch ones are fully written before being read, but a
  // defined start keeps a download of any of them meaningful).
  const float zero = 0.0f;
  for (DeviceField* f : {&u_,  &v_,  &dye_, &u0_,  &v0_, &u1_, &v1_, &dye0_, &tu_, &tv_, &tdye_,
                         &p0_, &p1_, &pz_,  &div_, &a_,  &b_,  &a0_, &b0_,   &ta_, &tb_})
    if (f->buffer)
      opencl_check(clEnqueueFillBuffer(ctx.queue(), f->buffer.get(), &zero, sizeof zero, 0,
                                       f->buffer.bytes(), 0, nullptr, nullptr),
                   "clEnqueueFillBuffer");
  ctx.finish();
}

DeviceField& OpenClStamFrame::field(ClField which) {
  switch (which) {
    case ClField::kU:
      return u_;
    case ClField::kV:
      return v_;
    case ClField::kDye:
      return dye_;
    case ClField::kA:
      return a_;
    case ClField::kB:
      return b_;
  }
  return u_;
}

void OpenClStamFrame::upload(ClField which, const FieldF& host) {
  DeviceField& f = field(which);
  ARDCELL_CHECK(bool(f.buffer), "OpenCL frame: that field exists only with rd");
  cl_.context().upload(host, f);
}

void OpenClStamFrame::download(ClField which, FieldF& host) {
  DeviceField& f = field(which);
  ARDCELL_CHECK(bool(f.buffer), "OpenCL frame: that field exists only with rd");
  cl_.context().download(f, host);
}

void OpenClStamFrame::fill(DeviceField& f, int stam_b) {
  cl_.fill_boundary(f, BoundaryFill::stam(stam_b));
}

void OpenClStamFrame::solve(const DeviceField& init, const DeviceField& rhs, DeviceField& out,
                            DeviceField& tmp, const StamSweepParams& p, int stam_b) {
  const int total = p_.sweeps;
  const int k = schedule_ == ClSchedule::kBlocked ? per_residency_ : 1;
  const int passes = (total + k - 1) / k;
  const DeviceField* cur = &init;
  for (int j = 1; j <= passes; ++j) {
    const int sweeps = std::min(k, total - (j - 1) * k);
    // The last pass writes `out`; earlier ones alternate so that this holds.
    DeviceField* next = ((passes - j) % 2 == 0) ? &out : &tmp;
    if (schedule_ == ClSchedule::kBlocked) {
      cl_.stam_jacobi_blocked(rhs, *cur, *next, sweeps, p, BoundaryFill::stam(stam_b),
                              blocked_tile_);
    } else {
      cl_.stam_jacobi_sweep(rhs, *cur, *next, rhs.interior(), p);
      fill(*next, stam_b);
    }
    cur = next;
  }
}

void OpenClStamFrame::project(DeviceField& u, DeviceField& v, DeviceField& u_out,
                              DeviceField& v_out) {
  OpenClContext& ctx = cl_.context();
  const Box2 in = u.interior();
  cl_.pressure_rhs(u, v, div_, in, p_.project);
  fill(div_, 0);
  // The solve starts from p = 0 (pz_ stays zero: nothing ever writes it).
  solve(pz_, div_, p0_, p1_, p_.pressure, 0);
  for (auto [from, to] : {std::pair{&u, &u_out}, std::pair{&v, &v_out}})
    opencl_check(clEnqueueCopyBuffer(ctx.queue(), from->buffer.get(), to->buffer.get(), 0, 0,
                                     from->buffer.bytes(), 0, nullptr, nullptr),
                 "clEnqueueCopyBuffer");
  cl_.subtract_gradient(p0_, u_out, v_out, in, p_.project);
  fill(u_out, 1);
  fill(v_out, 2);
}

void OpenClStamFrame::step() {
  const Box2 in = box_of_size(p_.grid);
  // Sources, with the reaction riding along.
  int component = 0;
  for (DeviceField* f : {&u_, &v_, &dye_}) {
    for (int i = 0; i < p_.splats && p_.splat; ++i)
      cl_.add_splat(*f, in, p_.splat(p_.grid, component, i, frame_));
    fill(*f, component == 2 ? 0 : component + 1);
    ++component;
  }
  if (p_.rd) {
    ReactionParams rp;
    rp.model = ReactionModel::kGrayScott;
    rp.F = p_.reaction.F;
    rp.k = p_.reaction.k;
    cl_.reaction_implicit(a_, b_, a_, b_, in, rp, p_.reaction.dt);
    fill(a_, 0);
    fill(b_, 0);
  }
  // vel_step
  solve(u_, u_, u0_, tu_, p_.viscosity, 1);
  solve(v_, v_, v0_, tv_, p_.viscosity, 2);
  project(u0_, v0_, u1_, v1_);
  if (p_.rd) solve(a_, a_, a0_, ta_, p_.rd_a, 0);
  cl_.advect_velocity(u1_, v1_, u0_, v0_, in, p_.advect);
  fill(u0_, 1);
  fill(v0_, 2);
  project(u0_, v0_, u_, v_);
  if (p_.rd) solve(b_, b_, b0_, tb_, p_.rd_b, 0);
  // dens_step, and the chemicals carried by the same velocity.
  solve(dye_, dye_, dye0_, tdye_, p_.dye_diffusion, 0);
  if (p_.rd) {  // one back-trace for the three (as the CPU's advect_fields)
    cl_.advect_scalar3(dye0_, a0_, b0_, u_, v_, dye_, a_, b_, in, p_.advect);
    fill(dye_, 0);
    fill(a_, 0);
    fill(b_, 0);
  } else {
    cl_.advect_scalar(dye0_, u_, v_, dye_, in, p_.advect);
    fill(dye_, 0);
  }
  ++frame_;
}

}  // namespace ardcell
#endif
