#pragma once
// The diffusion propagator of a tensor sequence (the displacement pdf; Fig. 1's polar plots),
// seed 003 (McGraw):
//   seed 003, Eqn 23: p_tau(r) = N(0, 2 tau D2)(r) (1 + Q3/3! . H3(r) + Q4/4! . H4(r))
//   seed 003, Eqn 24: Q(n) = (-1)^n n! tau D(n)   =>  Q3/3! = -tau D3,  Q4/4! = +tau D4
//   seed 003, Eqn 38: the Hermite tensor polynomials of the appendix, built here by Grad's
//     recurrence H_{a S} = x_a H_S - sum_{b in S} delta_ab H_{S \ b} (the reference [33] the
//     appendix cites). "." is the full contraction, over the unique components with their
//     multiplicities (Eqn 18).
// Correction: the printed H4 ends with "- 3 delta_ijkl"; the Hermite tensor's constant term is
// + (delta_ij delta_kl + delta_ik delta_jl + delta_il delta_jk). In 1D that is He4 = x^4 - 6 x^2
// + 3, not - 3; and H_xxyy = (x^2 - 1)(y^2 - 1) has constant + 1, not 0. Only the corrected
// form is orthogonal to 1 under the unit Gaussian (E[He4] = 3 - 6 + 3 = 0), which is what
// makes Eqn 23 integrate to one as the text claims. Table 2's rank-3 and rank-4 tensors are
// traceless, so the printed constant only adds -3 tau (D_xxxx + D_yyyy) N(r): -6 tau N for (d),
// +6 tau N for (e), (f); the same lobe angles, but (d) would integrate to 1 - 6 tau.
// As printed, H(n)(r) takes r itself (not r standardised by S = 2 tau D2, which would use
// S^-1 for delta); ardcell follows that. Where D2 = I the traceless tensors still integrate to
// zero; (f) (D2 = diag(1, 2)) integrates to 1 - 0.12 tau (tests/kernels/gram_charlier_test.cpp).
// Pure functions, no field: nothing to read around a cell.
#include <span>
#include <vector>

#include "kernels/generalized_diffusion.h"

namespace ardcell {

// H^(n) component with nx x indices and ny y indices (n = nx + ny <= 4) at (x, y).
double hermite_tensor(int nx, int ny, double x, double y);

// The full contraction D(n) . H(n)(x, y) = sum_{nx + ny = n} mu D_{nx ny} H_{nx ny}(x, y).
double contract_with_hermite(const TensorSequence& d, int rank, double x, double y);

// p_tau(r) of Eqn 23 at r = (x, y).
double gram_charlier_propagator(const TensorSequence& d, double tau, double x, double y);

// p_tau at radius |r| = radius, at angles theta_k = 2 pi k / out.size() from the +x axis
// (counter-clockwise towards +y): the samples of a Fig. 1 polar plot.
void propagator_on_circle(const TensorSequence& d, double tau, double radius,
                          std::span<double> out);

// The directions of a polar plot's lobes: the local maxima of the circular sequence samples
// (theta_k = 2 pi k / samples.size()) that are above zero, in degrees in [0, 360), refined by a
// parabola through the three samples around each, in increasing order. Empty for a flat curve
// (an isotropic propagator has no preferred direction) or one with a non-finite sample.
std::vector<double> polar_maxima_degrees(std::span<const double> samples);

}  // namespace ardcell
