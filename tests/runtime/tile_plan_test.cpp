#include "runtime/tile_plan.h"

#include <gtest/gtest.h>

#include <vector>

#include "runtime/dma.h"

namespace ardcell {
namespace {

// Every interior cell lies in exactly one core; written boxes tile interior + halo exactly.
void expect_exact_cover(const TilePlan& plan) {
  const Int2 g = plan.grid();
  const int h = plan.field_halo();
  std::vector<int> core(std::size_t((g.x + 2 * h) * (g.y + 2 * h)), 0);
  std::vector<int> written(core.size(), 0);
  auto at = [&](std::vector<int>& v, int x, int y) -> int& {
    return v[std::size_t((y + h) * (g.x + 2 * h) + (x + h))];
  };
  for (const Tile& t : plan.tiles()) {
    for (int y = t.core.min.y; y < t.core.max.y; ++y)
      for (int x = t.core.min.x; x < t.core.max.x; ++x) ++at(core, x, y);
    const Box2 w = plan.written_box(t);
    for (int y = w.min.y; y < w.max.y; ++y)
      for (int x = w.min.x; x < w.max.x; ++x) ++at(written, x, y);
    // Puts are line-exact: the written box starts on a line and ends on one or at the row end.
    EXPECT_EQ((w.min.x + h) % 32, 0) << w;
    EXPECT_TRUE((w.max.x + h) % 32 == 0 || w.max.x == g.x + h) << w;
  }
  for (int y = -h; y < g.y + h; ++y)
    for (int x = -h; x < g.x + h; ++x) {
      const bool interior = x >= 0 && y >= 0 && x < g.x && y < g.y;
      ASSERT_EQ(at(core, x, y), interior ? 1 : 0) << x << "," << y;
      ASSERT_EQ(at(written, x, y), 1) << x << "," << y;
    }
}

TEST(TilePlan, AwkwardGridIsCoveredOnceWithLineExactPuts) {
  for (int halo : {0, 1, 3, 20}) {
    TilePlanRequest r;
    r.grid = {127, 93};
    r.halo = halo;
    r.fields_with_halo = 3;
    r.fields_core = 1;
    r.store_bytes = halo > 3 ? 192 * 1024 : 32 * 1024;  // small: many tiles, none dividing
    const TilePlan plan = TilePlan::make(r);
    EXPECT_GT(plan.tiles().size(), 1u);
    expect_exact_cover(plan);
  }
}

TEST(TilePlan, DoubleBufferedBuffersFitTheStoreAndRowsFitOneTransfer) {
  for (int n : {128, 1000, 2048}) {
    TilePlanRequest r;
    r.grid = {n, n};
    r.halo = 20;
    r.fields_with_halo = 2;
    r.fields_core = 1;
    const TilePlan plan = TilePlan::make(r);
    EXPECT_LE(plan.slot_bytes_needed() * LocalStore::kSlots, r.store_bytes);
    // Every tile's actual buffers (line-widened) fit one slot.
    for (const Tile& t : plan.tiles()) {
      const std::size_t bytes =
          2 * local_copy_bytes(plan.load_box(t, 20), 1) + local_copy_bytes(plan.written_box(t), 1);
      ASSERT_LE(bytes, r.store_bytes / 2) << t.core;
      const Box2 lb = plan.load_box(t, 20);
      ASSERT_LE(local_copy_bytes(lb, 1) / std::size_t(lb.height()), Dma::kMaxTransferBytes);
    }
    expect_exact_cover(plan);
  }
}

TEST(TilePlan, MinTilesSplitsSmallGridsForLoadBalance) {
  TilePlanRequest r;
  r.grid = {128, 128};
  r.min_tiles = 8;
  const TilePlan plan = TilePlan::make(r);
  EXPECT_GE(plan.tiles().size(), 8u);
  expect_exact_cover(plan);
}

TEST(TilePlan, LoadBoxClipsToTheFieldAndSweepRegionShrinks) {
  TilePlanRequest r;
  r.grid = {100, 50};
  const TilePlan plan = TilePlan::make(r);
  const Tile corner{Box2{{0, 0}, {31, 20}}, 5};
  EXPECT_EQ(plan.load_box(corner, 5), (Box2{{-1, -1}, {36, 25}}));
  // Sweep 1 of 5 computes 4 cells beyond the core on inner sides, none past the domain.
  EXPECT_EQ(plan.sweep_region(corner, 5, 1), (Box2{{0, 0}, {35, 24}}));
  EXPECT_EQ(plan.sweep_region(corner, 5, 5), corner.core);
  const Tile inner{Box2{{31, 20}, {63, 40}}, 2};
  EXPECT_EQ(plan.written_box(inner), inner.core);
  EXPECT_EQ(plan.written_box(corner), (Box2{{-1, -1}, {31, 20}}));
}

// A block of a larger domain: tiles cut the block only, on lines of the block's fields; the
// sides it shares with other blocks are inner sides (no ring, sweeps shrink there), and loads
// reach into the field's deep halo there but only the ring past the domain.
TEST(TilePlan, CutsABlockOfTheDomain) {
  TilePlanRequest r;
  r.grid = {200, 90};
  r.block = Box2{{67, 0}, {134, 45}};
  r.field_halo = 6;
  r.halo = 6;
  r.store_bytes = 64 * 1024;
  r.min_tiles = 4;
  const TilePlan plan = TilePlan::make(r);
  std::int64_t area = 0;
  for (const Tile& t : plan.tiles()) {
    EXPECT_TRUE(r.block.contains(t.core)) << t.core;
    area += t.core.area();
    const Box2 w = plan.written_box(t);
    EXPECT_EQ(w.min.x, t.core.min.x);  // no domain edge in x
    EXPECT_EQ(w.max.y, t.core.max.y);  // the top is another block's
    EXPECT_EQ(w.min.y, t.core.min.y == 0 ? -1 : t.core.min.y);
    // Cuts on the block's field lines (row start 67 - 6).
    if (t.core.min.x != r.block.min.x) {
      EXPECT_EQ((t.core.min.x - 61) % 32, 0) << t.core;
    }
  }
  EXPECT_EQ(area, r.block.area());
  EXPECT_EQ(plan.readable(), (Box2{{61, -1}, {140, 51}}));
  const Tile first = plan.tiles()[0];
  EXPECT_EQ(plan.load_box(first, 6).min, (Int2{61, -1}));
  EXPECT_EQ(plan.sweep_region(first, 6, 1).min, (Int2{62, 0}));
}

}  // namespace
}  // namespace ardcell
