#pragma once
// Shared by the tests of surfaces in `ardcell live` (surface_simulation_test,
// surface_fluid_live_test): presets, the live surface, pointer samples and what an image holds.
#include <gtest/gtest.h>

#include <cstdint>
#include <memory>
#include <set>

#include "host/surface/surface_simulation.h"

namespace ardcell::surface_live_test {

inline Preset preset(const char* name) {
  Preset p;
  EXPECT_TRUE(load_preset(name, p)) << name;
  return p;
}

// The mesh's limit surface as `ardcell live` builds it, 8 x 8 cells a patch.
inline std::shared_ptr<const LimitSurface> live_surface(PolyMesh mesh) {
  auto surface = std::make_shared<LimitSurface>();
  const Status s = build_live_surface(std::move(mesh), 8, *surface);
  EXPECT_TRUE(s) << s.message();
  return surface;
}

// A pointer sample at (x, y) of the canvas: the tip down (pressure 1) or hovering.
inline StrokeSample sample(float x, float y, bool tip, bool eraser = false) {
  StrokeSample s;
  s.x = x, s.y = y;
  s.pressure = tip ? 1.0f : 0.0f;
  s.buttons = tip ? uint32_t(kButtonTip) : 0u;
  s.in_range = true;
  s.eraser = eraser;
  return s;
}

inline int distinct_colours(const ImageRgb8& image) {
  std::set<int> colours;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const uint8_t* p = image.row(y) + 3 * x;
      colours.insert(p[0] << 16 | p[1] << 8 | p[2]);
    }
  return int(colours.size());
}

}  // namespace ardcell::surface_live_test
