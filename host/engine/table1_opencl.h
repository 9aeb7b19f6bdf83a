#pragma once
// The Table 1 workload (host/engine/table1.h) expressed for the OpenCL frame (kernels/cl/
// opencl_stam_frame.h): the same constants and splats, and the serial workload's initial state
// uploaded to the device. Shared by bench/table1_opencl_bench.cpp, drivers/cli_run.cpp and
// tests/host/opencl_table1_test.cpp.
#if defined(ARDCELL_WITH_OPENCL)
#include <algorithm>
#include <cmath>

#include "host/engine/table1.h"
#include "kernels/cl/opencl_stam_frame.h"

namespace ardcell {

// Four Gaussian splats at the quarter points whose forces turn slowly with the frame number:
// host/engine/table1.cpp's sources, value for value.
inline SplatParams table1_cl_splat(Int2 grid, int component, int i, std::int64_t frame) {
  constexpr float kPi = 3.14159265358979f;
  const float cx = (i == 0 || i == 3) ? 0.25f : 0.75f;
  const float cy = (i < 2) ? 0.25f : 0.75f;
  const float angle = 0.05f * float(frame) + float(i) * 0.5f * kPi + 0.25f * kPi;
  SplatParams s;
  s.cx = cx * float(grid.x);
  s.cy = cy * float(grid.y);
  s.radius = std::max(1.0f, float(std::min(grid.x, grid.y)) / 32.0f);
  const float force = 0.1f, dye = 0.1f;
  s.amount = component == 0   ? force * std::cos(angle)
             : component == 1 ? force * std::sin(angle)
                              : dye;
  return s;
}

// host/engine/table1.cpp's parameters for a grid (h = 1 / grid.x).
inline ClStamFrameParams table1_cl_params(Int2 grid, bool rd) {
  using C = Table1Constants;
  ClStamFrameParams p;
  p.grid = grid;
  p.rd = rd;
  p.sweeps = C::kSweeps;
  const float n = float(grid.x);
  const float dt = C::kDt;
  const auto diffusion = [](float a) { return StamSweepParams{a, 1.0f / (1.0f + 4.0f * a)}; };
  p.viscosity = diffusion(dt * C::kViscosity * n * n);
  p.dye_diffusion = diffusion(dt * C::kDyeDiffusion * n * n);
  p.pressure = StamSweepParams{1.0f, 0.25f};
  p.rd_a = diffusion(C::kRdStep * C::kDiffA);
  p.rd_b = diffusion(C::kRdStep * C::kDiffB);
  p.project = ProjectParams{1.0f / n};
  p.advect = AdvectParams{dt * n, grid, false};
  p.reaction = GrayScottImplicitParams{C::kGrayScottF, C::kGrayScottK, C::kRdStep};
  p.splats = C::kSplats;
  p.splat = &table1_cl_splat;
  return p;
}

// Uploads a workload's current fields (its initial conditions after construction or reset).
inline void table1_cl_upload(const Table1Workload& w, OpenClStamFrame& frame) {
  frame.upload(ClField::kU, w.u());
  frame.upload(ClField::kV, w.v());
  frame.upload(ClField::kDye, w.dye());
  if (w.options().rd) {
    frame.upload(ClField::kA, w.a());
    frame.upload(ClField::kB, w.b());
  }
  frame.set_frame(w.frame());
}

}  // namespace ardcell
#endif
