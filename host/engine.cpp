#include "host/engine.h"

#include "host/fluid_step.h"
#include "host/rd_step.h"

namespace ardcell {

// The solvers of one scene, built once in the constructor.
struct Engine::Solvers {
  std::unique_ptr<FluidStep> fluid;
  std::unique_ptr<RdStepper> rd;  // when config.rd.enabled (host/rd_step.h)
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
  if (config_.rd.enabled) {
    // Throws std::invalid_argument with one line naming a bad RD parameter.
    solvers_->rd = std::make_unique<RdStepper>(config_);
    solvers_->rd->init_state(state_);  // allocates A, B, theta0
  }
  reset();
}

Engine::~Engine() = default;

void Engine::reset() {
  state_.time = 0.0;
  state_.step = 0;
  state_.dt = config_.dt;
  if (config_.fluid.kind != FluidSceneKind::kNone) solvers_->fluid->reset(state_);
  if (solvers_->rd) solvers_->rd->init_state(state_);
}

void Engine::step() {
  // Fluid first: the RD is advected by this frame's velocity.
  solvers_->fluid->step(state_);
  // RD: implicit reaction -> anisotropic diffusion -> advection by this frame's u, v.
  if (solvers_->rd) solvers_->rd->step(state_);
  state_.time += state_.dt;
  ++state_.step;
}

}  // namespace ardcell
