#pragma once
// The built-in scenes, selectable by name (`ardcell run --scene NAME`, `ardcell run --list`).
// Each area registers its scenes through one function called from scene_registry.cpp.
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "host/config/scene_config.h"
#include "host/scenes/adaptive_quality.h"

namespace ardcell {

struct SceneEntry {
  std::string name;
  std::string description;
  std::function<SceneConfig()> make;  // the scene at its default parameters
  QualityBounds quality{};            // how far `ardcell live` may lower it (preset_from_entry)
};

class SceneRegistry {
 public:
  void add(SceneEntry entry) { entries_.push_back(std::move(entry)); }
  const SceneEntry* find(std::string_view name) const {
    for (const SceneEntry& e : entries_)
      if (e.name == name) return &e;
    return nullptr;
  }
  std::span<const SceneEntry> entries() const { return entries_; }

 private:
  std::vector<SceneEntry> entries_;
};

// Every built-in scene, registered once.
const SceneRegistry& builtin_scenes();

// Registration hooks, one per area (defined next to each area's scenes).
void register_fluid_scenes(SceneRegistry& registry);
void register_rd_scenes(SceneRegistry& registry);
void register_paint_scenes(SceneRegistry& registry);
void register_texture_scenes(SceneRegistry& registry);  // seed 003

}  // namespace ardcell
