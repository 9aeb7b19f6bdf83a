#include "host/engine/rd_step.h"

#include "host/scenes/scene_registry.h"
#include "kernels/explicit_rd.h"
#include "runtime/boundary.h"
#include "tests/support/rd_frame.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace ardcell {
namespace {

constexpr double kPi = std::numbers::pi;

// A small RD-only scene in grid units (h = 1).
SceneConfig small_scene(ReactionModel model, int n = 20) {
  SceneConfig s;
  s.name = "test";
  s.size = {n, n};
  s.domain_width = n;
  s.dt = 1.0;
  s.fluid.kind = FluidSceneKind::kNone;
  RdConfig& rd = s.rd;
  rd.enabled = true;
  rd.reaction.model = model;
  rd.dt = 1.0;
  rd.cell_size = 1.0;
  rd.diffusion_a = 1.0;
  rd.diffusion_b = 0.5;
  rd.diffusion_solver = {SolverKind::kIccg, 200, 1e-7};
  rd.boundary = BoundaryKind::kDirichlet;
  const ConcentrationBox r = typical_range(rd.reaction);
  const ConcentrationBox box = invariant_box(rd.reaction);
  rd.background_a = float(0.8 * r.a_lo + 0.2 * r.a_hi);
  rd.background_b = float(0.7 * r.b_lo + 0.3 * r.b_hi);
  rd.seed_a = float(0.3 * r.a_lo + 0.7 * r.a_hi);
  rd.seed_b = float(0.4 * r.b_lo + 0.6 * r.b_hi);
  rd.boundary_a = float(std::clamp(double(rd.background_a), box.a_lo, box.a_hi));
  rd.boundary_b = float(std::clamp(double(rd.background_b), box.b_lo, box.b_hi));
  rd.initial = RdInitialPattern::kRandomSpots;
  rd.spots = 6;
  rd.seed_radius = 3;
  rd.noise = 0.05;
  return s;
}

// Solid-body rotation about the centre, up to `speed` cells per step at the corners.
void add_rotating_fluid(SimState& st, double speed) {
  const Int2 n = st.size;
  st.u = FieldF(n, 1);
  st.v = FieldF(n, 1);
  const double c = 0.5 * (n.x - 1), w = speed / c;
  for (int y = 0; y < n.y; ++y)
    for (int x = 0; x < n.x; ++x) {
      st.u(x, y) = float(-(y - c) * w);
      st.v(x, y) = float((x - c) * w);
    }
}

SimState make_state(const SceneConfig& s) {
  SimState st;
  st.size = s.size;
  st.h = s.domain_width / s.size.x;
  st.dt = s.dt;
  return st;
}

struct Range {
  bool finite = true;
  double a_lo = 1e300, a_hi = -1e300, b_lo = 1e300, b_hi = -1e300;
};
Range range_of(const SimState& st) {
  Range r;
  for (int y = 0; y < st.size.y; ++y)
    for (int x = 0; x < st.size.x; ++x) {
      const double a = st.A(x, y), b = st.B(x, y);
      if (!std::isfinite(a) || !std::isfinite(b)) r.finite = false;
      r.a_lo = std::min(r.a_lo, a);
      r.a_hi = std::max(r.a_hi, a);
      r.b_lo = std::min(r.b_lo, b);
      r.b_hi = std::max(r.b_hi, b);
    }
  return r;
}

struct StabilityCase {
  ReactionModel model;
  bool anisotropic;
  bool fluid;
};

class Stability : public ::testing::TestWithParam<StabilityCase> {};

// Unconditional stability: dt = 1000 for 200 steps stays finite and inside the model's
// invariant box (to float32 solve rounding); forward Euler at the same dt blows up.
TEST_P(Stability, ImplicitStaysInTheInvariantBoxWhereExplicitBlowsUp) {
  const StabilityCase c = GetParam();
  SceneConfig s = small_scene(c.model);
  s.rd.dt = 1000.0;
  if (c.anisotropic) {
    s.rd.anisotropy.kind = AnisotropyKind::kCosineLobes;
    s.rd.anisotropy.lobes = 3;
    s.rd.anisotropy.lobe_speed[0] = 2.0f;
    s.rd.anisotropy.lobe_speed[1] = 0.5f;
    s.rd.anisotropy.lobe_speed[2] = 1.0f;
  }
  const ConcentrationBox box = invariant_box(s.rd.reaction);
  const double tol = 1e-3;
  {
    RdStepper rd(s);
    SimState st = make_state(s);
    rd.init_state(st);
    if (c.fluid) add_rotating_fluid(st, 3.0);
    RdFrame frame(rd, st);
    for (int step = 0; step < 200; ++step) {
      frame.step();
      const Range r = range_of(st);
      ASSERT_TRUE(r.finite) << "step " << step;
      ASSERT_GE(r.a_lo, box.a_lo - tol) << "step " << step;
      ASSERT_LE(r.a_hi, box.a_hi + tol) << "step " << step;
      ASSERT_GE(r.b_lo, box.b_lo - tol) << "step " << step;
      ASSERT_LE(r.b_hi, box.b_hi + tol) << "step " << step;
      if (c.model == ReactionModel::kGrayScott) {
        ASSERT_LE(r.b_hi, 1.0 + tol);
      }
    }
  }
  if (!c.anisotropic) {
    s.rd.scheme = RdScheme::kExplicit5;
    RdStepper rd(s);
    SimState st = make_state(s);
    rd.init_state(st);
    if (c.fluid) add_rotating_fluid(st, 3.0);
    RdFrame frame(rd, st);
    bool blew_up = false;
    for (int step = 0; step < 200 && !blew_up; ++step) {
      frame.step();
      const Range r = range_of(st);
      blew_up = !r.finite || r.a_lo < box.a_lo - 1 || r.a_hi > box.a_hi + 1 ||
                r.b_lo < box.b_lo - 1 || r.b_hi > box.b_hi + 1;
    }
    EXPECT_TRUE(blew_up) << "forward Euler at dt = 1000 should leave the invariant box";
  }
}

std::vector<StabilityCase> all_cases() {
  std::vector<StabilityCase> out;
  for (int m = 0; m < kReactionModelCount; ++m)
    for (bool an : {false, true})
      for (bool fl : {false, true}) out.push_back({ReactionModel(m), an, fl});
  return out;
}

INSTANTIATE_TEST_SUITE_P(Rd, Stability, ::testing::ValuesIn(all_cases()), [](const auto& info) {
  std::string n(reaction_model_name(info.param.model));
  for (char& ch : n)
    if (ch == '-') ch = '_';
  return n + (info.param.anisotropic ? "_aniso" : "_iso") +
         (info.param.fluid ? "_fluid" : "_nofluid");
});

// Consistency: the implicit scheme converges to the explicit result as dt shrinks.
TEST(RdStep, GrayScottImplicitConvergesToExplicitAsDtShrinks) {
  SceneConfig s = small_scene(ReactionModel::kGrayScott, 24);
  s.rd.boundary = BoundaryKind::kPeriodic;
  s.rd.diffusion_a = 0.2;
  s.rd.diffusion_b = 0.1;
  s.rd.background_a = 1.0f;
  s.rd.background_b = 0.0f;
  s.rd.seed_a = 0.5f;
  s.rd.seed_b = 0.25f;
  s.rd.noise = 0.0;
  const double T = 40.0;
  auto run = [&](RdScheme scheme, double dt) {
    SceneConfig c = s;
    c.rd.scheme = scheme;
    c.rd.dt = dt;
    RdStepper rd(c);
    SimState st = make_state(c);
    rd.init_state(st);
    RdFrame frame(rd, st);
    for (int i = 0, n = int(std::lround(T / dt)); i < n; ++i) frame.step();
    return st;
  };
  const SimState ref = run(RdScheme::kExplicit5, 0.005);
  double prev = 1e9;
  std::vector<double> errs;
  for (double dt : {2.0, 1.0, 0.5, 0.25}) {
    const SimState st = run(RdScheme::kImplicit, dt);
    double err = 0;
    for (int y = 0; y < 24; ++y)
      for (int x = 0; x < 24; ++x)
        err = std::max({err, std::abs(double(st.A(x, y)) - ref.A(x, y)),
                        std::abs(double(st.B(x, y)) - ref.B(x, y))});
    errs.push_back(err);
    EXPECT_LT(err, 0.75 * prev) << "dt=" << dt;  // first order: about halves
    prev = err;
  }
  std::printf("max error vs explicit (dt = 0.005) at dt 2, 1, 0.5, 0.25: %.3g %.3g %.3g %.3g\n",
              errs[0], errs[1], errs[2], errs[3]);
  EXPECT_LT(errs.back(), 0.05);
  EXPECT_GT(errs.front(), 1e-4);  // the comparison is not trivially zero
}

// Dominant orientation of the pattern's gradients (structure tensor), in [0, pi), and its
// coherence (lambda1 - lambda2) / (lambda1 + lambda2).
std::pair<double, double> orientation(const FieldF& f) {
  const int nx = f.nx(), ny = f.ny();
  double jxx = 0, jxy = 0, jyy = 0;
  for (int y = 0; y < ny; ++y)
    for (int x = 0; x < nx; ++x) {
      const double gx = 0.5 * (f((x + 1) % nx, y) - f((x + nx - 1) % nx, y));
      const double gy = 0.5 * (f(x, (y + 1) % ny) - f(x, (y + ny - 1) % ny));
      jxx += gx * gx;
      jxy += gx * gy;
      jyy += gy * gy;
    }
  double phi = 0.5 * std::atan2(2 * jxy, jxx - jyy);
  if (phi < 0) phi += kPi;
  const double coherence = std::sqrt((jxx - jyy) * (jxx - jyy) + 4 * jxy * jxy) / (jxx + jyy);
  return {phi, coherence};
}

TEST(RdStep, PatternOrientationFollowsTheta0) {
  auto pattern = [&](float theta0) {
    SceneConfig s = small_scene(ReactionModel::kGrayScott, 64);
    RdConfig& rd = s.rd;
    rd.reaction.F = 0.04f;
    rd.reaction.k = 0.06f;
    rd.boundary = BoundaryKind::kPeriodic;
    rd.background_a = 1.0f;
    rd.background_b = 0.0f;
    rd.seed_a = 0.5f;
    rd.seed_b = 0.25f;
    rd.spots = 40;
    rd.seed_radius = 3;
    rd.noise = 0.02;
    rd.dt = 2.0;
    rd.diffusion_solver = {SolverKind::kIccg, 60, 1e-5};
    rd.anisotropy.kind = AnisotropyKind::kCosineLobes;
    rd.anisotropy.lobes = 2;
    rd.anisotropy.lobe_speed[0] = 2.0f;
    rd.anisotropy.lobe_speed[1] = 2.0f;
    rd.anisotropy.theta0 = theta0;
    RdStepper stepper(s);
    SimState st = make_state(s);
    stepper.init_state(st);
    RdFrame frame(stepper, st);
    for (int i = 0; i < 1500; ++i) frame.step();
    return orientation(st.B);
  };
  const auto [phi0, coh0] = pattern(0.0f);
  const auto [phi45, coh45] = pattern(float(kPi / 4));
  std::printf("orientation theta0=0: %.2f deg (coherence %.2f); theta0=45: %.2f deg (%.2f)\n",
              phi0 * 180 / kPi, coh0, phi45 * 180 / kPi, coh45);
  EXPECT_GT(coh0, 0.3);
  EXPECT_GT(coh45, 0.3);
  double d = std::fmod(phi45 - phi0 + 2 * kPi, kPi);  // rotation mod 180 degrees
  if (d > kPi / 2) d -= kPi;
  EXPECT_NEAR(std::abs(d) * 180 / kPi, 45.0, 4.0);
}

TEST(RdStep, AnisotropyOffBLeavesBIsotropic) {
  // Diffusion only, from the same spots: with rd.anisotropy.on_b = false the single lobe steers
  // A's diffusion but B diffuses exactly as in the isotropic scene (Eqn 14 on A only); with the
  // default (on both) B differs too.
  auto run = [](AnisotropyKind kind, bool on_b) {
    SceneConfig s = small_scene(ReactionModel::kGrayScott, 24);
    s.rd.react = false;
    s.rd.anisotropy.kind = kind;
    s.rd.anisotropy.lobes = 1;
    s.rd.anisotropy.lobe_speed[0] = 2.0f;
    s.rd.anisotropy.theta0 = 0.5f;
    s.rd.anisotropy_on_b = on_b;
    RdStepper stepper(s);
    SimState st = make_state(s);
    stepper.init_state(st);
    RdFrame frame(stepper, st);
    for (int i = 0; i < 5; ++i) frame.step();
    return st;
  };
  auto max_difference = [](const FieldF& a, const FieldF& b) {
    double d = 0;
    for (int y = 0; y < a.ny(); ++y)
      for (int x = 0; x < a.nx(); ++x) d = std::max(d, std::abs(double(a(x, y)) - b(x, y)));
    return d;
  };
  const SimState iso = run(AnisotropyKind::kIsotropic, true);
  const SimState a_only = run(AnisotropyKind::kCosineLobes, false);
  const SimState both = run(AnisotropyKind::kCosineLobes, true);
  EXPECT_LT(max_difference(a_only.B, iso.B), 1e-6);
  EXPECT_GT(max_difference(a_only.A, iso.A), 1e-2);
  EXPECT_GT(max_difference(both.B, iso.B), 1e-2);
  EXPECT_LT(max_difference(both.A, a_only.A), 1e-6);
}

TEST(RdStep, BadConfigurationsGetOneLine) {
  SceneConfig s = small_scene(ReactionModel::kFitzHughNagumo);
  s.rd.reaction.fhn_a1 = -1;
  EXPECT_NE(rd_config_problem(s).find("a1"), std::string::npos);
  EXPECT_THROW(RdStepper{s}, std::invalid_argument);
  s = small_scene(ReactionModel::kGrayScott);
  s.rd.scheme = RdScheme::kExplicit9;
  s.rd.anisotropy.kind = AnisotropyKind::kWitkinKass;
  EXPECT_NE(rd_config_problem(s).find("isotropic"), std::string::npos);
  s = small_scene(ReactionModel::kGrayScott);
  s.rd.steps_per_frame = 0;
  EXPECT_FALSE(rd_config_problem(s).empty());
  EXPECT_TRUE(rd_config_problem(small_scene(ReactionModel::kBarkley)).empty());
}

TEST(RdStep, InitialPatternIsDeterministicAndPearsonSquareIsCentred) {
  SceneConfig s = small_scene(ReactionModel::kGrayScott, 32);
  s.rd.initial = RdInitialPattern::kCentreSquare;
  s.rd.seed_size = 0.25;
  s.rd.noise = 0.0;
  s.rd.background_a = 1;
  s.rd.background_b = 0;
  s.rd.seed_a = 0.5f;
  s.rd.seed_b = 0.25f;
  RdStepper rd(s);
  SimState a = make_state(s), b = make_state(s);
  rd.init_state(a);
  rd.init_state(b);
  int in_square = 0;
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 32; ++x) {
      EXPECT_EQ(a.A(x, y), b.A(x, y));
      const bool inside = x >= 12 && x < 20 && y >= 12 && y < 20;
      EXPECT_EQ(a.B(x, y), inside ? 0.25f : 0.0f);
      in_square += inside;
    }
  EXPECT_EQ(in_square, 64);
}

TEST(RdStep, TableAndNewtonGiveTheSamePattern) {
  SceneConfig s = small_scene(ReactionModel::kGrayScott, 24);
  s.rd.dt = 1.0;
  RdStepper newton(s);
  s.rd.use_table = true;
  s.rd.table_resolution = 512;
  RdStepper table(s);
  SimState a = make_state(s), b = make_state(s);
  newton.init_state(a);
  table.init_state(b);
  RdFrame newton_frame(newton, a), table_frame(table, b);
  for (int i = 0; i < 50; ++i) {
    newton_frame.step();
    table_frame.step();
  }
  double err = 0;
  for (int y = 0; y < 24; ++y)
    for (int x = 0; x < 24; ++x) err = std::max(err, std::abs(double(a.B(x, y)) - b.B(x, y)));
  EXPECT_LT(err, 5e-3);
}

// Seed 001's scheme (explicit 9-point Gray-Scott, wrap) runs a frame's steps as one op,
// temporally blocked (Device::gray_scott9_steps: GrayScott9Blocked, kernels/gray_scott9.h; on
// several workers: engine_backend_parity_test). Against the whole-field kernel stepped one step
// at a time (gray_scott9_explicit_tile, the same fused expressions: the same bits), from seed
// 001's start on a 72x56 crop, over 30 frames of 10 steps, and after a live change of F and k.
TEST(RdStep, Seed001SchemeRunsInParallelAndAgreesWithTheWholeFieldKernel) {
  SceneConfig s = builtin_scenes().find("seed001")->make();
  s.size = {72, 56};
  s.domain_width = 72;
  RdStepper rd(s);
  SimState st = make_state(s);
  rd.init_state(st);
  RdFrame frame(rd, st);
  FieldF a = st.A, b = st.B, a2(s.size, 1), b2(s.size, 1);
  std::vector<float> scratch(2 * std::size_t(s.size.x + 2) + 16);
  auto reference_frame = [&](const SceneConfig& scene) {
    const GrayScott9Params p{scene.rd.reaction.F, scene.rd.reaction.k, 1.0f, 1.0f, 0.5f};
    for (int k = 0; k < scene.rd.steps_per_frame; ++k) {
      fill_boundary(a.view(), s.size, BoundaryFill::periodic());
      fill_boundary(b.view(), s.size, BoundaryFill::periodic());
      gray_scott9_explicit_tile(a.view(), b.view(), a2.view(), b2.view(), a.interior(), p,
                                scratch.data());
      std::swap(a, a2);
      std::swap(b, b2);
    }
  };
  auto max_difference = [&] {
    double worst = 0;
    for (int y = 0; y < s.size.y; ++y)
      for (int x = 0; x < s.size.x; ++x)
        worst = std::max({worst, std::abs(double(st.A(x, y)) - a(x, y)),
                          std::abs(double(st.B(x, y)) - b(x, y))});
    return worst;
  };
  for (int f = 0; f < 30; ++f) {
    frame.step();
    reference_frame(s);
  }
  EXPECT_EQ(max_difference(), 0.0);
  EXPECT_GT(st.B(36, 28 + 8), 1e-3);  // the pattern has spread beyond the 10x10 seed
  s.rd.reaction.F = 0.035f;
  s.rd.reaction.k = 0.065f;
  rd.update_parameters(s);
  for (int f = 0; f < 10; ++f) {
    frame.step();
    reference_frame(s);
  }
  EXPECT_EQ(max_difference(), 0.0);
}

}  // namespace
}  // namespace ardcell
