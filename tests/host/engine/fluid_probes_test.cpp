// The obstacle channel's probes (host/engine/fluid_probes.h): the control-volume force by hand,
// the series summary on known signals, the CSV rows; and the generalised channel itself
// (host/engine/fluid_step.cpp): every inflow side is the same flow turned, and the cut-cell
// projection leaves no weighted divergence.
#include "host/engine/fluid_probes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "host/engine/engine.h"
#include "host/engine/fluid_step.h"
#include "host/scenes/scene_registry.h"

namespace ardcell {
namespace {

SceneConfig channel(Int2 size = {64, 32}) {
  SceneConfig s = builtin_scenes().find("dfg-2d1")->make();
  s.size = size;
  s.domain_width = 2.0;  // h = 2 / 64
  s.fluid.obstacle_x = 0.5;
  s.fluid.obstacle_y = 0.5;
  s.fluid.obstacle_radius = 0.1;
  return s;
}

SimState uniform_state(const SceneConfig& scene, float u, float v) {
  SimState st;
  st.size = scene.size;
  st.h = scene.domain_width / scene.size.x;
  st.dt = 0.1;
  st.u = FieldF(scene.size, 1);
  st.v = FieldF(scene.size, 1);
  st.u.fill(u);
  st.v.fill(v);
  return st;
}

// Uniform flow and uniform pressure: as much momentum leaves the box as enters, no force.
TEST(ObstacleProbes, UniformFlowAndPressureGiveNoForce) {
  const SceneConfig scene = channel();
  ObstacleProbes probes(scene);
  const SimState st = uniform_state(scene, 0.7f, -0.2f);
  FieldF p(scene.size, 1);
  p.fill(3.0f);
  const Field<uint8_t> no_solid;
  for (int frame = 0; frame < 2; ++frame) {
    const FluidProbeSample s = probes.sample(st, p, no_solid);
    EXPECT_NEAR(s.drag_coefficient, 0.0, 1e-9);
    EXPECT_NEAR(s.lift_coefficient, 0.0, 1e-9);
  }
}

// Fluid at rest in a pressure gradient P = -G x: the box's edges push with G times its area
// along +x, and with no change of momentum that is the force on what is inside:
// C_drag = 2 G A / (U^2 D), no lift.
TEST(ObstacleProbes, PressureGradientPushesWithItsIntegral) {
  const SceneConfig scene = channel();
  ObstacleProbes probes(scene);
  const SimState st = uniform_state(scene, 0.0f, 0.0f);
  const double h = st.h, g = 0.25;
  FieldF p(scene.size, 1);
  for (int j = -1; j <= scene.size.y; ++j)
    for (int i = -1; i <= scene.size.x; ++i) p(i, j) = float(-g * (i + 0.5) * h);
  const FluidProbeSample s = probes.sample(st, p, Field<uint8_t>());
  const Box2 b = probes.box();
  const double area = double(b.max.x - b.min.x) * (b.max.y - b.min.y) * h * h;
  const double u = scene.fluid.inflow_speed, d = 2 * scene.fluid.obstacle_radius;
  EXPECT_NEAR(s.drag_coefficient, 2 * g * area / (u * u * d), 1e-5);
  EXPECT_NEAR(s.lift_coefficient, 0.0, 1e-9);
  // The box is two radii from the centre, on cell faces.
  EXPECT_LE(b.min.x * h, scene.fluid.obstacle_x - 2 * scene.fluid.obstacle_radius + 1e-12);
  EXPECT_GE(b.max.x * h, scene.fluid.obstacle_x + 2 * scene.fluid.obstacle_radius - 1e-12);
}

// A force turns with the inflow direction: the same field seen from an inflow on the bottom is
// lift for the left inflow's drag.
TEST(ObstacleProbes, DragIsAlongTheInflowAndLiftAcrossIt) {
  SceneConfig left = channel({64, 64});
  SceneConfig bottom = left;
  bottom.fluid.inflow_side = BoundarySide::kBottom;
  const SimState st = uniform_state(left, 0.0f, 0.0f);
  FieldF p(left.size, 1);
  for (int j = -1; j <= left.size.y; ++j)
    for (int i = -1; i <= left.size.x; ++i) p(i, j) = float(-0.3 * i * st.h);
  ObstacleProbes from_left(left), from_bottom(bottom);
  const FluidProbeSample a = from_left.sample(st, p, Field<uint8_t>());
  const FluidProbeSample b = from_bottom.sample(st, p, Field<uint8_t>());
  EXPECT_GT(a.drag_coefficient, 0.0);
  EXPECT_NEAR(b.drag_coefficient, 0.0, 1e-9);
  EXPECT_NEAR(b.lift_coefficient, -a.drag_coefficient, 1e-6);  // +x is to the right of +y
}

TEST(ObstacleProbes, ProbesInterpolateAndDifference) {
  SceneConfig scene = channel();
  scene.fluid.probes = {0.5f, 0.25f, 1.0f, 0.25f, -1, -1, -1, -1};
  ObstacleProbes probes(scene);
  const SimState st = uniform_state(scene, 1.5f, 0.5f);
  FieldF p(scene.size, 1);
  for (int j = -1; j <= scene.size.y; ++j)
    for (int i = -1; i <= scene.size.x; ++i) p(i, j) = float(2.0 * (i + 0.5) * st.h);  // P = 2x
  const FluidProbeSample s = probes.sample(st, p, Field<uint8_t>());
  ASSERT_EQ(s.probes, 2);
  EXPECT_FLOAT_EQ(s.u[0], 1.5f);
  EXPECT_FLOAT_EQ(s.v[1], 0.5f);
  EXPECT_NEAR(s.p[0], 1.0, 1e-5);
  EXPECT_NEAR(s.pressure_difference, 2.0 * (0.5 - 1.0), 1e-5);
  char row[kProbeCsvRowBytes];
  const std::size_t n = format_probe_csv_row(row, sizeof row, 7, s);
  const std::string text(row, n);
  EXPECT_EQ(text.substr(0, 2), "7,");
  EXPECT_EQ(text.back(), '\n');
  EXPECT_EQ(std::count(text.begin(), text.end(), ','), 4 + 3 * 2);
  EXPECT_EQ(probe_csv_header(2),
            "frame,time,drag_coefficient,lift_coefficient,pressure_difference,u1,v1,p1,u2,v2,p2");
}

std::vector<FluidProbeSample> sine_lift(double frequency, double amplitude, double dt, int n) {
  std::vector<FluidProbeSample> out(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    FluidProbeSample& s = out[std::size_t(i)];
    s.time = i * dt;
    s.lift_coefficient = 0.1 + amplitude * std::sin(2 * M_PI * frequency * s.time);
    s.drag_coefficient = 3.0 + 0.05 * std::cos(4 * M_PI * frequency * s.time);
    s.pressure_difference = 2.0 + std::sin(2 * M_PI * frequency * s.time);  // max at lift's max
  }
  return out;
}

TEST(ProbeSeries, StrouhalMaximaAndTheHalfPeriodPressureDifference) {
  const double f = 3.0, dt = 0.001;
  const auto s = sine_lift(f, 1.0, dt, 6000);
  const ProbeSeriesSummary r = summarize_probe_series(s, 2.0, 1.0, 0.1);
  EXPECT_NEAR(r.strouhal, f * 0.1, 1e-4);
  EXPECT_GE(r.periods, 10);
  EXPECT_NEAR(r.lift_max, 1.1, 1e-4);
  EXPECT_NEAR(r.drag_max, 3.05, 1e-4);
  // Half a period after the lift's maximum the pressure difference is at its minimum.
  EXPECT_NEAR(r.pressure_difference, 1.0, 1e-3);
  // A twice faster inflow halves St.
  EXPECT_NEAR(summarize_probe_series(s, 2.0, 2.0, 0.1).strouhal, f * 0.05, 1e-4);
}

TEST(ProbeSeries, ASteadyLiftHasNoPeriod) {
  const auto s = sine_lift(3.0, 0.001, 0.001, 6000);  // wobbles below kMinLiftAmplitude
  const ProbeSeriesSummary r = summarize_probe_series(s, 2.0, 1.0, 0.1);
  EXPECT_EQ(r.strouhal, 0.0);
  EXPECT_EQ(r.periods, 0);
  EXPECT_EQ(r.pressure_difference, s.back().pressure_difference);
}

// The channel along y (inflow at the bottom) is the channel along x (inflow at the left)
// mirrored across the diagonal: u and v exchange, and so do the walls.
TEST(Channel, EveryInflowSideIsTheSameFlowTurned) {
  SceneConfig along_x = channel({48, 24});
  along_x.fluid.wall_low = FluidWalls::kNoSlip;
  along_x.fluid.wall_high = FluidWalls::kFreeSlip;
  along_x.fluid.obstacle_x = 0.4;
  along_x.fluid.obstacle_y = 0.45;
  along_x.fluid.inflow_speed = 1.0;
  along_x.dt = 0.01;
  SceneConfig along_y = along_x;
  along_y.size = {24, 48};
  along_y.domain_width = along_x.domain_width / 2;  // the same h
  along_y.fluid.inflow_side = BoundarySide::kBottom;
  std::swap(along_y.fluid.obstacle_x, along_y.fluid.obstacle_y);
  Engine ex(along_x), ey(along_y);
  for (int i = 0; i < 20; ++i) ex.step(), ey.step();
  const SimState &a = ex.state(), &b = ey.state();
  double worst = 0.0, largest = 0.0;
  for (int j = 0; j < 24; ++j)
    for (int i = 0; i < 48; ++i) {
      worst = std::max({worst, std::abs(double(a.u(i, j)) - b.v(j, i)),
                        std::abs(double(a.v(i, j)) - b.u(j, i)),
                        std::abs(double(a.dye(i, j)) - b.dye(j, i))});
      largest = std::max(largest, std::abs(double(a.u(i, j))));
    }
  EXPECT_GT(largest, 0.5);
  EXPECT_LT(worst, 1e-4 * largest);
  // The outflow is the opposite side: a right inflow carries the fluid leftwards.
  SceneConfig from_right = along_x;
  from_right.fluid.inflow_side = BoundarySide::kRight;
  Engine er(from_right);
  for (int i = 0; i < 5; ++i) er.step();
  EXPECT_LT(er.state().u(40, 12), -0.5f);
}

// The cut-cell projection: every cell's open faces carry no net flux (to the solver's
// tolerance), while the staircase's cells along the circle do not see its faces' fractions.
TEST(Channel, CutCellProjectionConservesMassThroughOpenFaces) {
  SceneConfig scene = channel({96, 48});
  scene.fluid.pressure_solver = {SolverKind::kMultigrid, 50, 1e-9};
  Engine engine(scene);
  for (int i = 0; i < 3; ++i) engine.step();
  FluidStep& fluid = *engine.fluid_step();
  SimState& st = engine.state();
  fluid.project(st);
  const FieldF &uf = fluid.face_u(), &vf = fluid.face_v();
  const FieldF &ox = fluid.open_x(), &oy = fluid.open_y();
  ASSERT_FALSE(ox.empty());
  // The fractions: in [0, 1], some faces cut part way, the faces through the disc's centre
  // shut over its diameter (2 r / h = 9.6 cells: at least 3 whole faces).
  int partial = 0;
  for (std::size_t i = 0; i < ox.raw_size(); ++i) {
    ASSERT_GE(ox.raw()[i], 0.0f);
    ASSERT_LE(ox.raw()[i], 1.0f);
    partial += ox.raw()[i] > 0.0f && ox.raw()[i] < 1.0f;
  }
  EXPECT_GT(partial, 4);
  const int centre_face = int(std::lround(scene.fluid.obstacle_x / st.h));
  int shut = 0;
  for (int j = 0; j < scene.size.y; ++j) shut += ox(centre_face, j) == 0.0f;
  EXPECT_GE(shut, 3);
  double worst = 0.0, unweighted = 0.0, cut_cells = 0;
  for (int j = 1; j < scene.size.y - 1; ++j)
    for (int i = 1; i < scene.size.x - 1; ++i) {
      const double ol = ox(i, j), orr = ox(i + 1, j), ob = oy(i, j), oa = oy(i, j + 1);
      if (ol + orr + ob + oa == 0.0) continue;  // covered
      const double flux = orr * uf(i + 1, j) - ol * uf(i, j) + oa * vf(i, j + 1) - ob * vf(i, j);
      worst = std::max(worst, std::abs(flux));
      if (ol < 1 || orr < 1 || ob < 1 || oa < 1) {
        ++cut_cells;
        unweighted = std::max(unweighted,
                              std::abs(double(uf(i + 1, j)) - uf(i, j) + vf(i, j + 1) - vf(i, j)));
      }
    }
  EXPECT_GT(cut_cells, 20);
  EXPECT_LT(worst, 1e-4 * scene.fluid.inflow_speed);
  EXPECT_GT(unweighted, 100 * worst);  // the weights are what balances the cut cells
}

TEST(Channel, BadChannelSettingsAreRefusedWithOneLine) {
  SceneConfig s = channel();
  s.fluid.wall_low = FluidWalls::kPeriodic;
  EXPECT_NE(fluid_config_problem(s).find("fluid.wall_low"), std::string::npos);
  s = channel();
  s.fluid.probes = {0.5f, -1, -1, -1, -1, -1, -1, -1};
  EXPECT_NE(fluid_config_problem(s).find("fluid.probes"), std::string::npos);
  EXPECT_THROW(Engine e(s), std::invalid_argument);
  EXPECT_EQ(fluid_config_problem(channel()), "");
  EXPECT_THROW(ObstacleProbes p(builtin_scenes().find("cavity")->make()), std::invalid_argument);
}

}  // namespace
}  // namespace ardcell
