// The built-in fluid scenes (seed 000, section 7): plain SceneConfig data. Their initial
// conditions are applied by Engine::reset() (host/engine/fluid_step.cpp).
#include "host/scenes/scene_registry.h"

namespace ardcell {

namespace {

SceneConfig cavity_scene() {
  SceneConfig s;
  s.name = "cavity";
  s.description = "lid-driven cavity with dye bands, unit square, lid speed 1, Re 1000 (Fig. 5)";
  s.size = {256, 256};
  s.domain_width = 1.0;
  s.dt = 0.01;
  s.default_steps = 1000;
  s.fluid.kind = FluidSceneKind::kCavity;
  s.fluid.lid_speed = 1.0;
  set_reynolds_number(s.fluid, 1000.0, s.domain_width);
  s.output.show = "dye";
  return s;
}

SceneConfig obstacle_scene() {
  SceneConfig s;
  s.name = "obstacle";
  s.description =
      "channel flow past a disc: inflow at the top, outflow at the bottom, Re 200 (Fig. 6)";
  s.size = {256, 512};
  s.domain_width = 1.0;  // 1 wide, 2 tall
  s.dt = 0.005;
  s.default_steps = 1500;
  s.fluid.kind = FluidSceneKind::kObstacle;
  s.fluid.inflow_speed = 1.0;
  s.fluid.obstacle_x = 0.5;
  s.fluid.obstacle_y = 1.5;
  s.fluid.obstacle_radius = 0.08;
  set_reynolds_number(s.fluid, 200.0, s.domain_width);
  s.output.show = "dye";
  return s;
}

// The DFG benchmark "flow around a cylinder" (Schaefer & Turek 1996): a 2.2 x 0.41 channel,
// parabolic inflow on the left (mean `mean_speed`), no-slip walls, a cylinder of diameter 0.1
// at (0.2, 0.2) (off the centre line by 0.005, which lets 2D-2 shed vortices), nu 1e-3, so
// Re = mean speed x 0.1 / 1e-3. Probes at the cylinder's front and back for the pressure
// difference. 440 x 82 cells: 20 across the cylinder.
SceneConfig dfg_scene(const char* name, const char* description, double mean_speed, double dt,
                      int64_t steps) {
  SceneConfig s;
  s.name = name;
  s.description = description;
  s.size = {440, 82};
  s.domain_width = 2.2;
  s.dt = dt;
  s.default_steps = steps;
  FluidConfig& f = s.fluid;
  f.kind = FluidSceneKind::kObstacle;
  f.inflow_side = BoundarySide::kLeft;
  f.inflow_profile = InflowProfile::kParabolic;
  f.inflow_speed = mean_speed;
  f.wall_low = f.wall_high = FluidWalls::kNoSlip;
  f.obstacle_x = 0.2;
  f.obstacle_y = 0.2;
  f.obstacle_radius = 0.05;
  f.obstacle_boundary = ObstacleBoundary::kCutCell;
  f.viscosity = 1e-3;
  f.advection = AdvectionScheme::kMacCormack;
  f.inflow_dye_stripes = 6;
  f.probes = {0.15f, 0.2f, 0.25f, 0.2f, -1, -1, -1, -1};
  s.output.show = "dye";
  return s;
}

SceneConfig dfg_2d1() {
  return dfg_scene("dfg-2d1",
                   "DFG benchmark 2D-1: steady flow around a cylinder in a channel, Re 20 "
                   "(drag 5.58, lift 0.0106, pressure difference 0.1174)",
                   0.2, 0.01, 1500);
}

SceneConfig dfg_2d2() {
  return dfg_scene("dfg-2d2",
                   "DFG benchmark 2D-2: vortex shedding behind a cylinder in a channel, Re 100 "
                   "(drag max 3.23, lift max 1.00, Strouhal 0.30)",
                   1.0, 0.0025, 4000);
}

SceneConfig ink_scene() {
  SceneConfig s;
  s.name = "ink";
  s.description = "closed box stirred by three swirling ink emitters (the playground)";
  s.size = {256, 256};
  s.domain_width = 1.0;
  s.dt = 0.01;
  s.default_steps = 800;
  s.fluid.kind = FluidSceneKind::kInk;
  s.fluid.viscosity = 1e-4;
  s.fluid.walls = FluidWalls::kFreeSlip;
  // At viscosity 1e-4 the swirls' detail is what semi-Lagrangian advection's interpolation
  // smears first; MacCormack keeps it for about a fifth more time per frame.
  s.fluid.advection = AdvectionScheme::kMacCormack;
  s.fluid.emitters = {
      {0.25, 0.3, 0.03, 2.0, 0.0, 4.0, 0.7},
      {0.75, 0.3, 0.03, 2.0, 0.0, 4.0, -0.9},
      {0.5, 0.75, 0.03, 2.0, 0.0, -4.0, 0.5},
  };
  s.output.show = "dye";
  return s;
}

// seed 000's Table 1 workload (section 7.2; bench/README.md): Stam's stable fluid in a free-slip
// box, 20 Jacobi sweeps a solve, stirred by four turning splats; with `rd`, Gray-Scott riding on
// it (F 0.055, k 0.062, one RD time unit a frame, D_A 1 and D_B 0.5 cells^2 per unit). The
// engine runs it as a frame plan of tile passes (host/engine/table1_plan.h; `--schedule`).
SceneConfig table1_scene(bool rd) {
  SceneConfig s;
  s.name = rd ? "table1-ard" : "table1";
  s.description = rd ? "Table 1 workload (seed 000, 7.2): fluid + Gray-Scott RD riding on it, "
                       "on the frame plan"
                     : "Table 1 workload (seed 000, 7.2): Stam's stable fluid alone, on the frame "
                       "plan";
  s.size = {256, 256};
  s.domain_width = 1.0;
  s.dt = 0.1;
  s.default_steps = 100;
  s.fluid.kind = FluidSceneKind::kTable1;
  s.fluid.viscosity = 1e-4;
  s.fluid.dye_diffusion = 1e-4;
  s.fluid.conserve_dye = false;
  s.fluid.walls = FluidWalls::kFreeSlip;
  s.fluid.viscosity_solver = {SolverKind::kJacobi, 20, 0.0};
  s.fluid.pressure_solver = {SolverKind::kJacobi, 20, 0.0};
  if (rd) {
    s.rd.enabled = true;
    s.rd.reaction.model = ReactionModel::kGrayScott;
    s.rd.reaction.F = 0.055f;
    s.rd.reaction.k = 0.062f;
    s.rd.dt = 1.0;
    s.rd.diffusion_a = 1.0;
    s.rd.diffusion_b = 0.5;
    s.rd.diffusion_solver = {SolverKind::kJacobi, 20, 0.0};
    s.rd.boundary = BoundaryKind::kNeumann;
  }
  s.output.show = "dye";
  return s;
}

SceneConfig table1_fluid() { return table1_scene(false); }
SceneConfig table1_ard() { return table1_scene(true); }

}  // namespace

void register_fluid_scenes(SceneRegistry& registry) {
  for (SceneConfig (*make)() :
       {cavity_scene, obstacle_scene, ink_scene, dfg_2d1, dfg_2d2, table1_fluid, table1_ard}) {
    const SceneConfig s = make();
    registry.add({s.name, s.description, make});
  }
}

}  // namespace ardcell
