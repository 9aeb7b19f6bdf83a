#include "kernels/anisotropy.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace ardcell {
namespace {

constexpr double kPi = std::numbers::pi;

AnisotropyParams witkin_kass(float a1, float a2, float theta0 = 0) {
  AnisotropyParams p;
  p.kind = AnisotropyKind::kWitkinKass;
  p.a1 = a1;
  p.a2 = a2;
  p.theta0 = theta0;
  return p;
}

AnisotropyParams lobes(int j) {
  AnisotropyParams p;
  p.kind = AnisotropyKind::kCosineLobes;
  p.lobes = j;
  for (int n = 0; n < j; ++n) p.lobe_speed[n] = 1.0f + 0.37f * n;
  return p;
}

TEST(Anisotropy, WitkinKassMatchesEqn15ClosedForm) {
  const double a1 = 2.0, a2 = 0.5, alpha = (a1 + a2) / 4;
  const AnisotropyParams p = witkin_kass(float(a1), float(a2));
  // Lobe peaks, slice boundaries and the midpoints where cos(4 phi) = 0.
  EXPECT_NEAR(anisotropy_value(p, 0.0), a1, 1e-12);
  EXPECT_NEAR(anisotropy_value(p, kPi), a1, 1e-12);
  EXPECT_NEAR(anisotropy_value(p, kPi / 2), a2, 1e-12);
  EXPECT_NEAR(anisotropy_value(p, 3 * kPi / 2), a2, 1e-12);
  EXPECT_NEAR(anisotropy_value(p, kPi / 4), alpha, 1e-12);
  EXPECT_NEAR(anisotropy_value(p, 3 * kPi / 4), alpha, 1e-12);
  EXPECT_NEAR(anisotropy_value(p, kPi / 8), alpha + (a1 - alpha) / 2, 1e-12);
  EXPECT_NEAR(anisotropy_value(p, 3 * kPi / 8), alpha + (a2 - alpha) / 2, 1e-12);
  // Everywhere: the printed piecewise formula.
  for (int i = 0; i < 720; ++i) {
    const double phi = -kPi + 2 * kPi * i / 720.0 + 1e-3;
    double w = std::fmod(phi + 2 * kPi, 2 * kPi);
    if (w > 7 * kPi / 4) w -= 2 * kPi;  // [-pi/4, 7pi/4)
    const bool first = (w >= -kPi / 4 && w <= kPi / 4) || (w >= 3 * kPi / 4 && w <= 5 * kPi / 4);
    const double an = first ? a1 : a2;
    EXPECT_NEAR(anisotropy_value(p, phi), alpha + (an - alpha) / 2 * (1 + std::cos(4 * phi)),
                1e-12);
  }
}

TEST(Anisotropy, CosineLobesMatchEqn16ClosedForm) {
  for (int j : {1, 2, 3, 4, 5, 8}) {
    const AnisotropyParams p = lobes(j);
    for (int n = 0; n < j; ++n) {
      const double peak = 2 * kPi * n / j;
      EXPECT_NEAR(anisotropy_value(p, peak), p.lobe_speed[n], 1e-6) << "j=" << j;
      EXPECT_NEAR(anisotropy_value(p, peak + kPi / (2 * j)), p.lobe_speed[n] / 2, 1e-6);
      EXPECT_NEAR(anisotropy_value(p, peak - kPi / (2 * j)), p.lobe_speed[n] / 2, 1e-6);
      EXPECT_NEAR(anisotropy_value(p, peak + kPi / j), 0.0, 1e-6);  // between lobes
      const double phi = peak + 0.3 * kPi / j;
      EXPECT_NEAR(anisotropy_value(p, phi), p.lobe_speed[n] / 2 * (1 + std::cos(j * phi)), 1e-9);
    }
  }
}

TEST(Anisotropy, JLobeFunctionHasJMaximaOverOneTurn) {
  for (int j = 1; j <= 8; ++j) {
    const AnisotropyParams p = lobes(j);
    const int n = 3600;
    int maxima = 0;
    for (int i = 0; i < n; ++i) {
      const double prev = anisotropy_value(p, 2 * kPi * (i - 1) / n);
      const double here = anisotropy_value(p, 2 * kPi * i / n);
      const double next = anisotropy_value(p, 2 * kPi * (i + 1) / n);
      if (here > prev && here >= next) ++maxima;
    }
    EXPECT_EQ(maxima, j);
  }
}

TEST(Anisotropy, Theta0RotatesTheFunction) {
  const AnisotropyParams p0 = witkin_kass(3.0f, 1.0f, 0.0f);
  const AnisotropyParams p1 = witkin_kass(3.0f, 1.0f, 0.4f);
  FieldF a({8, 8}, 1), k0({8, 8}, 1), k1({8, 8}, 1);
  for (int y = -1; y < 9; ++y)
    for (int x = -1; x < 9; ++x) a(x, y) = float(0.3 * x + 0.2 * y * y);
  conductivity_tile(a.view(), {}, k1.view(), a.interior(), p1);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) {
      const double theta = gradient_angle(a.view(), x, y, 1e-6f);
      EXPECT_NEAR(k1(x, y), anisotropy_value(p0, theta + 0.4), 1e-6);
    }
}

TEST(Anisotropy, PolarSamplesInterpolatePeriodically) {
  AnisotropyParams p;
  p.kind = AnisotropyKind::kPolarSamples;
  p.samples = 4;
  p.sample[0] = 1;
  p.sample[1] = 2;
  p.sample[2] = 3;
  p.sample[3] = 5;
  ASSERT_EQ(anisotropy_params_problem(p), nullptr);
  EXPECT_NEAR(anisotropy_value(p, 0), 1, 1e-12);
  EXPECT_NEAR(anisotropy_value(p, kPi / 2), 2, 1e-12);
  EXPECT_NEAR(anisotropy_value(p, kPi / 4), 1.5, 1e-12);
  EXPECT_NEAR(anisotropy_value(p, 7 * kPi / 4), 3, 1e-12);  // between 5 and 1 (wraps)
  EXPECT_NEAR(anisotropy_value(p, -kPi / 4), 3, 1e-12);
  EXPECT_NEAR(anisotropy_value(p, 2 * kPi + kPi), 3, 1e-12);
  EXPECT_DOUBLE_EQ(anisotropy_max(p), 5);
}

TEST(Anisotropy, GradientAngleIsTheAngleOfGradA) {
  FieldF a({5, 5}, 1);
  auto angle_of = [&](auto f) {
    for (int y = -1; y < 6; ++y)
      for (int x = -1; x < 6; ++x) a(x, y) = float(f(x, y));
    return gradient_angle(a.view(), 2, 2, 1e-6f);
  };
  EXPECT_NEAR(angle_of([](int x, int) { return x; }), 0, 1e-12);
  EXPECT_NEAR(angle_of([](int, int y) { return y; }), kPi / 2, 1e-12);
  EXPECT_NEAR(angle_of([](int x, int) { return -x; }), kPi, 1e-12);
  EXPECT_NEAR(angle_of([](int x, int y) { return x + y; }), kPi / 4, 1e-12);
  EXPECT_EQ(angle_of([](int, int) { return 0.7; }), 0.0);  // vanishing gradient
}

TEST(Anisotropy, PerCellTheta0FieldIsUsed) {
  const AnisotropyParams p = lobes(3);
  FieldF a({6, 4}, 1), t0({6, 4}, 1), k({6, 4}, 1);
  for (int y = -1; y < 5; ++y)
    for (int x = -1; x < 7; ++x) a(x, y) = float(x * x - 0.5 * y);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 6; ++x) t0(x, y) = float(0.1 * x + 0.7 * y);
  conductivity_tile(a.view(), t0.view(), k.view(), a.interior(), p);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 6; ++x)
      EXPECT_NEAR(k(x, y), anisotropy_value(p, gradient_angle(a.view(), x, y, 1e-6f) + t0(x, y)),
                  1e-6);
}

TEST(Anisotropy, BadParametersAreNamed) {
  AnisotropyParams p = lobes(3);
  p.lobes = 0;
  EXPECT_NE(anisotropy_params_problem(p), nullptr);
  p = lobes(3);
  p.lobe_speed[1] = -1;
  EXPECT_NE(anisotropy_params_problem(p), nullptr);
  AnisotropyKind k{};
  EXPECT_TRUE(parse_anisotropy_kind("witkin-kass", k));
  EXPECT_EQ(k, AnisotropyKind::kWitkinKass);
  EXPECT_FALSE(parse_anisotropy_kind("wk", k));
}

// conductivity_tile evaluates Eqn 16 without atan2 and cos per cell (the gradient's direction
// to the j-th power, the slice by pseudo-angles): within one float ulp of
// anisotropy_value(gradient_angle + theta0) everywhere, for every j, a uniform theta0 and a
// per-cell one, flat patches (theta = 0) and gradients on the slice boundaries included.
TEST(Anisotropy, CosineLobesConductivityAgreesWithTheClosedForm) {
  const Int2 n{61, 47};
  FieldF a(n, 1), theta0(n, 1);
  uint32_t state = 12345;
  const auto next = [&state] {
    state = state * 1664525u + 1013904223u;
    return float(state >> 8) / float(1u << 24);
  };
  for (int y = -1; y <= n.y; ++y)
    for (int x = -1; x <= n.x; ++x) {
      a(x, y) = (x > 40 && y > 30) ? 0.5f : next();  // a flat patch: theta = 0 there
      theta0(x, y) = y < 20 ? 0.3f : 6.0f * next() - 3.0f;
    }
  // Gradients exactly along slice boundaries of j = 4 (45 degrees) at a few cells.
  for (int k = 0; k < 5; ++k) {
    const int x = 5 + 2 * k, y = 5;
    a(x + 1, y) = 0.75f;
    a(x - 1, y) = 0.25f;
    a(x, y + 1) = 0.75f;
    a(x, y - 1) = 0.25f;
  }
  int compared = 0;
  for (int j : {1, 2, 3, 4, 5, 8, 16})
    for (bool per_cell : {false, true}) {
      AnisotropyParams p = lobes(j);
      p.theta0 = 0.7f;
      FieldF k(n, 1);
      conductivity_tile(a.view(), per_cell ? theta0.view() : View<const float>{}, k.view(),
                        a.interior(), p);
      for (int y = 0; y < n.y; ++y)
        for (int x = 0; x < n.x; ++x) {
          const double t0 = per_cell ? double(theta0(x, y)) : double(p.theta0);
          const float want =
              float(anisotropy_value(p, gradient_angle(a.view(), x, y, p.gradient_epsilon) + t0));
          const float got = k(x, y);
          // One float ulp of the lobe's peak (a value near 0 sits on a slice boundary, where
          // either lobe gives 0).
          const float ulp = std::nextafter(p.lobe_speed[j - 1], 100.0f) - p.lobe_speed[j - 1];
          ASSERT_NEAR(got, want, ulp)
              << "j " << j << " per_cell " << per_cell << " at " << x << "," << y;
          ++compared;
        }
    }
  EXPECT_EQ(compared, 7 * 2 * n.x * n.y);
}

}  // namespace
}  // namespace ardcell
