#include "host/scenes/scene_registry.h"

namespace ardcell {

const SceneRegistry& builtin_scenes() {
  static const SceneRegistry registry = [] {
    SceneRegistry r;
    register_fluid_scenes(r);
    register_rd_scenes(r);
    register_paint_scenes(r);
    register_texture_scenes(r);
    return r;
  }();
  return registry;
}

}  // namespace ardcell
