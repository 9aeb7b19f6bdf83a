#include "kernels/anisotropy.h"

#include <algorithm>
#include <array>
#include <cmath>
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
  for (int y = region.min.y; y < region.max.y; ++y) {
    float* k = k_out.row(y);
    for (int x = region.min.x; x < region.max.x; ++x) {
      const double t0 = per_cell ? double(theta0(x, y)) : double(p.theta0);
      k[x] = float(anisotropy_value(p, gradient_angle(a, x, y, p.gradient_epsilon) + t0));
    }
  }
}

}  // namespace ardcell
