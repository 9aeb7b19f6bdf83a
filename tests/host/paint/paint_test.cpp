// Painting: no jump on the first sample after pen-down, every mode does what it says,
// pressure sets the width, the eraser end erases, orient strokes set theta0 everywhere.
#include "host/paint/paint.h"

#include <gtest/gtest.h>

#include <cmath>
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
