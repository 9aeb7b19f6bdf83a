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

std::uint64_t text_fingerprint(std::string_view text) {
  std::uint64_t h = 0xcbf29ce484222325ull;
  for (unsigned char c : text) h = (h ^ c) * 0x100000001b3ull;
  return h;
}

namespace {
// Eight 32-bit lanes (GCC's vector extension: one AVX2 register, or two SSE ones).
typedef std::uint32_t Lanes8 __attribute__((vector_size(32)));
}  // namespace

std::uint64_t state_fingerprint(const SimState& state) {
  // Sixteen independent 32-bit multiply-xorshift lanes over the cells' bits (no carried
  // dependence from one cell to the next: sixteen cells at a time), each field's size folded in,
  // the lanes folded into 64 bits at the end.
  constexpr std::uint32_t kMul = 0x9e3779b1u;
  Lanes8 lo = {1, 2, 3, 4, 5, 6, 7, 8}, hi = {9, 10, 11, 12, 13, 14, 15, 16};
  std::uint32_t tail = std::uint32_t(state.step) ^ std::uint32_t(std::uint64_t(state.step) >> 32);
  const auto mix = [](Lanes8 h, const float* cells) {
    Lanes8 bits;
    std::memcpy(&bits, cells, sizeof bits);
    h = (h ^ bits) * kMul;
    return h ^ (h >> 15);
  };
  state.for_each_field([&](std::string_view, const FieldF& f) {
    const Int2 n = f.size();
    tail = ((tail ^ std::uint32_t(n.x)) * kMul ^ std::uint32_t(n.y)) * kMul;
    for (int y = f.origin().y; y < f.origin().y + n.y; ++y) {
      const float* row = f.row(y) + f.origin().x;
      int x = 0;
      for (; x + 16 <= n.x; x += 16) {
        lo = mix(lo, row + x);
        hi = mix(hi, row + x + 8);
      }
      for (; x < n.x; ++x) tail = (tail ^ std::bit_cast<std::uint32_t>(row[x])) * kMul;
    }
  });
  const Field<std::uint8_t>& solid = state.obstacle;  // painted obstacles (rare): bytes
  for (int y = solid.origin().y; !solid.empty() && y < solid.origin().y + solid.ny(); ++y) {
    const std::uint8_t* row = solid.row(y) + solid.origin().x;
    for (int x = 0; x < solid.nx(); ++x) tail = (tail ^ row[x]) * kMul;
  }
  std::uint64_t h = tail;
  for (int k = 0; k < 8; ++k)
    h = ((h ^ lo[k]) * 0x9e3779b97f4a7c15ull ^ hi[k]) * 0x9e3779b97f4a7c15ull;
  return h ^ (h >> 31);
}

}  // namespace ardcell
