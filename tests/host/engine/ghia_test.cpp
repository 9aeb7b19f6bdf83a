// The lid-driven cavity at Re = 100 on 128 x 128 cells, run to steady state and compared with
// Ghia, Ghia & Shin (1982), Tables I and II (../shared/refdata/ghia/).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "host/engine/engine.h"
#include "host/scenes/scene_registry.h"

namespace ardcell {
namespace {

struct GhiaPoint {
  double position;  // y for Table I (u on x = 0.5), x for Table II (v on y = 0.5)
  double value;     // at Re = 100
};

// Reads the Re = 100 column: Table I rows are "y u100 ...", Table II rows are
// "gridpoint x v100 ..."; '#' and '-' lines are comments.
std::vector<GhiaPoint> read_ghia(const std::string& file, int position_column) {
  std::ifstream in(std::string(ARDCELL_SHARED_DIR) + "/refdata/ghia/" + file);
  EXPECT_TRUE(in.good()) << "cannot open " << file;
  std::vector<GhiaPoint> points;
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream row(line);
    std::vector<double> numbers;
    double value;
    while (row >> value) numbers.push_back(value);
    if (line.empty() || line[0] == '#' || numbers.size() < size_t(position_column) + 2) continue;
    points.push_back({numbers[position_column], numbers[position_column + 1]});
  }
  return points;
}

// Bilinear interpolation of a cell-centred field at a point (domain units), with the ghost cells
// (filled by the boundary rules) giving the wall values.
double sample(const FieldF& f, double h, double x, double y) {
  const double gx = x / h - 0.5, gy = y / h - 0.5;  // cell (i, j) is centred at ((i+.5)h, (j+.5)h)
  const int i0 = std::min(std::max(int(std::floor(gx)), -1), f.nx() - 1);
  const int j0 = std::min(std::max(int(std::floor(gy)), -1), f.ny() - 1);
  const double s = gx - i0, t = gy - j0;
  return (1 - t) * ((1 - s) * f(i0, j0) + s * f(i0 + 1, j0)) +
         t * ((1 - s) * f(i0, j0 + 1) + s * f(i0 + 1, j0 + 1));
}

TEST(Ghia, CavityRe100MatchesGhia1982) {
  const auto u_ref = read_ghia("ghia1982_tableI_u_vertical_centerline.txt", 0);
  const auto v_ref = read_ghia("ghia1982_tableII_v_horizontal_centerline.txt", 1);
  ASSERT_EQ(u_ref.size(), 17u);
  ASSERT_EQ(v_ref.size(), 17u);

  SceneConfig scene = builtin_scenes().find("cavity")->make();
  scene.size = {128, 128};
  scene.dt = 0.02;
  set_reynolds_number(scene.fluid, 100.0, scene.domain_width);
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
  for (const GhiaPoint& p : u_ref) {
    const double ours = sample(s.u, s.h, 0.5, p.position);
    u_error = std::max(u_error, std::abs(ours - p.value));
    std::printf("u(0.5, %.4f) = %+.5f  Ghia %+.5f\n", p.position, ours, p.value);
  }
  for (const GhiaPoint& p : v_ref) {
    const double ours = sample(s.v, s.h, p.position, 0.5);
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

}  // namespace
}  // namespace ardcell
