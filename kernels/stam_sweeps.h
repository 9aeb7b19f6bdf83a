#pragma once
// Stam's lin_solve sweeps for (c I - a sum of the 4 neighbours) x = x0 with constant
// coefficients: implicit diffusion (a = dt nu / h^2, c = 1 + 4a) and the pressure Poisson
// equation (a = 1, c = 4, x0 = the pressure_rhs of kernels/project.h). These are the tile
// kernels of the Table 1 workload ("diffuse 20 Jacobi sweeps, project 20 sweeps"); the caller
// refills the domain boundary (runtime/boundary.h) after each sweep.
// Reads x over the region grown by 1 (the 4 neighbours) and x0 over the region.
#include "runtime/field.h"

namespace ardcell {

struct StamSweepParams {
  float a = 0.0f;      // neighbour weight
  float inv_c = 1.0f;  // 1 / diagonal
};

// One Jacobi sweep: x_out = (x0 + a (x_in(-1,0) + x_in(+1,0) + x_in(0,-1) + x_in(0,+1))) / c.
// x_out must not alias x_in.
void stam_jacobi_sweep(View<const float> x0, View<const float> x_in, View<float> x_out, Box2 region,
                       const StamSweepParams& params);

// Half a red-black Gauss-Seidel sweep in place: the cells of region with (x + y) % 2 == color
// (global coordinates, so tiles agree on the colouring). A full sweep is color 0 then 1, with a
// boundary fill after each half when the region touches the domain edge.
void stam_rbgs_half_sweep(View<const float> x0, View<float> x, Box2 region, int color,
                          const StamSweepParams& params);

}  // namespace ardcell
