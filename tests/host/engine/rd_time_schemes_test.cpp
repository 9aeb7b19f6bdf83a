// The reaction-diffusion time schemes (docs/numerics.md, "Reaction-diffusion in time"):
//  - convergence: each scheme against its own fine-step run on a small periodic Gray-Scott grid,
//    observed order 1 (implicit), 2 (crank-nicolson-am2, sbdf2) or 4 (etdrk4);
//  - growth rate: on Pearson's domain (2.5 x 2.5, periodic, D_A 2e-5, D_B 1e-5, F 0.060,
//    k 0.062) around the Turing-unstable homogeneous state with a small random perturbation,
//    the growth rate of the most unstable Fourier mode measured by projecting the field onto it,
//    against the linear stability of the Gray-Scott system with the 5-point Laplacian's symbol
//    (computed here), within 5% at the largest dt each scheme claims;
//  - sbdf2's history: its first step and the first after a restart are SBDF1;
//  - serial and threads give the same bits with every new scheme.
#include "tests/support/rd_frame.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <cstring>
#include <numbers>
#include <string>
#include <vector>

#include "host/engine/engine.h"
#include "host/engine/rd_step.h"

namespace ardcell {
namespace {

constexpr double kPi = std::numbers::pi;

SimState make_state(const SceneConfig& s) {
  SimState st;
  st.size = s.size;
  st.h = s.domain_width / s.size.x;
  st.dt = s.dt;
  return st;
}

// Fixed Jacobi sweeps that take a solve's error below 1e-10 at the contraction 4s / (1 + 4s),
// s = D dt / h^2: no tolerance decides when a solve stops, so runs differ only in their time
// steps, and the diffusion is solved to float rounding.
int jacobi_sweeps(double s) {
  return int(std::ceil(std::log(1e-10) / std::log(4 * s / (1 + 4 * s))));
}

// A periodic Gray-Scott scene on an n x n grid of the given width, no fluid, uniform start: what
// the scenes below share.
SceneConfig periodic_gray_scott(RdScheme scheme, double dt, int n, double width) {
  SceneConfig s;
  s.name = "rd-time";
  s.size = {n, n};
  s.domain_width = width;
  s.dt = dt;
  s.fluid.kind = FluidSceneKind::kNone;
  RdConfig& rd = s.rd;
  rd.enabled = true;
  rd.scheme = scheme;
  rd.reaction.model = ReactionModel::kGrayScott;
  rd.dt = dt;
  rd.boundary = BoundaryKind::kPeriodic;
  rd.initial = RdInitialPattern::kUniform;
  rd.noise = 0.0;
  return s;
}

// --- convergence ----------------------------------------------------------------------------

// Gray-Scott (F 0.04, k 0.06, D_A 0.2, D_B 0.1 in cells) on a 32^2 periodic grid from a smooth
// bump: the solution is smooth in time, so each scheme shows its order.
SceneConfig convergence_scene(RdScheme scheme, double dt) {
  SceneConfig s = periodic_gray_scott(scheme, dt, 32, 32.0);
  s.rd.reaction.F = 0.04f;
  s.rd.reaction.k = 0.06f;
  s.rd.diffusion_a = 0.2;
  s.rd.diffusion_b = 0.1;
  s.rd.diffusion_solver = {SolverKind::kJacobi, jacobi_sweeps(0.2 * dt), 0.0};
  return s;
}

SimState run_convergence(RdScheme scheme, double dt, double t_end) {
  const SceneConfig s = convergence_scene(scheme, dt);
  RdStepper rd(s);
  SimState st = make_state(s);
  rd.init_state(st);
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 32; ++x) {
      const double r2 = (x - 15.5) * (x - 15.5) + (y - 13.0) * (y - 13.0);
      const double g = std::exp(-r2 / 18.0);
      st.A(x, y) = float(1.0 - 0.5 * g);
      st.B(x, y) = float(0.25 * g);
    }
  RdFrame frame(rd, st);
  for (int i = 0, n = int(std::lround(t_end / dt)); i < n; ++i) frame.step();
  return st;
}

double max_difference(const SimState& a, const SimState& b) {
  double e = 0;
  for (int y = 0; y < a.size.y; ++y)
    for (int x = 0; x < a.size.x; ++x)
      e = std::max(
          {e, std::abs(double(a.A(x, y)) - b.A(x, y)), std::abs(double(a.B(x, y)) - b.B(x, y))});
  return e;
}

struct ConvergenceCase {
  RdScheme scheme;
  const char* name;
  double order;         // expected
  double dt0;           // the coarsest of three steps dt0, dt0 / 2, dt0 / 4
  double reference_dt;  // the fine-step run
};

class Convergence : public testing::TestWithParam<ConvergenceCase> {};

TEST_P(Convergence, ObservedOrderAgainstAFineStepReference) {
  const ConvergenceCase& c = GetParam();
  const double t_end = 48.0;
  const SimState reference = run_convergence(c.scheme, c.reference_dt, t_end);
  double e[3];
  for (int i = 0; i < 3; ++i)
    e[i] = max_difference(run_convergence(c.scheme, c.dt0 / (1 << i), t_end), reference);
  const double p1 = std::log2(e[0] / e[1]), p2 = std::log2(e[1] / e[2]);
  std::printf("%s: max error at dt %g, %g, %g: %.3g %.3g %.3g; observed order %.2f, %.2f\n", c.name,
              c.dt0, c.dt0 / 2, c.dt0 / 4, e[0], e[1], e[2], p1, p2);
  EXPECT_GT(e[2], 20 * 1e-6) << "errors near float rounding say nothing about the order";
  EXPECT_NEAR(p1, c.order, 0.3 * c.order);
  EXPECT_NEAR(p2, c.order, 0.2 * c.order);
}

INSTANTIATE_TEST_SUITE_P(
    EveryScheme, Convergence,
    testing::Values(ConvergenceCase{RdScheme::kImplicit, "implicit", 1, 2.0, 1.0 / 16},
                    ConvergenceCase{RdScheme::kCrankNicolsonAm2, "crank_nicolson_am2", 2, 4.0,
                                    1.0 / 16},
                    ConvergenceCase{RdScheme::kSbdf2, "sbdf2", 2, 2.0, 1.0 / 16},
                    ConvergenceCase{RdScheme::kEtdrk4, "etdrk4", 4, 12.0, 3.0 / 8}),
    [](const testing::TestParamInfo<ConvergenceCase>& info) {
      return std::string(info.param.name);
    });

// --- growth rate of the most unstable mode --------------------------------------------------

constexpr double kF = 0.060, kK = 0.062, kDa = 2e-5, kDb = 1e-5, kWidth = 2.5;

// The homogeneous state (A*, B*) = ((F + k) / B*, B*) on the upper branch of
// (F + k) B^2 - F B + F (F + k) = 0, which is stable to uniform perturbations and
// Turing-unstable (Pearson 1993).
void homogeneous_state(double& a, double& b) {
  const double fk = kF + kK;
  b = (kF + std::sqrt(kF * kF - 4 * kF * fk * fk)) / (2 * fk);
  a = fk / b;
}

struct Mode {
  int mx = 0, my = 0;
  double growth = -1e300;  // per unit time
};

// Linear stability with the discrete Laplacian: for each grid mode k, the largest real part of
// the eigenvalues of J + diag(D_A, D_B) lap5(k) / h^2, J the Gray-Scott Jacobian at (A*, B*);
// the most unstable mode (mx >= my >= 0; its symmetric copies grow alike).
Mode most_unstable_mode(int n) {
  double a, b;
  homogeneous_state(a, b);
  const double j11 = -b * b - kF, j12 = -2 * a * b, j21 = b * b, j22 = 2 * a * b - (kF + kK);
  const double h = kWidth / n;
  Mode best;
  for (int mx = 0; mx <= n / 2; ++mx)
    for (int my = 0; my <= mx; ++my) {
      const double lap =
          (2 * std::cos(2 * kPi * mx / n) + 2 * std::cos(2 * kPi * my / n) - 4) / (h * h);
      const double m11 = j11 + kDa * lap, m22 = j22 + kDb * lap;
      const double half_trace = 0.5 * (m11 + m22), det = m11 * m22 - j12 * j21;
      const double disc = half_trace * half_trace - det;
      const double growth = disc >= 0 ? half_trace + std::sqrt(disc) : half_trace;
      if (growth > best.growth) best = {mx, my, growth};
    }
  return best;
}

// Pearson's domain on an n x n grid, around (A*, B*) with a uniform random perturbation of
// 1e-3 (relative); the diffusion solved to float rounding, so the measurement sees the time
// scheme alone.
SceneConfig growth_scene(RdScheme scheme, double dt, int n) {
  double a, b;
  homogeneous_state(a, b);
  SceneConfig s = periodic_gray_scott(scheme, dt, n, kWidth);
  RdConfig& rd = s.rd;
  rd.reaction.F = float(kF);
  rd.reaction.k = float(kK);
  rd.diffusion_a = kDa;
  rd.diffusion_b = kDb;
  rd.diffusion_solver = {SolverKind::kJacobi,
                         jacobi_sweeps(kDa * dt / ((kWidth / n) * (kWidth / n))), 0.0};
  rd.background_a = float(a);
  rd.background_b = float(b);
  rd.noise = 1e-3;
  rd.seed = 7;
  return s;
}

// |A^(k)|^2 summed over the mode's four independent copies (+-mx, +-my and the transpose; the
// conjugates add nothing new for a real field), A's mean removed.
double mode_power(const FieldF& f, const Mode& m) {
  const int n = f.nx();
  double mean = 0;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) mean += f(x, y);
  mean /= double(n) * n;
  const int copies[4][2] = {{m.mx, m.my}, {m.mx, -m.my}, {m.my, m.mx}, {m.my, -m.mx}};
  const int count = (m.my == 0 || m.mx == m.my) ? 2 : 4;  // the others repeat these
  double power = 0;
  for (int c = 0; c < count; ++c) {
    std::complex<double> sum = 0;
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        const long phase = (long(copies[c][0]) * x + long(copies[c][1]) * y) % n;
        sum += (double(f(x, y)) - mean) * std::polar(1.0, -2 * kPi * double(phase) / n);
      }
    power += std::norm(sum);
  }
  return power;
}

// The growth rate of the mode's amplitude between t0 and t1 (the linear phase: the decaying
// eigenvalue of the mode, -0.09, has died out by t0).
double measured_growth(RdScheme scheme, double dt, int n, const Mode& mode, double t0 = 150,
                       double t1 = 550) {
  const SceneConfig s = growth_scene(scheme, dt, n);
  RdStepper rd(s);
  SimState st = make_state(s);
  rd.init_state(st);
  const int k0 = int(std::lround(t0 / dt)), k1 = int(std::lround(t1 / dt));
  double p0 = 0;
  RdFrame frame(rd, st);
  for (int k = 0; k < k1; ++k) {
    if (k == k0) p0 = mode_power(st.A, mode);
    frame.step();
  }
  const double p1 = mode_power(st.A, mode);
  return 0.5 * std::log(p1 / p0) / ((k1 - k0) * dt);
}

struct GrowthCase {
  RdScheme scheme;
  const char* name;
  double dt;  // the largest dt the scheme claims within 5% (docs/numerics.md)
};

class GrowthRate : public testing::TestWithParam<GrowthCase> {};

TEST_P(GrowthRate, MostUnstableModeWithinFivePercentOfLinearTheory) {
  const GrowthCase& c = GetParam();
  const int n = 128;
  const Mode mode = most_unstable_mode(n);
  const double growth = measured_growth(c.scheme, c.dt, n, mode);
  std::printf("%s at dt %g: growth of mode (%d, %d) %.4g, theory %.4g (%+.1f%%)\n", c.name, c.dt,
              mode.mx, mode.my, growth, mode.growth, 100 * (growth / mode.growth - 1));
  EXPECT_NEAR(growth, mode.growth, 0.05 * mode.growth);
}

INSTANTIATE_TEST_SUITE_P(
    AtTheLargestClaimedStep, GrowthRate,
    testing::Values(GrowthCase{RdScheme::kCrankNicolsonAm2, "crank_nicolson_am2", 6.0},
                    GrowthCase{RdScheme::kSbdf2, "sbdf2", 8.0},
                    GrowthCase{RdScheme::kEtdrk4, "etdrk4", 16.0}),
    [](const testing::TestParamInfo<GrowthCase>& info) { return std::string(info.param.name); });

// The issue this answers: backward Euler with Lie splitting (the paper's scheme) at the presets'
// dt 1 grows the mode at a fraction of the theory's rate.
TEST(GrowthRate, ImplicitEulerAtDtOneIsFarBelowTheory) {
  const int n = 128;
  const Mode mode = most_unstable_mode(n);
  const double growth = measured_growth(RdScheme::kImplicit, 1.0, n, mode, 100, 300);
  std::printf("implicit at dt 1: %.4g, theory %.4g (%+.1f%%)\n", growth, mode.growth,
              100 * (growth / mode.growth - 1));
  EXPECT_LT(growth, 0.5 * mode.growth);
}

// The table of docs/numerics.md (run with --gtest_also_run_disabled_tests; minutes in Debug).
TEST(GrowthRate, DISABLED_PrintsTheTable) {
  const int n = 128;
  const Mode mode = most_unstable_mode(n);
  std::printf("theory: mode (%d, %d) of %d^2, growth %.5g\n", mode.mx, mode.my, n, mode.growth);
  const std::pair<RdScheme, const char*> schemes[] = {
      {RdScheme::kImplicit, "implicit"},
      {RdScheme::kExplicit5, "explicit5"},
      {RdScheme::kCrankNicolsonAm2, "crank-nicolson-am2"},
      {RdScheme::kSbdf2, "sbdf2"},
      {RdScheme::kEtdrk4, "etdrk4"}};
  for (const auto& [scheme, name] : schemes)
    for (double dt : {0.25, 0.5, 1.0, 2.0, 4.0, 6.0, 8.0, 12.0, 16.0}) {
      if (scheme == RdScheme::kExplicit5 && dt > 1.0) continue;  // unstable above dt 4.7 here
      const double g = measured_growth(scheme, dt, n, mode);
      std::printf("%-20s dt %5g: %.4g (%+.1f%%)\n", name, dt, g, 100 * (g / mode.growth - 1));
      std::fflush(stdout);
    }
}

// --- sbdf2's history --------------------------------------------------------------------------

TEST(Sbdf2, StartsWithSbdf1AndAgainAfterARestart) {
  const SceneConfig s = convergence_scene(RdScheme::kSbdf2, 1.0);
  RdStepper rd(s);
  SimState st = make_state(s);
  rd.init_state(st);
  EXPECT_FALSE(rd.has_history());
  // Two SBDF2 runs from the same state: one keeps its history, the other restarts before its
  // second step, which is then an SBDF1 step again (first order: a different result).
  SimState a = st, b = st;
  RdStepper ra(s), rb(s);
  RdFrame ra_a(ra, a), rb_b(rb, b);
  ra_a.step();
  rb_b.step();
  EXPECT_TRUE(ra.has_history());
  rb.restart();
  ra_a.step();
  rb_b.step();
  EXPECT_GT(max_difference(a, b), 1e-7);
  // An SBDF1 step is the first step of a fresh stepper from the same state.
  SimState c = a, d = a;
  RdStepper rc(s);
  RdFrame rc_c(rc, c), ra_d(ra, d);
  rc_c.step();
  ra.restart();
  ra_d.step();
  EXPECT_EQ(max_difference(c, d), 0.0);
}

TEST(Sbdf2, EngineRestartsTheHistoryWhenItsStateIsHandedOut) {
  SceneConfig s = convergence_scene(RdScheme::kSbdf2, 1.0);
  s.rd.steps_per_frame = 1;
  s.rd.initial = RdInitialPattern::kCentreSquare;
  s.rd.seed_size = 0.25;
  // Two engines stepped alike: reading through the const state() changes nothing; the
  // non-const state() (which a painter or a loader writes through) restarts the history.
  Engine e1(s, {EngineOptions::Backend::kSerial, 1}), e2(s, {EngineOptions::Backend::kSerial, 1});
  Engine e3(s, {EngineOptions::Backend::kSerial, 1});
  for (Engine* e : {&e1, &e2, &e3}) e->step();
  (void)std::as_const(e2).state();
  (void)e3.state();
  for (Engine* e : {&e1, &e2, &e3}) e->step();
  EXPECT_EQ(max_difference(std::as_const(e1).state(), std::as_const(e2).state()), 0.0);
  EXPECT_GT(max_difference(std::as_const(e1).state(), std::as_const(e3).state()), 1e-7);
}

// --- the same bits on any number of workers ---------------------------------------------------

std::string first_difference(const FieldF& f, const FieldF& g, const char* name) {
  for (int y = 0; y < f.ny(); ++y)
    for (int x = 0; x < f.nx(); ++x)
      if (std::memcmp(&f(x, y), &g(x, y), sizeof(float)) != 0)
        return std::string(name) + " at (" + std::to_string(x) + ", " + std::to_string(y) + ")";
  return "";
}

class SchemeParity : public testing::TestWithParam<RdScheme> {};

TEST_P(SchemeParity, ThreadsEqualSerialBitForBit) {
  SceneConfig s = growth_scene(GetParam(), 2.0, 64);
  s.size = {127, 93};  // no tiling divides it evenly; > RowExecutor::kMinParallelCells
  s.rd.initial = RdInitialPattern::kCentreSquare;
  s.rd.background_a = 1.0f;
  s.rd.background_b = 0.0f;
  s.rd.seed_size = 0.2;
  s.rd.noise = 0.01;
  s.rd.steps_per_frame = 3;
  s.rd.diffusion_solver = {SolverKind::kIccg, 40, 1e-6};  // a tolerance: residual reductions
  Engine serial(s, {EngineOptions::Backend::kSerial, 1});
  for (int k = 0; k < 10; ++k) serial.step();
  for (int workers : {2, 4}) {
    Engine threads(s, {EngineOptions::Backend::kThreads, workers});
    for (int k = 0; k < 10; ++k) threads.step();
    const SimState &a = std::as_const(serial).state(), &b = std::as_const(threads).state();
    EXPECT_EQ(first_difference(a.A, b.A, "A") + first_difference(a.B, b.B, "B"), "")
        << workers << " workers";
  }
}

INSTANTIATE_TEST_SUITE_P(EveryNewScheme, SchemeParity,
                         testing::Values(RdScheme::kCrankNicolsonAm2, RdScheme::kSbdf2,
                                         RdScheme::kEtdrk4));

}  // namespace
}  // namespace ardcell
