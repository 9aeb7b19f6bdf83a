#include "kernels/periodic_etdrk4.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "runtime/thread/thread_backend.h"

namespace ardcell {
namespace {

constexpr double kPi = std::numbers::pi;

// Diffusion alone is exact in each Fourier mode: a cosine mode of the 5-point Laplacian decays
// by exp(dt c symbol) per step, at any dt, on even and odd grids.
TEST(PeriodicEtdrk4, DiffusionAloneIsTheExactExponentialOfEachMode) {
  for (Int2 n : {Int2{32, 32}, Int2{37, 23}}) {
    const int mx = 3, my = 2;
    const double ca = 0.7, cb = 0.2, dt = 5.0;
    PeriodicEtdrk4 etd(n);
    etd.set_step(dt, ca, cb);
    FieldF a(n, 1), b(n, 1);
    auto mode = [&](int x, int y) {
      return std::cos(2 * kPi * (double(mx) * x / n.x + double(my) * y / n.y));
    };
    for (int y = 0; y < n.y; ++y)
      for (int x = 0; x < n.x; ++x) {
        a(x, y) = float(1.0 + 0.5 * mode(x, y));
        b(x, y) = float(0.5 * mode(x, y));
      }
    const int steps = 3;
    for (int k = 0; k < steps; ++k) etd.step(a, b, nullptr);
    const double s = etd.symbol(mx, my);
    EXPECT_NEAR(s, 2 * std::cos(2 * kPi * mx / n.x) + 2 * std::cos(2 * kPi * my / n.y) - 4, 1e-15);
    const double ga = std::exp(steps * dt * ca * s), gb = std::exp(steps * dt * cb * s);
    double err = 0;
    for (int y = 0; y < n.y; ++y)
      for (int x = 0; x < n.x; ++x)
        err = std::max({err, std::abs(a(x, y) - (1.0 + 0.5 * ga * mode(x, y))),
                        std::abs(b(x, y) - 0.5 * gb * mode(x, y))});
    EXPECT_LT(err, 2e-6) << n;
  }
}

// A uniform field is mode 0 alone (z = 0): the contour means give Q = dt / 2 and
// f1 = f2 = f3 = dt / 6 there, and ETDRK4 is the classical fourth-order Runge-Kutta step.
TEST(PeriodicEtdrk4, UniformFieldTakesTheClassicalRungeKuttaStep) {
  ReactionParams p;
  p.model = ReactionModel::kGrayScott;
  p.F = 0.04f;
  p.k = 0.06f;
  const double dt = 4.0;
  PeriodicEtdrk4 etd({16, 12});
  etd.set_step(dt, 0.3, 0.1);
  FieldF a({16, 12}, 1), b({16, 12}, 1);
  a.fill(0.5f);
  b.fill(0.25f);
  etd.step(a, b, &p);
  auto f = [&](double A, double B, double& ra, double& rb) { reaction_rates(p, A, B, ra, rb); };
  double ka[4], kb[4];
  f(0.5, 0.25, ka[0], kb[0]);
  f(0.5 + dt / 2 * ka[0], 0.25 + dt / 2 * kb[0], ka[1], kb[1]);
  f(0.5 + dt / 2 * ka[1], 0.25 + dt / 2 * kb[1], ka[2], kb[2]);
  f(0.5 + dt * ka[2], 0.25 + dt * kb[2], ka[3], kb[3]);
  const double ea = 0.5 + dt / 6 * (ka[0] + 2 * ka[1] + 2 * ka[2] + ka[3]);
  const double eb = 0.25 + dt / 6 * (kb[0] + 2 * kb[1] + 2 * kb[2] + kb[3]);
  for (int y = 0; y < 12; ++y)
    for (int x = 0; x < 16; ++x) {
      EXPECT_NEAR(a(x, y), ea, 1e-6);
      EXPECT_NEAR(b(x, y), eb, 1e-6);
    }
}

// Rows and column blocks are the tasks, each on one plan: any number of workers gives the same
// bits.
TEST(PeriodicEtdrk4, SameBitsOnAnyNumberOfWorkers) {
  ReactionParams p;
  const Int2 n{127, 93};
  FieldF a0(n, 1), b0(n, 1);
  for (int y = 0; y < n.y; ++y)
    for (int x = 0; x < n.x; ++x) {
      a0(x, y) =
          float(1.0 - 0.5 * std::exp(-((x - 60.0) * (x - 60.0) + (y - 40.0) * (y - 40.0)) / 50.0));
      b0(x, y) = float(0.25 * std::sin(0.3 * x) * std::sin(0.2 * y) + 0.25);
    }
  FieldF a_ref = a0, b_ref = b0;
  {
    PeriodicEtdrk4 etd(n);
    etd.set_step(2.0, 0.4, 0.2);
    for (int k = 0; k < 3; ++k) etd.step(a_ref, b_ref, &p);
  }
  for (int workers : {2, 3}) {
    ThreadBackendOptions o;
    o.workers = workers;
    ThreadBackend backend(o);
    RowExecutor ex(backend);
    PeriodicEtdrk4 etd(n, ex);
    etd.set_step(2.0, 0.4, 0.2);
    FieldF a = a0, b = b0;
    for (int k = 0; k < 3; ++k) etd.step(a, b, &p);
    int differ = 0;
    for (int y = 0; y < n.y; ++y)
      for (int x = 0; x < n.x; ++x) differ += a(x, y) != a_ref(x, y) || b(x, y) != b_ref(x, y);
    EXPECT_EQ(differ, 0) << workers << " workers";
  }
}

}  // namespace
}  // namespace ardcell
