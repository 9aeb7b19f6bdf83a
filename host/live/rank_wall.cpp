#include "host/live/rank_wall.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <type_traits>

#include "runtime/check.h"

namespace ardcell {

static_assert(std::is_trivially_copyable_v<WallInput>, "WallInput travels as bytes");

RankWall::RankWall(const BlockLayout& layout, int bezel_cells, const MpiWorld& world, bool mirrored)
    : layout_(layout),
      world_(world),
      bezel_cells_(bezel_cells),
      mirrored_(mirrored),
      fingerprints_(std::size_t(layout.count())),
      all_(std::size_t(layout.count())) {
  ARDCELL_CHECK(world.size() == layout.count(), "RankWall: one rank per block");
  for (int b = 0; b < layout.count(); ++b) {
    views_.push_back(wall_view(layout, b, bezel_cells));
    ARDCELL_CHECK(!views_.back().empty(), "RankWall: a screen shows no cell");
  }
}

std::span<const WallInput> RankWall::share(const WallInput& mine) {
  world_.all_gather(&mine, sizeof(WallInput), all_.data());
  return all_;
}

bool RankWall::gather_image(const ImageRgb8& mine, ImageRgb8& wall) {
  // Each rank's image: its width and height, then its pixels.
  std::vector<unsigned char> out(2 * sizeof(int) + mine.rgb.size());
  const int size[2] = {mine.width, mine.height};
  std::memcpy(out.data(), size, sizeof size);
  if (!mine.rgb.empty()) std::memcpy(out.data() + sizeof size, mine.rgb.data(), mine.rgb.size());
  world_.gather_to_root(out, bytes_, counts_);
  if (world_.rank() != 0) return false;
  // Pixels per cell: screen 0's.
  const int scale = std::max(1, mine.width / std::max(1, views_[0].width()));
  const Int2 grid = layout_.domain();
  wall.resize(grid.x * scale, grid.y * scale);
  std::size_t at = 0;
  ImageRgb8 image;
  for (int r = 0; r < world_.size(); ++r) {
    int wh[2];
    std::memcpy(wh, bytes_.data() + at, sizeof wh);
    image.width = wh[0];
    image.height = wh[1];
    const auto* pixels = bytes_.data() + at + sizeof wh;
    image.rgb.assign(pixels, pixels + std::size_t(counts_[std::size_t(r)]) - sizeof wh);
    place_on_wall(image, views_[std::size_t(r)], grid, scale, wall);
    at += std::size_t(counts_[std::size_t(r)]);
  }
  return true;
}

int RankWall::first_drifted(std::uint64_t fingerprint) {
  world_.all_gather(&fingerprint, sizeof fingerprint, fingerprints_.data());
  for (std::size_t r = 1; r < fingerprints_.size(); ++r)
    if (fingerprints_[r] != fingerprints_[0]) return int(r);
  return -1;
}

template <class T>
void RankWall::send_cells(Field<T>& f) {
  if (f.empty()) return;
  // The interior only, through one buffer: a field's halo may be wider on one screen's back end
  // than on another's.
  const Int2 n = f.size(), o = f.origin();
  const std::size_t row = std::size_t(n.x) * sizeof(T), bytes = row * std::size_t(n.y);
  if (staging_.size() < bytes) staging_.resize(bytes);  // at a drift, which is rare
  const bool root = world_.rank() == 0;
  for (int y = 0; root && y < n.y; ++y)
    std::memcpy(staging_.data() + row * std::size_t(y), f.row(o.y + y) + o.x, row);
  world_.broadcast(staging_.data(), bytes);
  for (int y = 0; !root && y < n.y; ++y)
    std::memcpy(f.row(o.y + y) + o.x, staging_.data() + row * std::size_t(y), row);
}

void RankWall::send_state(SimState& state) {
  state.for_each_field([&](std::string_view, FieldF& f) { send_cells(f); });
  send_cells(state.obstacle);
  struct Clock {
    double time, rd_time;
    std::int64_t step;
  } clock{state.time, state.rd_time, state.step};
  world_.broadcast(&clock, sizeof clock);
  state.time = clock.time;
  state.rd_time = clock.rd_time;
  state.step = clock.step;
}

bool RankWall::regrid(Int2 grid) {
  if (!mirrored_) return grid == layout_.domain();
  BlockLayout layout;
  try {
    layout = BlockLayout::split(grid, layout_.parts());
  } catch (const std::invalid_argument&) {
    return false;  // fewer cells than screens along an axis
  }
  std::vector<Box2> views;
  for (int b = 0; b < layout.count(); ++b) {
    views.push_back(wall_view(layout, b, bezel_cells_));
    if (views.back().empty()) return false;
  }
  layout_ = layout;
  views_ = std::move(views);
  return true;
}

}  // namespace ardcell
