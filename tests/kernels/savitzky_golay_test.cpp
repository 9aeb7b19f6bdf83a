#include "kernels/savitzky_golay.h"

#include <gtest/gtest.h>

#include <cmath>

namespace ardcell {
namespace {

// The 5x5 kernel applied at the origin to the monomial x^p y^q.
double apply_to_monomial(const Stencil5x5& k, int p, int q) {
  double s = 0;
  for (int y = -2; y <= 2; ++y)
    for (int x = -2; x <= 2; ++x) s += k.at(x, y) * std::pow(x, p) * std::pow(y, q);
  return s;
}

// d^{i+j}/dx^i dy^j of x^p y^q at the origin: p! q! when (p, q) == (i, j), else 0.
double exact_derivative_at_origin(int i, int j, int p, int q) {
  return (p == i && q == j) ? factorial(i) * factorial(j) : 0.0;
}

// A degree-5 derivative kernel is determined only off the null vector x^5 - 5x^3 + 4x (and its
// y twin): d/dx, d^3/dx^3 on x, x^3, x^5 (and y's) are the ones the minimum norm leaves inexact.
bool in_degree5_null_family(int i, int j) {
  return (j == 0 && (i == 1 || i == 3 || i == 5)) || (i == 0 && (j == 1 || j == 3 || j == 5));
}

TEST(SavitzkyGolay, Degree4FiltersAreExactOnEveryMonomialUpToDegree4) {
  const SavitzkyGolay5x5 sg(4);
  EXPECT_EQ(sg.term_count(), 15);
  EXPECT_EQ(sg.rank(), 15);
  EXPECT_TRUE(sg.full_rank());
  for (int i = 0; i <= 4; ++i)
    for (int j = 0; i + j <= 4; ++j) {
      const Stencil5x5 k = sg.derivative(i, j);
      for (int p = 0; p <= 4; ++p)
        for (int q = 0; p + q <= 4; ++q)
          EXPECT_NEAR(apply_to_monomial(k, p, q), exact_derivative_at_origin(i, j, p, q), 1e-12)
              << "kernel d^" << i << "x d^" << j << "y on x^" << p << " y^" << q;
    }
}

TEST(SavitzkyGolay, DerivativeKernelsSumToZeroAndTheSmoothingOneToOne) {
  for (int degree : {4, 5}) {
    const SavitzkyGolay5x5 sg(degree);
    for (int i = 0; i <= degree; ++i)
      for (int j = 0; i + j <= degree; ++j)
        EXPECT_NEAR(sg.derivative(i, j).sum(), (i + j == 0) ? 1.0 : 0.0, 1e-12)
            << "degree " << degree << " d^" << i << "x d^" << j << "y";
  }
  for (auto [i, j] : {std::pair{2, 0}, {1, 1}, {0, 2}})
    EXPECT_EQ(central_second_derivative(i, j).sum(), 0.0);
}

TEST(SavitzkyGolay, MixedDerivativeSignIsFixedByXTimesY) {
  // d^2/dxdy of x*y is +1: the kernel weighs u(x + dx, y + dy), so (1, 1) and (-1, -1) are
  // positive whatever way a printed matrix is laid out.
  for (int degree : {4, 5}) {
    const Stencil5x5 k = SavitzkyGolay5x5(degree).derivative(1, 1);
    EXPECT_NEAR(apply_to_monomial(k, 1, 1), 1.0, 1e-12);
    EXPECT_GT(k.at(1, 1), 0.0);
    EXPECT_LT(k.at(1, -1), 0.0);
  }
  const Stencil5x5 c = central_second_derivative(1, 1);
  EXPECT_DOUBLE_EQ(apply_to_monomial(c, 1, 1), 1.0);
  EXPECT_DOUBLE_EQ(apply_to_monomial(central_second_derivative(2, 0), 2, 0), 2.0);
  EXPECT_DOUBLE_EQ(apply_to_monomial(central_second_derivative(0, 2), 0, 2), 2.0);
  EXPECT_DOUBLE_EQ(apply_to_monomial(central_second_derivative(2, 0), 0, 2), 0.0);
}

TEST(SavitzkyGolay, Degree5IsRankDeficientAndItsMinimumNormFitIsExactOffTheNullVector) {
  const SavitzkyGolay5x5 sg(5);
  EXPECT_EQ(sg.term_count(), 21);
  EXPECT_EQ(sg.rank(), 19);  // x^5 = 5 x^3 - 4 x and y^5 = 5 y^3 - 4 y on the grid
  EXPECT_FALSE(sg.full_rank());
  for (int i = 0; i <= 5; ++i)
    for (int j = 0; i + j <= 5; ++j) {
      const Stencil5x5 k = sg.derivative(i, j);
      for (int p = 0; p <= 5; ++p)
        for (int q = 0; p + q <= 5; ++q) {
          if (in_degree5_null_family(i, j) && in_degree5_null_family(p, q) && (i == 0) == (p == 0))
            continue;  // checked below
          EXPECT_NEAR(apply_to_monomial(k, p, q), exact_derivative_at_origin(i, j, p, q), 1e-12)
              << "kernel d^" << i << "x d^" << j << "y on x^" << p << " y^" << q;
        }
    }
  // The minimum-norm coefficients of x^3 are its projection off the null vector
  // n = (a_10, a_30, a_50) = (4, -5, 1), |n|^2 = 42: a_30 = 1 - 25/42 = 17/42.
  EXPECT_NEAR(apply_to_monomial(sg.derivative(3, 0), 3, 0), 6.0 * 17.0 / 42.0, 1e-12);
  EXPECT_NEAR(apply_to_monomial(sg.derivative(0, 3), 0, 3), 6.0 * 17.0 / 42.0, 1e-12);
  // ... and the d^3/dx^3 kernel even answers a linear ramp: 6 * (20/42) on u = x.
  EXPECT_NEAR(apply_to_monomial(sg.derivative(3, 0), 1, 0), 6.0 * 20.0 / 42.0, 1e-12);
  // The fit itself still reproduces every monomial on the 25 points (X X^+ u = u).
  for (int p = 0; p <= 5; ++p)
    for (int q = 0; p + q <= 5; ++q)
      for (int y = -2; y <= 2; ++y)
        for (int x = -2; x <= 2; ++x) {
          double fitted = 0;
          for (int i = 0; i <= 5; ++i)
            for (int j = 0; i + j <= 5; ++j)
              fitted += apply_to_monomial(sg.coefficient_row(i, j), p, q) * std::pow(x, i) *
                        std::pow(y, j);
          EXPECT_NEAR(fitted, std::pow(x, p) * std::pow(y, q), 1e-9)
              << "x^" << p << " y^" << q << " at (" << x << ", " << y << ")";
        }
}

TEST(SavitzkyGolay, LowerDegreesAreTheClassicSmoothingFilters) {
  // Degree 1 (plane fit): the smoothing row is the 5x5 mean and d/dx is x / sum(x^2) = x / 50.
  const SavitzkyGolay5x5 sg(1);
  EXPECT_NEAR(sg.coefficient_row(0, 0).at(2, -1), 1.0 / 25.0, 1e-15);
  EXPECT_NEAR(sg.derivative(1, 0).at(2, 1), 2.0 / 50.0, 1e-15);
  EXPECT_NEAR(sg.derivative(1, 0).at(0, 2), 0.0, 1e-15);
}

}  // namespace
}  // namespace ardcell
