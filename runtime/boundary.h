#pragma once
// Boundary fills: the one layer of ghost cells around a domain of `domain` cells (x = -1,
// x = nx, y = -1, y = ny), and the solid cells of an obstacle mask.
//
// Coordinates: cell (i, j) has its centre at ((i + 0.5) h, (j + 0.5) h); y grows upward, so the
// "top" wall is the ghost row y = ny (the cavity's moving lid) and "bottom" is y = -1.
//
// Tile-local fills: every fill takes a View (a whole field or a tile copied into a local store)
// and writes only the ghost cells of the domain that lie inside the view's box, reading only
// cells inside the view. So a tile at a domain edge can refill its own boundary after each
// Jacobi sweep, and the result equals the same cells of a whole-field fill. Periodic edges read
// the opposite side of the domain: on a tile they are skipped (the runtime's DMA wraps instead).
#include <cstdint>

#include "runtime/field.h"

namespace ardcell {

// The four sides of the domain (y grows upward: bottom is j = 0, top is j = ny - 1), in the
// order of BoundaryFill's members.
enum class BoundarySide : uint8_t { kLeft, kRight, kBottom, kTop };

enum class EdgeRule : uint8_t {
  kCopy,       // ghost = nearest interior cell: zero normal derivative (Neumann); Stam's b = 0
  kFixed,      // ghost = value: Dirichlet on the ghost cell centre (outflow pressure p = 0)
  kMirror,     // ghost = 2 value - nearest interior: Dirichlet `value` on the wall face itself.
               // value 0 is Stam's negation (normal velocity at a wall, no-slip); value U is a
               // moving lid or an inflow speed
  kPeriodic,   // ghost = the cell one domain width away (wrap)
  kParabolic,  // ghost = 2 U - nearest interior: a Poiseuille profile of mean `value` on the wall
               // face, U = value * parabolic_profile(k, n) at the k-th of the side's n cells
};

// 6 s (1 - s) at s = (k + 1/2) / n: the profile of a channel's laminar inflow, mean 1 over the
// side (max 1.5 at its middle). In float, in this order, as the OpenCL twin (kernels/cl/fluid.cl).
inline float parabolic_profile(int k, int n) {
  const float s = (float(k) + 0.5f) / float(n);
  return 6.0f * s * (1.0f - s);
}

struct EdgeFill {
  EdgeRule rule = EdgeRule::kCopy;
  float value = 0.0f;
};

// One rule per side. Corner ghost cells are the average of their two edge neighbours (Stam),
// or wrap when both axes are periodic.
struct BoundaryFill {
  EdgeFill left, right, bottom, top;  // x = -1, x = nx, y = -1, y = ny

  static BoundaryFill all(EdgeFill e) { return {e, e, e, e}; }
  static BoundaryFill copy() { return all({EdgeRule::kCopy, 0.0f}); }
  static BoundaryFill fixed(float value) { return all({EdgeRule::kFixed, value}); }
  static BoundaryFill periodic() { return all({EdgeRule::kPeriodic, 0.0f}); }
  // Stam's set_bnd(b): b = 0 copy everywhere; b = 1 (u) negated at left/right walls, copied at
  // bottom/top; b = 2 (v) negated at bottom/top, copied at left/right.
  static BoundaryFill stam(int b);
  // No-slip walls for one velocity component, with the top wall moving at `lid` (tangential
  // component only: pass lid = 0 for v).
  static BoundaryFill no_slip(float lid = 0.0f);
};

// Fills the ghost cells of the domain [0, domain) that lie inside f.box(). Reads only f.
void fill_boundary(View<float> f, Int2 domain, const BoundaryFill& fill);

// Shorthand for fill_boundary(f, domain, BoundaryFill::stam(b)).
void set_bnd(View<float> f, Int2 domain, int b);

enum class ObstacleRule : uint8_t {
  kCopy,    // solid cell = mean of its fluid 4-neighbours (Neumann at obstacle faces: p, dye)
  kNoSlip,  // solid cell = -mean of its fluid 4-neighbours: velocity zero on the faces
  kZero,    // solid cell = 0
};

// Sets every solid cell (solid(x, y) != 0) of `region` from its fluid 4-neighbours; solid cells
// with no fluid neighbour become 0. Only solid cells are written and only fluid cells are read,
// so the result does not depend on the order. Reads f and solid over region grown by 1, which
// both views must contain.
void fill_obstacle(View<float> f, View<const uint8_t> solid, Box2 region, ObstacleRule rule);

}  // namespace ardcell
