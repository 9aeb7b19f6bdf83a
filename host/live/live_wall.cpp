#include "host/live/live_wall.h"

#include <algorithm>
#include <bit>
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

std::uint64_t state_fingerprint(const SimState& state) {
  // Four independent multiply-xorshift lanes over the cells' bits (no carried dependence from
  // one cell to the next: the CPU hashes four at a time), folded with the field's size.
  constexpr std::uint64_t kMul = 0x9e3779b97f4a7c15ull;
  std::uint64_t lane[4] = {1, 2, 3, std::uint64_t(state.step)};
  state.for_each_field([&](std::string_view, const FieldF& f) {
    const Int2 n = f.size();
    lane[0] ^= std::uint64_t(std::uint32_t(n.x)) << 32 | std::uint32_t(n.y);
    for (int y = f.origin().y; y < f.origin().y + n.y; ++y) {
      const float* row = f.row(y) + f.origin().x;
      int x = 0;
      for (; x + 4 <= n.x; x += 4)
        for (int k = 0; k < 4; ++k) {
          lane[k] = (lane[k] ^ std::bit_cast<std::uint32_t>(row[x + k])) * kMul;
          lane[k] ^= lane[k] >> 29;
        }
      for (; x < n.x; ++x) lane[0] = (lane[0] ^ std::bit_cast<std::uint32_t>(row[x])) * kMul;
    }
  });
  std::uint64_t h = 0;
  for (std::uint64_t l : lane) h = (h ^ l) * kMul;
  return h ^ (h >> 31);
}

}  // namespace ardcell
