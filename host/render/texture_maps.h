#pragma once
// Texture maps for artists (seed 003, Fig. 7: reaction-diffusion textures as bump maps): a
// grayscale height image of a field, 8- or 16-bit, and a tangent-space normal map derived from
// it. Like frames (host/render/frame_render.h), row 0 of an image is the grid's top row
// y = ny - 1, so the grid's +y is the image's up: the normal map follows the OpenGL convention
// (green = +y up, blue = +z out of the surface).
//
// Height: the finite interior values map linearly from [min, max] to [0, 1] (a constant field
// to 0.5). Non-finite cells never reach a pixel as NaN arithmetic: they are left out of the
// range and take a fixed height, +inf 1, -inf 0, NaN 0.5 (neither peak nor pit), counted in
// HeightRange::non_finite so that the caller can warn.
#include <cstdint>
#include <vector>

#include "host/render/image.h"
#include "runtime/field.h"

namespace ardcell {

struct ImageGray8 {
  int width = 0, height = 0;
  std::vector<uint8_t> pixels;  // width * height, row-major from the top
  void resize(int w, int h) {
    width = w;
    height = h;
    pixels.assign(std::size_t(w) * std::size_t(h), 0);
  }
  bool empty() const { return width <= 0 || height <= 0; }
};

struct ImageGray16 {
  int width = 0, height = 0;
  std::vector<uint16_t> pixels;  // width * height, row-major from the top, native byte order
  void resize(int w, int h) {
    width = w;
    height = h;
    pixels.assign(std::size_t(w) * std::size_t(h), 0);
  }
  bool empty() const { return width <= 0 || height <= 0; }
};

// The finite values' range of the interior and the count of the others.
struct HeightRange {
  float lo = 0, hi = 0;    // lo == hi when constant (or no finite value at all)
  int64_t non_finite = 0;  // NaN and +-inf cells
};
HeightRange height_range(const FieldF& field);

// A value's height in [0, 1] under `range` (as described above; never NaN).
double normalized_height(float value, const HeightRange& range);

// The interior of `field` as a height image, sized to it. Returns the range used.
HeightRange height_map_8(const FieldF& field, ImageGray8& out);
HeightRange height_map_16(const FieldF& field, ImageGray16& out);

struct NormalMapOptions {
  // The relief: the height range [min, max] stands this many cells tall, so the normals do not
  // depend on the field's units. Larger is bumpier.
  double strength = 4.0;
  // Central differences that wrap around the edges, so the map of a tileable (periodic) field
  // tiles too; otherwise one-sided differences at the border.
  bool periodic = true;
};

// n = normalize(-strength dh/dx, -strength dh/dy, 1) from the normalized height of the
// interior, RGB = round((n * 0.5 + 0.5) * 255): a flat field is (128, 128, 255). Fields
// narrower than 2 cells along an axis have a zero slope along it.
HeightRange normal_map(const FieldF& field, const NormalMapOptions& options, ImageRgb8& out);

}  // namespace ardcell
