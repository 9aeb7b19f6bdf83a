#pragma once
// Semi-Lagrangian advection (Stam 1999; seed 000 Eqn 20):
//   q(x) = q0(x - dt u(x)), bilinear interpolation of q0 at the back-traced point.
// Coordinates are in cells (cell (i, j) has its centre at (i, j)), so the back-trace moves by
// dt/h * u cells. It is clamped to the domain walls [-0.5, n - 0.5] (Stam's clamp), so q0's
// ghost layer (x = -1, x = n) must be filled first; on a periodic domain it wraps instead.
// Reads u, v at the region's cells and q0 over the region grown by ceil(dt/h |u|max) + 1 cells.
// The back-trace is also clamped to q0's view, so an undersized tile halo gives a clamped
// answer, never an out-of-bounds read.
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

}  // namespace ardcell
