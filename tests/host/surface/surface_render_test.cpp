// The fixed-camera render of a field on a surface (host/surface/surface_render.h): a constant
// field draws its colour, shaded, inside the outline and the background outside; the depth buffer
// shows the near side (a field that is 1 on the half facing the camera draws bright, turned away,
// dark); a quarter turn of the camera around a symmetric surface covers as many pixels; skipping
// the triangles that face away keeps the near side of a closed surface however it is wound, and
// skips nothing on an open one.
// SurfaceRenderer (the real-time loop's): a second frame of the same size allocates nothing;
// cell_at names the cell drawn at a pixel; the kSphere fit keeps the scale as the view turns; the
// caller's field, ghosts included, is left as it was.
#include "host/surface/surface_render.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

#include "host/surface/patch_metric.h"
#include "host/surface/procedural_mesh.h"
#include "runtime/row_executor.h"
#include "runtime/thread/thread_backend.h"
#include "tests/support/alloc_counter.h"

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

// The faces of `mesh` wound the other way: the same surface, its normals inward.
PolyMesh reversed(PolyMesh mesh) {
  for (int f = 0; f < mesh.face_count(); ++f)
    std::reverse(mesh.face_vertices.begin() + mesh.face_offsets[std::size_t(f)],
                 mesh.face_vertices.begin() + mesh.face_offsets[std::size_t(f) + 1]);
  return mesh;
}

// `b` moved by `dx` along x beside `a`, in one mesh of two pieces.
PolyMesh joined(PolyMesh a, const PolyMesh& b, double dx) {
  const int offset = int(a.points.size());
  for (auto p : b.points) a.points.push_back({p[0] + dx, p[1], p[2]});
  for (int f = 0; f < b.face_count(); ++f) {
    for (int k = 0; k < b.face_size(f); ++k) a.face_vertices.push_back(b.face(f)[k] + offset);
    a.face_offsets.push_back(int(a.face_vertices.size()));
  }
  return a;
}

Scene scene_of(PolyMesh mesh, int n) {
  Scene s;
  EXPECT_TRUE(LimitSurface::build(std::move(mesh), {}, s.surface));
  s.grid = PatchGrid(s.surface.topology(), n, CornerGhosts::kDiagonalExtrapolate);
  return s;
}

int covered_pixels(const Scene& s, const SurfaceView& view) {
  const ImageRgb8 image = render_surface(s.surface, s.grid, s.grid.make_field(1.0), gray(), view);
  int covered = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) covered += !is_background(image.row(y) + 3 * x, view);
  return covered;
}

// On a closed surface the renderer skips the triangles facing away, which side that is coming
// from the surface's own winding: wound inwards, the cube-sphere covers the same pixels and still
// shows its near side; two pieces wound opposite ways each show theirs.
TEST(SurfaceRender, AClosedSurfaceShowsItsNearSideWoundEitherWay) {
  const Scene outward = cube_sphere(8), inward = scene_of(reversed(cube_mesh(2)), 8);
  for (double azimuth : {0.0, 35.0, 120.0})
    for (double elevation : {-50.0, 25.0}) {
      SurfaceView view;
      view.width = view.height = 200;
      view.azimuth_deg = azimuth, view.elevation_deg = elevation;
      // Reversed faces parametrise the patches otherwise (the cells' diagonals run the other
      // way): a few pixels along the outline may differ by rounding.
      EXPECT_NEAR(covered_pixels(inward, view), covered_pixels(outward, view), 20)
          << azimuth << "," << elevation;
    }
  const auto x = cell_positions(inward.surface, inward.grid)[0];
  PatchField field = inward.grid.make_field();
  for (std::size_t k = 0; k < field.size(); ++k) field[k] = x[k] > 0 ? 1.0 : 0.0;
  EXPECT_LT(dark_fraction(inward, field, 0), 0.02);
  EXPECT_GT(dark_fraction(inward, field, 180), 0.98);

  // An outward cube at the origin beside an inward one at x = 3, against both outward: seen along
  // -y (azimuth 90) they cover the same pixels; seen along x, the near cube hides the far one.
  const Scene mixed = scene_of(joined(cube_mesh(2), reversed(cube_mesh(2)), 3), 6);
  const Scene same = scene_of(joined(cube_mesh(2), cube_mesh(2), 3), 6);
  SurfaceView side;
  side.width = 300, side.height = 150, side.azimuth_deg = 90, side.elevation_deg = 10;
  EXPECT_NEAR(covered_pixels(mixed, side), covered_pixels(same, side), 20);
  const auto mx = cell_positions(mixed.surface, mixed.grid)[0];
  PatchField right = mixed.grid.make_field();
  for (std::size_t k = 0; k < right.size(); ++k) right[k] = mx[k] > 1.5 ? 1.0 : 0.0;
  EXPECT_LT(dark_fraction(mixed, right, 0), 0.02);    // the inward cube, in front
  EXPECT_GT(dark_fraction(mixed, right, 180), 0.98);  // the outward one, in front
}

// An open surface skips nothing: a curved sheet of 3 x 3 quads (a trough, so that it has a side
// facing each way and encloses some volume against its mean) covers the same pixels seen from
// opposite directions (the same outline, mirrored), every one shaded no darker than the ambient.
TEST(SurfaceRender, AnOpenSurfaceShowsBothSides) {
  PolyMesh sheet;
  for (int j = 0; j <= 3; ++j)
    for (int i = 0; i <= 3; ++i)
      sheet.points.push_back({double(i), double(j), 0.4 * (i - 1.5) * (i - 1.5)});
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) {
      for (int v : {j * 4 + i, j * 4 + i + 1, (j + 1) * 4 + i + 1, (j + 1) * 4 + i})
        sheet.face_vertices.push_back(v);
      sheet.face_offsets.push_back(int(sheet.face_vertices.size()));
    }
  const Scene s = scene_of(sheet, 8);
  SurfaceView above, below;
  above.width = below.width = above.height = below.height = 160;
  above.azimuth_deg = 20, above.elevation_deg = 60;
  below.azimuth_deg = 200, below.elevation_deg = -60;
  const int up = covered_pixels(s, above), down = covered_pixels(s, below);
  EXPECT_GT(up, 160 * 160 / 10);
  EXPECT_NEAR(up, down, 0.01 * up);
  const ImageRgb8 image = render_surface(s.surface, s.grid, s.grid.make_field(1.0), gray(), below);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      if (!is_background(image.row(y) + 3 * x, below)) {
        ASSERT_GE(image.row(y)[3 * x], 63);
      }
}

Scene torus(int n) {
  Scene s;
  EXPECT_TRUE(LimitSurface::build(torus_mesh(8, 6, 2, 0.7), {}, s.surface));
  s.grid = PatchGrid(s.surface.topology(), n, CornerGhosts::kDiagonalExtrapolate);
  return s;
}

TEST(SurfaceRenderer, ASecondFrameOfTheSameSizeAllocatesNothing) {
  const Scene s = torus(8);
  SurfaceRenderer renderer(s.surface, s.grid);
  PatchField field = s.grid.make_field();
  for (std::size_t k = 0; k < field.size(); ++k) field[k] = std::sin(0.01 * double(k));
  SurfaceView view;
  view.width = 160, view.height = 120;
  ImageRgb8 image;
  const long first = g_allocations.load();
  renderer.render(field, SurfaceColours{}, view, image);  // sizes the image and the buffers
  const long before = g_allocations.load();
  EXPECT_GT(before - first, 0);  // the counter sees the renderer's allocations
  // Another view and fit of the same size, and a changed field: the live loop's frames.
  view.azimuth_deg = 80, view.elevation_deg = -30, view.fit = SurfaceFit::kSphere;
  field[s.grid.index(3, 2, 2)] = 5;
  renderer.render(field, SurfaceColours{}, view, image);
  renderer.render(field, gray(), view, image);
  EXPECT_EQ(g_allocations.load() - before, 0);
  EXPECT_EQ(image.width, 160);
  EXPECT_EQ(image.height, 120);
}

// Rasterised in bands of rows on a threads back end (the live window's), the image and the pick
// buffer are the serial renderer's, pixel for pixel (the torus at N = 16: enough corners for the
// corner pass to run on the workers too); a second frame, of another view, equals a new
// renderer's first (what the last frame drew is cleared) and allocates nothing.
TEST(SurfaceRenderer, BandsOnWorkersDrawTheSerialImage) {
  const Scene s = torus(16);
  PatchField field = s.grid.make_field();
  for (std::size_t k = 0; k < field.size(); ++k) field[k] = std::sin(0.01 * double(k));
  SurfaceView view;
  view.width = 160, view.height = 121;  // an odd height: uneven bands
  view.azimuth_deg = 50, view.elevation_deg = 40, view.fit = SurfaceFit::kSphere;
  SurfaceRenderer serial(s.surface, s.grid);
  ImageRgb8 expected;
  serial.render(field, SurfaceColours{}, view, expected);
  ThreadBackendOptions options;
  options.workers = 3;
  options.pin = false;
  ThreadBackend backend(options);
  RowExecutor executor(backend);
  SurfaceRenderer banded(s.surface, s.grid);
  banded.set_executor(executor);
  ImageRgb8 image;
  banded.render(field, SurfaceColours{}, view, image);
  EXPECT_EQ(image.rgb, expected.rgb);
  long picked = 0;
  for (int y = 0; y < view.height; ++y)
    for (int x = 0; x < view.width; ++x) {
      ASSERT_EQ(banded.cell_at(x, y), serial.cell_at(x, y)) << "pixel " << x << ", " << y;
      picked += banded.cell_at(x, y) >= 0;
    }
  EXPECT_GT(picked, view.width * view.height / 10) << "the torus covers part of the image";
  SurfaceView next = view;
  next.azimuth_deg = 45, next.elevation_deg = 80, next.fit = SurfaceFit::kOutline;
  SurfaceRenderer fresh(s.surface, s.grid);
  fresh.render(field, gray(), next, expected);
  const long before = g_allocations.load();
  banded.render(field, gray(), next, image);
  EXPECT_EQ(g_allocations.load() - before, 0);
  ImageRgb8 serial_next;
  serial.render(field, gray(), next, serial_next);
  EXPECT_EQ(image.rgb, expected.rgb);
  EXPECT_EQ(serial_next.rgb, expected.rgb);
  for (int y = 0; y < view.height; ++y)
    for (int x = 0; x < view.width; ++x) {
      ASSERT_EQ(banded.cell_at(x, y), fresh.cell_at(x, y)) << "pixel " << x << ", " << y;
      ASSERT_EQ(serial.cell_at(x, y), fresh.cell_at(x, y)) << "pixel " << x << ", " << y;
    }
}

// No cracks: the convex cube-sphere covers, in every row and every column of the image, one
// unbroken run of pixels (a pixel centre between two triangles sharing an edge is filled, and
// no triangle facing the camera is skipped).
TEST(SurfaceRenderer, AConvexSurfaceHasNoCracks) {
  const Scene s = cube_sphere(8);
  PatchField field = s.grid.make_field();
  SurfaceRenderer renderer(s.surface, s.grid);
  ImageRgb8 image;
  for (double azimuth : {35.0, 80.0, 200.0}) {
    SurfaceView view;
    view.width = 203, view.height = 151, view.azimuth_deg = azimuth;
    renderer.render(field, gray(), view, image);
    const auto runs = [&](int n, auto covered) {
      int count = 0;
      for (int i = 0; i < n; ++i) count += covered(i) && (i == 0 || !covered(i - 1));
      return count;
    };
    for (int y = 0; y < view.height; ++y)
      ASSERT_LE(runs(view.width, [&](int x) { return renderer.cell_at(x, y) >= 0; }), 1)
          << "row " << y << ", azimuth " << azimuth;
    for (int x = 0; x < view.width; ++x)
      ASSERT_LE(runs(view.height, [&](int y) { return renderer.cell_at(x, y) >= 0; }), 1)
          << "column " << x << ", azimuth " << azimuth;
  }
}

TEST(SurfaceRenderer, CellAtNamesTheCellDrawnAtAPixel) {
  const Scene s = cube_sphere(4);  // large cells: fewer of the near-white pixels are beside them
  SurfaceRenderer renderer(s.surface, s.grid);
  SurfaceView view;
  view.width = view.height = 300;

  // A constant field: every drawn pixel names a cell, the background none.
  ImageRgb8 image;
  renderer.render(s.grid.make_field(1.0), gray(), view, image);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      ASSERT_EQ(renderer.cell_at(x, y) == -1, is_background(image.row(y) + 3 * x, view))
          << x << "," << y;
  EXPECT_EQ(renderer.cell_at(0, 0), -1);  // a corner: background
  EXPECT_EQ(renderer.cell_at(-1, 100), -1);
  EXPECT_EQ(renderer.cell_at(100, 300), -1);

  // One cell at 1, looked at along its normal (the cube-sphere is convex: nothing hides it).
  // Its four corners are the only ones at 0.25, the top of the colours: pixels near white are
  // inside it, or in the row of a neighbour's pixels along their shared edge (a neighbour
  // blends the white of two corners with the black of the others).
  const int p = 5, i = 1, j = 2, n = s.grid.n();
  double position[3], normal[3];
  limit_vertex(s.surface, p, (i + 0.5) / n, (j + 0.5) / n, position, normal);
  view.azimuth_deg = std::atan2(normal[1], normal[0]) * 180 / std::numbers::pi;
  view.elevation_deg = std::asin(normal[2]) * 180 / std::numbers::pi;
  PatchField field = s.grid.make_field();
  const long cell = long(s.grid.index(p, i, j));
  field[std::size_t(cell)] = 1;
  SurfaceColours colours = gray();
  colours.hi = 0.25;
  renderer.render(field, colours, view, image);
  int white = 0, named = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      if (image.row(y)[3 * x] < 250) continue;
      ++white;
      named += renderer.cell_at(x, y) == cell;
    }
  EXPECT_GT(white, 400);  // the cell is some 40 pixels across
  EXPECT_GE(named, 0.9 * white) << white;

  EXPECT_EQ(renderer.cell_at(0, 0), -1);
}

// Rows and columns with a drawn pixel.
struct Extent {
  int width, height;
};
Extent drawn_extent(const ImageRgb8& image, const SurfaceView& view) {
  int x0 = image.width, x1 = -1, y0 = image.height, y1 = -1;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      if (!is_background(image.row(y) + 3 * x, view))
        x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
  return {x1 - x0 + 1, y1 - y0 + 1};
}

TEST(SurfaceRenderer, TheSphereFitKeepsTheScaleAsTheViewTurns) {
  const Scene s = cube_sphere(8);
  SurfaceRenderer renderer(s.surface, s.grid);
  const PatchField one = s.grid.make_field(1.0);
  ImageRgb8 image;
  const auto extent = [&](double azimuth, double elevation, SurfaceFit fit) {
    SurfaceView view;
    view.width = view.height = 200;
    view.azimuth_deg = azimuth, view.elevation_deg = elevation, view.fit = fit;
    renderer.render(one, gray(), view, image);
    return drawn_extent(image, view);
  };
  // Turned by 45 degrees the rounded cube is wider (its diagonal). The outline fit shrinks it to
  // keep filling 90% (180 pixels); the sphere fit keeps the scale, so the height - the z range,
  // the same from every azimuth at elevation 0 - stays, and the width grows.
  const Extent o0 = extent(0, 0, SurfaceFit::kOutline), o45 = extent(45, 0, SurfaceFit::kOutline);
  EXPECT_NEAR(std::max(o0.width, o0.height), 180, 2);
  EXPECT_NEAR(std::max(o45.width, o45.height), 180, 2);
  const Extent s0 = extent(0, 0, SurfaceFit::kSphere), s45 = extent(45, 0, SurfaceFit::kSphere);
  EXPECT_NEAR(s0.height, s45.height, 2);
  EXPECT_NEAR(s0.width, s0.height, 2);
  EXPECT_LT(o45.height, o0.height - 4);  // the outline fit did change the scale
  EXPECT_GT(s45.width, s0.width + 4);
  // The sphere reaches the farthest vertex, a rounded corner of the cube nearer the centre than
  // the box's corner: from the front the surface is wider than inside the box's corner sphere
  // (180 / sqrt(3) pixels across) and no wider than the sphere's disc.
  EXPECT_GT(s0.width, 180 / std::sqrt(3.0) + 4);
  EXPECT_LE(s0.width, 182);
  // Any direction, elevation included: the surface stays inside the sphere's 180-pixel disc.
  for (double az : {10.0, 60.0, 200.0})
    for (double el : {-70.0, 20.0, 45.0}) {
      const Extent e = extent(az, el, SurfaceFit::kSphere);
      EXPECT_LE(std::max(e.width, e.height), 182) << az << "," << el;
      EXPECT_NEAR(e.height, s0.height, 0.3 * s0.height) << az << "," << el;
    }
}

TEST(SurfaceRenderer, TheCallersFieldIsNotWritten) {
  const Scene s = torus(6);
  PatchField field = s.grid.make_field(-7.0);  // ghosts at -7: an exchange would overwrite them
  for (int p = 0; p < s.grid.patches(); ++p)
    for (int j = 0; j < s.grid.n(); ++j)
      for (int i = 0; i < s.grid.n(); ++i) field[s.grid.index(p, i, j)] = 0.1 * (p + i - j);
  const PatchField before = field;
  SurfaceRenderer renderer(s.surface, s.grid);
  SurfaceView view;
  view.width = 120, view.height = 90;
  ImageRgb8 image;
  renderer.render(field, SurfaceColours{}, view, image);
  EXPECT_EQ(field, before);
  const ImageRgb8 free_function = render_surface(s.surface, s.grid, field, SurfaceColours{}, view);
  EXPECT_EQ(field, before);
  // The renderer drew the exchanged field, not the -7 ghosts: the free function (its own copy
  // of the field) and a field exchanged by the caller draw the same pixels.
  PatchField exchanged = field;
  s.grid.exchange(exchanged);
  ImageRgb8 again;
  renderer.render(exchanged, SurfaceColours{}, view, again);
  EXPECT_EQ(image.rgb, again.rgb);
  EXPECT_EQ(image.rgb, free_function.rgb);
}

}  // namespace
}  // namespace ardcell
