#pragma once
// Parameters of the stable-fluids half of a scene (Stam 1999). Plain data: presets (TOML), the
// CLI and saved states all map onto these fields. Owned by the fluid solver
// (host/engine/fluid_step.h). Positions and lengths are in domain units (the domain is domain_width
// wide, y grows upward).
#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "kernels/linear_solver.h"
#include "runtime/boundary.h"

namespace ardcell {

enum class FluidSceneKind : uint8_t {
  kNone,      // no fluid: RD alone
  kCavity,    // lid-driven cavity (seed 000, Fig. 5)
  kObstacle,  // channel with inflow, outflow and a disc (seed 000, Fig. 6)
  kInk,       // closed or periodic box stirred by sources and forces
  kTable1,    // seed 000's Table 1 workload: Stam's box stirred by four turning splats, run as
              // a frame plan (host/engine/table1_plan.h)
};

// The walls of the ink box.
enum class FluidWalls : uint8_t {
  kFreeSlip,  // Stam's set_bnd: normal velocity zero, tangential copied
  kNoSlip,    // both components zero on the walls
  kPeriodic,  // no walls: the box wraps around
};

// A stirring emitter of the ink scene: a Gaussian blob that adds dye and pushes the fluid.
struct FluidEmitter {
  double x = 0.5, y = 0.5;              // centre
  double radius = 0.03;                 // e-folding radius
  double dye_rate = 1.0;                // dye added per unit time at the centre
  double force_x = 0.0, force_y = 0.0;  // acceleration at the centre
  double swirl = 0.0;  // the force direction turns at this rate (rad per unit time)
};

// How the velocity and the dye are carried (kernels/advect.h).
enum class AdvectionScheme : uint8_t {
  kSemiLagrangian,  // Stam's: first order, the interpolation diffuses (seed 000 Eqn 20)
  kMacCormack,      // Selle et al. 2008: a forward and a backward step, limited: second order
};

// The obstacle channel's inflow across its inflow side.
enum class InflowProfile : uint8_t {
  kPlug,       // inflow_speed everywhere on the side
  kParabolic,  // Poiseuille: 6 s (1 - s) times inflow_speed, so inflow_speed is the mean
};

// How the projection sees the obstacle's disc (host/engine/fluid_step.cpp).
enum class ObstacleBoundary : uint8_t {
  kStaircase,  // cells whose centre is inside are solid; their faces are walls
  kCutCell,    // as staircase, and the pressure equation weighs each face by the fraction of
               // its length outside the disc (Batty et al. 2007's variational weights), so the
               // projection sees the circle, not its cells
};

struct FluidConfig {
  FluidSceneKind kind = FluidSceneKind::kCavity;
  double viscosity = 0.01;  // kinematic; Re = lid_speed * L / viscosity for the cavity
  double lid_speed = 1.0;
  SolverSettings viscosity_solver{SolverKind::kMultigrid, 8, 1e-6};
  SolverSettings pressure_solver{SolverKind::kMultigrid, 20, 1e-6};
  double dye_diffusion = 0.0;
  // Semi-Lagrangian advection is not conservative: bilinear interpolation acts as a diffusion
  // whose coefficient varies with the sub-cell position of each departure point, and in a
  // closed box that drifts the total (measured: -1.8% over 1000 steps of the 64^2 cavity, -25%
  // for a small blob in a strong vortex). With conserve_dye, in closed domains (cavity, ink) the
  // mass advection lost or gained is put back after each advection, weighted by
  // (q - min)(max - q) of the field before advection, so advection keeps its total as the
  // continuous equation does and never leaves the range it started from (a global mass fixer
  // in the manner of semi-Lagrangian transport models).
  bool conserve_dye = true;
  AdvectionScheme advection = AdvectionScheme::kSemiLagrangian;

  // obstacle: a channel with inflow through one side (into the domain at inflow_speed, its
  // mean with a parabolic profile), outflow through the opposite side (velocity copied,
  // pressure 0: do-nothing), two walls (low and high across the flow: bottom and top for a
  // channel along x, left and right along y), and a solid disc.
  double inflow_speed = 1.0;
  BoundarySide inflow_side = BoundarySide::kTop;
  InflowProfile inflow_profile = InflowProfile::kPlug;
  FluidWalls wall_low = FluidWalls::kFreeSlip, wall_high = FluidWalls::kFreeSlip;
  double obstacle_x = 0.5, obstacle_y = 1.5, obstacle_radius = 0.08;
  ObstacleBoundary obstacle_boundary = ObstacleBoundary::kStaircase;
  int inflow_dye_stripes = 8;  // dye enters through the inflow in this many stripes
  // Points (x, y pairs, domain units) whose velocity and physical pressure `ardcell run
  // --probe-csv` writes each frame; the first two also give the pressure difference. Unused
  // entries are -1.
  static constexpr int kMaxProbes = 4;
  std::array<float, 2 * kMaxProbes> probes{-1, -1, -1, -1, -1, -1, -1, -1};
  int probe_count() const {
    int n = 0;
    while (n < kMaxProbes && probes[2 * n] >= 0.0f && probes[2 * n + 1] >= 0.0f) ++n;
    return n;
  }

  // ink: walls and emitters.
  FluidWalls walls = FluidWalls::kFreeSlip;
  std::vector<FluidEmitter> emitters;
};

// Reynolds number Re = U L / nu with the scene's characteristic speed and length: the lid speed
// and the cavity width; the inflow speed and the disc diameter; 1 and the box width for ink.
inline double fluid_reference_speed(const FluidConfig& f) {
  switch (f.kind) {
    case FluidSceneKind::kCavity:
      return std::abs(f.lid_speed);
    case FluidSceneKind::kObstacle:
      return std::abs(f.inflow_speed);
    default:
      return 1.0;
  }
}
inline double fluid_reference_length(const FluidConfig& f, double domain_width) {
  return f.kind == FluidSceneKind::kObstacle ? 2.0 * f.obstacle_radius : domain_width;
}
inline double reynolds_number(const FluidConfig& f, double domain_width) {
  return f.viscosity > 0.0
             ? fluid_reference_speed(f) * fluid_reference_length(f, domain_width) / f.viscosity
             : 0.0;
}
// Sets the viscosity so that the scene runs at Reynolds number re (> 0).
inline void set_reynolds_number(FluidConfig& f, double re, double domain_width) {
  f.viscosity = fluid_reference_speed(f) * fluid_reference_length(f, domain_width) / re;
}

// `--solver NAME --sweeps N` for both implicit solves: Jacobi and red-black GS run exactly N
// sweeps (tolerance 0, the real-time mode); ICCG and multigrid stop at a relative residual of
// 1e-6 or after N iterations / V-cycles.
inline void set_fluid_solver(FluidConfig& f, SolverKind kind, int sweeps) {
  const bool fixed = kind == SolverKind::kJacobi || kind == SolverKind::kRedBlackGaussSeidel;
  const SolverSettings s{kind, std::max(1, sweeps), fixed ? 0.0 : 1e-6};
  f.viscosity_solver = s;
  f.pressure_solver = s;
}

}  // namespace ardcell
