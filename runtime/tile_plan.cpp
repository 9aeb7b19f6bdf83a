#include "runtime/tile_plan.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#include "runtime/check.h"
#include "runtime/dma.h"

namespace ardcell {
namespace {
constexpr int kLine = int(Dma::kAlignBytes / sizeof(float));
int round_up(int v, int m) { return (v + m - 1) / m * m; }
}  // namespace

std::size_t TilePlan::slot_bytes_for(Int2 size, const TilePlanRequest& r) {
  // Written boxes reach the domain's ghost ring, not the whole of a deep field halo.
  const int ring = TilePlan::ring(r.field_halo);
  if (!r.buffer_halos.empty()) {
    std::size_t total = 0;
    for (int h : r.buffer_halos) {
      const int reach = std::max(h, ring);
      total += std::size_t(size.x + 2 * round_up(reach, kLine)) * sizeof(float) *
               std::size_t(size.y + 2 * reach);
    }
    return total;
  }
  // A halo buffer spans the core plus `halo` lines' worth on each side, line-widened; a
  // written-box buffer spans the core plus the domain halo. Both rounded to whole lines.
  const int reach = std::max(r.halo, ring);
  const std::size_t halo_row = std::size_t(size.x + 2 * round_up(reach, kLine)) * sizeof(float);
  const std::size_t core_row = std::size_t(size.x + 2 * round_up(ring, kLine)) * sizeof(float);
  return std::size_t(r.fields_with_halo) * halo_row * std::size_t(size.y + 2 * reach) +
         std::size_t(r.fields_core) * core_row * std::size_t(size.y + 2 * ring);
}

TilePlan TilePlan::make(const TilePlanRequest& r) {
  ARDCELL_CHECK(r.grid.x > 0 && r.grid.y > 0 && r.halo >= 0 && r.field_halo >= 0,
                "TilePlan needs a non-empty grid and non-negative halos");
  const Box2 block = r.block.empty() ? box_of_size(r.grid) : r.block;
  ARDCELL_CHECK(box_of_size(r.grid).contains(block), "TilePlan: the block lies outside the domain");
  const Int2 cells = block.size();
  const std::size_t slot = r.store_bytes / LocalStore::kSlots;
  int reach = std::max(r.halo, ring(r.field_halo));
  for (int h : r.buffer_halos) reach = std::max(reach, h);
  // Widest row a single DMA transfer may carry.
  const int max_row_cells = int(Dma::kMaxTransferBytes / sizeof(float));
  const int grid_w = round_up(cells.x + r.field_halo, kLine);
  // Shape: the largest core that fits. With the store full, that is also the smallest share of
  // halo in the bytes copied (a side's halo costs whole 128-byte lines in x, rows in y); scoring
  // by the ghost zone's recomputation instead (w h / ((w + H)(h + H))) made halo-1 tiles square
  // and slowed the stream schedule at 512^2 by about a quarter.
  int best_w = 0, best_h = 0;
  long best_area = -1;
  for (int w = kLine; w <= grid_w; w += kLine) {
    if (r.max_width > 0 && w > std::max(r.max_width, kLine)) break;
    if (w + 2 * round_up(reach, kLine) > max_row_cells) break;
    // Tallest core that fits the slot for this width.
    int lo = 0, hi = cells.y;
    while (lo < hi) {
      const int mid = (lo + hi + 1) / 2;
      if (slot_bytes_for(Int2{w, mid}, r) <= slot)
        lo = mid;
      else
        hi = mid - 1;
    }
    int h = lo;
    if (r.max_height > 0) h = std::min(h, r.max_height);
    if (h <= 0) continue;
    const int cw = std::min(w, cells.x + r.field_halo);
    const long area = long(cw) * h;
    if (area > best_area) {
      best_area = area;
      best_w = w;
      best_h = h;
    }
  }
  if (best_w == 0) {
    char why[224];
    std::snprintf(why, sizeof why,
                  "local store of %zu KiB a worker: no tile fits its %zu-byte slot for a pass "
                  "with halo %d, %d halo buffers and %d core buffers (expected a larger store)",
                  r.store_bytes / 1024, slot, r.halo, r.fields_with_halo, r.fields_core);
    throw std::invalid_argument(why);
  }
  // Load balance: shorter tiles until there are min_tiles, where the grid allows.
  auto count = [&](int w, int h) {
    const int cols = (cells.x + r.field_halo + w - 1) / w;
    return long(cols) * ((cells.y + h - 1) / h);
  };
  while (best_h > 1 && count(best_w, best_h) < r.min_tiles) best_h = (best_h + 1) / 2;
  while (best_w > kLine && count(best_w, best_h) < r.min_tiles) best_w -= kLine;

  TilePlan plan;
  plan.grid_ = r.grid;
  plan.block_ = block;
  plan.field_halo_ = r.field_halo;
  plan.halo_ = r.halo;
  plan.tile_ = Int2{best_w, best_h};
  plan.slot_bytes_needed_ = slot_bytes_for(plan.tile_, r);
  // x cuts at line boundaries of the field rows: x = block.min.x + j*w - field_halo.
  std::vector<int> xs{block.min.x};
  for (int x = block.min.x + best_w - r.field_halo; x < block.max.x; x += best_w)
    if (x > block.min.x) xs.push_back(x);
  xs.push_back(block.max.x);
  for (int y = block.min.y; y < block.max.y; y += best_h) {
    const int y1 = std::min(y + best_h, block.max.y);
    for (std::size_t i = 0; i + 1 < xs.size(); ++i)
      plan.tiles_.push_back(Tile{Box2{{xs[i], y}, {xs[i + 1], y1}}, r.halo});
  }
  return plan;
}

Box2 TilePlan::written_box(const Tile& t) const {
  const int ring = this->ring();
  Box2 b = t.core;
  if (b.min.x == 0) b.min.x = -ring;
  if (b.min.y == 0) b.min.y = -ring;
  if (b.max.x == grid_.x) b.max.x = grid_.x + ring;
  if (b.max.y == grid_.y) b.max.y = grid_.y + ring;
  return b;
}

Box2 TilePlan::readable() const {
  return block_.grown(field_halo_).intersected(domain().grown(ring()));
}

Box2 TilePlan::load_box(const Tile& t, int halo) const {
  return t.core.grown(halo).intersected(readable());
}

Box2 TilePlan::sweep_region(const Tile& t, int halo, int sweep) const {
  const int s = halo - sweep;  // how far beyond the core the sweep still computes exactly
  const Int2 grid = grid_;
  Box2 b = t.core;
  b.min.x = t.core.min.x == 0 ? 0 : std::max(0, t.core.min.x - s);
  b.min.y = t.core.min.y == 0 ? 0 : std::max(0, t.core.min.y - s);
  b.max.x = t.core.max.x == grid.x ? grid.x : std::min(grid.x, t.core.max.x + s);
  b.max.y = t.core.max.y == grid.y ? grid.y : std::min(grid.y, t.core.max.y + s);
  return b;
}

}  // namespace ardcell
