#pragma once
// The Laplace-Beltrami operator on one patch of a parametric surface, in flux form, and the
// Jacobi sweep of implicit diffusion with it (seed 004, Carvalho et al.).
//
// Sec. 2 (unnumbered; the seed prints no equation numbers):
//   lap phi = 1/sqrt(G) d/dx^i ( sqrt(G) g^ij d phi / dx^j )
// Sec. 4.2, its 9-point discretisation on an N x N cell grid (h = 1/N): the flux through the
// face between cells i-1 and i (and its x2 twin)
//   f1(i, j) = h sqrt(G) (g^11 dphi/dx1 + g^12 dphi/dx2) at (i - 1/2, j)
//            = [sqrt(G) g^11] (phi_ij - phi_i-1,j)
//              + [sqrt(G) g^12] (phi_i,j+1 - phi_i,j-1 + phi_i-1,j+1 - phi_i-1,j-1) / 4
//   f2(i, j) = [sqrt(G) g^22] (phi_ij - phi_i,j-1)
//              + [sqrt(G) g^12] (phi_i+1,j - phi_i-1,j + phi_i+1,j-1 - phi_i-1,j-1) / 4
//   (lap phi)_ij = (f1(i+1, j) - f1(i, j) + f2(i, j+1) - f2(i, j)) / (sqrt(G)_ij h^2)
// The printed dphi/dx2 at (i - 1/2, j) averages columns i-1 and i+1, which centres it on i, not
// on the face; the columns i-1 and i used here are the face's own.
// Sec. 6, implicit diffusion: (I - dt r lap) phi' = phi.
//
// Reads phi with a halo of 1 (the ghost ring, corners included); the coefficients in brackets
// are per face, sqrt(G) per cell, precomputed from the metric (PatchStencil).
#include "runtime/field.h"

namespace ardcell {

// One patch's coefficients: ax = sqrt(G) g^11 and bx = sqrt(G) g^12 on the x1-faces
// [0, N] x [0, N); ay = sqrt(G) g^22 and by = sqrt(G) g^12 on the x2-faces [0, N) x [0, N];
// area = sqrt(G) h^2 on the cells [0, N)^2.
struct PatchStencil {
  View<const double> ax, bx, ay, by, area;
};

// f1 on [0, N] x [0, N) and f2 on [0, N) x [0, N]; phi covers [-1, N]^2.
void surface_face_fluxes(View<const double> phi, const PatchStencil& s, View<double> f1,
                         View<double> f2, int n);

// out = (f1(i+1, j) - f1(i, j) + f2(i, j+1) - f2(i, j)) / area over [0, N)^2.
void surface_flux_divergence(View<const double> f1, View<const double> f2, View<const double> area,
                             View<double> out, int n);

// The diagonal of lap: -(ax(i,j) + ax(i+1,j) + ay(i,j) + ay(i,j+1)) / area.
void surface_laplacian_diagonal(const PatchStencil& s, View<double> diag, int n);

// One Jacobi sweep of (I - c lap) x = b from lap x (computed from x by the two kernels above):
//   r = b - x + c lap x,  x' = x + r / (1 - c diag),   per cell (x_out may be x);
// returns max |r| over the patch (the residual of x, before the sweep). diag is lap's diagonal
// (plain Jacobi), or minus its row's absolute sum (the l1 smoother of multigrid).
double surface_jacobi_update(View<const double> b, View<const double> lap_x,
                             View<const double> diag, View<const double> x, View<double> x_out,
                             double c, int n);

}  // namespace ardcell
