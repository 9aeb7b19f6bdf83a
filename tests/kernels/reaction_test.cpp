#include "kernels/reaction.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace ardcell {
namespace {

ReactionParams params_for(ReactionModel m) {
  ReactionParams p;
  p.model = m;
  return p;
}

// (A, B) samples spread over a model's typical range.
std::vector<std::pair<double, double>> grid_over(const ConcentrationBox& r, int n) {
  std::vector<std::pair<double, double>> out;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      out.emplace_back(r.a_lo + (r.a_hi - r.a_lo) * i / (n - 1),
                       r.b_lo + (r.b_hi - r.b_lo) * j / (n - 1));
  return out;
}

class EveryModel : public ::testing::TestWithParam<ReactionModel> {};

TEST_P(EveryModel, NewtonResidualBelow1e6OverAGridOfStatesAndSteps) {
  const ReactionParams p = params_for(GetParam());
  ASSERT_EQ(reaction_params_problem(p), nullptr);
  const ConcentrationBox range = typical_range(p);
  int cases = 0;
  for (double dt : {1e-3, 0.1, 1.0, 10.0, 100.0, 1000.0}) {
    for (auto [A, B] : grid_over(range, 17)) {
      const ImplicitResult r = implicit_reaction_cell(p, dt, A, B);
      ASSERT_TRUE(std::isfinite(r.a) && std::isfinite(r.b));
      EXPECT_LT(r.residual, 1e-6) << reaction_model_name(p.model) << " dt=" << dt << " A=" << A
                                  << " B=" << B;
      // The residual of the 2x2 system itself (Eqn 6), not only of the reduced equation.
      EXPECT_LT(implicit_reaction_residual(p, dt, A, B, r.a, r.b), 1e-6)
          << reaction_model_name(p.model) << " dt=" << dt << " A=" << A << " B=" << B;
      EXPECT_LE(r.iterations, 200);
      ++cases;
    }
  }
  EXPECT_EQ(cases, 6 * 17 * 17);
}

TEST_P(EveryModel, ImplicitUpdateStaysInTheInvariantBoxAtAnyStep) {
  const ReactionParams p = params_for(GetParam());
  const ConcentrationBox box = invariant_box(p);
  const ConcentrationBox range = typical_range(p);
  for (double dt : {0.5, 1000.0}) {
    for (auto [A, B] : grid_over(range, 9)) {
      double a = A, b = B;
      for (int step = 0; step < 200; ++step) {
        const ImplicitResult r = implicit_reaction_cell(p, dt, a, b);
        a = r.a;
        b = r.b;
        ASSERT_TRUE(std::isfinite(a) && std::isfinite(b));
        ASSERT_GE(a, box.a_lo - 1e-9);
        ASSERT_LE(a, box.a_hi + 1e-9);
        ASSERT_GE(b, box.b_lo - 1e-9);
        ASSERT_LE(b, box.b_hi + 1e-9);
      }
    }
  }
}

TEST_P(EveryModel, SmallStepMatchesForwardEulerToSecondOrder) {
  // Backward and forward Euler differ by O(dt^2) per step.
  const ReactionParams p = params_for(GetParam());
  const ConcentrationBox range = typical_range(p);
  double worst_ratio = 0;
  for (auto [A, B] : grid_over(range, 5)) {
    if (B == 0 && p.model == ReactionModel::kMeinhardt) continue;  // A^2/B singular
    double errs[2] = {0, 0};
    int idx = 0;
    for (double dt : {1e-3, 5e-4}) {
      double ra, rb;
      reaction_rates(p, A, B, ra, rb);
      // Where forward Euler leaves A >= 0, the implicit update is the projection (O(dt)).
      if (A + dt * ra < 0) continue;
      const ImplicitResult r = implicit_reaction_cell(p, dt, A, B, 1e-14);
      errs[idx++] = std::max(std::abs(r.a - (A + dt * ra)), std::abs(r.b - (B + dt * rb)));
    }
    if (idx == 2 && errs[0] > 1e-12) worst_ratio = std::max(worst_ratio, errs[1] / errs[0]);
  }
  EXPECT_LT(worst_ratio, 0.3);  // 0.25 for exact second order
}

// The trapezoidal rule (Adams-Moulton 2): (A^, B^) - (A, B) = dt/2 (R(A, B) + R(A^, B^)) where
// the forward half step stays in the invariant box, and one step is third-order accurate (local
// error O(dt^3)) against the ODE, here against many tiny forward Euler steps.
TEST_P(EveryModel, TrapezoidalRuleSolvesItsEquationAndIsSecondOrder) {
  const ReactionParams p = params_for(GetParam());
  const ConcentrationBox range = typical_range(p), box = invariant_box(p);
  // The stiff models' rates (Barkley's 1/eps = 50) need their own step scale.
  const double scale =
      p.model == ReactionModel::kBarkley || p.model == ReactionModel::kBarkleyTurbulent ? 0.01
      : p.model == ReactionModel::kFitzHughNagumo                                       ? 0.1
                                                                                        : 1.0;
  // Errors summed over the states: at a few states the dt^3 term's coefficient nearly vanishes
  // and the next term shows instead.
  double worst_residual = 0, total[2] = {0, 0};
  for (auto [A, B] : grid_over(range, 5)) {
    if (B == 0 && p.model == ReactionModel::kMeinhardt) continue;  // A^2/B singular
    double errs[2] = {0, 0};
    for (int i = 0; i < 2; ++i) {
      const double dt = scale * (i == 0 ? 0.1 : 0.05);
      double ra, rb;
      reaction_rates(p, A, B, ra, rb);
      const double ha = A + 0.5 * dt * ra, hb = B + 0.5 * dt * rb;
      if (ha < box.a_lo || ha > box.a_hi || hb < box.b_lo || hb > box.b_hi) break;
      const ImplicitResult r = trapezoidal_reaction_cell(p, dt, A, B, 1e-14);
      double ra1, rb1;
      reaction_rates(p, r.a, r.b, ra1, rb1);
      worst_residual = std::max({worst_residual, std::abs(r.a - A - 0.5 * dt * (ra + ra1)),
                                 std::abs(r.b - B - 0.5 * dt * (rb + rb1))});
      double a = A, b = B;
      for (int k = 0; k < 20000; ++k) {  // the ODE, to O(dt / 20000)
        double fa, fb;
        reaction_rates(p, a, b, fa, fb);
        a += dt / 20000 * fa;
        b += dt / 20000 * fb;
      }
      errs[i] = std::max(std::abs(r.a - a), std::abs(r.b - b));
    }
    if (errs[1] > 0) total[0] += errs[0], total[1] += errs[1];
  }
  EXPECT_LT(worst_residual, 1e-9) << reaction_model_name(p.model);
  ASSERT_GT(total[0], 1e-9) << reaction_model_name(p.model);
  EXPECT_LT(total[1] / total[0], 0.2) << reaction_model_name(p.model);  // 0.125 for O(dt^3)
}

INSTANTIATE_TEST_SUITE_P(Reaction, EveryModel,
                         ::testing::Values(ReactionModel::kGrayScott, ReactionModel::kTuring,
                                           ReactionModel::kMeinhardt,
                                           ReactionModel::kFitzHughNagumo, ReactionModel::kBarkley,
                                           ReactionModel::kBarkleyTurbulent),
                         [](const auto& info) {
                           std::string n(reaction_model_name(info.param));
                           for (char& c : n)
                             if (c == '-') c = '_';
                           return n;
                         });

TEST(Reaction, GrayScottEqn11ClosesTheAEquation) {
  ReactionParams p;
  const double dt = 7.0, A = 0.6, B = 0.3;
  const ImplicitResult r = implicit_reaction_cell(p, dt, A, B);
  EXPECT_NEAR(r.a, (A + p.F * dt) / (1 + p.F * dt + dt * r.b * r.b), 1e-15);
}

TEST(Reaction, GrayScottTrivialStateIsAFixedPoint) {
  ReactionParams p;
  const ImplicitResult r = implicit_reaction_cell(p, 1000.0, 1.0, 0.0);
  EXPECT_DOUBLE_EQ(r.a, 1.0);
  EXPECT_DOUBLE_EQ(r.b, 0.0);
}

TEST(Reaction, TuringEquilibriumIsAFixedPoint) {
  ReactionParams p = params_for(ReactionModel::kTuring);
  const ImplicitResult r = implicit_reaction_cell(p, 100.0, 4.0, 4.0);
  EXPECT_NEAR(r.a, 4.0, 1e-9);
  EXPECT_NEAR(r.b, 4.0, 1e-9);
}

TEST(Reaction, ModelNamesRoundTrip) {
  for (int i = 0; i < kReactionModelCount; ++i) {
    ReactionModel m{};
    ASSERT_TRUE(parse_reaction_model(reaction_model_name(ReactionModel(i)), m));
    EXPECT_EQ(int(m), i);
  }
  ReactionModel m{};
  EXPECT_FALSE(parse_reaction_model("grey-scot", m));
}

TEST(Reaction, BadParametersAreNamed) {
  ReactionParams p = params_for(ReactionModel::kMeinhardt);
  p.meinhardt_p1 = 0.5f;
  ASSERT_NE(reaction_params_problem(p), nullptr);
  EXPECT_NE(std::string(reaction_params_problem(p)).find("p1"), std::string::npos);
}

TEST(Reaction, TileKernelsMatchTheCellSolverAndWorkInPlace) {
  FieldF a({8, 6}, 1), b({8, 6}, 1), a2({8, 6}, 1), b2({8, 6}, 1);
  for (int y = 0; y < 6; ++y)
    for (int x = 0; x < 8; ++x) {
      a(x, y) = 0.1f * x + 0.1f;
      b(x, y) = 0.05f * y;
    }
  a2 = a;
  b2 = b;
  ReactionParams p;
  const Box2 region{{1, 1}, {7, 5}};
  gray_scott_implicit_tile(a.view(), b.view(), a2.view(), b2.view(), region, {p.F, p.k, 3.0f});
  for (int y = 0; y < 6; ++y)
    for (int x = 0; x < 8; ++x) {
      if (!region.contains(Int2{x, y})) {
        EXPECT_EQ(a2(x, y), a(x, y));
        continue;
      }
      const ImplicitResult r = implicit_reaction_cell(p, 3.0f, a(x, y), b(x, y));
      EXPECT_FLOAT_EQ(a2(x, y), float(r.a));
      EXPECT_FLOAT_EQ(b2(x, y), float(r.b));
    }
  // In place gives the same values.
  FieldF a3 = a, b3 = b;
  reaction_implicit_tile(a3.view(), b3.view(), a3.view(), b3.view(), region, p, 3.0f);
  for (int y = region.min.y; y < region.max.y; ++y)
    for (int x = region.min.x; x < region.max.x; ++x) {
      EXPECT_EQ(a3(x, y), a2(x, y));
      EXPECT_EQ(b3(x, y), b2(x, y));
    }
}

TEST(Reaction, TrapezoidalTileMatchesTheCellSolverAndStaysBoundedAtLongSteps) {
  for (int m = 0; m < kReactionModelCount; ++m) {
    const ReactionParams p = params_for(ReactionModel(m));
    const ConcentrationBox r = typical_range(p), box = invariant_box(p);
    FieldF a({7, 5}, 1), b({7, 5}, 1);
    for (int y = 0; y < 5; ++y)
      for (int x = 0; x < 7; ++x) {
        a(x, y) = float(r.a_lo + (r.a_hi - r.a_lo) * x / 6.0);
        b(x, y) = float(r.b_lo + (r.b_hi - r.b_lo) * (y + 0.5) / 5.0);
      }
    for (float dt : {0.5f, 1000.0f}) {
      FieldF a2 = a, b2 = b;
      reaction_trapezoidal_tile(a2.view(), b2.view(), a2.view(), b2.view(), box_of_size({7, 5}), p,
                                dt);
      for (int y = 0; y < 5; ++y)
        for (int x = 0; x < 7; ++x) {
          const ImplicitResult c = trapezoidal_reaction_cell(p, dt, a(x, y), b(x, y));
          EXPECT_EQ(a2(x, y), float(c.a));
          EXPECT_EQ(b2(x, y), float(c.b));
          // A long step's forward half may leave the box; the update stays inside it.
          EXPECT_GE(a2(x, y), box.a_lo - 1e-6) << reaction_model_name(p.model);
          EXPECT_LE(a2(x, y), box.a_hi + 1e-6) << reaction_model_name(p.model);
          EXPECT_GE(b2(x, y), box.b_lo - 1e-6) << reaction_model_name(p.model);
          EXPECT_LE(b2(x, y), box.b_hi + 1e-6) << reaction_model_name(p.model);
        }
    }
  }
}

TEST(Reaction, ExplicitReactionBlowsUpAtLargeStepsWhereImplicitDoesNot) {
  for (int m = 0; m < kReactionModelCount; ++m) {
    const ReactionParams p = params_for(ReactionModel(m));
    const ConcentrationBox r = typical_range(p);
    double ea = 0.3 * r.a_hi + 0.7 * r.a_lo, eb = 0.6 * r.b_hi + 0.4 * r.b_lo;
    double ia = ea, ib = eb;
    bool exploded = false;
    for (int step = 0; step < 200 && !exploded; ++step) {
      double ra, rb;
      reaction_rates(p, ea, eb, ra, rb);
      ea += 1000.0 * ra;
      eb += 1000.0 * rb;
      exploded = !std::isfinite(ea) || !std::isfinite(eb) || std::abs(ea) > 1e6;
      const ImplicitResult ir = implicit_reaction_cell(p, 1000.0, ia, ib);
      ia = ir.a;
      ib = ir.b;
    }
    EXPECT_TRUE(exploded) << reaction_model_name(p.model);
    EXPECT_TRUE(std::isfinite(ia) && std::isfinite(ib)) << reaction_model_name(p.model);
  }
}

}  // namespace
}  // namespace ardcell
