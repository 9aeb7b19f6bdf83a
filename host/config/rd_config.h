#pragma once
// Parameters of the reaction-diffusion half of a scene (Kim & Lin). Plain data, like
// FluidConfig. Owned by the RD solver (host/engine/rd_step.h).
//
// Units: the RD runs with its own step rd.dt (0: the scene's dt) and cell size rd.cell_size
// (0: the scene's h), so that Pearson's and seed 001's parameters apply unchanged; the
// chemicals are advected by the fluid with the scene's dt and h (Eqn 20).
#include <cstdint>

#include "kernels/anisotropy.h"
#include "kernels/generalized_diffusion.h"
#include "kernels/generalized_rd.h"
#include "kernels/linear_solver.h"
#include "kernels/reaction.h"
#include "kernels/stencil_operator.h"

namespace ardcell {

enum class RdScheme : uint8_t {
  kImplicit,      // Eqns 6 + 19 (+ 20): unconditionally stable (the paper); with the generalized
                  // operator, Eqn 6 then the periodic solve of (I - dt D K) (seed 003, Eqn 28)
  kExplicit5,     // forward Euler, 5-point Laplacian (Eqn 5)
  kExplicit9,     // forward Euler, seed 001's 9-point Laplacian
  kExplicit,      // generalized operator: forward Euler, seed 003's Eqn 27
  kSemiImplicit,  // generalized operator: explicit reaction, implicit diffusion (seed 003, Eqn 28)
  // The second-order schemes (docs/numerics.md, "Reaction-diffusion in time"), Laplacian only:
  kCrankNicolsonAm2,  // Strang: trapezoidal reaction dt/2 (Newton per cell, like Eqn 6), Crank-
                      // Nicolson diffusion dt, trapezoidal reaction dt/2 (sec. 3.2's suggestion)
  kSbdf2,             // IMEX: BDF2 diffusion with the implicit solvers, reaction extrapolated
                      // 2 f^n - f^(n-1); an SBDF1 step first and after every restart
  kEtdrk4,            // exponential time differencing RK4 by FFT (periodic, isotropic)
};

// What diffuses the chemicals.
enum class RdOperator : uint8_t {
  kLaplacian,    // Kim & Lin: the 5-point (an)isotropic Laplacian, Eqns 13-19
  kGeneralized,  // McGraw (seed 003): the 25-point non-Gaussian operator of a tensor sequence,
                 // on a periodic (tileable) grid
};

// seed 003's operator: D_A K and D_B K with K the 25-point stencil of `tensors` (Eqns 19-21, 37;
// kernels/generalized_diffusion.h), derivatives of ranks 3 and 4 by Savitzky-Golay filters.
struct GeneralizedRdConfig {
  TensorSequence tensors = kTable2A;
  int savitzky_golay_degree = 4;  // 4, or 5 (minimum-norm pseudo-inverse)
  SecondDerivatives second_derivatives = SecondDerivatives::kCentralDifference;
  // Table 1's last row at rank 2: a per-cell tensor D(x) = d_along e e^T + d_across (I - e e^T)
  // in place of the sequence (kernels/generalized_rd.h rank2_tensor_field; the rank-3 and rank-4
  // components 0; semi-implicit and implicit solve by BiCGSTAB, kernels/tensor_field_solve.h).
  // kUniform: the homogeneous sequence above.
  TensorFieldKind field = TensorFieldKind::kUniform;
  double d_along = 1.0, d_across = 0.25;  // in the domain's units, like the sequence
};

enum class RdInitialPattern : uint8_t {
  kUniform,       // A = background_a, B = background_b everywhere (plus noise)
  kCentreSquare,  // Pearson: a central square of (seed_a, seed_b), side seed_size * width
  kSeedSquare,    // seed 001: a square of seed_cells x seed_cells cells at the centre
  kRandomSpots,   // `spots` discs of (seed_a, seed_b), radius seed_radius cells
  kStripe,        // a vertical band of (seed_a, seed_b) at the left (waves, Barkley)
  kCentreDisc,    // a disc of (seed_a, seed_b), radius seed_radius cells, at the grid's centre
};

struct RdConfig {
  bool enabled = false;

  // Reaction (Eqn 6, Appendix A).
  ReactionParams reaction;
  // Gray-Scott's parameter map (seed 003, Fig. 6): F runs linearly from reaction.F at the left
  // edge to map_f at the right, k from reaction.k at the bottom to map_k at the top, so one
  // image shows every pattern of the range (the generalized operator's explicit and
  // semi-implicit schemes).
  bool map = false;
  float map_f = 0.0f, map_k = 0.0f;
  bool react = true;       // false: passive chemicals (the "advection only" columns)
  bool use_table = false;  // precomputed implicit update (kernels/reaction_table.h)
  int table_resolution = 256;
  bool table_range_auto = true;  // true: the model's typical range
  ConcentrationBox table_range{0, 1, 0, 1};

  // Diffusion (Eqns 13-19, or seed 003's generalized operator).
  bool diffuse = true;
  RdOperator diffusion_operator = RdOperator::kLaplacian;
  GeneralizedRdConfig generalized;
  double diffusion_a = 1.0;     // D_A in cell_size^2 per unit of rd.dt
  double diffusion_b = 0.5;     // D_B
  AnisotropyParams anisotropy;  // k = a(theta); A's rate D_A k, B's rate D_B k
  // false: Eqn 14 as printed, a(theta) replaces A's diffusion constant only and B keeps its
  // isotropic rate D_B (Eqn 3). With the same k on both chemicals a Turing pattern can settle
  // into a stretched copy of its isotropic steady state and stop moving (Fig. 3 bottom).
  bool anisotropy_on_b = true;
  SolverSettings diffusion_solver{SolverKind::kIccg, 40, 1e-6};
  BoundaryKind boundary = BoundaryKind::kDirichlet;  // the paper's choice
  float boundary_a = 1.0f;                           // Dirichlet ghost values of A and B
  float boundary_b = 0.0f;
  bool crank_nicolson = false;

  // Advection by the fluid (Eqn 20), when the scene has a fluid.
  bool advect = true;

  // Time stepping.
  RdScheme scheme = RdScheme::kImplicit;
  double dt = 0.0;         // RD step; 0: the scene's dt
  double cell_size = 0.0;  // h of the RD; 0: the scene's h
  int steps_per_frame = 1;

  // Initial conditions.
  RdInitialPattern initial = RdInitialPattern::kCentreSquare;
  float background_a = 1.0f, background_b = 0.0f;
  float seed_a = 0.5f, seed_b = 0.25f;
  double seed_size = 0.1;  // kCentreSquare: side as a fraction of the width
  int seed_cells = 10;     // kSeedSquare: side in cells
  int spots = 12;          // kRandomSpots
  double seed_radius = 4;  // kRandomSpots, kCentreDisc: radius in cells
  double noise = 0.01;     // relative noise (Pearson: +-1%)
  uint64_t seed = 1;       // random seed of the noise and spots
};

}  // namespace ardcell
