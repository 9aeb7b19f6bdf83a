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

}  // namespace

void register_fluid_scenes(SceneRegistry& registry) {
  for (SceneConfig (*make)() : {cavity_scene, obstacle_scene, ink_scene}) {
    const SceneConfig s = make();
    registry.add({s.name, s.description, make});
  }
}

}  // namespace ardcell
