#pragma once
// Semi-Lagrangian advection (Stam 1999; seed 000 Eqn 20):
//   q(x) = q0(x - dt u(x - dt/2 u(x))), bilinear interpolation of q0 (and of u at the midpoint).
// The back-trace uses the midpoint rule (RK2): Euler's x - dt u(x) maps a vortex outward and
// loses (omega dt)^2 of the mass per step; the midpoint rule's error is fourth order in omega dt.
// Coordinates are in cells (cell (i, j) has its centre at (i, j)), so the back-trace moves by
// dt/h * u cells. It is clamped to the domain walls [-0.5, n - 0.5] (Stam's clamp), so the ghost
// layers of q0, u and v (x = -1, x = n) must be filled first; on a periodic domain it wraps.
// Reads q0, u and v over the region grown by ceil(dt/h |u|max) + 1 cells. Every sample is also
// clamped to the views, so an undersized tile halo gives a clamped answer, never an
// out-of-bounds read.
#include <span>

#include "runtime/field.h"

namespace ardcell {

struct AdvectParams {
  float dt_over_h = 0.0f;  // back-trace length in cells per unit velocity
  Int2 domain{};           // domain size in cells
  bool periodic = false;   // wrap the back-trace (whole fields) instead of clamping at walls
};

// q = q0 carried by (u, v) over region. q must not alias q0.
void advect_scalar(View<const float> q0, View<const float> u, View<const float> v, View<float> q,
                   Box2 region, const AdvectParams& params);

// Self-advection of the velocity: (u, v) = (u0, v0) at x - dt (u0, v0)(x). Outputs must not
// alias inputs.
void advect_velocity(View<const float> u0, View<const float> v0, View<float> u, View<float> v,
                     Box2 region, const AdvectParams& params);

// Several scalars carried by one velocity: q[i] = q0[i] at x - dt (u, v)(x - dt/2 (u, v)(x)),
// the back-trace and its bilinear weights computed once per cell and applied to every field.
// Bit for bit the same as advect_scalar(q0[i], u, v, q[i]) for each i when all q0 views have
// one box (the clamps depend on the views' common box); with q0 = {u, v} and outputs {u', v'}
// it is advect_velocity. Vectorised (AVX2 gathers, 8 cells at a time) where the build targets
// AVX2 and FMA and the domain is not periodic; the arithmetic is the scalar kernel's, operation
// for operation, so both paths agree exactly. At most kMaxAdvectFields fields; outputs must not
// alias inputs.
inline constexpr int kMaxAdvectFields = 4;
void advect_fields(View<const float> u, View<const float> v, std::span<const View<const float>> q0,
                   std::span<const View<float>> q, Box2 region, const AdvectParams& params);

// The same for a scalar carried by the MAC face velocities of the projection
// (kernels/project.h face_velocities): uf(i, j) on the face between cells (i-1, j) and (i, j),
// vf(i, j) between (i, j-1) and (i, j). Their bilinear interpolant is exactly divergence-free
// when the face fluxes are, so dye and chemicals keep their mass (the cell-centred velocity of
// the approximate projection is divergence-free only to O(h^2), and loses mass steadily).
// Tangential face components are clamped at the walls (no ghost rows needed); on a periodic
// whole field uf needs its ghost rows -1 and ny, vf its ghost columns -1 and nx (wrapped).
// Reads q0, uf, vf over the region grown by ceil(dt/h |u|max) + 1.
void advect_scalar_mac(View<const float> q0, View<const float> uf, View<const float> vf,
                       View<float> q, Box2 region, const AdvectParams& params);

// MacCormack's correction with its limiter (Selle, Fedkiw, Kim, Liu & Rossignac, "An
// Unconditionally Stable MacCormack Method", J. Sci. Comput. 35, 2008): after the forward
// semi-Lagrangian step q_hat = A(q0) and the backward one q_back = A^R(q_hat) (the same advection
// with dt negated),
//   q = q_hat + (q0 - q_back) / 2,
// which cancels the leading error of A: second order where the field is smooth. The limiter
// clamps q to the range of the four cells of q0 that A interpolated between at this cell's
// departure point, so the correction creates no new extremum and the scheme keeps A's
// unconditional stability. (Selle et al. also revert to q_hat instead of clamping; the clamp
// keeps q continuous in q_hat, q0 and q_back. The bounds themselves jump where the departure
// point crosses a cell edge, so two back ends that round a back-trace differently can differ
// there by up to the local variation of q0.)
// u, v: the velocity of the forward step (cell-centred, as advect_fields). Reads q0, u, v over
// the region grown by ceil(dt/h |u|max) + 1, q_hat and q_back over the region. q[i] may be
// q_hat[i] (each cell reads only its own q_hat); it must not alias q0 or q_back.
void maccormack_correct(View<const float> u, View<const float> v,
                        std::span<const View<const float>> q0,
                        std::span<const View<const float>> q_hat,
                        std::span<const View<const float>> q_back, std::span<const View<float>> q,
                        Box2 region, const AdvectParams& params);

// The same for a scalar carried by the MAC face velocities (advect_scalar_mac's departure point).
void maccormack_correct_mac(View<const float> q0, View<const float> q_hat, View<const float> q_back,
                            View<const float> uf, View<const float> vf, View<float> q, Box2 region,
                            const AdvectParams& params);

}  // namespace ardcell
