#pragma once
// A scene is plain data: grid, time step, the fluid and RD parameters, initial conditions and
// how frames look. Built-in scenes (host/scenes/scene_registry.h) and TOML presets both produce
// one; the Engine (host/engine/engine.h) runs one.
#include <cstdint>
#include <string>

#include "host/config/fluid_config.h"
#include "host/config/rd_config.h"
#include "runtime/box.h"

namespace ardcell {

struct OutputConfig {
  std::string show = "dye";  // field drawn in frames: dye, speed, vorticity, pressure, A, B
  std::string colormap = "viridis";
};

struct SceneConfig {
  std::string name;
  std::string description;  // one line, for `ardcell run --list`
  Int2 size{256, 256};
  double domain_width = 1.0;  // h = domain_width / size.x
  double dt = 0.01;
  int64_t default_steps = 500;
  FluidConfig fluid;
  RdConfig rd;
  OutputConfig output;
};

}  // namespace ardcell
