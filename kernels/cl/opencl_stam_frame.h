#pragma once
// The Table 1 frame (host/engine/table1_plan.h: Stam's stable fluid, optionally with Gray-Scott RD
// riding on it) on an OpenCL device, with every field resident in device memory across frames: a
// frame enqueues kernels only (no allocation, no read-back); download() reads a field when one
// is asked for. The stages and their order are those of Table1Plan's serial schedule, so
// the fields agree with it (tests/host/engine/opencl_table1_test.cpp):
//   sources (+ reaction) -> diffuse u, v -> project (+ A's diffusion) -> advect u, v ->
//   project (+ B's diffusion) -> diffuse dye -> advect dye (+ A, B).
// Two schedules of the same kernels:
//   stream  - every Jacobi sweep is one tiled launch (work-groups walk tiles double-buffered in
//             __local memory) followed by a boundary fill;
//   blocked - each solve runs `sweeps_per_residency` sweeps per tile load (ghost-zone temporal
//             blocking in __local memory, boundary refilled in place).
// Parameters live in params() and are passed as kernel arguments on every launch: changing one
// between frames rebuilds nothing.
#if defined(ARDCELL_WITH_OPENCL)
#include <cstdint>

#include "kernels/cl/opencl_kernels.h"

namespace ardcell {

enum class ClSchedule : uint8_t { kStream, kBlocked };

struct ClStamFrameParams {
  Int2 grid{};
  bool rd = false;
  int sweeps = 20;  // Jacobi sweeps per solve
  StamSweepParams viscosity, dye_diffusion, pressure, rd_a, rd_b;
  ProjectParams project;
  AdvectParams advect;
  GrayScottImplicitParams reaction;
  // Splat i (0 .. splats-1) of a component (0 u, 1 v, 2 dye) at a frame number.
  int splats = 0;
  SplatParams (*splat)(Int2 grid, int component, int i, std::int64_t frame) = nullptr;
};

enum class ClField : uint8_t { kU, kV, kDye, kA, kB };

class OpenClStamFrame {
 public:
  OpenClStamFrame(OpenClKernels& cl, const ClStamFrameParams& params, ClSchedule schedule,
                  int sweeps_per_residency = 20);

  // Sets a field's whole allocation (initial conditions); the layout must be grid, halo 1.
  void upload(ClField which, const FieldF& host);
  void download(ClField which, FieldF& host);
  // Enqueues one frame.
  void step();
  void finish() { cl_.context().finish(); }

  std::int64_t frame() const { return frame_; }
  void set_frame(std::int64_t f) { frame_ = f; }
  ClStamFrameParams& params() { return p_; }
  ClSchedule schedule() const { return schedule_; }

 private:
  DeviceField& field(ClField which);
  void fill(DeviceField& f, int stam_b);
  // `sweeps` Jacobi sweeps from init with right-hand side rhs, result in out; tmp is scratch.
  // init may equal rhs, never out or tmp.
  void solve(const DeviceField& init, const DeviceField& rhs, DeviceField& out, DeviceField& tmp,
             const StamSweepParams& p, int stam_b);
  void project(DeviceField& u, DeviceField& v, DeviceField& u_out, DeviceField& v_out);

  OpenClKernels& cl_;
  ClStamFrameParams p_;
  ClSchedule schedule_;
  int per_residency_;
  Int2 blocked_tile_{};
  std::int64_t frame_ = 0;
  DeviceField u_, v_, dye_, u0_, v0_, u1_, v1_, dye0_, tu_, tv_, tdye_, p0_, p1_, pz_, div_;
  DeviceField a_, b_, a0_, b0_, ta_, tb_;
};

}  // namespace ardcell
#endif
