#pragma once
// Helpers for tests parameterised over every built-in preset: the preset's scene at a size no
// tiling divides evenly, and a gtest-safe name for each preset.
#include <gtest/gtest.h>

#include <cctype>
#include <string>

#include "host/scenes/preset.h"

namespace ardcell {

inline constexpr Int2 kAwkwardSize{127, 93};

inline SceneConfig awkward_preset_scene(const std::string& name) {
  Preset preset;
  EXPECT_TRUE(load_preset(name, preset)) << name;
  SceneConfig scene = preset.scene;
  scene.size = kAwkwardSize;
  return scene;
}

// A built-in preset's scene as it is (a failed load fails the test).
inline SceneConfig builtin_preset_scene(const char* name) {
  Preset p;
  const Status s = load_builtin_preset(name, p);
  EXPECT_TRUE(s) << s.message();
  return p.scene;
}

inline std::string preset_test_name(const testing::TestParamInfo<std::string>& info) {
  std::string name = info.param;
  for (char& c : name)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return name;
}

}  // namespace ardcell
