#include "kernels/gram_charlier.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "runtime/check.h"

namespace ardcell {
namespace {

// Grad's recurrence on an index list (0 = x, 1 = y) of length n: H_{a S} = x_a H_S -
// sum_{b in S} delta_ab H_{S \ b}. The expansion is a sum over partial pairings of the
// indices, each pair contributing -delta: for n = 4 the constant term is
// + (d_ij d_kl + d_ik d_jl + d_il d_jk).
double hermite_recurrence(const int* idx, int n, const double r[2]) {
  if (n == 0) return 1.0;
  const int a = idx[0];
  const int* rest = idx + 1;
  double h = r[a] * hermite_recurrence(rest, n - 1, r);
  for (int b = 0; b < n - 1; ++b) {
    if (rest[b] != a) continue;
    int without[4];
    int m = 0;
    for (int c = 0; c < n - 1; ++c)
      if (c != b) without[m++] = rest[c];
    h -= hermite_recurrence(without, m, r);
  }
  return h;
}

}  // namespace

double hermite_tensor(int nx, int ny, double x, double y) {
  ARDCELL_CHECK(nx >= 0 && ny >= 0 && nx + ny <= 4, "hermite_tensor: rank 0..4");
  int idx[4];
  int n = 0;
  for (int k = 0; k < nx; ++k) idx[n++] = 0;
  for (int k = 0; k < ny; ++k) idx[n++] = 1;
  const double r[2] = {x, y};
  return hermite_recurrence(idx, n, r);
}

double contract_with_hermite(const TensorSequence& d, int rank, double x, double y) {
  double s = 0;
  for (int ny = 0; ny <= rank; ++ny) {
    const int nx = rank - ny;
    const double c = d.component(nx, ny);
    if (c != 0) s += multiplicity(nx, ny) * c * hermite_tensor(nx, ny, x, y);
  }
  return s;
}

double gram_charlier_propagator(const TensorSequence& d, double tau, double x, double y) {
  // N(0, S) with S = 2 tau D2.
  const double sxx = 2 * tau * d.xx, sxy = 2 * tau * d.xy, syy = 2 * tau * d.yy;
  const double det = sxx * syy - sxy * sxy;
  ARDCELL_CHECK(det > 0, "gram_charlier_propagator: D2 must be positive definite");
  const double quad = (syy * x * x - 2 * sxy * x * y + sxx * y * y) / det;  // r^T S^-1 r
  const double gauss = std::exp(-0.5 * quad) / (2 * std::numbers::pi * std::sqrt(det));
  // Eqn 24: Q3 / 3! = -tau D3, Q4 / 4! = +tau D4.
  const double series =
      1 - tau * contract_with_hermite(d, 3, x, y) + tau * contract_with_hermite(d, 4, x, y);
  return gauss * series;
}

void propagator_on_circle(const TensorSequence& d, double tau, double radius,
                          std::span<double> out) {
  const double n = double(out.size());
  for (std::size_t k = 0; k < out.size(); ++k) {
    const double theta = 2 * std::numbers::pi * double(k) / n;
    out[k] = gram_charlier_propagator(d, tau, radius * std::cos(theta), radius * std::sin(theta));
  }
}

std::vector<double> polar_maxima_degrees(std::span<const double> samples) {
  std::vector<double> out;
  const std::size_t n = samples.size();
  if (n < 3) return out;
  double lo = samples[0], hi = samples[0];
  for (double v : samples) {
    if (!std::isfinite(v)) return out;
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  // Rounding alone makes an isotropic propagator ripple at ~1e-16 relative: not a lobe.
  if (hi - lo <= 1e-9 * std::max(std::abs(hi), std::abs(lo))) return out;
  for (std::size_t k = 0; k < n; ++k) {
    const double prev = samples[(k + n - 1) % n], cur = samples[k], next = samples[(k + 1) % n];
    if (!(cur > 0 && cur > prev && cur >= next)) continue;
    const double curvature = prev - 2 * cur + next;
    const double offset =
        curvature < 0 ? std::clamp(0.5 * (prev - next) / curvature, -0.5, 0.5) : 0.0;
    double deg = (double(k) + offset) * 360.0 / double(n);
    if (deg < 0) deg += 360.0;
    if (deg >= 360.0 - 1e-9) deg = std::max(0.0, deg - 360.0);  // rounding just below 360
    out.push_back(deg);
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace ardcell
