#include "host/engine/fluid_step.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "host/engine/engine.h"
#include "host/scenes/scene_registry.h"
#include "kernels/advect.h"

namespace ardcell {
namespace {

SceneConfig ink_box(Int2 size, SolverKind solver) {
  SceneConfig s = builtin_scenes().find("ink")->make();
  s.size = size;
  s.fluid.emitters.clear();
  s.fluid.viscosity = 1e-3;
  s.fluid.walls = FluidWalls::kFreeSlip;
  s.fluid.pressure_solver = {solver, 400, 1e-7};
  s.fluid.viscosity_solver = {solver, 400, 1e-7};
  return s;
}

void fill_random(FieldF& f, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> dist(-1.0f, 1.0f);
  for (int j = 0; j < f.ny(); ++j)
    for (int i = 0; i < f.nx(); ++i) f(i, j) = dist(rng);
}

// |div|_2 of the MAC face fluxes u_f = (u(i) + u(i+1)) / 2 - (p(i+1) - p(i)) / h, in double,
// from the velocity before the projection (ghosts filled by the scene's rules) and the pressure.
double face_divergence(const FieldF& u, const FieldF& v, const FieldF* p, double h) {
  auto pr = [&](int i, int j) { return p ? double((*p)(i, j)) : 0.0; };
  auto flux_x = [&](int i, int j) {  // face between (i, j) and (i + 1, j)
    return 0.5 * (double(u(i, j)) + u(i + 1, j)) - (pr(i + 1, j) - pr(i, j)) / h;
  };
  auto flux_y = [&](int i, int j) {
    return 0.5 * (double(v(i, j)) + v(i, j + 1)) - (pr(i, j + 1) - pr(i, j)) / h;
  };
  double sum = 0.0;
  for (int j = 0; j < u.ny(); ++j)
    for (int i = 0; i < u.nx(); ++i) {
      const double d = (flux_x(i, j) - flux_x(i - 1, j) + flux_y(i, j) - flux_y(i, j - 1)) / h;
      sum += d * d;
    }
  return std::sqrt(sum);
}

double central_divergence(const FieldF& u, const FieldF& v, double h) {
  double sum = 0.0;
  for (int j = 0; j < u.ny(); ++j)
    for (int i = 0; i < u.nx(); ++i) {
      const double d = (double(u(i + 1, j)) - u(i - 1, j) + v(i, j + 1) - v(i, j - 1)) / (2 * h);
      sum += d * d;
    }
  return std::sqrt(sum);
}

class Projection : public ::testing::TestWithParam<SolverKind> {};

// The projection makes the face fluxes divergence-free (relative to the divergence it started
// from) to 1e-6. A white-noise velocity is the hard case: its divergence lives at every scale.
TEST_P(Projection, LeavesFaceFluxesDivergenceFree) {
  const SceneConfig scene = ink_box({48, 40}, GetParam());
  FluidStep fluid(scene.fluid, scene.size, scene.domain_width / scene.size.x, scene.dt);
  SimState s;
  s.dt = scene.dt;
  fluid.reset(s);
  fill_random(s.u, 1);
  fill_random(s.v, 2);
  fluid.fill_velocity(s);
  const FieldF u0 = s.u, v0 = s.v;
  const double before = face_divergence(u0, v0, nullptr, s.h);
  const SolveReport report = fluid.project(s);
  const double after = face_divergence(u0, v0, &s.p, s.h);
  std::printf("%s: relative face divergence %.2e (%d iterations, solver residual %.2e)\n",
              std::string(solver_kind_name(GetParam())).c_str(), after / before, report.iterations,
              report.relative_residual);
  EXPECT_LT(after / before, 1e-6);
  // The normal velocity on the walls stays zero (free-slip box: Stam's set_bnd).
  for (int j = 0; j < s.size.y; ++j) EXPECT_EQ(s.u(-1, j), -s.u(0, j));
}

// For a smooth flow the cell-centred velocity (the average of the projected face velocities)
// is divergence-free to O(h^2) in central differences.
TEST_P(Projection, ReducesCellCentredDivergenceOfSmoothFlow) {
  const SceneConfig scene = ink_box({64, 64}, GetParam());
  FluidStep fluid(scene.fluid, scene.size, scene.domain_width / scene.size.x, scene.dt);
  SimState s;
  s.dt = scene.dt;
  fluid.reset(s);
  const double pi = 3.14159265358979;
  for (int j = 0; j < 64; ++j)
    for (int i = 0; i < 64; ++i) {
      const double x = (i + 0.5) / 64, y = (j + 0.5) / 64;
      s.u(i, j) = float(std::sin(pi * x) * std::cos(2 * pi * y) + 0.5 * std::sin(2 * pi * x));
      s.v(i, j) = float(std::sin(pi * y) * (0.3 + x * x));
    }
  fluid.fill_velocity(s);
  const double before = central_divergence(s.u, s.v, s.h);
  fluid.project(s);
  const double after = central_divergence(s.u, s.v, s.h);
  std::printf("smooth flow: central divergence %.3g -> %.3g (ratio %.2e)\n", before, after,
              after / before);
  EXPECT_LT(after / before, 2e-2);
}

INSTANTIATE_TEST_SUITE_P(Solvers, Projection,
                         ::testing::Values(SolverKind::kIccg, SolverKind::kMultigrid),
                         [](const auto& info) {
                           return std::string(solver_kind_name(info.param));
                         });

double total(const FieldF& f) {
  double sum = 0.0;
  for (int j = 0; j < f.ny(); ++j)
    for (int i = 0; i < f.nx(); ++i) sum += f(i, j);
  return sum;
}

float max_of(const FieldF& f) {
  float m = f(0, 0);
  for (int j = 0; j < f.ny(); ++j)
    for (int i = 0; i < f.nx(); ++i) m = std::max(m, f(i, j));
  return m;
}

float min_of(const FieldF& f) {
  float m = f(0, 0);
  for (int j = 0; j < f.ny(); ++j)
    for (int i = 0; i < f.nx(); ++i) m = std::min(m, f(i, j));
  return m;
}

void swirl(SimState& s, double speed) {
  // A smooth vortex filling the box (zero normal velocity on the walls).
  const double pi = 3.14159265358979;
  for (int j = 0; j < s.size.y; ++j)
    for (int i = 0; i < s.size.x; ++i) {
      const double x = (i + 0.5) / s.size.x, y = (j + 0.5) / s.size.y;
      s.u(i, j) = float(speed * std::sin(pi * x) * std::sin(pi * x) * std::sin(2 * pi * y));
      s.v(i, j) = float(-speed * std::sin(pi * y) * std::sin(pi * y) * std::sin(2 * pi * x));
    }
}

TEST(FluidStep, DyeMassConservedInAClosedBox) {
  SceneConfig scene = ink_box({64, 64}, SolverKind::kMultigrid);
  scene.fluid.pressure_solver = {SolverKind::kMultigrid, 20, 1e-5};
  scene.fluid.viscosity_solver = {SolverKind::kMultigrid, 8, 1e-5};
  scene.dt = 0.01;
  Engine engine(scene);
  SimState& s = engine.state();
  swirl(s, 1.0);
  for (int j = 0; j < 64; ++j)
    for (int i = 0; i < 64; ++i) {
      const double dx = (i - 20.0) / 6.0, dy = (j - 36.0) / 6.0;
      s.dye(i, j) = float(std::exp(-(dx * dx + dy * dy)));
    }
  const double mass0 = total(s.dye);
  double worst = 0.0;
  for (int k = 0; k < 1000; ++k) {
    engine.step();
    worst = std::max(worst, std::abs(total(s.dye) - mass0) / mass0);
    // The mass fix rescales; it must not create dye beyond the initial range.
    ASSERT_LE(max_of(s.dye), 1.0f + 1e-4f) << "step " << k;
    ASSERT_GE(min_of(s.dye), -1e-6f) << "step " << k;
  }
  std::printf("dye mass: worst relative change over 1000 steps %.3e\n", worst);
  EXPECT_LT(worst, 0.01);
}

TEST(FluidStep, StableAtHundredTimesTheCflLimit) {
  // Cavity, lid speed 1: the advective CFL limit is dt = h / 1 = 1/64; run at 100x that.
  SceneConfig scene = builtin_scenes().find("cavity")->make();
  scene.size = {64, 64};
  scene.dt = 100.0 / 64.0;
  scene.fluid.pressure_solver = {SolverKind::kMultigrid, 20, 1e-5};
  scene.fluid.viscosity_solver = {SolverKind::kMultigrid, 8, 1e-5};
  Engine engine(scene);
  const SimState& s = engine.state();
  double top_speed = 0.0;
  for (int k = 0; k < 1000; ++k) {
    engine.step();
    for (int j = 0; j < 64; ++j)
      for (int i = 0; i < 64; ++i) {
        ASSERT_TRUE(std::isfinite(s.u(i, j)) && std::isfinite(s.v(i, j)) &&
                    std::isfinite(s.p(i, j)))
            << "step " << k;
        top_speed = std::max({top_speed, double(std::abs(s.u(i, j))), double(std::abs(s.v(i, j)))});
        // Bilinear back-tracing never leaves the range of the dye it samples.
        ASSERT_GE(s.dye(i, j), -1e-6f);
        ASSERT_LE(s.dye(i, j), 1.0f + 1e-6f);
      }
  }
  std::printf("largest speed over 1000 steps at 100x CFL: %.3f (lid 1)\n", top_speed);
  EXPECT_LT(top_speed, 2.0);
}

}  // namespace
}  // namespace ardcell
