#pragma once
// Engine: runs one scene. Owns the simulation state and the solvers, built once from a
// SceneConfig; step() advances one frame (fluid step, then the RD step when the scene has RD)
// and does no heap allocation once the first frame has run.
#include <memory>

#include "host/scene_config.h"
#include "host/sim_state.h"

namespace ardcell {

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

  SimState& state() { return state_; }
  const SimState& state() const { return state_; }
  const SceneConfig& config() const { return config_; }

 private:
  struct Solvers;  // the fluid and RD solvers and their scratch (host/engine.cpp)
  SceneConfig config_;
  SimState state_;
  std::unique_ptr<Solvers> solvers_;
};

}  // namespace ardcell
