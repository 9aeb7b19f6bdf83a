#pragma once
// Reaction terms of seed 000 and their implicit (backward Euler) updates.
//
// Eqn 6: (A^, B^) = (A, B) + dt R(A^, B^), solved per cell. Reads halo 0 (no neighbours).
// As the paper derives for Gray-Scott (Eqn 9 to Eqn 12 below) and for the models of Appendix A,
// one unknown is eliminated in closed form and the reduced scalar equation g(x) = 0 is solved by
// Newton-Raphson, safeguarded by a bracket that provably holds a root (bisection whenever a
// Newton step leaves it), to |g| < 1e-6.
//
//   Gray-Scott, Eqn 7:  R_A = -A B^2 + F (1 - A)      Eqn 8:  R_B = A B^2 - (F + k) B
//     Eqn 9:  A^ = A + dt R_A(A^, B^)     Eqn 10:  B^ = B + dt R_B(A^, B^)   (Eqn 6 here)
//     Eqn 11: A^ = (A + F dt) / (1 + F dt + dt B^2), Eqn 9 solved for A^ in terms of B^
//             (reaction.cpp solve_gray_scott, once B^ is known)
//     Eqn 12: B^ = B + dt (A^(B^) B^2 - (F + k) B^), Eqn 11 put into Eqn 10: a cubic in B^,
//             solved by the safeguarded Newton above (solve_gray_scott)
//     The printed Eqn 9, Eqn 10 and Eqn 11 write A^ B^ where Eqn 7 and Eqn 8 have A B^2 (the
//     printed Eqn 12 keeps the square); ardcell keeps the square throughout.
//   seed 003's Eqn 3 and Eqn 4 (its Gray-Scott, u = A, v = B) have these rates.
//   Turing:                 R_A = s (A B - A - beta)          R_B = s (sigma - A B)
//     reduced in A^;         B^ = (B + sigma s dt) / (1 + s A^ dt)  (the printed rule drops s)
//     sigma (turing_supply) is Turk's and Kim & Lin's 16; seed 003's Eqn 2 is the same model
//     with s = 1, beta = its alpha, sigma = its beta (12 and 15 in its Results).
//   Meinhardt:              R_A = s (A p1 + 0.01 alpha A^2 / B + p3)
//                           R_B = s (B p2 + 0.01 alpha A^2)
//     reduced in A^;         B^ = (B + dt s 0.01 alpha A^2) / (1 - dt s p2)
//   FitzHugh-Nagumo:        R_A = A - A^3 - B                 R_B = eps (A - a1 B - a0)
//     reduced in A^;         B^ = (B + dt eps (A^ - a0)) / (1 + dt eps a1)
//   Barkley:                R_A = A (1 - A) (A - (B + b) / a) / eps    R_B = A - B
//     reduced in A^;         B^ = (B + dt A^) / (1 + dt)   (the printed rule drops the 1/a)
//   Turbulent Barkley:      as Barkley with R_B = A^3 - B;  B^ = (B + dt A^3) / (1 + dt)
//
// The trapezoidal rule (Adams-Moulton 2, the second-order reaction Kim & Lin suggest in sec. 3.2):
//   (A^, B^) = (A, B) + dt/2 R(A, B) + dt/2 R(A^, B^)
// is Eqn 6 over dt/2 started from the forward half step (A, B) + dt/2 R(A, B), so the same
// per-cell Newton solves it. That start is first brought into the invariant box like every
// input of Eqn 6: where a long step's forward half leaves the box the update stays bounded
// (and first order there); where it does not, it is the trapezoidal rule.
//
// Where a model's concentrations cannot go negative (Turing, Meinhardt's A) and g has no root
// at or above 0, the update is the projected one (x = 0 with g(0) > 0: the complementarity
// solution, as Turk clamps Turing's chemicals at 0); residual() reports that case as 0.
#include <cmath>
#include <cstdint>
#include <string_view>

#include "runtime/field.h"

namespace ardcell {

enum class ReactionModel : uint8_t {
  kGrayScott,
  kTuring,
  kMeinhardt,
  kFitzHughNagumo,
  kBarkley,
  kBarkleyTurbulent,
};
inline constexpr int kReactionModelCount = 6;

// "gray-scott", "turing", "meinhardt", "fitzhugh-nagumo", "barkley", "barkley-turbulent".
std::string_view reaction_model_name(ReactionModel m);
bool parse_reaction_model(std::string_view name, ReactionModel& out);

// Plain parameters of every model (only the selected model's are read). Defaults: Gray-Scott
// as in seed 001, Turing as in Turk 1991, Barkley's spiral regime, FitzHugh-Nagumo excitable.
struct ReactionParams {
  ReactionModel model = ReactionModel::kGrayScott;
  // Gray-Scott
  float F = 0.055f, k = 0.062f;
  // Turing (s: rate; beta: decay; supply: the substrate's constant production, Turk's 16)
  float turing_s = 1.0f / 128.0f, turing_beta = 12.0f, turing_supply = 16.0f;
  // Meinhardt (p1, p2 <= 0: decays; p3 >= 0: base production)
  float meinhardt_s = 0.01f, meinhardt_alpha = 100.0f;
  float meinhardt_p1 = -1.0f, meinhardt_p2 = -1.5f, meinhardt_p3 = 0.1f;
  // FitzHugh-Nagumo (a1 >= 0)
  float fhn_epsilon = 0.05f, fhn_a0 = -0.1f, fhn_a1 = 2.0f;
  // Barkley and turbulent Barkley
  float barkley_epsilon = 0.02f, barkley_a = 0.75f, barkley_b = 0.02f;
};

// Empty when the parameters are usable at every dt; otherwise one line naming the bad value.
// (Unconditional stability needs the linear decay terms to be decays: Meinhardt p1, p2 <= 0,
// FitzHugh-Nagumo a1 >= 0, Gray-Scott F, k >= 0, Barkley a, eps > 0, Turing s >= 0.)
const char* reaction_params_problem(const ReactionParams& p);

// Box [lo, hi] of each chemical that the model's flow never leaves (and that the implicit
// update, implicit diffusion and bilinear advection keep). Infinite bounds where unbounded.
struct ConcentrationBox {
  double a_lo, a_hi, b_lo, b_hi;
};
ConcentrationBox invariant_box(const ReactionParams& p);

// A typical working range per model, the default range of the reaction table.
ConcentrationBox typical_range(const ReactionParams& p);

// Explicit reaction rates R_A, R_B at (A, B).
void reaction_rates(const ReactionParams& p, double A, double B, double& ra, double& rb);

struct ImplicitResult {
  double a, b;      // A^, B^
  double residual;  // |g(x)| of the reduced equation at the solution (0 when projected)
  int iterations;   // Newton/bisection steps taken
};

// One cell of Eqn 6 by safeguarded Newton, in double. tolerance: |g| to stop at.
ImplicitResult implicit_reaction_cell(const ReactionParams& p, double dt, double A, double B,
                                      double tolerance = 1e-9);

// One cell of the trapezoidal rule over dt (above), in double.
ImplicitResult trapezoidal_reaction_cell(const ReactionParams& p, double dt, double A, double B,
                                         double tolerance = 1e-9);

// Residual of the implicit system itself, max(|A^ - A - dt R_A|, |B^ - B - dt R_B|) at
// (A^, B^), with a projected component counted as 0 when the constraint is active.
double implicit_reaction_residual(const ReactionParams& p, double dt, double A, double B,
                                  double a_hat, double b_hat);

// --- Tile kernels (halo 0). Outputs may alias inputs (per-cell, in place). ---------------------

// Gray-Scott backward Euler (Eqn 9 and Eqn 10, solved by Eqn 12 then Eqn 11) over region;
// F, k, dt plain floats so the kernel fuses into other passes and has a one-to-one OpenCL twin.
struct GrayScottImplicitParams {
  float F = 0.055f, k = 0.062f, dt = 1.0f;
};
void gray_scott_implicit_tile(View<const float> a, View<const float> b, View<float> a_out,
                              View<float> b_out, Box2 region, const GrayScottImplicitParams& p);

// Any model, backward Euler (Eqn 6).
void reaction_implicit_tile(View<const float> a, View<const float> b, View<float> a_out,
                            View<float> b_out, Box2 region, const ReactionParams& p, float dt);

// Any model, the trapezoidal rule over dt (trapezoidal_reaction_cell per cell).
void reaction_trapezoidal_tile(View<const float> a, View<const float> b, View<float> a_out,
                               View<float> b_out, Box2 region, const ReactionParams& p, float dt);

// Any model, forward Euler of the reaction alone: A + dt R_A(A, B), B + dt R_B(A, B).
void reaction_explicit_tile(View<const float> a, View<const float> b, View<float> a_out,
                            View<float> b_out, Box2 region, const ReactionParams& p, float dt);

}  // namespace ardcell
