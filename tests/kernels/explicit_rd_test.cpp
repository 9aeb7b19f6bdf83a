#include "kernels/explicit_rd.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "kernels/generalized_diffusion.h"

namespace ardcell {
namespace {

constexpr Int2 kSize{12, 9};

TEST(ExplicitRd, FivePointIsEqn5) {
  FieldF a(kSize, 1), b(kSize, 1), ao(kSize, 1), bo(kSize, 1);
  for (int y = -1; y <= kSize.y; ++y)
    for (int x = -1; x <= kSize.x; ++x) {
      a(x, y) = float(0.5 + 0.3 * std::sin(0.7 * x + 0.2 * y));
      b(x, y) = float(0.2 + 0.1 * std::cos(0.3 * x - 0.5 * y));
    }
  ExplicitRdParams p;
  p.dt = 0.7f;
  p.diffusion_a = 0.2f;
  p.diffusion_b = 0.1f;
  explicit_rd5_tile(a.view(), b.view(), ao.view(), bo.view(), a.interior(), p);
  for (int y = 0; y < kSize.y; ++y)
    for (int x = 0; x < kSize.x; ++x) {
      const double A = a(x, y), B = b(x, y);
      const double la = double(a(x - 1, y)) + a(x + 1, y) + a(x, y - 1) + a(x, y + 1) - 4 * A;
      const double lb = double(b(x - 1, y)) + b(x + 1, y) + b(x, y - 1) + b(x, y + 1) - 4 * B;
      const double ra = -A * B * B + p.reaction.F * (1 - A);
      const double rb = A * B * B - (double(p.reaction.F) + p.reaction.k) * B;
      EXPECT_NEAR(ao(x, y), A + p.dt * ra + p.diffusion_a * la, 1e-6);
      EXPECT_NEAR(bo(x, y), B + p.dt * rb + p.diffusion_b * lb, 1e-6);
    }
}

TEST(ExplicitRd, NinePointLaplacianHasSeed001Weights) {
  // A single impulse spreads with the weights 0.05 (corners), 0.2 (edges), -1 (centre).
  FieldF a(kSize, 1), b(kSize, 1), ao(kSize, 1), bo(kSize, 1);
  a(5, 4) = 1.0f;
  ExplicitRdParams p;
  p.reaction.F = 0.0f;
  p.reaction.k = 0.0f;
  p.diffusion_a = 1.0f;
  explicit_rd9_tile(a.view(), b.view(), ao.view(), bo.view(), a.interior(), p);
  EXPECT_FLOAT_EQ(ao(5, 4), 0.0f);
  EXPECT_FLOAT_EQ(ao(4, 4), 0.2f);
  EXPECT_FLOAT_EQ(ao(5, 5), 0.2f);
  EXPECT_FLOAT_EQ(ao(4, 3), 0.05f);
  EXPECT_FLOAT_EQ(ao(6, 5), 0.05f);
  EXPECT_FLOAT_EQ(ao(7, 4), 0.0f);
}

TEST(ExplicitRd, FastGrayScott9MatchesTheGenericKernel) {
  FieldF a(kSize, 1), b(kSize, 1);
  for (int y = 0; y < kSize.y; ++y)
    for (int x = 0; x < kSize.x; ++x) {
      a(x, y) = float(0.6 + 0.3 * std::sin(0.9 * x + 0.4 * y));
      b(x, y) = float(0.25 + 0.2 * std::cos(0.5 * x - 0.8 * y));
    }
  fill_periodic_halo(a);
  fill_periodic_halo(b);
  FieldF ao(kSize, 1), bo(kSize, 1), af(kSize, 1), bf(kSize, 1);
  ExplicitRdParams p;  // seed 001: DA 1, DB 0.5, dt 1
  explicit_rd9_tile(a.view(), b.view(), ao.view(), bo.view(), a.interior(), p);
  std::vector<float> scratch(2 * (kSize.x + 2));
  const Box2 part{{2, 1}, {11, 8}};  // a sub-region: the tile kernel writes only it
  gray_scott9_explicit_tile(a.view(), b.view(), af.view(), bf.view(), part,
                            {p.reaction.F, p.reaction.k, 1.0f, 1.0f, 0.5f}, scratch.data());
  for (int y = 0; y < kSize.y; ++y)
    for (int x = 0; x < kSize.x; ++x) {
      if (!part.contains(Int2{x, y})) {
        EXPECT_EQ(af(x, y), 0.0f);
        continue;
      }
      EXPECT_NEAR(af(x, y), ao(x, y), 2e-6);
      EXPECT_NEAR(bf(x, y), bo(x, y), 2e-6);
    }
}

TEST(ExplicitRd, ForwardEulerIsStableBelowTheBoundAndBlowsUpAbove) {
  // 5-point diffusion alone: stable for D dt / h^2 <= 1/4 (2 D dt / h^2 < 1 per axis pair).
  for (float s : {0.24f, 0.3f}) {
    FieldF a(kSize, 1), b(kSize, 1), ao(kSize, 1), bo(kSize, 1);
    for (int y = 0; y < kSize.y; ++y)
      for (int x = 0; x < kSize.x; ++x) a(x, y) = ((x + y) % 2) ? 1.0f : -1.0f;
    ExplicitRdParams p;
    p.dt = 0.0f;  // no reaction
    p.diffusion_a = s;
    p.diffusion_b = 0.0f;
    for (int i = 0; i < 200; ++i) {
      fill_periodic_halo(a);
      fill_periodic_halo(b);
      explicit_rd5_tile(a.view(), b.view(), ao.view(), bo.view(), a.interior(), p);
      std::swap(a, ao);
      std::swap(b, bo);
    }
    if (s < 0.25f) {
      EXPECT_LT(std::abs(a(3, 3)), 1.0f);
    } else
      EXPECT_GT(std::abs(a(3, 3)), 1e10f);
  }
}

}  // namespace
}  // namespace ardcell
