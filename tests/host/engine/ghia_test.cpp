// The lid-driven cavity at Re = 100 on 128 x 128 cells, run to steady state and compared with
// Ghia, Ghia & Shin (1982), Tables I and II (../shared/refdata/ghia/).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "host/engine/engine.h"
#include "host/scenes/scene_registry.h"
#include "tests/support/ghia_reference.h"

namespace ardcell {
namespace {

class Ghia : public ::testing::TestWithParam<AdvectionScheme> {};

TEST_P(Ghia, CavityRe100MatchesGhia1982) {
  const auto u_ref = ghia::read(false, 100);
  const auto v_ref = ghia::read(true, 100);
  ASSERT_EQ(u_ref.size(), 17u);
  ASSERT_EQ(v_ref.size(), 17u);

  SceneConfig scene = builtin_scenes().find("cavity")->make();
  scene.size = {128, 128};
  scene.dt = 0.02;
  set_reynolds_number(scene.fluid, 100.0, scene.domain_width);
  scene.fluid.advection = GetParam();
  ASSERT_NEAR(scene.fluid.viscosity, 0.01, 1e-12);
  Engine engine(scene);
  SimState& s = engine.state();

  // Steady state: the largest change of u or v per unit time below 1e-3 (the lid speed is 1).
  FieldF previous_u = s.u, previous_v = s.v;
  double rate = 1.0;
  int steps = 0;
  while (steps < 4000) {
    engine.step();
    ++steps;
    if (steps % 50) continue;
    double change = 0.0;
    for (int j = 0; j < s.size.y; ++j)
      for (int i = 0; i < s.size.x; ++i)
        change = std::max({change, double(std::abs(s.u(i, j) - previous_u(i, j))),
                           double(std::abs(s.v(i, j) - previous_v(i, j)))});
    rate = change / (50 * scene.dt);
    previous_u = s.u;
    previous_v = s.v;
    if (rate < 1e-3) break;
  }
  std::printf("steady after %d steps (t = %.1f), max |du/dt| = %.2e\n", steps, s.time, rate);
  ASSERT_LT(rate, 1e-3);

  double u_error = 0.0, v_error = 0.0;
  for (const ghia::Point& p : u_ref) {
    const double ours = ghia::sample(s.u, s.h, 0.5, p.position);
    u_error = std::max(u_error, std::abs(ours - p.value));
    std::printf("u(0.5, %.4f) = %+.5f  Ghia %+.5f\n", p.position, ours, p.value);
  }
  for (const ghia::Point& p : v_ref) {
    const double ours = ghia::sample(s.v, s.h, p.position, 0.5);
    v_error = std::max(v_error, std::abs(ours - p.value));
    std::printf("v(%.4f, 0.5) = %+.5f  Ghia %+.5f\n", p.position, ours, p.value);
  }
  std::printf("max error: u on x = 0.5: %.4f, v on y = 0.5: %.4f\n", u_error, v_error);
  // Measured (dt = 0.02, multigrid, steady at t ~ 10): 0.0053 for u, 0.0043 for v, i.e. under
  // 0.5% of the lid speed. The scheme is first-order semi-Lagrangian, whose interpolation adds
  // a numerical diffusivity of about h^2 s(1 - s) / (2 dt) <= (1/128)^2 / (8 * 0.02) ~ 4e-4,
  // a few per cent of nu = 0.01 at Re = 100, so the profiles come out slightly flattened (the
  // largest deviations sit at the extrema near the walls, v(0.95, 0.5) and u(0.5, 0.73)).
  // The bound 0.01 (1% of the lid speed) leaves about 2x margin over the measurement for other
  // compilers, FMA contraction and solver round-off, while staying well inside the spread that
  // coarse or more diffusive cavity solvers typically show against Ghia (several per cent).
  EXPECT_LT(u_error, 0.01);
  EXPECT_LT(v_error, 0.01);
}

INSTANTIATE_TEST_SUITE_P(Advection, Ghia,
                         ::testing::Values(AdvectionScheme::kSemiLagrangian,
                                           AdvectionScheme::kMacCormack),
                         [](const ::testing::TestParamInfo<AdvectionScheme>& info) {
                           return info.param == AdvectionScheme::kMacCormack
                                      ? std::string("MacCormack")
                                      : std::string("SemiLagrangian");
                         });

}  // namespace
}  // namespace ardcell
