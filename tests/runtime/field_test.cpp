#include "runtime/field.h"

#include <gtest/gtest.h>

#include <cstdint>

namespace ardcell {
namespace {

TEST(Box2, AreaGrowIntersect) {
  const Box2 b{{-2, -1}, {5, 3}};
  EXPECT_EQ(b.width(), 7);
  EXPECT_EQ(b.height(), 4);
  EXPECT_EQ(b.area(), 28);
  EXPECT_TRUE(b.contains(Int2{-2, -1}));
  EXPECT_FALSE(b.contains(Int2{5, 0}));
  EXPECT_EQ(b.grown(1), (Box2{{-3, -2}, {6, 4}}));
  EXPECT_EQ(b.intersected(Box2{{0, 0}, {10, 10}}), (Box2{{0, 0}, {5, 3}}));
  EXPECT_TRUE(b.intersected(Box2{{6, 6}, {7, 7}}).empty());
  EXPECT_EQ(Box2{}.area(), 0);
}

TEST(Field, HaloIndexingReachesEveryCellOnce) {
  FieldF f(Int2{13, 7}, 3);
  EXPECT_EQ(f.with_halo(), (Box2{{-3, -3}, {16, 10}}));
  // Write a distinct value into every cell of interior + halo, then read them all back.
  for (int y = -3; y < 10; ++y)
    for (int x = -3; x < 16; ++x) f(x, y) = float(1000 * y + x);
  for (int y = -3; y < 10; ++y)
    for (int x = -3; x < 16; ++x) ASSERT_EQ(f(x, y), float(1000 * y + x));
  // row(y)[x] is the same cell as f(x, y), negative x included.
  EXPECT_EQ(f.row(-2)[-3], f(-3, -2));
  EXPECT_EQ(&f.row(4)[15], &f(15, 4));
}

TEST(Field, RowsArePaddedAnd128ByteAligned) {
  for (int nx : {1, 31, 32, 33, 127, 128, 129}) {
    FieldF f(Int2{nx, 4}, 2);
    EXPECT_EQ(f.stride() * sizeof(float) % kRowAlignBytes, 0u) << nx;
    EXPECT_GE(f.stride(), nx + 4);
    for (int y = -2; y < 6; ++y)
      EXPECT_EQ(reinterpret_cast<std::uintptr_t>(&f(-2, y)) % kRowAlignBytes, 0u);
  }
}

TEST(Field, DeepCopyAndFill) {
  FieldF a(Int2{5, 5}, 1);
  a.fill(2.5f);
  FieldF b = a;
  b(0, 0) = 7.f;
  EXPECT_EQ(a(0, 0), 2.5f);
  EXPECT_EQ(b(-1, -1), 2.5f);
  a = b;
  EXPECT_EQ(a(0, 0), 7.f);
}

TEST(View, CropSharesMemoryAndKeepsGlobalCoordinates) {
  FieldF f(Int2{10, 8}, 2);
  const Box2 box{{-1, 3}, {4, 7}};
  ViewF v = f.view(box);
  EXPECT_EQ(v.box(), box);
  v(-1, 3) = 42.f;
  v(3, 6) = 43.f;
  EXPECT_EQ(f(-1, 3), 42.f);
  EXPECT_EQ(f(3, 6), 43.f);
  EXPECT_EQ(&v.row(5)[0], &f(0, 5));
  ConstViewF c = v;  // views of T convert to views of const T
  EXPECT_EQ(c(3, 6), 43.f);
  ViewF inner = v.crop(Box2{{0, 4}, {2, 5}});
  inner(1, 4) = -1.f;
  EXPECT_EQ(f(1, 4), -1.f);
}

TEST(View, CopyBoxBetweenFieldsOfDifferentHalo) {
  FieldF a(Int2{6, 6}, 1), b(Int2{6, 6}, 4);
  for (int y = -1; y < 7; ++y)
    for (int x = -1; x < 7; ++x) a(x, y) = float(x * 10 + y);
  const Box2 box{{-1, -1}, {7, 7}};
  copy_box<float>(a.view(), b.view(), box);
  for (int y = -1; y < 7; ++y)
    for (int x = -1; x < 7; ++x) EXPECT_EQ(b(x, y), a(x, y));
  EXPECT_EQ(b(-2, 0), 0.f);
}

}  // namespace
}  // namespace ardcell
