// The fixed-camera render of a field on a surface (host/surface/surface_render.h): a constant
// field draws its colour, shaded, inside the outline and the background outside; the depth buffer
// shows the near side (a field that is 1 on the half facing the camera draws bright, turned away,
// dark); a quarter turn of the camera around a symmetric surface covers as many pixels.
#include "host/surface/surface_render.h"

#include <gtest/gtest.h>

#include "host/surface/patch_metric.h"
#include "host/surface/procedural_mesh.h"

namespace ardcell {
namespace {

struct Scene {
  LimitSurface surface;
  PatchGrid grid;
};

Scene cube_sphere(int n) {
  Scene s;
  EXPECT_TRUE(LimitSurface::build(cube_mesh(2), {}, s.surface));
  s.grid = PatchGrid(s.surface.topology(), n, CornerGhosts::kDiagonalExtrapolate);
  return s;
}

SurfaceColours gray() {
  SurfaceColours o;
  o.colormap = Colormap::kGray;
  return o;
}

bool is_background(const uint8_t* px, const SurfaceView& v) {
  return px[0] == v.background.r && px[1] == v.background.g && px[2] == v.background.b;
}

TEST(SurfaceRender, ConstantFieldIsItsColourShadedInsideTheOutline) {
  const Scene s = cube_sphere(8);
  SurfaceView view;
  view.width = 160, view.height = 120;
  const ImageRgb8 image = render_surface(s.surface, s.grid, s.grid.make_field(1.0), gray(), view);
  ASSERT_EQ(image.width, 160);
  ASSERT_EQ(image.height, 120);
  for (int y : {0, 119})
    for (int x : {0, 159}) EXPECT_TRUE(is_background(image.row(y) + 3 * x, view)) << x << "," << y;
  int covered = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const uint8_t* px = image.row(y) + 3 * x;
      if (is_background(px, view)) continue;
      ++covered;
      ASSERT_EQ(px[0], px[1]);  // gray, white shaded
      ASSERT_EQ(px[1], px[2]);
      ASSERT_GE(px[0], 63) << x << "," << y;  // 0.25 ambient
    }
  // The outline fills 90% of the smaller side: a rounded shape about 108 pixels across.
  EXPECT_GT(covered, 108 * 108 / 2);
  EXPECT_LT(covered, 120 * 120);
}

// Fraction of the covered pixels that are darker than the ambient floor of white (field 0).
double dark_fraction(const Scene& s, const PatchField& field, double azimuth) {
  SurfaceView view;
  view.width = 200, view.height = 200, view.azimuth_deg = azimuth, view.elevation_deg = 0;
  const ImageRgb8 image = render_surface(s.surface, s.grid, field, gray(), view);
  int covered = 0, dark = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const uint8_t* px = image.row(y) + 3 * x;
      if (is_background(px, view)) continue;
      ++covered;
      dark += px[0] < 32;
    }
  return double(dark) / covered;
}

TEST(SurfaceRender, TheDepthBufferShowsTheNearSide) {
  const Scene s = cube_sphere(8);
  const auto x = cell_positions(s.surface, s.grid)[0];
  PatchField field = s.grid.make_field();
  for (std::size_t k = 0; k < field.size(); ++k) field[k] = x[k] > 0 ? 1.0 : 0.0;
  EXPECT_LT(dark_fraction(s, field, 0), 0.02);    // looking at the x > 0 half
  EXPECT_GT(dark_fraction(s, field, 180), 0.98);  // at the x < 0 half
}

TEST(SurfaceRender, AQuarterTurnAroundASymmetricSurfaceCoversAsMuch) {
  const Scene s = cube_sphere(8);
  SurfaceView a, b;
  a.width = b.width = a.height = b.height = 200;
  a.azimuth_deg = 10, b.azimuth_deg = 100;
  const PatchField one = s.grid.make_field(1.0);
  const auto covered = [&](const SurfaceView& v) {
    const ImageRgb8 image = render_surface(s.surface, s.grid, one, gray(), v);
    int n = 0;
    for (int y = 0; y < image.height; ++y)
      for (int x = 0; x < image.width; ++x) n += !is_background(image.row(y) + 3 * x, v);
    return n;
  };
  const int ca = covered(a), cb = covered(b);
  EXPECT_NEAR(ca, cb, 0.01 * ca);
}

}  // namespace
}  // namespace ardcell
