#include "kernels/anisotropy.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

namespace ardcell {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr std::array<std::string_view, 4> kKindNames = {"isotropic", "witkin-kass", "lobes",
                                                        "polar"};

double wrap_angle(double phi) {
  double w = std::fmod(phi, kTwoPi);
  if (w < 0) w += kTwoPi;
  if (w >= kTwoPi) w = 0;
  return w;
}

// A number in [0, 4) that grows with the angle of (x, y) in [0, 2 pi) (a "pseudo-angle": the
// direction's position along the diamond |x| + |y| = 1): orders directions without atan2.
inline double pseudo_angle(double x, double y) {
  const double t = x / (std::abs(x) + std::abs(y));
  return y >= 0 ? 1.0 - t : 3.0 + t;
}

// Eqn 16 over a row without atan2 and cos per cell. With the gradient's direction
// (c, s) = grad A / |grad A| (theta = 0 where it vanishes) and phi = theta + theta0:
//   cos(j phi) = Re((c + i s)^j e^{i j theta0}),
// and the lobe's slice n = floor(wrap(phi + pi/j) j / 2 pi) from the direction rotated by
// theta0 + pi/j against the slice boundaries 2 pi m / j, compared as pseudo-angles. The value
// is anisotropy_value's to a few double ulps (the tests bound it), then rounded to float; at a
// slice boundary both neighbouring lobes give a(phi) = 0, so the slice chosen there is moot.
class CosineLobesRow {
 public:
  explicit CosineLobesRow(const AnisotropyParams& p)
      : p_(p), j_(std::clamp(p.lobes, 1, kMaxLobes)) {
    for (int m = 1; m < j_; ++m)
      bound_[m - 1] = pseudo_angle(std::cos(kTwoPi * m / j_), std::sin(kTwoPi * m / j_));
  }
  float at(View<const float> a, int x, int y, double t0) {
    if (t0 != t0_) set_theta0(t0);
    const double gx = 0.5 * (double(a(x + 1, y)) - a(x - 1, y));
    const double gy = 0.5 * (double(a(x, y + 1)) - a(x, y - 1));
    double c = 1.0, s = 0.0;
    if (!(std::abs(gx) <= p_.gradient_epsilon && std::abs(gy) <= p_.gradient_epsilon)) {
      const double r = std::sqrt(gx * gx + gy * gy);
      c = gx / r;
      s = gy / r;
    }
    // (c + i s)^j by binary powering.
    double pr = 1.0, pi = 0.0, br = c, bi = s;
    for (int e = j_; e > 0; e >>= 1) {
      if (e & 1) {
        const double r = pr * br - pi * bi;
        pi = pr * bi + pi * br;
        pr = r;
      }
      const double r = br * br - bi * bi;
      bi = 2.0 * br * bi;
      br = r;
    }
    const double cos_j_phi = pr * rot_j_.real - pi * rot_j_.imag;
    // The slice: the direction rotated by theta0 + pi / j, against the boundaries.
    const double vx = c * rot_slice_.real - s * rot_slice_.imag;
    const double vy = c * rot_slice_.imag + s * rot_slice_.real;
    const double q = pseudo_angle(vx, vy);
    int n = 0;
    while (n < j_ - 1 && q >= bound_[n]) ++n;
    return float(p_.lobe_speed[n] / 2.0 * (1.0 + cos_j_phi));
  }

 private:
  struct Turn {
    double real = 1.0, imag = 0.0;
  };
  void set_theta0(double t0) {
    t0_ = t0;
    rot_j_ = {std::cos(j_ * t0), std::sin(j_ * t0)};
    const double slice = t0 + std::numbers::pi / j_;
    rot_slice_ = {std::cos(slice), std::sin(slice)};
  }
  const AnisotropyParams& p_;
  int j_;
  double bound_[kMaxLobes] = {};
  double t0_ = std::numeric_limits<double>::quiet_NaN();  // no theta0 seen yet
  Turn rot_j_, rot_slice_;
};

}  // namespace

std::string_view anisotropy_kind_name(AnisotropyKind k) { return kKindNames[int(k)]; }

bool parse_anisotropy_kind(std::string_view name, AnisotropyKind& out) {
  for (int i = 0; i < int(kKindNames.size()); ++i)
    if (kKindNames[i] == name) {
      out = AnisotropyKind(i);
      return true;
    }
  return false;
}

const char* anisotropy_params_problem(const AnisotropyParams& p) {
  switch (p.kind) {
    case AnisotropyKind::kIsotropic:
      return p.isotropic_value >= 0 ? nullptr : "anisotropy: isotropic value must be >= 0";
    case AnisotropyKind::kWitkinKass:
      return p.a1 >= 0 && p.a2 >= 0 ? nullptr : "anisotropy: witkin-kass a1, a2 must be >= 0";
    case AnisotropyKind::kCosineLobes:
      if (p.lobes < 1 || p.lobes > kMaxLobes) return "anisotropy: lobes must be 1 to 16";
      for (int n = 0; n < p.lobes; ++n)
        if (!(p.lobe_speed[n] >= 0)) return "anisotropy: lobe speeds must be >= 0";
      return nullptr;
    case AnisotropyKind::kPolarSamples:
      if (p.samples < 2 || p.samples > kMaxPolarSamples)
        return "anisotropy: polar function needs 2 to 64 samples";
      for (int i = 0; i < p.samples; ++i)
        if (!(p.sample[i] >= 0)) return "anisotropy: polar samples must be >= 0";
      return nullptr;
  }
  return "anisotropy: unknown kind";
}

double anisotropy_value(const AnisotropyParams& p, double phi) {
  switch (p.kind) {
    case AnisotropyKind::kIsotropic:
      return p.isotropic_value;
    case AnisotropyKind::kWitkinKass: {
      const double w = wrap_angle(phi), pi = std::numbers::pi;
      const double alpha = (double(p.a1) + p.a2) / 4.0;
      const bool a1_slice = w <= pi / 4 || w >= 7 * pi / 4 || (w >= 3 * pi / 4 && w <= 5 * pi / 4);
      const double an = a1_slice ? p.a1 : p.a2;
      return alpha + (an - alpha) / 2.0 * (1.0 + std::cos(4.0 * w));
    }
    case AnisotropyKind::kCosineLobes: {
      const int j = std::clamp(p.lobes, 1, kMaxLobes);
      // Lobe n (0-based) peaks at 2 pi n / j; its slice is (peak - pi/j, peak + pi/j].
      const double w = wrap_angle(phi + std::numbers::pi / j);
      int n = int(std::floor(w * j / kTwoPi));
      n = std::clamp(n, 0, j - 1);
      return p.lobe_speed[n] / 2.0 * (1.0 + std::cos(j * phi));
    }
    case AnisotropyKind::kPolarSamples: {
      const int count = std::clamp(p.samples, 1, kMaxPolarSamples);
      const double s = wrap_angle(phi) * count / kTwoPi;
      const int i0 = std::min(int(std::floor(s)), count - 1);
      const int i1 = (i0 + 1) % count;
      const double t = s - i0;
      return (1.0 - t) * p.sample[i0] + t * p.sample[i1];
    }
  }
  return 0.0;
}

double anisotropy_max(const AnisotropyParams& p) {
  switch (p.kind) {
    case AnisotropyKind::kIsotropic:
      return p.isotropic_value;
    case AnisotropyKind::kWitkinKass:
      return std::max({double(p.a1), double(p.a2), (double(p.a1) + p.a2) / 4.0});
    case AnisotropyKind::kCosineLobes: {
      double m = 0;
      for (int n = 0; n < std::clamp(p.lobes, 1, kMaxLobes); ++n)
        m = std::max(m, double(p.lobe_speed[n]));
      return m;
    }
    case AnisotropyKind::kPolarSamples: {
      double m = 0;
      for (int i = 0; i < std::clamp(p.samples, 0, kMaxPolarSamples); ++i)
        m = std::max(m, double(p.sample[i]));
      return m;
    }
  }
  return 0.0;
}

double gradient_angle(View<const float> a, int x, int y, float gradient_epsilon) {
  const double gx = 0.5 * (double(a(x + 1, y)) - a(x - 1, y));
  const double gy = 0.5 * (double(a(x, y + 1)) - a(x, y - 1));
  if (std::abs(gx) <= gradient_epsilon && std::abs(gy) <= gradient_epsilon) return 0.0;
  return std::atan2(gy, gx);
}

void conductivity_tile(View<const float> a, View<const float> theta0, View<float> k_out,
                       Box2 region, const AnisotropyParams& p) {
  ARDCELL_DCHECK(a.box().contains(region.grown(1)), "conductivity reads halo 1 of A");
  const bool per_cell = theta0.data() != nullptr && !theta0.box().empty();
  if (p.kind == AnisotropyKind::kIsotropic) {
    for (int y = region.min.y; y < region.max.y; ++y) {
      float* k = k_out.row(y);
      for (int x = region.min.x; x < region.max.x; ++x) k[x] = p.isotropic_value;
    }
    return;
  }
  if (p.kind == AnisotropyKind::kCosineLobes) {
    CosineLobesRow lobes(p);
    for (int y = region.min.y; y < region.max.y; ++y) {
      float* k = k_out.row(y);
      for (int x = region.min.x; x < region.max.x; ++x)
        k[x] = lobes.at(a, x, y, per_cell ? double(theta0(x, y)) : double(p.theta0));
    }
    return;
  }
  for (int y = region.min.y; y < region.max.y; ++y) {
    float* k = k_out.row(y);
    for (int x = region.min.x; x < region.max.x; ++x) {
      const double t0 = per_cell ? double(theta0(x, y)) : double(p.theta0);
      k[x] = float(anisotropy_value(p, gradient_angle(a, x, y, p.gradient_epsilon) + t0));
    }
  }
}

}  // namespace ardcell
