#include "kernels/savitzky_golay.h"

#include <algorithm>
#include <cmath>

#include "runtime/check.h"

namespace ardcell {

double Stencil5x5::sum() const {
  double s = 0;
  for (double v : w) s += v;
  return s;
}

Stencil5x5& Stencil5x5::operator+=(const Stencil5x5& o) {
  for (int k = 0; k < 25; ++k) w[k] += o.w[k];
  return *this;
}

double factorial(int n) {
  double f = 1;
  for (int k = 2; k <= n; ++k) f *= k;
  return f;
}

namespace {

constexpr int kPoints = 25;  // the 5x5 neighbourhood of Eqn 30

// Minimum-norm pseudo-inverse of the kPoints x n matrix x (column-major: x[c][r]) by one-sided
// (Hestenes) Jacobi SVD: rotate column pairs until all columns are orthogonal, X V = U S. Unlike
// the normal equations (X^T X)^{-1} X^T of Eqn 34, it does not square X's condition number
// (the monomials up to x^5 = 3125 on [-2, 2]), and it gives the minimum-norm X^+ = V S^+ U^T
// when X is rank-deficient (degree 5). Returns pinv[c][r] and the numerical rank.
int pseudo_inverse(const std::vector<std::array<double, kPoints>>& x,
                   std::vector<std::array<double, kPoints>>& pinv) {
  const int n = int(x.size());
  std::vector<std::array<double, kPoints>> a = x;  // becomes U S
  std::vector<std::vector<double>> v(n, std::vector<double>(n, 0.0));
  for (int k = 0; k < n; ++k) v[k][k] = 1.0;

  for (int sweep = 0; sweep < 60; ++sweep) {
    bool rotated = false;
    for (int p = 0; p < n - 1; ++p)
      for (int q = p + 1; q < n; ++q) {
        double alpha = 0, beta = 0, gamma = 0;
        for (int r = 0; r < kPoints; ++r) {
          alpha += a[p][r] * a[p][r];
          beta += a[q][r] * a[q][r];
          gamma += a[p][r] * a[q][r];
        }
        if (gamma == 0 || std::abs(gamma) <= 1e-15 * std::sqrt(alpha * beta)) continue;
        rotated = true;
        const double zeta = (beta - alpha) / (2 * gamma);
        const double t = (zeta >= 0 ? 1.0 : -1.0) / (std::abs(zeta) + std::sqrt(1 + zeta * zeta));
        const double c = 1 / std::sqrt(1 + t * t), s = c * t;
        for (int r = 0; r < kPoints; ++r) {
          const double ap = a[p][r], aq = a[q][r];
          a[p][r] = c * ap - s * aq;
          a[q][r] = s * ap + c * aq;
        }
        for (int r = 0; r < n; ++r) {
          const double vp = v[r][p], vq = v[r][q];
          v[r][p] = c * vp - s * vq;
          v[r][q] = s * vp + c * vq;
        }
      }
    if (!rotated) break;
  }

  std::vector<double> sigma2(n);
  double max_sigma2 = 0;
  for (int k = 0; k < n; ++k) {
    sigma2[k] = 0;
    for (int r = 0; r < kPoints; ++r) sigma2[k] += a[k][r] * a[k][r];
    max_sigma2 = std::max(max_sigma2, sigma2[k]);
  }
  // Singular values below 1e-10 sigma_max are the null space (x^5 - 5 x^3 + 4 x = 0 on the
  // grid); the true ones are well above it (the smallest at degree 5 is ~0.1 of ~10^3).
  const double cutoff2 = 1e-20 * max_sigma2;
  int rank = 0;
  pinv.assign(n, {});
  for (int k = 0; k < n; ++k) {
    if (sigma2[k] <= cutoff2) continue;
    ++rank;
    // X^+ = V S^-1 U^T, and U_k = a_k / s_k, so the k-th term is V_k a_k^T / s_k^2.
    for (int c = 0; c < n; ++c)
      for (int r = 0; r < kPoints; ++r) pinv[c][r] += v[c][k] * a[k][r] / sigma2[k];
  }
  return rank;
}

}  // namespace

SavitzkyGolay5x5::SavitzkyGolay5x5(int degree) : degree_(degree) {
  ARDCELL_CHECK(degree >= 1 && degree <= 5, "Savitzky-Golay 5x5: degree 1..5");
  for (int total = 0; total <= degree; ++total)
    for (int j = 0; j <= total; ++j) terms_.push_back({total - j, j});

  // Eqn 33: one column per term x^i y^j, one row per offset (x, y) of Eqn 30, in the
  // Stencil5x5 order (row r = (y + 2) * 5 + (x + 2)).
  std::vector<std::array<double, kPoints>> x(terms_.size());
  for (std::size_t c = 0; c < terms_.size(); ++c)
    for (int y = -2; y <= 2; ++y)
      for (int xx = -2; xx <= 2; ++xx)
        x[c][(y + 2) * 5 + (xx + 2)] = std::pow(xx, terms_[c].i) * std::pow(y, terms_[c].j);

  std::vector<std::array<double, kPoints>> pinv;
  rank_ = pseudo_inverse(x, pinv);
  pinv_rows_.resize(terms_.size());
  for (std::size_t c = 0; c < terms_.size(); ++c) pinv_rows_[c].w = pinv[c];
}

int SavitzkyGolay5x5::term_index(int i, int j) const {
  for (std::size_t c = 0; c < terms_.size(); ++c)
    if (terms_[c].i == i && terms_[c].j == j) return int(c);
  ARDCELL_CHECK(false, "Savitzky-Golay 5x5: x^i y^j is above the fit degree");
  return -1;
}

Stencil5x5 SavitzkyGolay5x5::coefficient_row(int i, int j) const {
  return pinv_rows_[std::size_t(term_index(i, j))];
}

Stencil5x5 SavitzkyGolay5x5::derivative(int i, int j) const {
  return (factorial(i) * factorial(j)) * coefficient_row(i, j);
}

Stencil5x5 central_second_derivative(int i, int j) {
  Stencil5x5 k;
  if (i == 2 && j == 0) {
    k.at(-1, 0) = 1;
    k.at(0, 0) = -2;
    k.at(1, 0) = 1;
  } else if (i == 0 && j == 2) {
    k.at(0, -1) = 1;
    k.at(0, 0) = -2;
    k.at(0, 1) = 1;
  } else {
    ARDCELL_CHECK(i == 1 && j == 1, "central_second_derivative: (2,0), (1,1) or (0,2)");
    k.at(1, 1) = 0.25;
    k.at(-1, -1) = 0.25;
    k.at(-1, 1) = -0.25;
    k.at(1, -1) = -0.25;
  }
  return k;
}

}  // namespace ardcell
