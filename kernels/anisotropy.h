#pragma once
// Anisotropy functions a(phi), phi = theta + theta0 (seed 000, section 4), and the per-cell
// conductivity they give.
//
// Eqn 14 (the diffusion constant replaced by a polar function of theta, the angle of grad A):
//   dA/dt = div(a(theta) grad A) + R
//
// Eqn 15 (Witkin-Kass), alpha = (a1 + a2) / 4:
//   a = alpha + (a1 - alpha)/2 (1 + cos 4 phi)  for phi in [-pi/4, pi/4] or [3pi/4, 5pi/4]
//   a = alpha + (a2 - alpha)/2 (1 + cos 4 phi)  otherwise
// Eqn 16 (j cosine lobes, one speed a_n per lobe):
//   a = a_n / 2 (1 + cos j phi)  on lobe n's slice of width 2pi/j around its peak
//   phi = 2 pi (n - 1) / j, i.e. ((2n - 3) pi / j, (2n - 1) pi / j]. (The printed bounds,
//   ((n - 2) pi / j, n pi / j], overlap and centre every other slice on a trough; these are the
//   2pi/j slices the text describes, and j = 1 gives the single lobe of Fig. 3.)
// Polar samples: a user-drawn function, N samples at phi_i = 2 pi i / N, interpolated
// linearly and periodically (linear keeps a >= 0 where the samples are).
//
// theta = atan2(dA/dy, dA/dx) by central differences (y grows upward), 0 where |grad A| is
// below gradient_epsilon. conductivity_tile reads halo 1 of A (fill A's ghosts first).
#include <cstdint>
#include <string_view>

#include "runtime/field.h"

namespace ardcell {

enum class AnisotropyKind : uint8_t {
  kIsotropic,     // a = isotropic_value everywhere (Eqn 13)
  kWitkinKass,    // Eqn 15
  kCosineLobes,   // Eqn 16
  kPolarSamples,  // arbitrary polar function from samples
};

// "isotropic", "witkin-kass", "lobes", "polar".
std::string_view anisotropy_kind_name(AnisotropyKind k);
bool parse_anisotropy_kind(std::string_view name, AnisotropyKind& out);

inline constexpr int kMaxLobes = 16;
inline constexpr int kMaxPolarSamples = 64;

struct AnisotropyParams {  // plain data, copyable into a local store
  AnisotropyKind kind = AnisotropyKind::kIsotropic;
  float isotropic_value = 1.0f;
  float a1 = 1.0f, a2 = 0.25f;  // Witkin-Kass
  int lobes = 4;                // Eqn 16 j
  float lobe_speed[kMaxLobes] = {1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1};
  int samples = 0;  // polar samples used
  float sample[kMaxPolarSamples] = {};
  float theta0 = 0.0f;  // used where no per-cell theta0 field is given
  float gradient_epsilon = 1e-6f;
};

// One line naming the problem, or nullptr when the parameters are usable.
const char* anisotropy_params_problem(const AnisotropyParams& p);

// a(phi) with phi = theta + theta0 (radians, any value; wrapped into [0, 2pi)).
double anisotropy_value(const AnisotropyParams& p, double phi);
// max over phi of a(phi) (the explicit scheme's stability bound uses it).
double anisotropy_max(const AnisotropyParams& p);

// theta of the gradient of A at (x, y) (central differences; 0 where it vanishes).
double gradient_angle(View<const float> a, int x, int y, float gradient_epsilon);

// k(x, y) = a(theta(x, y) + theta0(x, y)) over region. theta0 may be an empty View (then
// p.theta0 is used everywhere). Reads a over region grown by 1, theta0 over region.
void conductivity_tile(View<const float> a, View<const float> theta0, View<float> k_out,
                       Box2 region, const AnisotropyParams& p);

}  // namespace ardcell
