#pragma once
// Parameters of the stable-fluids half of a scene (Stam 1999). Plain data: presets (TOML), the
// CLI and saved states all map onto these fields. Owned by the fluid solver (host/fluid_step.h).
#include <string>

#include "kernels/linear_solver.h"

namespace ardcell {

enum class FluidSceneKind : uint8_t {
  kNone,      // no fluid: RD alone
  kCavity,    // lid-driven cavity (seed 000, Fig. 5)
  kObstacle,  // channel with inflow, outflow and a disc (seed 000, Fig. 6)
  kInk,       // closed or periodic box stirred by sources and forces
};

struct FluidConfig {
  FluidSceneKind kind = FluidSceneKind::kCavity;
  double viscosity = 0.01;      // kinematic; Re = lid_speed * L / viscosity for the cavity
  double lid_speed = 1.0;
  SolverSettings viscosity_solver{SolverKind::kMultigrid, 8, 1e-6};
  SolverSettings pressure_solver{SolverKind::kMultigrid, 20, 1e-8};
  double dye_diffusion = 0.0;
};

}  // namespace ardcell
