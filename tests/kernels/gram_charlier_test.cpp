#include "kernels/gram_charlier.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

namespace ardcell {
namespace {

constexpr double kTau = 0.1;  // Fig. 1: tau = 0.1, |r| = 1
constexpr double kPi = std::numbers::pi;

TEST(GramCharlier, HermiteTensorsAreGradsPolynomials) {
  const double x = 0.7, y = -1.3;
  EXPECT_DOUBLE_EQ(hermite_tensor(0, 0, x, y), 1.0);
  EXPECT_DOUBLE_EQ(hermite_tensor(1, 0, x, y), x);
  EXPECT_NEAR(hermite_tensor(2, 0, x, y), x * x - 1, 1e-15);
  EXPECT_NEAR(hermite_tensor(1, 1, x, y), x * y, 1e-15);
  EXPECT_NEAR(hermite_tensor(3, 0, x, y), x * x * x - 3 * x, 1e-14);
  EXPECT_NEAR(hermite_tensor(2, 1, x, y), x * x * y - y, 1e-14);
  EXPECT_NEAR(hermite_tensor(3, 1, x, y), (x * x * x - 3 * x) * y, 1e-14);
  // The constant term of H4: + (d_ij d_kl + d_ik d_jl + d_il d_jk), not the printed -3 d_ijkl.
  EXPECT_DOUBLE_EQ(hermite_tensor(4, 0, 0, 0), 3.0);  // He4 = x^4 - 6 x^2 + 3
  EXPECT_DOUBLE_EQ(hermite_tensor(2, 2, 0, 0), 1.0);  // (x^2 - 1)(y^2 - 1)
  EXPECT_NEAR(hermite_tensor(4, 0, x, y), std::pow(x, 4) - 6 * x * x + 3, 1e-13);
  EXPECT_NEAR(hermite_tensor(2, 2, x, y), (x * x - 1) * (y * y - 1), 1e-13);
}

// Integral of f(x, y) times the unit Gaussian over the plane (midpoint rule on [-9, 9]^2).
template <class F>
double unit_gaussian_expectation(F f) {
  const double h = 0.02;
  double s = 0;
  for (double y = -9 + h / 2; y < 9; y += h)
    for (double x = -9 + h / 2; x < 9; x += h)
      s += f(x, y) * std::exp(-0.5 * (x * x + y * y)) / (2 * kPi);
  return s * h * h;
}

TEST(GramCharlier, HermiteTensorsAreOrthogonalToOneOnlyWithTheCorrectedConstant) {
  for (int rank = 1; rank <= 4; ++rank)
    for (int ny = 0; ny <= rank; ++ny)
      EXPECT_NEAR(unit_gaussian_expectation(
                      [&](double x, double y) { return hermite_tensor(rank - ny, ny, x, y); }),
                  0.0, 1e-9)
          << "H_" << rank - ny << "," << ny;
  // The printed H_xxxx (constant -3) has expectation 3 - 6 - 3 = -6, not 0.
  EXPECT_NEAR(
      unit_gaussian_expectation([](double x, double) { return std::pow(x, 4) - 6 * x * x - 3; }),
      -6.0, 1e-9);
}

TEST(GramCharlier, PropagatorsOfTable2IntegrateToOneWhereD2IsIsotropic) {
  // Eqn 23 takes H(r) unstandardised (the appendix's H uses delta, not (2 tau D2)^-1). Table 2's
  // rank-3 and rank-4 tensors are traceless, so where D2 = I ((a), (c), (d), (e)) their Hermite
  // terms still integrate to zero against N(0, 2 tau I): p integrates to one. (With the printed
  // H4 constant, (d) would integrate to 1 - 6 tau = 0.4.) (b) has no higher rank. (f) pairs
  // (e)'s rank 4 with D2 = diag(1, 2): with S = 2 tau D2 = diag(0.2, 0.4), E[H_xxxx] = 3 0.2^2 -
  // 6 0.2 + 3 = 1.92, E[H_yyyy] = 1.08, E[H_xxyy] = 0.08 - 0.6 + 1 = 0.48, so E[D4 . H4] =
  // -1.92 + 6 0.48 - 1.08 = -0.12 and p integrates to 1 - 0.012: the price of the unstandardised
  // form (Fig. 1 only draws shapes, which it keeps).
  const double expected[6] = {1, 1, 1, 1, 1, 1 - kTau * 0.12};
  for (int i = 0; i < 6; ++i) {
    const double h = 0.01;
    double integral = 0;
    for (double y = -4 + h / 2; y < 4; y += h)
      for (double x = -4 + h / 2; x < 4; x += h)
        integral += gram_charlier_propagator(kTable2[i].tensors, kTau, x, y);
    EXPECT_NEAR(integral * h * h, expected[i], 1e-6) << "sequence " << kTable2[i].name;
  }
}

TEST(GramCharlier, ClosedFormsOnTheUnitCircle) {
  // D2 = I: N(0, 2 tau I) is 1 / (4 pi tau) e^{-1 / (4 tau)} at |r| = 1. On the circle,
  // (d): D4 . H4 = c^4 - 6 c^2 + 3 - 6 (c^2 s^2 - 1 + 1) + s^4 - 6 s^2 + 3 = 1 - 8 c^2 s^2
  //      = cos 4 theta, so p = N (1 + tau cos 4 theta); (e) is its negative;
  // (c): D3 . H3 = x^3 - 3x + 3 (x^2 y - y)(-1) + 3 (x y^2 - x)(-1) + y^3 - 3y
  //      = (x^3 - 3 x y^2) - (3 x^2 y - y^3) = cos 3 theta - sin 3 theta
  //      = sqrt(2) cos(3 theta + pi/4), so p = N (1 - tau sqrt(2) cos(3 theta + pi/4)).
  const double gauss = std::exp(-1 / (4 * kTau)) / (4 * kPi * kTau);
  for (double theta = 0; theta < 2 * kPi; theta += 0.1) {
    const double x = std::cos(theta), y = std::sin(theta);
    EXPECT_NEAR(gram_charlier_propagator(kTable2D, kTau, x, y),
                gauss * (1 + kTau * std::cos(4 * theta)), 1e-14);
    EXPECT_NEAR(gram_charlier_propagator(kTable2E, kTau, x, y),
                gauss * (1 - kTau * std::cos(4 * theta)), 1e-14);
    EXPECT_NEAR(gram_charlier_propagator(kTable2C, kTau, x, y),
                gauss * (1 - kTau * std::sqrt(2.0) * std::cos(3 * theta + kPi / 4)), 1e-14);
    EXPECT_NEAR(gram_charlier_propagator(kTable2A, kTau, x, y), gauss, 1e-14);
  }
}

// Angles (degrees) of the strict local maxima of p_tau at |r| = 1, sampled every 0.05 degree.
std::vector<double> lobe_angles(const TensorSequence& d) {
  std::vector<double> p(7200);
  propagator_on_circle(d, kTau, 1.0, p);
  std::vector<double> lobes;
  const std::size_t n = p.size();
  for (std::size_t k = 0; k < n; ++k)
    if (p[k] > p[(k + n - 1) % n] && p[k] >= p[(k + 1) % n]) lobes.push_back(360.0 * k / n);
  return lobes;
}

void expect_lobes(const char* name, const std::vector<double>& expected_degrees) {
  const std::vector<double> got = lobe_angles(kTable2[name[0] - 'a'].tensors);
  ASSERT_EQ(got.size(), expected_degrees.size()) << "sequence " << name;
  for (std::size_t i = 0; i < got.size(); ++i)
    EXPECT_NEAR(got[i], expected_degrees[i], 1.0) << "sequence " << name << " lobe " << i;
}

TEST(GramCharlier, LobesOfFig1) {
  // (b): N(0, 2 tau diag(1, 2)) is widest along y: maxima at 90 and 270 degrees.
  expect_lobes("b", {90, 270});
  // (c): 1 - tau sqrt(2) cos(3 theta + 45) peaks at 3 theta + 45 = 180 (mod 360):
  // theta = 45, 165, 285.
  expect_lobes("c", {45, 165, 285});
  // (d): 1 + tau cos 4 theta, on the axes; (e): 1 - tau cos 4 theta, on the diagonals.
  expect_lobes("d", {0, 90, 180, 270});
  expect_lobes("e", {45, 135, 225, 315});
  // (a) is isotropic: no lobe at all (flat to rounding).
  std::vector<double> a(360);
  propagator_on_circle(kTable2A, kTau, 1.0, a);
  for (double v : a) EXPECT_NEAR(v, a[0], 1e-15);
}

}  // namespace
}  // namespace ardcell
