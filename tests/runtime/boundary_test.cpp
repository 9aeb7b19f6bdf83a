#include "runtime/boundary.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <utility>

namespace ardcell {
namespace {

FieldF random_field(Int2 size, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> dist(-1.0f, 1.0f);
  FieldF f(size, 1);
  for (int j = -1; j <= size.y; ++j)
    for (int i = -1; i <= size.x; ++i) f(i, j) = dist(rng);
  return f;
}

const Int2 kSize{9, 7};

TEST(Boundary, EachRuleOnEachSide) {
  FieldF f = random_field(kSize, 1);
  const BoundaryFill fill{{EdgeRule::kCopy, 0.0f},
                          {EdgeRule::kFixed, 2.5f},
                          {EdgeRule::kMirror, 0.0f},
                          {EdgeRule::kMirror, 1.0f}};
  fill_boundary(f.view(), kSize, fill);
  for (int j = 0; j < kSize.y; ++j) {
    EXPECT_EQ(f(-1, j), f(0, j));    // copy (Neumann)
    EXPECT_EQ(f(kSize.x, j), 2.5f);  // fixed (Dirichlet on the ghost)
  }
  for (int i = 0; i < kSize.x; ++i) {
    EXPECT_EQ(f(i, -1), -f(i, 0));  // Stam's negation: wall value 0
    EXPECT_FLOAT_EQ(0.5f * (f(i, kSize.y) + f(i, kSize.y - 1)), 1.0f);  // lid: wall value 1
  }
  // Corners: average of the two edge ghosts next to them.
  EXPECT_FLOAT_EQ(f(-1, -1), 0.5f * (f(0, -1) + f(-1, 0)));
  EXPECT_FLOAT_EQ(f(kSize.x, kSize.y), 0.5f * (f(kSize.x - 1, kSize.y) + f(kSize.x, kSize.y - 1)));
  EXPECT_FLOAT_EQ(f(kSize.x, -1), 0.5f * (f(kSize.x - 1, -1) + f(kSize.x, 0)));
  EXPECT_FLOAT_EQ(f(-1, kSize.y), 0.5f * (f(0, kSize.y) + f(-1, kSize.y - 1)));
}

// A Poiseuille inflow: the wall-face value (ghost and interior averaged) follows 6 s (1 - s)
// times the side's value, whose mean over the side is that value (midpoint rule on a parabola:
// exact up to 1 / (2 n^2)).
TEST(Boundary, ParabolicInflowHasTheProfileAndTheMean) {
  for (int n : {8, 41, 82}) {
    const Int2 size{2 * n, n};
    FieldF f = random_field(size, 3);
    BoundaryFill fill = BoundaryFill::copy();
    fill.left = {EdgeRule::kParabolic, 1.0f};
    fill_boundary(f.view(), size, fill);
    double mean = 0.0, peak = 0.0;
    for (int j = 0; j < n; ++j) {
      const double s = (j + 0.5) / n;
      const double face = 0.5 * (double(f(-1, j)) + double(f(0, j)));
      EXPECT_NEAR(face, 6.0 * s * (1.0 - s), 2e-6) << n << " " << j;
      mean += face / n;
      peak = std::max(peak, face);
    }
    EXPECT_NEAR(mean, 1.0 + 0.5 / (double(n) * n), 1e-5) << n;
    EXPECT_LE(peak, 1.5 + 1e-6);
  }
}

TEST(Boundary, StamSetBndSemantics) {
  for (int b : {0, 1, 2}) {
    FieldF f = random_field(kSize, 2);
    set_bnd(f.view(), kSize, b);
    for (int j = 0; j < kSize.y; ++j) {
      const float sx = b == 1 ? -1.0f : 1.0f;
      EXPECT_EQ(f(-1, j), sx * f(0, j));
      EXPECT_EQ(f(kSize.x, j), sx * f(kSize.x - 1, j));
    }
    for (int i = 0; i < kSize.x; ++i) {
      const float sy = b == 2 ? -1.0f : 1.0f;
      EXPECT_EQ(f(i, -1), sy * f(i, 0));
      EXPECT_EQ(f(i, kSize.y), sy * f(i, kSize.y - 1));
    }
    EXPECT_FLOAT_EQ(f(-1, -1), 0.5f * (f(0, -1) + f(-1, 0)));
  }
}

TEST(Boundary, NoSlipNegatesBothComponentsAndMovesTheLid) {
  FieldF f = random_field(kSize, 3);
  fill_boundary(f.view(), kSize, BoundaryFill::no_slip(1.0f));
  for (int j = 0; j < kSize.y; ++j) EXPECT_EQ(f(-1, j), -f(0, j));
  for (int i = 0; i < kSize.x; ++i) EXPECT_FLOAT_EQ(f(i, kSize.y), 2.0f - f(i, kSize.y - 1));
}

TEST(Boundary, PeriodicWrapsEdgesAndCorners) {
  FieldF f = random_field(kSize, 4);
  fill_boundary(f.view(), kSize, BoundaryFill::periodic());
  for (int j = -1; j <= kSize.y; ++j)
    for (int i = -1; i <= kSize.x; ++i)
      ASSERT_EQ(f(i, j), f((i + kSize.x) % kSize.x, (j + kSize.y) % kSize.y)) << i << "," << j;
}

// A fill on a tile copied out of the field (a local store) writes exactly the ghost cells a
// whole-field fill writes in that box, and reads nothing outside the tile.
TEST(Boundary, TileLocalFillEqualsWholeFieldFill) {
  const Int2 n{20, 14};
  const BoundaryFill fills[] = {
      BoundaryFill::copy(),
      BoundaryFill::fixed(-0.5f),
      BoundaryFill::stam(1),
      BoundaryFill::stam(2),
      BoundaryFill::no_slip(1.0f),
      BoundaryFill{{EdgeRule::kMirror, 0.0f},
                   {EdgeRule::kCopy, 0.0f},
                   {EdgeRule::kFixed, 0.0f},
                   {EdgeRule::kMirror, -0.7f}},
      BoundaryFill{{EdgeRule::kParabolic, 1.0f},
                   {EdgeRule::kCopy, 0.0f},
                   {EdgeRule::kMirror, 0.0f},
                   {EdgeRule::kParabolic, -0.5f}},
  };
  const Box2 tiles[] = {
      {{-1, -1}, {6, 5}},  {{5, -1}, {12, 4}}, {{14, -1}, {21, 6}}, {{-1, 4}, {5, 10}},
      {{15, 5}, {21, 11}}, {{-1, 9}, {8, 15}}, {{8, 10}, {13, 15}}, {{16, 10}, {21, 15}},
      {{4, 3}, {12, 9}},  // interior tile: nothing to fill
  };
  int case_index = 0;
  for (const BoundaryFill& fill : fills) {
    const FieldF original = random_field(n, 10 + case_index++);
    FieldF whole = original;
    fill_boundary(whole.view(), n, fill);
    for (const Box2& box : tiles) {
      // The tile's store holds only its box; poison-free copy of the unfilled field.
      FieldF store(box.size(), 0);
      View<float> tile(store.raw(), store.stride(), box);
      copy_box(original.view(), tile, box);
      fill_boundary(tile, n, fill);
      for (int y = box.min.y; y < box.max.y; ++y)
        for (int x = box.min.x; x < box.max.x; ++x)
          ASSERT_EQ(tile(x, y), whole(x, y)) << "tile " << box << " cell " << x << "," << y;
    }
  }
}

TEST(Boundary, PeriodicOnATileLeavesTheWrapToTheDma) {
  const Int2 n{10, 10};
  FieldF f = random_field(n, 5);
  const Box2 box{{-1, -1}, {4, 4}};
  FieldF store(box.size(), 0);
  View<float> tile(store.raw(), store.stride(), box);
  copy_box(std::as_const(f).view(), tile, box);
  fill_boundary(tile, n, BoundaryFill::periodic());
  for (int y = box.min.y; y < box.max.y; ++y)
    for (int x = box.min.x; x < box.max.x; ++x) ASSERT_EQ(tile(x, y), f(x, y));
}

TEST(Boundary, ObstacleNoSlipAndCopy) {
  const Int2 n{8, 8};
  Field<uint8_t> solid(n, 1);
  for (int j = 3; j < 6; ++j)
    for (int i = 3; i < 6; ++i) solid(i, j) = 1;  // a 3x3 block; (4,4) has no fluid neighbour
  for (ObstacleRule rule : {ObstacleRule::kNoSlip, ObstacleRule::kCopy, ObstacleRule::kZero}) {
    const FieldF original = random_field(n, 6);
    FieldF f = original;
    fill_obstacle(f.view(), solid.view(), f.interior(), rule);
    const float sign = rule == ObstacleRule::kNoSlip ? -1.0f : 1.0f;
    // Edge cell (3, 4): one fluid neighbour (2, 4).
    EXPECT_FLOAT_EQ(f(3, 4), rule == ObstacleRule::kZero ? 0.0f : sign * original(2, 4));
    // Corner cell (3, 3): fluid neighbours (2, 3) and (3, 2).
    EXPECT_FLOAT_EQ(f(3, 3), rule == ObstacleRule::kZero
                                 ? 0.0f
                                 : sign * 0.5f * (original(2, 3) + original(3, 2)));
    EXPECT_EQ(f(4, 4), 0.0f);  // buried
    for (int j = 0; j < n.y; ++j)
      for (int i = 0; i < n.x; ++i)
        if (!solid(i, j)) {
          ASSERT_EQ(f(i, j), original(i, j));  // fluid untouched
        }
    // No-slip: the face between the fluid cell and the solid one carries zero velocity.
    if (rule == ObstacleRule::kNoSlip) {
      EXPECT_FLOAT_EQ(0.5f * (f(3, 4) + f(2, 4)), 0.0f);
    }

    // Tile-local fill over a sub-region equals the whole-field fill there.
    const Box2 region{{2, 2}, {5, 5}};
    FieldF store(region.grown(1).size(), 0);
    View<float> tile(store.raw(), store.stride(), region.grown(1));
    copy_box(original.view(), tile, region.grown(1));
    fill_obstacle(tile, solid.view(), region, rule);
    for (int y = region.min.y; y < region.max.y; ++y)
      for (int x = region.min.x; x < region.max.x; ++x) ASSERT_EQ(tile(x, y), f(x, y));
  }
}

}  // namespace
}  // namespace ardcell
