#pragma once
// Reaction-diffusion with seed 003's generalized (non-Gaussian) diffusion on a periodic grid:
//   seed 003, Eqn 27: u' = (I + delta A) u + delta f(u)       (explicit; generalized_rd_rows;
//     Eqn 26, (u' - u) / delta = A u + f(u), solved for u')
//   seed 003, Eqn 28: u' = (I - delta A)^-1 (u + delta f(u))  (semi-implicit: these rows with
//     the diffusion scales at 0 give u + delta f(u); kernels/periodic_stencil_solve.h inverts)
// for A and B with their own rates: A' = A + s_A K A + dt R_A(A, B), B' = B + s_B K B + dt R_B,
// s = delta D / h^2, K the 25-point stencil of kernels/generalized_diffusion.h (Eqn 19,
// Eqn 20, Eqn 21, Eqn 37) and R the reaction of kernels/reaction.h (seed 003's Eqn 2 is its
// Turing model with s = 1, Eqn 3 and Eqn 4 its Gray-Scott).
// Reads no halo: the domain is periodic (a texture that tiles), and the kernel wraps its
// indices itself, so fields of any halo width work and no boundary fill runs between steps.
// Each cell sums its taps in float by symmetry groups (GeneralizedTaps), in one fixed order
// (the OpenCL twin in kernels/cl/reaction_generalized.cl does the same; both without fused
// multiply-adds), so any band of rows gives the same bits, PoCL gives the CPU's, and a step
// commutes EXACTLY with every symmetry of the stencil (a quarter turn of (d) and (e), the
// transpose of (c)): seed 003's symmetries hold for any number of steps, not to rounding.
// Every result is clamped to [lo, hi] of its chemical: the rank-4 terms of Table 2's (d), (e), (f)
// are anti-diffusive along some directions (the sign of D_xxxx k_x^4 + 6 D_xxyy k_x^2 k_y^2 +
// D_yyyy k_y^4), so the PDE grows without bound at high wavenumbers and only this saturation
// bounds the pattern (where the oriented, sharp-cornered shapes of seed 003's figures come from).
// The engine passes the reaction's typical range (kernels/reaction.h typical_range).
#include <cstddef>
#include <cstdint>

#include "kernels/generalized_diffusion.h"
#include "kernels/reaction.h"
#include "runtime/field.h"

namespace ardcell {

// The stencil's nonzero taps in float (a weight under 1e-12 of the largest is the assembly's
// rounding of a zero and no tap), gathered into groups of equal weight that the stencil's
// symmetries map onto each other. The symmetries are those of its weights (to 1e-12 relative;
// a group's taps all take its first tap's float weight) among the point reflection (dx, dy) ->
// (-dx, -dy), the quarter turn (-dy, dx) and the transpose (dy, dx). A group of n = 1, 2, 4 or 8
// taps (in `taps`, from `first`) adds its values as a balanced tree,
// ((t0 + t1) + (t2 + t3)) + ((t4 + t5) + (t6 + t7)), where t1 is t0's reflection, t2..t3 the
// quarter turn (or the transpose) of t0..t1, and t4..t7 the transpose of t0..t3: every symmetry
// permutes each group's taps within pairs or swaps whole subtrees, and float addition is
// commutative, so a mapped field gets the mapped sums bit for bit. A cell's sum is
// sum over groups, in the order of their first tap row-major, of weight * tree.
struct GeneralizedTaps {
  struct Tap {
    int dx, dy;
    float weight;
  };
  struct Group {
    int first, count;
    float weight;
  };
  Tap taps[25];
  int count = 0;
  Group groups[25];
  int group_count = 0;

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

// The most steps generalized_rd_fused_rows runs in one walk: its rings (5 rows of A and B per
// step) stay in a core's L2 at 1024 cells a row (160 KiB).
inline constexpr int kGeneralizedFusedSteps = 4;

// Floats of scratch per worker that generalized_rd_rows and generalized_rd_fused_rows need for
// an nx-wide grid.
std::size_t generalized_rd_scratch_floats(int nx);

// Rows [y0, y1) of the nx x ny interior (a.size()): a_out, b_out from a, b. Outputs must not
// alias inputs. scratch: generalized_rd_scratch_floats(nx) floats, 64-byte aligned preferred.
void generalized_rd_rows(const GeneralizedTaps& k, View<const float> a, View<const float> b,
                         View<float> a_out, View<float> b_out, Int2 size, int y0, int y1,
                         const GeneralizedRdParams& p, float* scratch);

// `steps` steps at once (1 .. kGeneralizedFusedSteps): rows [y0, y1) of the last step from a, b,
// the same bits as generalized_rd_rows over every row `steps` times. Each step's rows stay in the
// scratch (a ring of 5 rows per step, each step two rows behind the one before), so a band moves
// its fields through memory once for all the steps (at 1024^2 a single step streams them), at
// the cost of steps (steps - 1) row-steps computed again at each band edge. Needs a diffusion
// (scale_a or scale_b not 0). Outputs must not alias inputs.
void generalized_rd_fused_rows(const GeneralizedTaps& k, View<const float> a, View<const float> b,
                               View<float> a_out, View<float> b_out, Int2 size, int y0, int y1,
                               const GeneralizedRdParams& p, int steps, float* scratch);

// --- Seed 003, Table 1, last row at rank 2: an inhomogeneous (per-cell) diffusion tensor --------
//   seed 003, Table 1 (inhomogeneous, anisotropic Gaussian): tr(D H(u)) + grad u . div D
//     (div D the row-wise divergence of Eqn 22), i.e.
//     du/dt = div(D(x) grad u) + f(u) = D_ij d_i d_j u + (d_i D_ij) d_j u ("the evaluation of
//     additional terms ... due to the spatially varying diffusion coefficients", sec. 7),
//     with D(x) a symmetric positive (semi)definite 2x2 tensor per cell (Eqn 5 with D varying).
// Discretised in flux form, so that the total is conserved on a periodic grid (to rounding):
//   L u (x, y) = F(x + 1/2, y) - F(x - 1/2, y) + G(x, y + 1/2) - G(x, y - 1/2)
//   F(x + 1/2, y) = Dxx_f (u(x+1, y) - u(x, y))
//                 + Dxy_f (u(x, y+1) + u(x+1, y+1) - u(x, y-1) - u(x+1, y-1)) / 4
//   G(x, y + 1/2) = Dyy_g (u(x, y+1) - u(x, y))
//                 + Dxy_g (u(x+1, y) + u(x+1, y+1) - u(x-1, y) - u(x-1, y+1)) / 4
// with the face's D the mean of its two cells' (Dxx_f = (Dxx(x) + Dxx(x+1)) / 2, ...). Each face's
// flux is one expression of the same operands from either side (the same bits), so the sum over
// the grid telescopes. For a uniform D it is exactly seed 003's Eqn 29 (the 9-point Gaussian
// stencil: corners D_xy / 2 at (1, 1), (-1, -1)), summed in another order.
// Step (seed 003, Eqn 27 with this L): A' = A + s_A L A + dt R_A, B' likewise, s = delta D_A (the
// tensor in cells^2: the domain's D times h^-2), the same reactions, parameter map and clamp as
// generalized_rd_rows. Reads no halo: indices wrap (periodic only), as generalized_rd_rows does.
// Each cell's arithmetic is fixed, so any band of rows gives the same bits.

// Per-face tensor coefficients, in cells^2 (halo 0): x_xx, x_xy at (x, y) belong to the face
// between cells x and x + 1 (wrapped); y_xy, y_yy at (x, y) to the face between rows y and y + 1.
struct Rank2FaceField {
  FieldF x_xx, x_xy, y_xy, y_yy;
  Int2 size() const { return x_xx.size(); }
};

// The faces of a per-cell tensor field (cells xx, xy, yy of one size): each the mean of its two
// cells, wrapped.
Rank2FaceField rank2_faces(const FieldF& xx, const FieldF& xy, const FieldF& yy);

// Built-in fields: D = d_along e e^T + d_across (I - e e^T), e = (cos phi, sin phi) turning around
// the grid's centre c = (nx / 2, ny / 2), seen from the cell's centre (x + 1/2, y + 1/2):
// kVortex phi = atan2(y - c_y, x - c_x) + pi / 2 (tangential), kRadial without the pi / 2,
// kUniform phi = 0. A cell exactly at the centre gets the isotropic mean (d_along + d_across) / 2.
enum class TensorFieldKind : uint8_t { kUniform, kVortex, kRadial };
// The field in cells^2 (d_along, d_across already scaled by h^-2), as faces.
Rank2FaceField rank2_tensor_field(Int2 size, TensorFieldKind kind, double d_along, double d_across);

// Rows [y0, y1) of the nx x ny interior: a_out, b_out from a, b with L of the face field d.
// Outputs must not alias inputs.
void tensor_field_rd_rows(const Rank2FaceField& d, View<const float> a, View<const float> b,
                          View<float> a_out, View<float> b_out, Int2 size, int y0, int y1,
                          const GeneralizedRdParams& p);

}  // namespace ardcell
