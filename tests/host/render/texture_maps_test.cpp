// Height and normal maps (host/render/texture_maps.h): a flat field is (128, 128, 255) and
// mid-grey; a periodic sine's normals follow its slope and wrap; heights span the full range;
// non-finite cells take their stated heights and never make a NaN normal.
#include "host/render/texture_maps.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace ardcell {
namespace {

FieldF filled(Int2 size, float v) {
  FieldF f(size, 1);
  for (int y = 0; y < size.y; ++y)
    for (int x = 0; x < size.x; ++x) f(x, y) = v;
  return f;
}

const uint8_t* pixel(const ImageRgb8& im, int col, int row) { return im.row(row) + 3 * col; }

TEST(TextureMaps, ConstantFieldIsFlatAndMidGrey) {
  const FieldF f = filled({16, 8}, 3.5f);
  ImageRgb8 n;
  normal_map(f, {}, n);
  ASSERT_EQ(n.width, 16);
  ASSERT_EQ(n.height, 8);
  for (int r = 0; r < 8; ++r)
    for (int c = 0; c < 16; ++c) {
      const uint8_t* p = pixel(n, c, r);
      EXPECT_EQ(p[0], 128);
      EXPECT_EQ(p[1], 128);
      EXPECT_EQ(p[2], 255);
    }
  ImageGray8 h8;
  ImageGray16 h16;
  height_map_8(f, h8);
  height_map_16(f, h16);
  for (uint8_t v : h8.pixels) EXPECT_EQ(v, 128);
  for (uint16_t v : h16.pixels) EXPECT_EQ(v, 32768);
}

TEST(TextureMaps, PeriodicSineNormalsFollowTheSlopeAndWrap) {
  constexpr int n = 32;
  const double a = 2 * std::numbers::pi / n;
  FieldF f({n, 4}, 1);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < n; ++x) f(x, y) = float(std::sin(a * x));
  const double strength = 4.0;
  ImageRgb8 im;
  normal_map(f, {strength, true}, im);
  const HeightRange range = height_range(f);
  const double span = double(range.hi) - double(range.lo);
  for (int x = 0; x < n; ++x) {
    // Periodic central difference of the normalized height: cos(a x) sin(a) / span.
    const double slope = std::cos(a * x) * std::sin(a) / span;
    const double gx = -strength * slope, inv = 1 / std::sqrt(gx * gx + 1);
    const uint8_t* p = pixel(im, x, 1);
    EXPECT_NEAR(p[0], (gx * inv * 0.5 + 0.5) * 255, 1.0) << "x=" << x;
    EXPECT_EQ(p[1], 128) << "x=" << x;
    EXPECT_NEAR(p[2], (inv * 0.5 + 0.5) * 255, 1.0) << "x=" << x;
    // Rising height (cos > 0) tilts the normal towards -x.
    if (std::cos(a * x) > 0.1) {
      EXPECT_LT(p[0], 128) << "x=" << x;
    }
    if (std::cos(a * x) < -0.1) {
      EXPECT_GT(p[0], 128) << "x=" << x;
    }
  }
  // The wrap: the first column is the steepest rise (it reads column n - 1), and the last
  // column mirrors the second (it reads column 0), as in an endless sine.
  EXPECT_EQ(pixel(im, 0, 0)[0], *std::min_element(im.rgb.begin(), im.rgb.end()));
  EXPECT_EQ(pixel(im, n - 1, 0)[0], pixel(im, 1, 0)[0]);
  // The map tiles: shifting the field by k columns shifts the map by k columns, exactly.
  for (int k : {1, 5, 31}) {
    FieldF g({n, 4}, 1);
    for (int y = 0; y < 4; ++y)
      for (int x = 0; x < n; ++x) g(x, y) = f((x + k) % n, y);
    ImageRgb8 shifted;
    normal_map(g, {strength, true}, shifted);
    for (int r = 0; r < 4; ++r)
      for (int x = 0; x < n; ++x)
        for (int c = 0; c < 3; ++c)
          ASSERT_EQ(pixel(shifted, x, r)[c], pixel(im, (x + k) % n, r)[c]) << k << " " << x;
  }
  // One-sided differences at the border make a different, non-tiling map there: a cosine's
  // crest at column 0 is flat only when the difference wraps.
  FieldF c({n, 4}, 1);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < n; ++x) c(x, y) = float(std::cos(a * x));
  ImageRgb8 wrapped, clamped;
  normal_map(c, {strength, true}, wrapped);
  normal_map(c, {strength, false}, clamped);
  EXPECT_EQ(pixel(wrapped, 0, 0)[0], 128);
  EXPECT_GT(pixel(clamped, 0, 0)[0], 128);
  EXPECT_EQ(pixel(clamped, n / 2 + 3, 0)[0], pixel(wrapped, n / 2 + 3, 0)[0]);
}

TEST(TextureMaps, NormalsFollowTheGridsUpwardYAxis) {
  // Height rising with y: the normal leans towards -y (green below 128). Row 0 is the top.
  FieldF f({8, 8}, 1);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) f(x, y) = float(y);
  ImageRgb8 im;
  normal_map(f, {4.0, false}, im);
  EXPECT_EQ(pixel(im, 3, 3)[0], 128);
  EXPECT_LT(pixel(im, 3, 3)[1], 128);
  ImageGray8 h;
  height_map_8(f, h);
  EXPECT_EQ(h.pixels[0], 255);                 // top row: y = 7, the highest
  EXPECT_EQ(h.pixels[std::size_t(7 * 8)], 0);  // bottom row: y = 0
}

TEST(TextureMaps, HeightMapsSpanTheFullRange) {
  FieldF f({10, 3}, 1);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 10; ++x) f(x, y) = -2.0f + 0.37f * float(x + 10 * y);
  ImageGray8 h8;
  ImageGray16 h16;
  const HeightRange r = height_map_8(f, h8);
  height_map_16(f, h16);
  EXPECT_FLOAT_EQ(r.lo, -2.0f);
  EXPECT_EQ(r.non_finite, 0);
  EXPECT_EQ(*std::min_element(h8.pixels.begin(), h8.pixels.end()), 0);
  EXPECT_EQ(*std::max_element(h8.pixels.begin(), h8.pixels.end()), 255);
  EXPECT_EQ(*std::min_element(h16.pixels.begin(), h16.pixels.end()), 0);
  EXPECT_EQ(*std::max_element(h16.pixels.begin(), h16.pixels.end()), 65535);
  // Monotonic along a row, and the 16-bit one finer than the 8-bit one.
  for (int x = 1; x < 10; ++x) {
    EXPECT_GT(h16.pixels[std::size_t(x)], h16.pixels[std::size_t(x - 1)]);
    EXPECT_NEAR(h16.pixels[std::size_t(x)] / 257.0, h8.pixels[std::size_t(x)], 0.51);
  }
}

TEST(TextureMaps, NonFiniteCellsTakeFixedHeightsAndNeverANanNormal) {
  constexpr float kInf = std::numeric_limits<float>::infinity();
  // Rule: left out of the range; NaN 0.5, +inf 1, -inf 0.
  FieldF f = filled({8, 8}, 1.0f);
  f(2, 2) = std::numeric_limits<float>::quiet_NaN();
  ImageRgb8 n;
  const HeightRange r = normal_map(f, {4.0, true}, n);
  EXPECT_EQ(r.non_finite, 1);
  EXPECT_EQ(r.lo, 1.0f);
  EXPECT_EQ(r.hi, 1.0f);
  // A constant field is mid-height everywhere, and so is its NaN: still flat.
  for (int i = 0; i < 64; ++i) {
    EXPECT_EQ(n.rgb[std::size_t(3 * i)], 128);
    EXPECT_EQ(n.rgb[std::size_t(3 * i + 2)], 255);
  }
  f(5, 5) = kInf;
  f(6, 1) = -kInf;
  ImageGray8 h8;
  ImageGray16 h16;
  EXPECT_EQ(height_map_8(f, h8).non_finite, 3);
  height_map_16(f, h16);
  auto at8 = [&](int x, int y) { return h8.pixels[std::size_t((7 - y) * 8 + x)]; };
  auto at16 = [&](int x, int y) { return h16.pixels[std::size_t((7 - y) * 8 + x)]; };
  EXPECT_EQ(at8(2, 2), 128);
  EXPECT_EQ(at8(5, 5), 255);
  EXPECT_EQ(at8(6, 1), 0);
  EXPECT_EQ(at16(5, 5), 65535);
  EXPECT_EQ(at16(6, 1), 0);
  // The normals around +inf lean away from it, with finite components: z never 0 or NaN.
  normal_map(f, {1e30, true}, n);
  for (int i = 0; i < 64; ++i) EXPECT_GE(n.rgb[std::size_t(3 * i + 2)], 127);
  EXPECT_GT(pixel(n, 6, 7 - 5)[0], 128);  // right of the peak: leans towards +x
  EXPECT_LT(pixel(n, 4, 7 - 5)[0], 128);
  // No finite value at all, and a NaN strength: still mid-grey and flat.
  const FieldF nan = filled({4, 4}, std::numeric_limits<float>::quiet_NaN());
  normal_map(nan, {std::nan(""), true}, n);
  for (int i = 0; i < 16; ++i) EXPECT_EQ(n.rgb[std::size_t(3 * i + 2)], 255);
  height_map_8(nan, h8);
  for (uint8_t v : h8.pixels) EXPECT_EQ(v, 128);
}

TEST(TextureMaps, OneCellWideFieldsHaveNoSlopeAlongThatAxis) {
  const FieldF f = filled({1, 5}, 2.0f);
  ImageRgb8 n;
  normal_map(f, {}, n);
  ASSERT_EQ(n.width, 1);
  EXPECT_EQ(pixel(n, 0, 2)[2], 255);
}

}  // namespace
}  // namespace ardcell
