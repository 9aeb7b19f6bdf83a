// Frame rendering: values land on the right pixels (y up), ranges and colormaps are applied as
// documented, derived fields are exact on fields where central differences are exact,
// non-finite cells never leak into the colour range, and rendering allocates nothing.
#include "host/render/frame_render.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <new>

#include "tests/support/alloc_counter.h"

namespace ardcell {
namespace {

SimState make_state(Int2 size, double h = 1.0) {
  SimState s;
  s.size = size;
  s.h = h;
  s.u = FieldF(size, 1);
  s.v = FieldF(size, 1);
  s.p = FieldF(size, 1);
  s.dye = FieldF(size, 1);
  return s;
}

Rgb8 pixel(const ImageRgb8& img, int x, int y) {
  const uint8_t* p = img.row(y) + 3 * x;
  return {p[0], p[1], p[2]};
}

TEST(FrameRenderTest, FieldNamesRoundTrip) {
  for (FrameField f : {FrameField::kDye, FrameField::kSpeed, FrameField::kVorticity,
                       FrameField::kPressure, FrameField::kA, FrameField::kB}) {
    FrameField back{};
    ASSERT_TRUE(parse_frame_field(frame_field_name(f), back));
    EXPECT_EQ(back, f);
  }
  FrameField f{};
  EXPECT_FALSE(parse_frame_field("temperature", f));
}

TEST(FrameRenderTest, GrayDyeMapsValuesExactlyWithYUp) {
  SimState s = make_state({6, 4});
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 6; ++x) s.dye(x, y) = float(10 * x + 50 * y) / 255.0f;
  RenderSettings r = default_render_settings(FrameField::kDye);
  r.colormap = Colormap::kGray;
  ImageRgb8 img;
  img.resize(6, 4);
  const RenderStats st = render_frame(s, r, img);
  EXPECT_EQ(st.non_finite, 0);
  EXPECT_EQ(st.lo, 0.0f);
  EXPECT_EQ(st.hi, 1.0f);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 6; ++x) {
      const uint8_t g = uint8_t(10 * x + 50 * y);
      // Image row 0 is the top of the domain, y = ny - 1.
      EXPECT_EQ(pixel(img, x, 3 - y), (Rgb8{g, g, g})) << x << "," << y;
    }
}

TEST(FrameRenderTest, AutoRangeUsesMinAndMaxAndIgnoresNonFiniteCells) {
  SimState s = make_state({5, 5});
  for (int y = 0; y < 5; ++y)
    for (int x = 0; x < 5; ++x) s.p(x, y) = float(x + y) - 3.0f;  // -3 .. 5
  s.p(0, 0) = std::numeric_limits<float>::quiet_NaN();
  s.p(4, 4) = std::numeric_limits<float>::infinity();
  s.p(2, 0) = -std::numeric_limits<float>::infinity();
  RenderSettings r = default_render_settings(FrameField::kPressure);
  EXPECT_EQ(r.range, RangeMode::kAuto);
  r.colormap = Colormap::kGray;
  ImageRgb8 img;
  img.resize(5, 5);
  const RenderStats st = render_frame(s, r, img);
  EXPECT_EQ(st.non_finite, 3);
  EXPECT_EQ(st.lo, -2.0f);  // (1, 0) and (0, 1)
  EXPECT_EQ(st.hi, 4.0f);   // (3, 4) and (4, 3)
  EXPECT_EQ(pixel(img, 0, 4), kNonFiniteRgb);
  EXPECT_EQ(pixel(img, 4, 0), kNonFiniteRgb);
  EXPECT_EQ(pixel(img, 2, 4), kNonFiniteRgb);
  EXPECT_EQ(pixel(img, 1, 4), (Rgb8{0, 0, 0}));        // -2: low end
  EXPECT_EQ(pixel(img, 3, 0), (Rgb8{255, 255, 255}));  // 4: high end
}

TEST(FrameRenderTest, AllNonFiniteFieldStillRendersOnlyTheFixedColour) {
  SimState s = make_state({3, 2});
  s.dye.fill(std::numeric_limits<float>::quiet_NaN());
  for (RangeMode mode : {RangeMode::kFixed, RangeMode::kAuto, RangeMode::kAutoSymmetric}) {
    RenderSettings r = default_render_settings(FrameField::kDye);
    r.range = mode;
    ImageRgb8 img;
    img.resize(3, 2);
    const RenderStats st = render_frame(s, r, img);
    EXPECT_EQ(st.non_finite, 6);
    for (int y = 0; y < 2; ++y)
      for (int x = 0; x < 3; ++x) EXPECT_EQ(pixel(img, x, y), kNonFiniteRgb);
  }
}

TEST(FrameRenderTest, SpeedIsTheVelocityMagnitude) {
  SimState s = make_state({3, 3});
  s.u.fill(3.0f);
  s.v.fill(-4.0f);
  EXPECT_EQ(frame_field_value(s, FrameField::kSpeed, 1, 2), 5.0f);
  RenderSettings r = default_render_settings(FrameField::kSpeed);
  ImageRgb8 img;
  img.resize(3, 3);
  const RenderStats st = render_frame(s, r, img);
  EXPECT_EQ(st.lo, 0.0f);
  EXPECT_EQ(st.hi, 5.0f);
  EXPECT_EQ(pixel(img, 0, 0), colormap_lut(r.colormap)[255]);
}

TEST(FrameRenderTest, VorticityOfSolidBodyRotationIsTwiceTheAngularVelocity) {
  // u = -w (y - yc), v = w (x - xc): curl = 2 w everywhere, and differences of a linear field
  // are exact, at the border too.
  const double h = 0.125, w = 0.75;
  SimState s = make_state({7, 5}, h);
  for (int y = 0; y < 5; ++y)
    for (int x = 0; x < 7; ++x) {
      s.u(x, y) = float(-w * (y - 2) * h);
      s.v(x, y) = float(w * (x - 3) * h);
    }
  for (int y = 0; y < 5; ++y)
    for (int x = 0; x < 7; ++x)
      EXPECT_NEAR(frame_field_value(s, FrameField::kVorticity, x, y), 2 * w, 1e-5) << x << y;
  // A symmetric range around a constant positive curl puts every pixel at the red end.
  RenderSettings r = default_render_settings(FrameField::kVorticity);
  EXPECT_EQ(r.colormap, Colormap::kRdBu);
  ImageRgb8 img;
  img.resize(7, 5);
  const RenderStats st = render_frame(s, r, img);
  EXPECT_NEAR(st.hi, 2 * w, 1e-5);
  EXPECT_NEAR(st.lo, -2 * w, 1e-5);
  EXPECT_EQ(pixel(img, 6, 4), colormap_lut(Colormap::kRdBu)[255]);
}

TEST(FrameRenderTest, ZeroFieldWithSymmetricRangeIsTheMapCentre) {
  SimState s = make_state({4, 4});
  RenderSettings r = default_render_settings(FrameField::kVorticity);
  ImageRgb8 img;
  img.resize(4, 4);
  render_frame(s, r, img);
  EXPECT_EQ(pixel(img, 2, 2), colormap_lut(Colormap::kRdBu)[128]);
}

TEST(FrameRenderTest, ObstacleCellsUseTheObstacleColourAndStayOutOfTheRange) {
  SimState s = make_state({4, 3});
  s.obstacle = Field<uint8_t>({4, 3}, 1);
  s.obstacle(1, 1) = 1;
  s.p(1, 1) = 1000.0f;
  s.p(0, 0) = 1.0f;
  RenderSettings r = default_render_settings(FrameField::kPressure);
  ImageRgb8 img;
  img.resize(4, 3);
  const RenderStats st = render_frame(s, r, img);
  EXPECT_EQ(st.hi, 1.0f);
  EXPECT_EQ(pixel(img, 1, 1), kObstacleRgb);
}

TEST(FrameRenderTest, AvailabilityFollowsTheAllocatedFields) {
  SimState s = make_state({4, 4});
  EXPECT_TRUE(frame_field_available(s, FrameField::kDye));
  EXPECT_TRUE(frame_field_available(s, FrameField::kVorticity));
  EXPECT_FALSE(frame_field_available(s, FrameField::kA));
  s.A = FieldF({4, 4}, 1);
  EXPECT_TRUE(frame_field_available(s, FrameField::kA));
  EXPECT_FALSE(frame_field_available(s, FrameField::kB));
}

TEST(FrameRenderTest, RenderingAllocatesNothing) {
  SimState s = make_state({64, 48});
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x) {
      s.u(x, y) = std::sin(0.1f * x);
      s.v(x, y) = std::cos(0.2f * y);
      s.dye(x, y) = 0.01f * x;
    }
  ImageRgb8 img;
  img.resize(64, 48);
  render_frame(s, default_render_settings(FrameField::kDye), img);  // builds the tables once
  for (Colormap m : {Colormap::kGray, Colormap::kViridis, Colormap::kMagma, Colormap::kRdBu})
    (void)colormap_lut(m);
  const long before = g_allocations.load();
  for (FrameField f :
       {FrameField::kDye, FrameField::kSpeed, FrameField::kVorticity, FrameField::kPressure})
    render_frame(s, default_render_settings(f), img);
  EXPECT_EQ(g_allocations.load() - before, 0);
}

}  // namespace
}  // namespace ardcell
