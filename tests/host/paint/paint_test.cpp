// Painting: no jump on the first sample after pen-down, every mode does what it says,
// pressure sets the width, the eraser end erases, orient strokes set theta0 everywhere.
#include "host/paint/paint.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

namespace ardcell {
namespace {

constexpr double kPi = 3.14159265358979323846;

SimState make_state(int n) {
  SimState s;
  s.size = {n, n};
  s.h = 1.0 / n;
  s.dt = 0.01;
  s.u = FieldF(s.size, 1);
  s.v = FieldF(s.size, 1);
  s.dye = FieldF(s.size, 1);
  s.A = FieldF(s.size, 1);
  s.B = FieldF(s.size, 1);
  s.A.fill(1);
  return s;
}

// A sample at grid cell coordinates (gx, gy) of an n x n grid.
StrokeSample at(int n, double gx, double gy, bool tip, float pressure = 1.f) {
  StrokeSample s;
  s.x = float(gx / n);
  s.y = float(1.0 - gy / n);
  s.pressure = pressure;
  s.in_range = true;
  s.buttons = tip ? uint32_t(kButtonTip) : 0u;
  return s;
}

int count_changed_b(const SimState& s) {
  int n = 0;
  for (int y = 0; y < s.size.y; ++y)
    for (int x = 0; x < s.size.x; ++x) n += s.B(x, y) != 0;
  return n;
}

TEST(Painter, NoJumpOnFirstSampleAfterPenDown) {
  const int n = 64;
  SimState s = make_state(n);
  PaintConfig c;
  c.radius = c.min_radius = 2;
  Painter p({n, n}, c);
  // Stroke 1 ends at (10, 10); the pen is lifted, moves (hovering) and comes down at (50, 50).
  const StrokeSample stroke[] = {at(n, 8, 10, true),   at(n, 10, 10, true), at(n, 10, 10, false),
                                 at(n, 30, 30, false), at(n, 50, 50, true), at(n, 52, 50, true)};
  p.apply(stroke, s);
  // Nothing was painted between the two strokes (the diagonal from (10,10) to (50,50)).
  for (int k = 16; k <= 44; ++k) EXPECT_EQ(s.B(k, k), 0.f) << k;
  EXPECT_GT(s.B(9, 10), 0.f);
  EXPECT_GT(s.B(51, 50), 0.f);
  // The same when the pen leaves the range instead of lifting, and when the first sample of
  // the new stroke is the first the painter ever sees.
  SimState s2 = make_state(n);
  Painter p2({n, n}, c);
  StrokeSample gone = at(n, 10, 10, true);
  gone.in_range = false;
  const StrokeSample stroke2[] = {at(n, 50, 50, true), at(n, 52, 50, true), gone,
                                  at(n, 10, 12, true)};
  p2.apply(stroke2, s2);
  for (int k = 16; k <= 44; ++k) EXPECT_EQ(s2.B(k, k + 1), 0.f) << k;
}

TEST(Painter, DepositBlendsTowardsTheDepositValues) {
  const int n = 32;
  SimState s = make_state(n);
  PaintConfig c;
  c.strength = 1;
  Painter p({n, n}, c);
  const StrokeSample line[] = {at(n, 5, 16, true), at(n, 25, 16, true)};
  p.apply(line, s);
  EXPECT_FLOAT_EQ(s.A(15, 16), c.deposit_a);
  EXPECT_FLOAT_EQ(s.B(15, 16), c.deposit_b);
  EXPECT_FLOAT_EQ(s.dye(15, 16), c.deposit_dye);
  EXPECT_FLOAT_EQ(s.B(15, 2), 0.f);  // far from the stroke
  EXPECT_FALSE(p.update_theta0(s));  // deposit sets no orientation
}

TEST(Painter, PressureSetsWidthAndStrength) {
  const int n = 64;
  PaintConfig c;
  c.radius = 8;
  c.min_radius = 1;
  int widths[3];
  float centre[3];
  const float pressures[3] = {0.1f, 0.5f, 1.0f};
  for (int i = 0; i < 3; ++i) {
    SimState s = make_state(n);
    Painter p({n, n}, c);
    const StrokeSample line[] = {at(n, 10, 32, true, pressures[i]),
                                 at(n, 50, 32, true, pressures[i])};
    p.apply(line, s);
    widths[i] = 0;
    for (int y = 0; y < n; ++y) widths[i] += s.B(30, y) != 0;
    centre[i] = s.B(30, 32);
  }
  EXPECT_LT(widths[0], widths[1]);
  EXPECT_LT(widths[1], widths[2]);
  EXPECT_NEAR(widths[2], 16, 1);  // diameter 2 * radius
  EXPECT_LT(centre[0], centre[1]);
  EXPECT_LE(centre[1], centre[2]);
}

TEST(Painter, EraserEndErasesTheModesLayer) {
  const int n = 32;
  SimState s = make_state(n);
  Painter p({n, n});
  const StrokeSample line[] = {at(n, 5, 16, true), at(n, 25, 16, true), at(n, 25, 16, false)};
  p.apply(line, s);
  ASSERT_GT(count_changed_b(s), 0);
  StrokeSample e1 = at(n, 3, 16, true), e2 = at(n, 28, 16, true);
  e1.eraser = e2.eraser = true;
  const StrokeSample erase[] = {e1, e2};
  p.apply(erase, s);
  EXPECT_EQ(count_changed_b(s), 0);
  EXPECT_FLOAT_EQ(s.A(15, 16), 1.f);
  EXPECT_FLOAT_EQ(s.dye(15, 16), 0.f);
}

TEST(Painter, ObstacleAndEraseMode) {
  const int n = 32;
  SimState s = make_state(n);
  Painter p({n, n});
  p.set_mode(PaintMode::kObstacle);
  const StrokeSample line[] = {at(n, 10, 10, true), at(n, 20, 10, true), at(n, 20, 10, false)};
  p.apply(line, s);
  ASSERT_FALSE(s.obstacle.empty());
  EXPECT_EQ(s.obstacle(15, 10), 1);
  EXPECT_EQ(s.obstacle(15, 25), 0);
  p.set_mode(PaintMode::kErase);  // switched mid-session
  p.apply(line, s);
  EXPECT_EQ(s.obstacle(15, 10), 0);
}

TEST(Painter, PushSetsVelocityAlongTheStroke) {
  const int n = 32;
  SimState s = make_state(n);
  PaintConfig c;
  c.mode = PaintMode::kPush;
  c.push_speed = 0.5f;
  Painter p({n, n}, c);
  // A stroke towards +y in grid coordinates (sample y decreasing: upwards on screen).
  const StrokeSample line[] = {at(n, 16, 5, true), at(n, 16, 25, true)};
  p.apply(line, s);
  EXPECT_NEAR(s.u(16, 15), 0.f, 1e-6);
  EXPECT_NEAR(s.v(16, 15), 0.5f, 1e-6);  // domain width 1: 0.5 widths per second
  EXPECT_EQ(s.v(2, 15), 0.f);
}

TEST(Painter, OrientStrokeSetsThetaZeroEverywhere) {
  const int n = 128;
  SimState s = make_state(n);
  PaintConfig c;
  c.mode = PaintMode::kOrient;
  c.theta_scale = 1;
  c.theta_offset = 0;
  Painter p({n, n}, c);
  // Straight stroke along +x in grid coordinates: theta0 = 0 everywhere.
  const StrokeSample line[] = {at(n, 20, 60, true), at(n, 60, 60, true), at(n, 100, 60, true)};
  p.apply(line, s);
  ASSERT_TRUE(p.update_theta0(s));
  for (int y = 0; y < n; y += 7)
    for (int x = 0; x < n; x += 7) EXPECT_NEAR(s.theta0(x, y), 0.f, 1e-4) << x << "," << y;
  EXPECT_FALSE(p.update_theta0(s));  // nothing changed since

  // The default mapping (-1, -pi): Eqn 16's lobe opposite to the stroke, i.e.
  // theta0 = -(angle + pi) = -pi for a stroke along +x.
  p.set_config(PaintConfig{});
  p.set_mode(PaintMode::kOrient);
  const StrokeSample again[] = {at(n, 20, 60, false), at(n, 20, 60, true), at(n, 40, 60, true)};
  p.apply(again, s);
  ASSERT_TRUE(p.update_theta0(s));
  EXPECT_NEAR(std::cos(s.theta0(5, 100)), -1.0, 1e-4);
  EXPECT_NEAR(std::sin(s.theta0(5, 100)), 0.0, 1e-3);
}

// Orient mode with a brush of one fixed radius.
PaintConfig orient_config(float radius) {
  PaintConfig c;
  c.mode = PaintMode::kOrient;
  c.radius = c.min_radius = radius;
  return c;
}

TEST(Painter, OrientCircleIsTangential) {
  const int n = 128;
  SimState s = make_state(n);
  PaintConfig c = orient_config(1.5f);
  c.theta_scale = 1;
  c.theta_offset = 0;
  Painter p({n, n}, c);
  for (int k = 0; k <= 120; ++k) {
    const double a = 2 * kPi * k / 120;
    p.apply(at(n, 64 + 35 * std::cos(a), 64 + 35 * std::sin(a), true), s);
  }
  ASSERT_TRUE(p.update_theta0(s));
  double sum = 0;
  int count = 0;
  for (int y = 0; y < n; y += 3)
    for (int x = 0; x < n; x += 3) {
      const double px = x + 0.5 - 64, py = y + 0.5 - 64;
      if (std::hypot(px, py) < 10) continue;
      const double want = std::atan2(py, px) + kPi / 2;
      double d = std::fmod(std::fabs(s.theta0(x, y) - want), 2 * kPi);
      d = std::min(d, 2 * kPi - d);
      sum += d;
      ++count;
    }
  EXPECT_LT(sum / count, 0.08);
}

TEST(Painter, OrientDabsAreSpacedAlongTheStroke) {
  const int n = 96;
  SimState s = make_state(n);
  PaintConfig c = orient_config(3);
  c.orient_dab_spacing = 4;  // 12 cells between dab centres
  Painter p({n, n}, c);
  // A straight stroke from x = 10 to x = 70 along y = 40, sampled every 2.5 cells (the dab
  // positions fall between samples), then a second stroke that starts again at x = 10.
  std::vector<StrokeSample> stroke;
  for (double x = 10; x <= 70; x += 2.5) stroke.push_back(at(n, x, 40, true));
  p.apply(stroke, s);
  // Dab centres at 10, 22, ..., 70 (cell x + 0.5 == centre, so cells 9/10 straddle x = 10).
  for (int k = 0; k <= 5; ++k) {
    const int cx = 10 + 12 * k;
    EXPECT_FLOAT_EQ(s.B(cx, 40), c.deposit_b) << cx;  // within half the radius: full blend
    EXPECT_EQ(s.B(cx + 6, 40), 0.f) << cx;            // halfway between dabs: nothing
    EXPECT_EQ(s.B(cx, 44), 0.f) << cx;                // beyond the radius across the stroke
  }
  EXPECT_EQ(s.B(77, 40), 0.f);  // no dab beyond the stroke's end
  // The orientation is rasterised along the whole stroke, dabs or not.
  for (int x = 12; x < 68; ++x) EXPECT_GT(p.orientation_weight()(x, 40), 0.f) << x;
  // A new stroke counts its length from its own pen-down.
  SimState s2 = make_state(n);
  // At half pressure (on this fixed-radius brush that would only halve the blend) the dabs
  // still blend fully.
  const StrokeSample second[] = {at(n, 30, 60, false), at(n, 30, 60, true, 0.5f),
                                 at(n, 45, 60, true, 0.5f)};
  p.apply(second, s2);
  EXPECT_FLOAT_EQ(s2.B(30, 60), c.deposit_b);
  EXPECT_FLOAT_EQ(s2.B(42, 60), c.deposit_b);
  EXPECT_EQ(s2.B(36, 60), 0.f);
}

// Blocks of one grid (MPI ranks, a video wall's screens): every block runs a Painter over the
// whole grid with the same samples.
constexpr Int2 kWallGrid{80, 64};
constexpr Box2 kWallBlocks[2] = {{{0, 0}, {40, 64}}, {{40, 0}, {80, 64}}};
constexpr float kOutside = -7.f;  // what a block's storage holds outside its cells

// A state over `box` of kWallGrid (the whole grid when box is), with a velocity when asked.
// Outside the box (halo and padding) A, B, u and v hold kOutside, so a write past the block
// shows.
SimState make_block_state(Box2 box, bool velocity = false) {
  SimState s;
  s.size = kWallGrid;
  s.h = 1.0 / kWallGrid.x;
  s.dt = 0.01;
  s.A = FieldF::over(box, 1);
  s.B = FieldF::over(box, 1);
  s.theta0 = FieldF::over(box, 1);
  if (velocity) {
    s.u = FieldF::over(box, 1);
    s.v = FieldF::over(box, 1);
  }
  for (FieldF* f : {&s.A, &s.B, &s.u, &s.v})
    if (!f->empty()) f->fill(kOutside);
  for (int y = box.min.y; y < box.max.y; ++y)
    for (int x = box.min.x; x < box.max.x; ++x) {
      s.A(x, y) = 1;
      s.B(x, y) = 0;
      if (velocity) s.u(x, y) = s.v(x, y) = 0.25f;
    }
  return s;
}

// A sample at grid cell coordinates (gx, gy) of kWallGrid.
StrokeSample wall_at(double gx, double gy, bool tip, bool eraser = false) {
  StrokeSample s = at(kWallGrid.x, gx, 0, tip);
  s.y = float(1.0 - gy / kWallGrid.y);
  s.eraser = eraser;
  return s;
}

// Cells of the block's box equal (bit for bit) the whole grid's, and nothing outside the box
// was written.
void expect_block_matches(const FieldF& block, const FieldF& whole, const char* what) {
  const Box2 box = block.interior();
  int differ = 0;
  for (int y = box.min.y; y < box.max.y; ++y)
    for (int x = box.min.x; x < box.max.x; ++x)
      differ += std::memcmp(&block(x, y), &whole(x, y), sizeof(float)) != 0;
  EXPECT_EQ(differ, 0) << what << " over " << box;
  const auto outside = std::count(block.raw(), block.raw() + block.raw_size(), kOutside);
  EXPECT_EQ(int64_t(outside), int64_t(block.raw_size()) - box.area()) << what << " over " << box;
}

TEST(Painter, BlocksRecordTheWholeGridsOrientation) {
  const Box2 grid = box_of_size(kWallGrid);
  SimState whole = make_block_state(grid);
  SimState blocks[2] = {make_block_state(kWallBlocks[0]), make_block_state(kWallBlocks[1])};
  PaintConfig c = orient_config(3);  // continuous deposit along the stroke too
  Painter pw(kWallGrid, c);
  Painter pb[2] = {Painter(kWallGrid, c), Painter(kWallGrid, c)};
  // A bent stroke across x = 40, both ways.
  const StrokeSample stroke[] = {wall_at(12, 14, true), wall_at(30, 22, true),
                                 wall_at(58, 30, true), wall_at(66, 46, true),
                                 wall_at(34, 52, true), wall_at(34, 52, false)};
  pw.apply(stroke, whole);
  ASSERT_TRUE(pw.update_theta0(whole));
  ASSERT_GT(whole.B(20, 18), 0.f);  // deposited on both sides of x = 40
  ASSERT_GT(whole.B(60, 34), 0.f);
  for (int i = 0; i < 2; ++i) {
    pb[i].apply(stroke, blocks[i]);
    EXPECT_TRUE(pb[i].update_theta0(blocks[i])) << i;
    // The orientation sources of every block are the whole grid's.
    int differ = 0;
    for (int y = 0; y < kWallGrid.y; ++y)
      for (int x = 0; x < kWallGrid.x; ++x)
        differ += pb[i].orientation_weight()(x, y) != pw.orientation_weight()(x, y) ||
                  pb[i].orientation_cos()(x, y) != pw.orientation_cos()(x, y) ||
                  pb[i].orientation_sin()(x, y) != pw.orientation_sin()(x, y);
    EXPECT_EQ(differ, 0) << i;
    int theta_differ = 0;
    for (int y = kWallBlocks[i].min.y; y < kWallBlocks[i].max.y; ++y)
      for (int x = kWallBlocks[i].min.x; x < kWallBlocks[i].max.x; ++x)
        theta_differ +=
            std::memcmp(&blocks[i].theta0(x, y), &whole.theta0(x, y), sizeof(float)) != 0;
    EXPECT_EQ(theta_differ, 0) << i;
    expect_block_matches(blocks[i].A, whole.A, "A");
    expect_block_matches(blocks[i].B, whole.B, "B");
  }
}

TEST(Painter, BlocksRecordTheWholeGridsObstacles) {
  const Box2 grid = box_of_size(kWallGrid);
  SimState whole = make_block_state(grid, true);
  SimState blocks[2] = {make_block_state(kWallBlocks[0], true),
                        make_block_state(kWallBlocks[1], true)};
  PaintConfig c;
  c.mode = PaintMode::kObstacle;
  c.radius = c.min_radius = 3;
  Painter pw(kWallGrid, c);
  Painter pb[2] = {Painter(kWallGrid, c), Painter(kWallGrid, c)};
  const StrokeSample stroke[] = {wall_at(10, 20, true), wall_at(70, 40, true),
                                 wall_at(70, 40, false)};
  // The eraser end over part of it, across x = 40 again.
  const StrokeSample erase[] = {wall_at(30, 16, true, true), wall_at(52, 40, true, true),
                                wall_at(52, 40, false, true)};
  auto expect_same_masks = [&](const char* when) {
    for (int i = 0; i < 2; ++i) {
      ASSERT_FALSE(blocks[i].obstacle.empty()) << when;
      int differ = 0;
      for (int y = 0; y < kWallGrid.y; ++y)
        for (int x = 0; x < kWallGrid.x; ++x)
          differ += blocks[i].obstacle(x, y) != whole.obstacle(x, y);
      EXPECT_EQ(differ, 0) << when << ", block " << i;
      // Solid cells stop the flow on the block's cells only.
      expect_block_matches(blocks[i].u, whole.u, when);
      expect_block_matches(blocks[i].v, whole.v, when);
    }
  };
  pw.apply(stroke, whole);
  ASSERT_EQ(whole.obstacle(20, 23), 1);  // solid on both sides of x = 40
  ASSERT_EQ(whole.obstacle(60, 37), 1);
  ASSERT_EQ(whole.obstacle(44, 31), 1);  // where the eraser crosses it
  ASSERT_EQ(whole.u(44, 31), 0.f);
  for (int i = 0; i < 2; ++i) pb[i].apply(stroke, blocks[i]);
  expect_same_masks("painted");
  pw.apply(erase, whole);
  ASSERT_EQ(whole.obstacle(44, 31), 0);  // erased where it crosses, kept at both ends
  ASSERT_EQ(whole.obstacle(12, 20), 1);
  ASSERT_EQ(whole.obstacle(68, 39), 1);
  for (int i = 0; i < 2; ++i) pb[i].apply(erase, blocks[i]);
  expect_same_masks("erased");
}

TEST(Painter, SceneDefaultsOrientWithDabsForASingleLobe) {
  SceneConfig scene;
  scene.size = {256, 256};
  scene.rd.enabled = true;
  scene.rd.seed_b = 0.3f;
  PaintConfig c = paint_config_for(scene);
  EXPECT_EQ(c.mode, PaintMode::kDeposit);
  EXPECT_EQ(c.deposit_b, 0.3f);
  scene.rd.anisotropy.kind = AnisotropyKind::kCosineLobes;
  scene.rd.anisotropy.lobes = 1;
  c = paint_config_for(scene);
  EXPECT_EQ(c.mode, PaintMode::kOrient);
  EXPECT_GT(c.orient_dab_spacing, 2.f);  // dabs at least one brush width apart
}

TEST(Painter, ModeNames) {
  for (int i = 0; i < kPaintModeCount; ++i) {
    PaintMode m;
    ASSERT_TRUE(parse_paint_mode(paint_mode_name(PaintMode(i)), m));
    EXPECT_EQ(int(m), i);
  }
  PaintMode m;
  EXPECT_FALSE(parse_paint_mode("smudge", m));
}

}  // namespace
}  // namespace ardcell
