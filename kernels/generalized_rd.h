#pragma once
// Reaction-diffusion with seed 003's generalized (non-Gaussian) diffusion on a periodic grid:
//   seed 003, Eqn 27: u' = (I + delta A) u + delta f(u)       (explicit; generalized_rd_rows)
//   seed 003, Eqn 28: u' = (I - delta A)^-1 (u + delta f(u))  (semi-implicit: these rows with
//     the diffusion scales at 0 give u + delta f(u); kernels/periodic_stencil_solve.h inverts)
// for A and B with their own rates: A' = A + s_A K A + dt R_A(A, B), B' = B + s_B K B + dt R_B,
// s = delta D / h^2, K the 25-point stencil of kernels/generalized_diffusion.h (Eqns 19-21, 37)
// and R the reaction of kernels/reaction.h (seed 003's Eqn 2 is its Turing model with s = 1,
// Eqns 3-4 its Gray-Scott).
// Reads no halo: the domain is periodic (a texture that tiles), and the kernel wraps its
// indices itself, so fields of any halo width work and no boundary fill runs between steps.
// Each cell sums its taps in the stencil's row-major order in float (the OpenCL twin in
// kernels/cl/reaction_generalized.cl does the same; both without fused multiply-adds), so any
// band of rows gives the same bits, and PoCL gives the CPU's.
// Every result is clamped to [lo, hi] of its chemical: the rank-4 terms of Table 2's (d), (e), (f)
// are anti-diffusive along some directions (the sign of D_xxxx k_x^4 + 6 D_xxyy k_x^2 k_y^2 +
// D_yyyy k_y^4), so the PDE grows without bound at high wavenumbers and only this saturation
// bounds the pattern (where the oriented, sharp-cornered shapes of seed 003's figures come from).
// The engine passes the reaction's typical range (kernels/reaction.h typical_range).
#include <cstddef>

#include "kernels/generalized_diffusion.h"
#include "kernels/reaction.h"
#include "runtime/field.h"

namespace ardcell {

// The stencil's nonzero taps in float, in row-major order (dy, then dx, from -2 to 2).
struct GeneralizedTaps {
  struct Tap {
    int dx, dy;
    float weight;
  };
  Tap taps[25];
  int count = 0;

  explicit GeneralizedTaps(const Stencil5x5& k);
  GeneralizedTaps() = default;
};

struct GeneralizedRdParams {
  ReactionParams reaction;
  float dt = 0.0f;       // reaction step; 0 with react off
  float scale_a = 0.0f;  // s_A = delta D_A / h^2 (0: no diffusion of A)
  float scale_b = 0.0f;
  float a_lo = -3.4e38f, a_hi = 3.4e38f;  // the clamp of A's and B's results
  float b_lo = -3.4e38f, b_hi = 3.4e38f;
  // Gray-Scott's parameter map (seed 003, Fig. 6): at cell (x, y) the reaction uses
  // F + f_step (x + 1/2) and k + k_step (y + 1/2), in float in that order (0, 0: uniform).
  float f_step = 0.0f, k_step = 0.0f;
};

// Floats of scratch per worker that generalized_rd_rows needs for an nx-wide grid.
std::size_t generalized_rd_scratch_floats(int nx);

// Rows [y0, y1) of the nx x ny interior (a.size()): a_out, b_out from a, b. Outputs must not
// alias inputs. scratch: generalized_rd_scratch_floats(nx) floats, 64-byte aligned preferred.
void generalized_rd_rows(const GeneralizedTaps& k, View<const float> a, View<const float> b,
                         View<float> a_out, View<float> b_out, Int2 size, int y0, int y1,
                         const GeneralizedRdParams& p, float* scratch);

}  // namespace ardcell
