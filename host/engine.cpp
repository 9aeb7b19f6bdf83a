#include "host/engine.h"

#include "host/fluid_step.h"

namespace ardcell {

// The solvers of one scene, built once in the constructor.
struct Engine::Solvers {
  std::unique_ptr<FluidStep> fluid;
  // ---- RD (owned by the RD engineer): the RD stepper and its scratch go here. ----
};

Engine::Engine(const SceneConfig& config) : config_(config), solvers_(std::make_unique<Solvers>()) {
  ARDCELL_CHECK(config.size.x > 0 && config.size.y > 0, "Engine: grid size must be positive");
  ARDCELL_CHECK(config.domain_width > 0.0 && config.dt > 0.0,
                "Engine: domain width and dt must be positive");
  state_.size = config_.size;
  state_.h = config_.domain_width / config_.size.x;
  state_.dt = config_.dt;
  solvers_->fluid = make_fluid_step(config_);
  if (config_.fluid.kind != FluidSceneKind::kNone) solvers_->fluid->allocate(state_);
  // ---- RD: allocate A, B, theta0 here (before reset()). ----
  reset();
}

Engine::~Engine() = default;

void Engine::reset() {
  state_.time = 0.0;
  state_.step = 0;
  state_.dt = config_.dt;
  if (config_.fluid.kind != FluidSceneKind::kNone) solvers_->fluid->reset(state_);
  // ---- RD: initial conditions of A, B here. ----
}

void Engine::step() {
  // Fluid first: the RD is advected by this frame's velocity.
  solvers_->fluid->step(state_);
  // ---- RD step goes here (reaction -> anisotropic diffusion -> advection by u, v). ----
  state_.time += state_.dt;
  ++state_.step;
}

}  // namespace ardcell
