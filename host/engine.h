#pragma once
// Engine: runs one scene. Owns the simulation state and the solvers, built once from a
// SceneConfig; step() advances one frame (fluid step, then the RD step when the scene has RD)
// and does no heap allocation once the first frame has run.
#include <memory>

#include "host/scene_config.h"
#include "host/sim_state.h"
#include "host/status.h"

namespace ardcell {

struct RdStepStats;

class Engine {
 public:
  explicit Engine(const SceneConfig& config);
  ~Engine();
  Engine(const Engine&) = delete;
  Engine& operator=(const Engine&) = delete;

  // Back to the scene's initial conditions (time 0, step 0).
  void reset();
  // Advances one frame of config().dt.
  void step();
  // The same frame without the RD stage (fluid, time and step count only): for a caller that
  // advances A and B itself, as the live display does on a coarser RD grid.
  void step_without_rd();

  // Applies the non-structural parameters of `next` from the next frame on, with no reset and
  // no heap allocation: dt, fluid viscosity, lid / inflow speed, dye diffusion, emitters (same
  // count), solver iterations and tolerances, RD reaction parameters (F, k, ...), diffusion
  // rates, anisotropy, RD dt / cell size / steps per frame, initial pattern (used by the next
  // reset), frame count and output. Structural changes (grid size or width, fluid scene, walls,
  // obstacle, solver kinds, RD on/off, model, scheme, boundary, react/diffuse, reaction table)
  // are refused: nothing changes and the message names the first such key and says to rebuild.
  // An invalid RD parameter is refused the same way. (A reaction table, when on, is rebuilt on
  // a change of reaction parameters or dt: the one case that allocates.)
  Status update_parameters(const SceneConfig& next);

  SimState& state() { return state_; }
  const SimState& state() const { return state_; }
  const SceneConfig& config() const { return config_; }
  // What the last RD step's solves did (iterations, residuals); nullptr when the scene has no RD.
  const RdStepStats* rd_stats() const;

 private:
  struct Solvers;  // the fluid and RD solvers and their scratch (host/engine.cpp)
  SceneConfig config_;
  SimState state_;
  std::unique_ptr<Solvers> solvers_;
};

}  // namespace ardcell
