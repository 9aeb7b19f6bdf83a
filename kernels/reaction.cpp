#include "kernels/reaction.h"

#include <algorithm>
#include <array>
#include <limits>

namespace ardcell {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr int kMaxIterations = 200;

constexpr std::array<std::string_view, kReactionModelCount> kModelNames = {
    "gray-scott", "turing", "meinhardt", "fitzhugh-nagumo", "barkley", "barkley-turbulent"};

// Root of g on [lo, hi], where g(lo) <= 0 <= g(hi) (or the reverse: `increasing` false), by
// Newton steps that fall back to bisection whenever a step leaves the bracket or fails to
// shrink |g| fast enough (Numerical Recipes' rtsafe). eval(x, g, dg) writes g(x), g'(x).
struct RootResult {
  double x, g;
  int iterations;
};
template <class Eval>
RootResult safeguarded_newton(const Eval& eval, double lo, double hi, double x0, double tol) {
  double g = 0, dg = 0;
  eval(lo, g, dg);
  if (std::abs(g) <= tol) return {lo, g, 0};
  const bool increasing = g < 0;
  eval(hi, g, dg);
  if (std::abs(g) <= tol) return {hi, g, 0};
  // Orient so that g(lo) < 0 < g(hi).
  const double sign = increasing ? 1.0 : -1.0;
  double x = std::clamp(x0, lo, hi);
  if (!(x == x)) x = 0.5 * (lo + hi);
  double dx_old = hi - lo, dx = dx_old;
  eval(x, g, dg);
  int it = 0;
  for (; it < kMaxIterations && std::abs(g) > tol; ++it) {
    const double gs = sign * g, dgs = sign * dg;
    if (gs < 0)
      lo = x;
    else
      hi = x;
    const double newton = dgs != 0 ? x - gs / dgs : kInf;
    if (!(newton > lo && newton < hi) || std::abs(2.0 * gs) > std::abs(dx_old * dgs)) {
      dx_old = dx;
      dx = 0.5 * (hi - lo);
      x = lo + dx;
    } else {
      dx_old = dx;
      dx = x - newton;
      x = newton;
    }
    if (hi - lo <= 1e-15 * (1.0 + std::abs(x))) {
      eval(x, g, dg);
      ++it;
      break;
    }
    eval(x, g, dg);
  }
  return {x, g, it};
}

ImplicitResult solve_gray_scott(const ReactionParams& p, double dt, double A, double B,
                                double tol) {
  const double F = p.F, k = p.k;
  const double c = A + F * dt, lin = 1.0 + (F + k) * dt, d0 = 1.0 + F * dt;
  auto eval = [&](double y, double& g, double& dg) {
    const double D = d0 + dt * y * y;
    g = y * lin - B - dt * c * y * y / D;
    dg = lin - dt * c * 2.0 * y * d0 / (D * D);
  };
  const double hi = std::max(0.0, (B + c) / lin);
  const RootResult r = safeguarded_newton(eval, 0.0, hi, B, tol);
  const double b_hat = r.x;
  return {c / (d0 + dt * b_hat * b_hat), b_hat, std::abs(r.g), r.iterations};
}

ImplicitResult solve_turing(const ReactionParams& p, double dt, double A, double B, double tol) {
  const double q = double(p.turing_s) * dt, beta = p.turing_beta;
  const double C = B + double(p.turing_supply) * q;
  auto b_of = [&](double x) { return C / (1.0 + q * x); };
  // g is convex on x >= 0 (q C x / (1 + q x) is concave).
  auto eval = [&](double x, double& g, double& dg) {
    const double den = 1.0 + q * x;
    g = x * (1.0 + q) - A + q * beta - q * C * x / den;
    dg = 1.0 + q - q * C / (den * den);
  };
  double g0, dg0;
  eval(0.0, g0, dg0);
  double lo = 0.0, hi;
  if (g0 <= 0) {
    hi = std::max(0.0, (A - q * beta + C) / (1.0 + q));
  } else {
    // The smaller root, if g dips below 0 at its minimum x*; else the projection x = 0.
    // Of the two roots around x*, the one on A's side (continuous in dt as dt -> 0).
    const double r2 = q > 0 ? q * C / (1.0 + q) : 0.0;
    if (r2 <= 1.0) return {0.0, b_of(0.0), 0.0, 0};
    const double x_star = (std::sqrt(r2) - 1.0) / q;
    double gs, dgs;
    eval(x_star, gs, dgs);
    if (gs > 0) return {0.0, b_of(0.0), 0.0, 0};
    if (A >= x_star) {
      lo = x_star;
      hi = std::max(x_star, (A - q * beta + C) / (1.0 + q));
    } else {
      hi = x_star;
    }
  }
  const RootResult r = safeguarded_newton(eval, lo, hi, A, tol);
  return {r.x, b_of(r.x), std::abs(r.g), r.iterations};
}

ImplicitResult solve_meinhardt(const ReactionParams& p, double dt, double A, double B, double tol) {
  const double q = double(p.meinhardt_s) * dt, m = 0.01 * double(p.meinhardt_alpha);
  const double p1 = p.meinhardt_p1, p2 = p.meinhardt_p2, p3 = p.meinhardt_p3;
  const double P = 1.0 - q * p2;
  auto eval = [&](double x, double& g, double& dg) {
    const double den = B + q * m * x * x;
    const double T = den > 0 ? m * x * x * P / den : 0.0;
    const double dT = den > 0 ? 2.0 * m * P * B * x / (den * den) : 0.0;
    g = x - A - q * (p1 * x + T + p3);
    dg = 1.0 - q * p1 - q * dT;
  };
  const double hi = std::max(0.0, (A + q * p3 + P) / (1.0 - q * p1));
  const RootResult r = safeguarded_newton(eval, 0.0, hi, A, tol);
  const double a_hat = r.x;
  return {a_hat, (B + q * m * a_hat * a_hat) / P, std::abs(r.g), r.iterations};
}

double fhn_box_m(const ReactionParams& p) {
  // The largest root M > 1 of M^3 - M = (M + |a0|) / a1: the square |A| <= M, |B| <= M^3 - M
  // is invariant (R_A <= 0 on A = M, R_B <= 0 on B = N, and symmetrically). Depressed cubic
  // M^3 + P M + Q = 0 with P < 0: the trigonometric form of its largest root.
  const double a0 = std::abs(double(p.fhn_a0)), a1 = p.fhn_a1;
  const double P = -(1.0 + 1.0 / a1), Q = -a0 / a1;
  const double c = std::clamp(1.5 * Q / P * std::sqrt(-3.0 / P), -1.0, 1.0);
  return 2.0 * std::sqrt(-P / 3.0) * std::cos(std::acos(c) / 3.0);
}

ImplicitResult solve_fhn(const ReactionParams& p, double dt, double A, double B, double tol) {
  const double r = double(p.fhn_epsilon) * dt, a0 = p.fhn_a0, a1 = p.fhn_a1;
  const double P = 1.0 + r * a1;
  auto b_of = [&](double x) { return (B + r * (x - a0)) / P; };
  auto eval = [&](double x, double& g, double& dg) {
    g = x - A - dt * (x - x * x * x - b_of(x));
    dg = 1.0 - dt * (1.0 - 3.0 * x * x - r / P);
  };
  const double M = fhn_box_m(p);
  const double lo = std::min(-M, A), hi = std::max(M, A);
  const RootResult res = safeguarded_newton(eval, lo, hi, A, tol);
  return {res.x, b_of(res.x), std::abs(res.g), res.iterations};
}

ImplicitResult solve_barkley(const ReactionParams& p, double dt, double A, double B, double tol,
                             bool turbulent) {
  const double inv_eps = 1.0 / double(p.barkley_epsilon), a = p.barkley_a, b = p.barkley_b;
  const double w = dt / (1.0 + dt);
  auto b_of = [&](double x) { return (B + dt * (turbulent ? x * x * x : x)) / (1.0 + dt); };
  auto eval = [&](double x, double& g, double& dg) {
    const double u = (b_of(x) + b) / a;
    const double du = (turbulent ? 3.0 * x * x * w : w) / a;
    const double h = x * (1.0 - x) * (x - u);
    const double dh = (1.0 - 2.0 * x) * (x - u) + x * (1.0 - x) * (1.0 - du);
    g = x - A - dt * inv_eps * h;
    dg = 1.0 - dt * inv_eps * dh;
  };
  const RootResult r = safeguarded_newton(eval, std::min(0.0, A), std::max(1.0, A), A, tol);
  return {r.x, b_of(r.x), std::abs(r.g), r.iterations};
}

}  // namespace

std::string_view reaction_model_name(ReactionModel m) { return kModelNames[static_cast<int>(m)]; }

bool parse_reaction_model(std::string_view name, ReactionModel& out) {
  for (int i = 0; i < kReactionModelCount; ++i)
    if (kModelNames[i] == name) {
      out = static_cast<ReactionModel>(i);
      return true;
    }
  return false;
}

const char* reaction_params_problem(const ReactionParams& p) {
  switch (p.model) {
    case ReactionModel::kGrayScott:
      if (!(p.F >= 0 && p.k >= 0)) return "gray-scott: F and k must be >= 0";
      return nullptr;
    case ReactionModel::kTuring:
      if (!(p.turing_s >= 0)) return "turing: s must be >= 0";
      return nullptr;
    case ReactionModel::kMeinhardt:
      if (!(p.meinhardt_s >= 0 && p.meinhardt_alpha >= 0))
        return "meinhardt: s and alpha must be >= 0";
      if (!(p.meinhardt_p1 <= 0 && p.meinhardt_p2 <= 0))
        return "meinhardt: p1 and p2 must be <= 0 (decay rates)";
      if (!(p.meinhardt_p3 >= 0)) return "meinhardt: p3 must be >= 0 (base production)";
      return nullptr;
    case ReactionModel::kFitzHughNagumo:
      if (!(p.fhn_epsilon >= 0)) return "fitzhugh-nagumo: epsilon must be >= 0";
      if (!(p.fhn_a1 > 0)) return "fitzhugh-nagumo: a1 must be > 0";
      return nullptr;
    case ReactionModel::kBarkley:
    case ReactionModel::kBarkleyTurbulent:
      if (!(p.barkley_epsilon > 0 && p.barkley_a > 0)) return "barkley: epsilon and a must be > 0";
      return nullptr;
  }
  return "unknown reaction model";
}

ConcentrationBox invariant_box(const ReactionParams& p) {
  switch (p.model) {
    case ReactionModel::kGrayScott:
      // A in [0, 1] and B >= 0 hold for any B (R_A(1, B) = -B^2 <= 0, R_A(0, B) = F >= 0,
      // R_B(A, 0) = 0); the reaction alone also keeps A + B <= 1.
      return {0.0, 1.0, 0.0, kInf};
    case ReactionModel::kBarkley:
    case ReactionModel::kBarkleyTurbulent:
      return {0.0, 1.0, 0.0, 1.0};
    case ReactionModel::kTuring:
    case ReactionModel::kMeinhardt:
      return {0.0, kInf, 0.0, kInf};
    case ReactionModel::kFitzHughNagumo: {
      const double M = fhn_box_m(p);
      return {-M, M, -(M * M * M - M), M * M * M - M};
    }
  }
  return {-kInf, kInf, -kInf, kInf};
}

ConcentrationBox typical_range(const ReactionParams& p) {
  switch (p.model) {
    case ReactionModel::kGrayScott:
      return {0.0, 1.0, 0.0, 1.0};
    case ReactionModel::kTuring:
      return {0.0, 12.0, 0.0, 12.0};
    case ReactionModel::kMeinhardt:
      return {0.0, 6.0, 0.0, 6.0};
    default:
      return invariant_box(p);
  }
}

void reaction_rates(const ReactionParams& p, double A, double B, double& ra, double& rb) {
  switch (p.model) {
    case ReactionModel::kGrayScott:
      ra = -A * B * B + p.F * (1.0 - A);
      rb = A * B * B - (double(p.F) + p.k) * B;
      return;
    case ReactionModel::kTuring:
      ra = p.turing_s * (A * B - A - p.turing_beta);
      rb = p.turing_s * (double(p.turing_supply) - A * B);
      return;
    case ReactionModel::kMeinhardt: {
      const double m = 0.01 * double(p.meinhardt_alpha) * A * A;
      ra = p.meinhardt_s * (A * p.meinhardt_p1 + (B != 0 ? m / B : 0.0) + p.meinhardt_p3);
      rb = p.meinhardt_s * (B * p.meinhardt_p2 + m);
      return;
    }
    case ReactionModel::kFitzHughNagumo:
      ra = A - A * A * A - B;
      rb = p.fhn_epsilon * (A - p.fhn_a1 * B - p.fhn_a0);
      return;
    case ReactionModel::kBarkley:
    case ReactionModel::kBarkleyTurbulent:
      ra = A * (1.0 - A) * (A - (B + p.barkley_b) / p.barkley_a) / p.barkley_epsilon;
      rb = (p.model == ReactionModel::kBarkley ? A : A * A * A) - B;
      return;
  }
  ra = rb = 0;
}

ImplicitResult implicit_reaction_cell(const ReactionParams& p, double dt, double A, double B,
                                      double tolerance) {
  // Inputs outside the invariant box (rounding, painted values) are first brought inside it,
  // where the bracket of each model provably holds a root.
  const ConcentrationBox box = invariant_box(p);
  A = std::clamp(A, box.a_lo, box.a_hi);
  B = std::clamp(B, box.b_lo, box.b_hi);
  switch (p.model) {
    case ReactionModel::kGrayScott:
      return solve_gray_scott(p, dt, A, B, tolerance);
    case ReactionModel::kTuring:
      return solve_turing(p, dt, A, B, tolerance);
    case ReactionModel::kMeinhardt:
      return solve_meinhardt(p, dt, A, B, tolerance);
    case ReactionModel::kFitzHughNagumo:
      return solve_fhn(p, dt, A, B, tolerance);
    case ReactionModel::kBarkley:
      return solve_barkley(p, dt, A, B, tolerance, false);
    case ReactionModel::kBarkleyTurbulent:
      return solve_barkley(p, dt, A, B, tolerance, true);
  }
  return {A, B, 0.0, 0};
}

ImplicitResult trapezoidal_reaction_cell(const ReactionParams& p, double dt, double A, double B,
                                         double tolerance) {
  double ra, rb;
  reaction_rates(p, A, B, ra, rb);
  const double half = 0.5 * dt;
  return implicit_reaction_cell(p, half, A + half * ra, B + half * rb, tolerance);
}

double implicit_reaction_residual(const ReactionParams& p, double dt, double A, double B,
                                  double a_hat, double b_hat) {
  double ra, rb;
  reaction_rates(p, a_hat, b_hat, ra, rb);
  double res_a = a_hat - A - dt * ra;
  const double res_b = b_hat - B - dt * rb;
  // Projection onto A >= 0 (Turing, Meinhardt): complementarity A^ = 0, A + dt R_A <= 0.
  const bool nonneg_a = p.model == ReactionModel::kTuring || p.model == ReactionModel::kMeinhardt;
  if (nonneg_a && a_hat == 0.0 && res_a >= 0.0) res_a = 0.0;
  return std::max(std::abs(res_a), std::abs(res_b));
}

namespace {
// cell(A, B, A_out, B_out) over region, row by row; each cell is read before it is written, so
// the outputs may alias the inputs.
template <class Cell>
void for_each_cell(View<const float> a, View<const float> b, View<float> a_out, View<float> b_out,
                   Box2 region, const Cell& cell) {
  for (int y = region.min.y; y < region.max.y; ++y) {
    const float* ar = a.row(y);
    const float* br = b.row(y);
    float* ao = a_out.row(y);
    float* bo = b_out.row(y);
    for (int x = region.min.x; x < region.max.x; ++x) cell(ar[x], br[x], ao[x], bo[x]);
  }
}
}  // namespace

void gray_scott_implicit_tile(View<const float> a, View<const float> b, View<float> a_out,
                              View<float> b_out, Box2 region, const GrayScottImplicitParams& gp) {
  ReactionParams p;
  p.model = ReactionModel::kGrayScott;
  p.F = gp.F;
  p.k = gp.k;
  const double dt = gp.dt;
  for_each_cell(a, b, a_out, b_out, region, [&](float a_in, float b_in, float& ao, float& bo) {
    const double A = std::clamp(double(a_in), 0.0, 1.0);
    const double B = std::max(double(b_in), 0.0);
    const ImplicitResult r = solve_gray_scott(p, dt, A, B, 1e-9);
    ao = float(r.a);
    bo = float(r.b);
  });
}

void reaction_implicit_tile(View<const float> a, View<const float> b, View<float> a_out,
                            View<float> b_out, Box2 region, const ReactionParams& p, float dt) {
  if (p.model == ReactionModel::kGrayScott) {
    gray_scott_implicit_tile(a, b, a_out, b_out, region, {p.F, p.k, dt});
    return;
  }
  for_each_cell(a, b, a_out, b_out, region, [&](float A, float B, float& ao, float& bo) {
    const ImplicitResult r = implicit_reaction_cell(p, dt, A, B);
    ao = float(r.a);
    bo = float(r.b);
  });
}

void reaction_trapezoidal_tile(View<const float> a, View<const float> b, View<float> a_out,
                               View<float> b_out, Box2 region, const ReactionParams& p, float dt) {
  for_each_cell(a, b, a_out, b_out, region, [&](float A, float B, float& ao, float& bo) {
    const ImplicitResult r = trapezoidal_reaction_cell(p, dt, A, B);
    ao = float(r.a);
    bo = float(r.b);
  });
}

void reaction_explicit_tile(View<const float> a, View<const float> b, View<float> a_out,
                            View<float> b_out, Box2 region, const ReactionParams& p, float dt) {
  for_each_cell(a, b, a_out, b_out, region, [&](float A, float B, float& ao, float& bo) {
    double ra, rb;
    reaction_rates(p, A, B, ra, rb);
    ao = float(A + dt * ra);
    bo = float(B + dt * rb);
  });
}

}  // namespace ardcell
