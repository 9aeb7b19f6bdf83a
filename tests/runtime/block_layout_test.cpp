#include "runtime/block_layout.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <thread>
#include <vector>

namespace ardcell {
namespace {

float cell_value(int x, int y) { return float(x * 1000 + y); }

// Every block's field: its owned cells numbered by their global coordinates, its other halo
// cells -1 (so a halo cell the exchange misses shows).
std::vector<FieldF> numbered_blocks(const BlockLayout& l, int halo) {
  std::vector<FieldF> f;
  for (int b = 0; b < l.count(); ++b) {
    f.push_back(FieldF::over(l.block(b), halo));
    FieldF& g = f.back();
    g.fill(-1.0f);
    const Box2 o = l.owned(b);
    for (int y = o.min.y; y < o.max.y; ++y)
      for (int x = o.min.x; x < o.max.x; ++x) g(x, y) = cell_value(x, y);
  }
  return f;
}

std::vector<FieldF*> pointers(std::vector<FieldF>& fields) {
  std::vector<FieldF*> p;
  for (FieldF& f : fields) p.push_back(&f);
  return p;
}

int wrap(int v, int n) { return ((v % n) + n) % n; }

TEST(BlockLayout, SplitsUnevenlyAndTilesTheDomain) {
  const BlockLayout l = BlockLayout::split({127, 93}, {3, 2});
  ASSERT_EQ(l.count(), 6);
  EXPECT_EQ(l.block(0), (Box2{{0, 0}, {43, 47}}));
  EXPECT_EQ(l.block(2), (Box2{{85, 0}, {127, 47}}));
  EXPECT_EQ(l.block(5), (Box2{{85, 47}, {127, 93}}));
  std::int64_t area = 0;
  for (int b = 0; b < l.count(); ++b) area += l.block(b).area();
  EXPECT_EQ(area, 127 * 93);
  // The ring belongs to the blocks along the domain's edges.
  EXPECT_EQ(l.owned(0), (Box2{{-1, -1}, {43, 47}}));
  EXPECT_EQ(l.owned(4), (Box2{{43, 47}, {85, 94}}));
  EXPECT_THROW(BlockLayout::split({4, 4}, {5, 1}), std::invalid_argument);
  EXPECT_THROW(BlockLayout::split({4, 4}, {0, 1}), std::invalid_argument);
}

TEST(BlockLayout, ParsesParts) {
  Int2 p;
  EXPECT_TRUE(parse_block_parts("2x1", p));
  EXPECT_EQ(p, (Int2{2, 1}));
  for (const char* bad : {"", "2", "x1", "2x", "0x1", "2x-1", "2x1x", "ax1", "2 x1"})
    EXPECT_FALSE(parse_block_parts(bad, p)) << bad;
}

// Each block's halo then holds the cells a whole field would hold there: interior cells and
// the domain's ring from their owners, nothing beyond the ring of a wall.
TEST(HaloExchange, FillsEveryHaloCellFromItsOwner) {
  for (const Int2 parts : {Int2{1, 1}, Int2{2, 1}, Int2{2, 2}, Int2{3, 1}, Int2{3, 4}}) {
    const BlockLayout l = BlockLayout::split({37, 29}, parts);
    const int width = 5;
    std::vector<FieldF> f = numbered_blocks(l, width);
    const std::vector<FieldF*> ptrs = pointers(f);
    const HaloExchange ex(l, width);
    for (int b = 0; b < l.count(); ++b) ex.fill(ptrs, b, width);
    const Box2 walls = box_of_size(l.domain()).grown(1);
    for (int b = 0; b < l.count(); ++b) {
      const Box2 h = l.block(b).grown(width);
      for (int y = h.min.y; y < h.max.y; ++y)
        for (int x = h.min.x; x < h.max.x; ++x)
          ASSERT_EQ(f[std::size_t(b)](x, y), walls.contains(Int2{x, y}) ? cell_value(x, y) : -1.0f)
              << parts << " block " << b << " cell " << x << "," << y;
    }
  }
}

// A shallower fill moves only the cells within its depth of the block.
TEST(HaloExchange, FillsOnlyAsDeepAsAsked) {
  const BlockLayout l = BlockLayout::split({40, 30}, {2, 2});
  std::vector<FieldF> f = numbered_blocks(l, 6);
  const std::vector<FieldF*> ptrs = pointers(f);
  const HaloExchange ex(l, 6);
  ex.fill(ptrs, 3, 2);
  const Box2 walls = box_of_size(l.domain()).grown(1);
  const Box2 near = l.block(3).grown(2), far = l.block(3).grown(6);
  for (int y = far.min.y; y < far.max.y; ++y)
    for (int x = far.min.x; x < far.max.x; ++x) {
      const bool filled = near.contains(Int2{x, y}) && walls.contains(Int2{x, y});
      ASSERT_EQ(f[3](x, y), filled ? cell_value(x, y) : -1.0f) << x << "," << y;
    }
}

TEST(HaloExchange, WrapsPeriodicAxes) {
  const BlockLayout l = BlockLayout::split({20, 12}, {2, 3}, true, false);
  const int width = 3;
  std::vector<FieldF> f = numbered_blocks(l, width);
  const std::vector<FieldF*> ptrs = pointers(f);
  const HaloExchange ex(l, width);
  for (int b = 0; b < l.count(); ++b) ex.fill(ptrs, b, width);
  for (int b = 0; b < l.count(); ++b) {
    const Box2 h = l.block(b).grown(width);
    for (int y = h.min.y; y < h.max.y; ++y)
      for (int x = h.min.x; x < h.max.x; ++x) {
        const bool held = y >= -1 && y <= 12;  // walls in y: the ring, no further
        ASSERT_EQ(f[std::size_t(b)](x, y), held ? cell_value(wrap(x, 20), y) : -1.0f)
            << "block " << b << " cell " << x << "," << y;
      }
  }
  // Block 0 is [0, 10) x [0, 4): its halo rows -1 .. 6, columns -3 .. 12, less what it owns
  // (its interior and the ring row y = -1 below it).
  EXPECT_EQ(ex.cells_into(0), std::size_t(16 * 8 - 10 * 5));
}

// The blocks on threads, each exchanging through its channel, as ranks would.
TEST(LocalBlockGroup, BlocksOnThreadsExchangeTheirHalos) {
  const BlockLayout l = BlockLayout::split({64, 40}, {2, 2}, true, true);
  LocalBlockGroup group(l, 4);
  std::vector<FieldF> f = numbered_blocks(l, 4);
  std::vector<std::thread> threads;
  for (int b = 0; b < l.count(); ++b)
    threads.emplace_back([&, b] {
      for (int round = 0; round < 3; ++round) group.channel(b).exchange(f[std::size_t(b)], 4);
    });
  for (std::thread& t : threads) t.join();
  for (int b = 0; b < l.count(); ++b) {
    const Box2 h = l.block(b).grown(4);
    for (int y = h.min.y; y < h.max.y; ++y)
      for (int x = h.min.x; x < h.max.x; ++x)
        ASSERT_EQ(f[std::size_t(b)](x, y), cell_value(wrap(x, 64), wrap(y, 40)))
            << "block " << b << " cell " << x << "," << y;
  }
}

// sum() adds the blocks' values in block order and hands every block the same totals, round
// after round (values whose sum depends on the order: 1e16 + 1 - 1e16).
TEST(LocalBlockGroup, SumsAddTheBlocksInBlockOrder) {
  const BlockLayout l = BlockLayout::split({30, 20}, {3, 1});
  LocalBlockGroup group(l, 1);
  const double values[3][2] = {{1e16, 1.0}, {1.0, 2.0}, {-1e16, 0.5}};
  std::vector<std::vector<double>> totals(3);
  std::vector<std::thread> threads;
  for (int b = 0; b < 3; ++b)
    threads.emplace_back([&, b] {
      for (int round = 0; round < 3; ++round) {
        double v[2] = {values[b][0] * (round + 1), values[b][1]};
        group.channel(b).sum(v);
        totals[std::size_t(b)].insert(totals[std::size_t(b)].end(), {v[0], v[1]});
      }
    });
  for (std::thread& t : threads) t.join();
  for (int round = 0; round < 3; ++round) {
    const double expected = ((0.0 + 1e16 * (round + 1)) + 1.0 * (round + 1)) - 1e16 * (round + 1);
    for (int b = 0; b < 3; ++b) {
      EXPECT_EQ(totals[std::size_t(b)][std::size_t(2 * round)], expected) << round;
      EXPECT_EQ(totals[std::size_t(b)][std::size_t(2 * round + 1)], 3.5) << round;
    }
  }
}

}  // namespace
}  // namespace ardcell
