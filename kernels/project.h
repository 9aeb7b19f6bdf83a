#pragma once
// Pressure projection of the collocated velocity (Stam 1999), in two tile kernels around a
// Poisson solve:
//   rhs = -h^2 div u = -h/2 (u(x+1) - u(x-1) + v(y+1) - v(y-1))
//   solve 4 p - (sum of the 4 neighbours) = rhs    (the 5-point operator: identity 0, scale 1)
//   u -= (p(x+1) - p(x-1)) / (2h),  v -= (p(y+1) - p(y-1)) / (2h)
// Read as a MAC scheme, the face velocities (u(x) + u(x+1)) / 2 - (p(x+1) - p(x)) / h are
// exactly divergence-free when p solves the 5-point equation (walls: u ghost mirrored so the wall
// face carries the wall velocity, p ghost copied); the cell-centred u is their consistent
// average (an approximate projection: its central divergence is O(h^2) for smooth flow).
// Both kernels read their inputs over the region grown by 1 (ghosts filled first).
#include "runtime/field.h"

namespace ardcell {

struct ProjectParams {
  float h = 1.0f;  // cell size
};

// rhs = -h^2 div(u, v) over region (central differences).
void pressure_rhs(View<const float> u, View<const float> v, View<float> rhs, Box2 region,
                  const ProjectParams& params);

// The cut-cell right-hand side (weights of kernels/stencil_operator.h weigh_faces): each face's
// mean velocity weighed by its open fraction, so the face fluxes open * ((u_a + u_b) / 2 -
// (p_b - p_a) / h) sum to zero on every cell when p solves the weighted equation; a solid face
// moves nothing. Open fractions: open_x (nx + 1) x ny (face between x - 1 and x), open_y nx x
// (ny + 1). Reads u, v over the region grown by 1 and the open fractions of its cells' faces.
//   rhs = -h/2 (ox(x+1) (u(x) + u(x+1)) - ox(x) (u(x-1) + u(x))
//               + oy(y+1) (v(y) + v(y+1)) - oy(y) (v(y-1) + v(y)))
void pressure_rhs_cut(View<const float> u, View<const float> v, View<const float> open_x,
                      View<const float> open_y, View<float> rhs, Box2 region,
                      const ProjectParams& params);

// (u, v) -= grad p over region (central differences).
void subtract_gradient(View<const float> p, View<float> u, View<float> v, Box2 region,
                       const ProjectParams& params);

// The divergence-free MAC face velocities of the projection, from the velocity BEFORE
// subtract_gradient and the solved pressure (ghosts filled):
//   uf(i, j) = (u(i-1, j) + u(i, j)) / 2 - (p(i, j) - p(i-1, j)) / h   (face between i-1 and i)
//   vf(i, j) = (v(i, j-1) + v(i, j)) / 2 - (p(i, j) - p(i, j-1)) / h
// for the faces of the region's cells: uf for i in [min.x, max.x] (both ends) and rows
// [min.y, max.y), vf for j in [min.y, max.y] and columns [min.x, max.x); without `top_faces`, vf
// row max.y is left out (it belongs to the band of rows above: bands of rows then write disjoint
// faces). Reads u, v, p over the region grown by 1.
void face_velocities(View<const float> u, View<const float> v, View<const float> p, View<float> uf,
                     View<float> vf, Box2 region, const ProjectParams& params,
                     bool top_faces = true);

}  // namespace ardcell
