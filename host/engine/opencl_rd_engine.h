#pragma once
// A reaction-diffusion-only scene (no fluid) run on an OpenCL device, frame for frame what the
// CPU Engine's RD step does (host/engine/rd_step.h): per RD step the implicit reaction (Eqn 6,
// Newton per cell or the precomputed table), then implicit (anisotropic, Eqns 13 / 17-19) diffusion
// of A and B with the scene's boundary kind and per-cell theta0. A, B, theta0, the conductivity,
// the solver scratch and the reaction table live on the device across frames: step() only
// enqueues kernels; A and B come back on request (download_state), theta0 goes up when painted.
//
// What the device does not do is refused with one line naming the setting (device_problem):
// a fluid, the explicit schemes, ICCG / multigrid diffusion and stopping on a residual. Numerics
// are never changed behind the user's back: a scene set to jacobi or rbgs with tolerance 0
// (fixed sweeps) runs here; the CPU Engine with the same settings agrees within 1e-5.
#if defined(ARDCELL_WITH_OPENCL)
#include <memory>
#include <string>

#include "host/config/scene_config.h"
#include "host/config/status.h"
#include "host/engine/engine.h"
#include "kernels/cl/opencl_diffusion.h"
#include "kernels/cl/opencl_kernels.h"

namespace ardcell {

class OpenClRdEngine {
 public:
  // One line naming the first setting of `scene` that the device path cannot run (and what it
  // expects), or "" when it can. Invalid RD parameters are named too (rd_config_problem).
  static std::string device_problem(const SceneConfig& scene);

  // Allocates the device fields on cl's context (its program is built already: building
  // nothing more) and uploads the scene's initial state. Throws std::invalid_argument with
  // device_problem()'s line. Several engines may share one OpenClKernels in turn (switching
  // presets): none rebuilds a program.
  OpenClRdEngine(OpenClKernels& cl, const SceneConfig& scene);
  ~OpenClRdEngine();
  OpenClRdEngine(const OpenClRdEngine&) = delete;
  OpenClRdEngine& operator=(const OpenClRdEngine&) = delete;

  // Back to the scene's initial conditions (time 0; a painted theta0 is kept), uploaded.
  void reset();
  // Enqueues one frame (rd.steps_per_frame RD steps); returns before the device is done.
  void step();
  // Waits for what step() enqueued.
  void finish();

  // The CPU Engine's update_parameters for this scene (same refusals: structural keys, invalid
  // values), plus device_problem() of `next`: reaction parameters, diffusion rates, anisotropy,
  // rd.dt / cell size / steps per frame, sweeps, dt, initial pattern of the next reset. Kernel
  // arguments only: no program is built; a reaction table is rebuilt and written when the
  // reaction parameters or dt change.
  Status update_parameters(const SceneConfig& next);

  // The host mirror: A, B, theta0, time and step. A and B are current after download_state().
  SimState& host_state() { return shadow_->state(); }
  // Downloads A and B (blocking) into the host mirror and returns it.
  const SimState& download_state();
  // Downloads only the chemical a display shows (false: A, true: B) into the mirror.
  const FieldF& download_chemical(bool b);
  // Uploads the host mirror's theta0 (after painting it) / A, B and theta0 (after loading a
  // saved state or painting chemicals). Blocking.
  void upload_theta0();
  void upload_state();

  const SceneConfig& config() const { return config_; }
  OpenClKernels& kernels() { return cl_; }

 private:
  void rebuild_table();

  OpenClKernels& cl_;
  SceneConfig config_;
  // A CPU Engine of the scene with diffusion off (so no solver is built), never stepped: it
  // validates parameter changes like Engine does, writes the initial state and holds the host
  // mirror of the fields.
  std::unique_ptr<Engine> shadow_;
  DeviceField a_, b_, theta0_, conductivity_;
  std::unique_ptr<OpenClDiffusion> diffuse_a_, diffuse_b_;
  ClReactionTable table_;
  double dt_ = 0, h_ = 0;  // the RD's step and cell size
};

}  // namespace ardcell
#endif
