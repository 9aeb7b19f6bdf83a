#include "host/live/live_wall.h"

#include <algorithm>
#include <cstring>

namespace ardcell {

Box2 wall_view(const BlockLayout& layout, int b, int bezel_cells) {
  const Box2 block = layout.block(b);
  const Int2 grid = layout.domain();
  Box2 view = block;
  const int low = bezel_cells / 2, high = bezel_cells - low;  // hidden below / above a gap
  if (block.min.x > 0) view.min.x += high;
  if (block.max.x < grid.x) view.max.x -= low;
  if (block.min.y > 0) view.min.y += high;
  if (block.max.y < grid.y) view.max.y -= low;
  return view;
}

void place_on_wall(const ImageRgb8& image, Box2 view, Int2 grid, int scale, ImageRgb8& wall) {
  const int x0 = view.min.x * scale, y0 = (grid.y - view.max.y) * scale;
  const int w = std::min(image.width, wall.width - x0),
            h = std::min(image.height, wall.height - y0);
  if (x0 < 0 || y0 < 0 || w <= 0 || h <= 0) return;
  for (int y = 0; y < h; ++y)
    std::memcpy(wall.row(y0 + y) + std::size_t(x0) * 3, image.row(y), std::size_t(w) * 3);
}

}  // namespace ardcell
