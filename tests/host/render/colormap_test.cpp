// Colormaps: the published end points, perceptual ordering (CIELAB lightness strictly rising
// for the sequential maps), smoothness of the tables (a mistyped entry would show as a jump),
// the diverging map's white centre, and non-finite values drawn in the fixed colour.
#include "host/render/colormap.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace ardcell {
namespace {

struct Lab {
  double L, a, b;
};

double srgb_to_linear(double c) {
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

// sRGB (D65) to CIELAB.
Lab to_lab(double r, double g, double b) {
  r = srgb_to_linear(r);
  g = srgb_to_linear(g);
  b = srgb_to_linear(b);
  const double X = (0.4124564 * r + 0.3575761 * g + 0.1804375 * b) / 0.95047;
  const double Y = 0.2126729 * r + 0.7151522 * g + 0.0721750 * b;
  const double Z = (0.0193339 * r + 0.1191920 * g + 0.9503041 * b) / 1.08883;
  auto f = [](double t) {
    return t > 216.0 / 24389 ? std::cbrt(t) : (24389.0 / 27 * t + 16) / 116;
  };
  return {116 * f(Y) - 16, 500 * (f(X) - f(Y)), 200 * (f(Y) - f(Z))};
}

double delta_e(const Lab& p, const Lab& q) {
  return std::sqrt((p.L - q.L) * (p.L - q.L) + (p.a - q.a) * (p.a - q.a) +
                   (p.b - q.b) * (p.b - q.b));
}

TEST(ColormapTest, NamesRoundTripAndUnknownNamesAreRefused) {
  for (Colormap m : {Colormap::kGray, Colormap::kViridis, Colormap::kMagma, Colormap::kRdBu}) {
    Colormap back{};
    ASSERT_TRUE(parse_colormap(colormap_name(m), back));
    EXPECT_EQ(back, m);
    EXPECT_NE(colormap_names().find(colormap_name(m)), std::string_view::npos);
  }
  Colormap m{};
  EXPECT_FALSE(parse_colormap("jet", m));
  EXPECT_FALSE(parse_colormap("", m));
  EXPECT_FALSE(parse_colormap("Viridis", m));
}

TEST(ColormapTest, PublishedEndPoints) {
  // viridis #440154 .. #fde725, magma #000004 .. #fcfdbf (matplotlib's documented hex values).
  const auto& v = colormap_lut(Colormap::kViridis);
  EXPECT_EQ(v[0], (Rgb8{0x44, 0x01, 0x54}));
  EXPECT_EQ(v[255], (Rgb8{0xfd, 0xe7, 0x25}));
  const auto& m = colormap_lut(Colormap::kMagma);
  EXPECT_EQ(m[0], (Rgb8{0x00, 0x00, 0x04}));
  EXPECT_EQ(m[255], (Rgb8{0xfc, 0xfd, 0xbf}));
  const auto& g = colormap_lut(Colormap::kGray);
  for (int i = 0; i < 256; ++i) EXPECT_EQ(g[i], (Rgb8{uint8_t(i), uint8_t(i), uint8_t(i)}));
}

TEST(ColormapTest, SequentialTablesRiseInLightnessAndAreSmooth) {
  for (Colormap map : {Colormap::kViridis, Colormap::kMagma}) {
    const auto table = colormap_source_table(map);
    ASSERT_EQ(table.size(), 256u);
    std::vector<double> steps;
    Lab prev = to_lab(table[0][0], table[0][1], table[0][2]);
    for (std::size_t i = 1; i < table.size(); ++i) {
      const Lab lab = to_lab(table[i][0], table[i][1], table[i][2]);
      EXPECT_GT(lab.L, prev.L) << colormap_name(map) << " entry " << i;
      steps.push_back(delta_e(lab, prev));
      prev = lab;
    }
    // Perceptually uniform: every step is close to the median step. A digit typed wrong
    // anywhere in the table breaks this.
    std::vector<double> sorted = steps;
    std::sort(sorted.begin(), sorted.end());
    const double median = sorted[sorted.size() / 2];
    for (std::size_t i = 0; i < steps.size(); ++i) {
      EXPECT_LT(steps[i], 2.0 * median) << colormap_name(map) << " step " << i + 1;
      EXPECT_GT(steps[i], 0.3 * median) << colormap_name(map) << " step " << i + 1;
    }
  }
  EXPECT_TRUE(colormap_source_table(Colormap::kGray).empty());
}

TEST(ColormapTest, DivergingMapIsDarkAtBothEndsAndWhiteInTheMiddle) {
  EXPECT_TRUE(colormap_is_diverging(Colormap::kRdBu));
  EXPECT_FALSE(colormap_is_diverging(Colormap::kViridis));
  const auto& lut = colormap_lut(Colormap::kRdBu);
  auto L = [&](int i) { return to_lab(lut[i].r / 255.0, lut[i].g / 255.0, lut[i].b / 255.0).L; };
  EXPECT_GT(L(127), 95.0);
  EXPECT_GT(L(128), 95.0);
  EXPECT_LT(L(0), 25.0);
  EXPECT_LT(L(255), 25.0);
  for (int i = 1; i < 128; ++i) EXPECT_GE(L(i), L(i - 1) - 1e-9) << i;
  for (int i = 129; i < 256; ++i) EXPECT_LE(L(i), L(i - 1) + 1e-9) << i;
  EXPECT_GT(lut[0].b, lut[0].r);      // negative: blue
  EXPECT_GT(lut[255].r, lut[255].b);  // positive: red
}

TEST(ColormapTest, LookupClampsAndDrawsNonFiniteInTheFixedColour) {
  const auto& lut = colormap_lut(Colormap::kViridis);
  EXPECT_EQ(colormap_at(lut, 0.0f), lut[0]);
  EXPECT_EQ(colormap_at(lut, 1.0f), lut[255]);
  EXPECT_EQ(colormap_at(lut, -5.0f), lut[0]);
  EXPECT_EQ(colormap_at(lut, 7.0f), lut[255]);
  EXPECT_EQ(colormap_at(lut, 0.5f), lut[128]);
  EXPECT_EQ(colormap_at(lut, 100.0f / 255.0f), lut[100]);
  for (float bad : {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
                    -std::numeric_limits<float>::infinity()})
    EXPECT_EQ(colormap_at(lut, bad), kNonFiniteRgb);
  EXPECT_EQ(colormap_at(lut, std::numeric_limits<float>::max()), lut[255]);
  // The fixed colour is in none of the maps, so it cannot be mistaken for data.
  for (Colormap m : {Colormap::kGray, Colormap::kViridis, Colormap::kMagma, Colormap::kRdBu})
    for (const Rgb8& c : colormap_lut(m)) ASSERT_NE(c, kNonFiniteRgb);
}

}  // namespace
}  // namespace ardcell
