#pragma once
// Stable fluids on one patch of a parametric surface, the MAC grid's operators (seed 004,
// Carvalho et al., after Stam 2003; the seed prints no equation numbers, its sections are cited).
//
// Layout (Sec. 4.1, Fig. 5; Sec. 7.1's arrays): the velocity's contravariant components
// u = u^1 X_1 + u^2 X_2 (X_i = dX/dx^i) sit on the faces of the N x N cells, h = 1/N: u^1 on the
// x1-faces (i - 1/2, j), stored as u1(i, j) for i in [-1, N+1], j in [-1, N] ((N+3) x (N+2)),
// u^2 on the x2-faces (i, j - 1/2), stored as u2(i, j) for i in [-1, N], j in [-1, N+1]. Faces
// 0 and N lie on the patch edges (both patches along an edge store them); the outer ring holds
// ghosts.
//
// Sec. 2 and 4.2, in flux form:
//   div u = 1/sqrt(G) d_i (sqrt(G) u^i):
//     (div u)_ij = (F1(i+1, j) - F1(i, j) + F2(i, j+1) - F2(i, j)) / (sqrt(G)_ij h^2),
//     F1(i, j) = h sqrt(G) u^1 at the face (i - 1/2, j), F2 alike;
//   (grad phi)^i = g^ij d_j phi, on the x1-face (i - 1/2, j):
//     h sqrt(G) (grad phi)^1 = [sqrt(G) g^11] (phi_ij - phi_i-1,j)
//       + [sqrt(G) g^12] (phi_i,j+1 - phi_i,j-1 + phi_i-1,j+1 - phi_i-1,j-1) / 4
//   (and (grad phi)^2 on the x2-faces alike): the flux of grad phi is the Laplace-Beltrami flux
//   of kernels/surface_laplacian.h with the same coefficients, so div grad = lap, the operator
//   the projection inverts, and the projected field's divergence is the solver's residual.
// Sec. 5, viscosity (I - dt nu A) u = u^F, with A here the simplified per-component operator
//   (A u^1)_(i-1/2,j) = (g^11 (u1_i+1,j - 2 u1_ij + u1_i-1,j) + g^22 (u1_i,j+1 - 2 u1_ij +
//   u1_i,j-1)) / h^2 (u^2 alike): the metric's cross term, the derivatives of the metric and the
//   connection terms of the vector Laplacian are dropped; exact for a flat patch, an approximation
//   elsewhere (as in Stam 2003, not the seed's full operator).
//
// Reads: the divergence no ghosts; the gradient phi's ghost ring (corners included); the
// viscosity sweep u's ghost faces; the samplers one ring (any point of the closed unit square).
#include "runtime/field.h"

namespace ardcell {

// The face coefficients of one patch: on the x1-faces [0, N] x [0, N): s1 = sqrt(G),
// a1 = sqrt(G) g^11, b1 = sqrt(G) g^12, and gii1 = g^11, gjj1 = g^22 (the viscosity's); on
// the x2-faces [0, N) x [0, N]: s2, a2 = sqrt(G) g^22, b2 = sqrt(G) g^12, gii2 = g^11,
// gjj2 = g^22; area = sqrt(G) h^2 on the cells [0, N)^2.
struct MacStencil {
  View<const double> s1, a1, b1, gii1, gjj1;
  View<const double> s2, a2, b2, gii2, gjj2;
  View<const double> area;
};

// out = div u on the cells [0, N)^2.
void mac_divergence(View<const double> u1, View<const double> u2, const MacStencil& s,
                    View<double> out, int n);

// u -= grad phi on every face of the patch (edge faces included); phi covers [-1, N]^2.
void mac_subtract_gradient(View<const double> phi, const MacStencil& s, View<double> u1,
                           View<double> u2, int n);

// One Jacobi sweep of the viscosity (I - c A) u = b, c = dt nu, on every face of the patch:
// u_out = (b + c (off-diagonal part of A) u) / (1 - c diag A); returns max |b - (I - c A) u|
// (the residual of u, before the sweep). u covers the ghost faces; b and u_out the patch faces.
double mac_viscosity_sweep(View<const double> u1, View<const double> u2, View<const double> b1,
                           View<const double> b2, const MacStencil& s, double c, View<double> out1,
                           View<double> out2, int n);

// Bilinear interpolation at parameter point (x1, x2) of the closed unit square: of a cell field
// (centres at ((i + 1/2) h, (j + 1/2) h), ghost ring filled), and of u1 and u2 (faces at
// (i h, (j + 1/2) h) and ((i + 1/2) h, j h), ghost faces filled).
double sample_cells(View<const double> f, double x1, double x2, int n);
double sample_u1(View<const double> u1, double x1, double x2, int n);
double sample_u2(View<const double> u2, double x1, double x2, int n);

}  // namespace ardcell
