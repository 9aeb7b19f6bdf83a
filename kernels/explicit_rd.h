#pragma once
// Forward Euler reaction-diffusion, the explicit schemes the implicit one is compared against.
//
// Eqn 5 (seed 000), 5-point Laplacian. Reads halo 1:
//   A' = A + dt R_A(A, B) + (DA dt / h^2) (A_W + A_E + A_S + A_N - 4 A)
// Seed 001's 9-point Laplacian (corners 0.05, edges 0.2, centre -1; it approximates
// 0.3 h^2 lap, and seed 001 uses it unscaled with dt = 1, h = 1). Reads halo 1:
//   A' = A + dt R_A(A, B) + (DA dt / h^2) L9(A)
// Stable only for 2 DA dt / h^2 < 1 (5-point); the stability test shows the blow-up.
#include "kernels/reaction.h"
#include "runtime/field.h"

namespace ardcell {

struct ExplicitRdParams {
  ReactionParams reaction;
  float dt = 1.0f;
  float diffusion_a = 1.0f;  // DA dt / h^2 multiplies the Laplacian stencil
  float diffusion_b = 0.5f;  // DB dt / h^2
};

// a, b must cover region grown by 1. Outputs must not alias inputs.
void explicit_rd5_tile(View<const float> a, View<const float> b, View<float> a_out,
                       View<float> b_out, Box2 region, const ExplicitRdParams& p);
void explicit_rd9_tile(View<const float> a, View<const float> b, View<float> a_out,
                       View<float> b_out, Box2 region, const ExplicitRdParams& p);

// Seed 001's Gray-Scott step, 9-point Laplacian, specialised for speed: rows are processed as
// a separable (1 4 1) x (1 4 1) sum, L9 = 0.05 * S - 1.8 * c (seed 001's own rewrite), in
// float, in contiguous row buffers the compiler vectorises. Reads halo 1. With the constants
// folded (GrayScott9Coeffs), each multiply-add fused as written:
//   v = fma(4, f(x, y), f(x, y - 1) + f(x, y + 1)),  S = fma(4, v(x), v(x - 1) + v(x + 1))
//   A' = fma(-A, dt B^2, fma(ca, S_A, fma(pa, A, q))),  B' = fma(A, dt B^2, fma(cb, S_B, pb B))
// - the expressions of the temporally blocked kernel (kernels/gray_scott9.h) and of the OpenCL
// twin, so that every schedule, block layout and back end steps seed 001 to the same bits.
struct GrayScott9Params {
  float F = 0.055f, k = 0.062f;
  float dt = 1.0f;
  float diffusion_a = 1.0f;  // DA dt / h^2
  float diffusion_b = 0.5f;  // DB dt / h^2
};
//   ca = 0.05 DA, pa = 1 - 1.8 DA - dt F, q = dt F; cb = 0.05 DB, pb = 1 - 1.8 DB - dt (F + k)
// (in float, unfused: this file is compiled with -ffp-contract=off).
struct GrayScott9Coeffs {
  float ca = 0, cb = 0, pa = 0, pb = 0, q = 0, dt = 0;
};
GrayScott9Coeffs gray_scott9_coeffs(const GrayScott9Params& p);
// scratch: at least 2 * (region.width() + 2) floats (row sums), 64-byte aligned preferred.
void gray_scott9_explicit_tile(View<const float> a, View<const float> b, View<float> a_out,
                               View<float> b_out, Box2 region, const GrayScott9Params& p,
                               float* scratch);

}  // namespace ardcell
