#pragma once
// The right-hand sides of the IMEX multistep schemes SBDF1 and SBDF2 (Ascher, Ruuth & Wetton
// 1995, "Implicit-explicit methods for time-dependent partial differential equations"):
// implicit (backward-differentiation) diffusion, extrapolated explicit reaction f = (R_A, R_B) of
// seed 000's Eqn 7, Eqn 8 and Appendix A:
//   SBDF1:  (I - dt L) u^{n+1}        = u^n + dt f(u^n)
//   SBDF2:  (I - 2/3 dt L) u^{n+1}    = (4 u^n - u^{n-1}) / 3 + 2/3 dt (2 f(u^n) - f(u^{n-1}))
// This kernel writes the right-hand side over u^n and moves u^n into the history (u^{n-1} of the
// next step), per cell; the caller then solves the implicit diffusion with 1 or 2/3 of dt
// (kernels/aniso_diffusion.h, any boundary). SBDF2 is second order and, with the diffusion
// implicit, stable at any dt in the diffusion; the reaction is explicit, so its step is bounded
// by the reaction's rates (|lambda dt| < 4/3 for a real decay rate lambda; docs/numerics.md).
// Reads halo 0; a, b and the history are read and written in place.
#include "kernels/reaction.h"
#include "runtime/field.h"

namespace ardcell {

struct SbdfRhsParams {
  ReactionParams reaction;
  float dt = 1.0f;
  int order = 2;      // 1: SBDF1 (the start, no history yet); 2: SBDF2
  bool react = true;  // false: f = 0
};

// a, b <- the right-hand side above; a_prev, b_prev <- the a, b read (u^n). With order 2,
// a_prev and b_prev hold u^{n-1} on entry. In double, rounded to float once.
void sbdf_rhs_tile(View<float> a, View<float> b, View<float> a_prev, View<float> b_prev,
                   Box2 region, const SbdfRhsParams& p);

// The implicit diffusion's share of dt for an SBDF step of `order`: 1 or 2/3.
inline double sbdf_diffusion_fraction(int order) { return order == 2 ? 2.0 / 3.0 : 1.0; }

}  // namespace ardcell
