#pragma once
// Reaction-diffusion on a patched surface (seed 004, Sec. 6): two chemicals per cell, the
// reaction per cell, then implicit diffusion of each with the surface's Laplace-Beltrami
// operator:
//   a^L = a^n + dt F(a^n, b^n),  b^L = b^n + dt G(a^n, b^n)       (the seed's forward Euler)
//   (I - dt r_a lap) a^{n+1} = a^L,  (I - dt r_b lap) b^{n+1} = b^L
// (by Jacobi sweeps as the seed does, or by multigrid V-cycles)
// with the seed's Gray-Scott F = -a b^2 + f (1 - a), G = a b^2 - (f + k) b. kImplicit replaces
// the forward Euler reaction by ardcell's per-cell backward Euler (kernels/reaction.h, seed 000
// Eqn 6: any reaction model, unconditionally stable, Kim & Lin's splitting).
//
// Rates are in surface units (area per unit time): the operator carries the metric of the
// limit surface, so the pattern's wavelength is set by r_a, r_b and the surface, not by N.
#include <array>
#include <cstdint>

#include "host/surface/surface_laplacian.h"
#include "kernels/reaction.h"

namespace ardcell {

class SurfaceMultigrid;

enum class SurfaceReaction : std::uint8_t { kForwardEuler, kImplicit };

struct SurfaceRdParams {
  ReactionParams reaction;                        // Gray-Scott F = 0.055, k = 0.062 by default
  double diffusion_a = 1e-3, diffusion_b = 5e-4;  // r_a, r_b: surface area per unit time
  double dt = 1.0;
  SurfaceReaction scheme = SurfaceReaction::kForwardEuler;
  DiffusionSolve solve{1e-6, 500};
};

// The classic flat Gray-Scott's rates (0.3 and 0.15 cells^2 a step, seed 001's 9-point
// scale) for cells of side `length` on the surface.
SurfaceRdParams gray_scott_for_length(double length);

class SurfaceGrayScott {
 public:
  // Keeps a reference to `op` (and to `multigrid`, which then solves the implicit diffusion
  // instead of op's Jacobi sweeps: host/surface/surface_multigrid.h); both must outlive it.
  SurfaceGrayScott(const SurfaceLaplacian& op, const SurfaceRdParams& params,
                   const SurfaceMultigrid* multigrid = nullptr);

  // The seed's start (Sec. 8): a = 1, b = 0, except in random discs where a = 0.5, b = 0.25,
  // each with +-1% noise. The seed draws its discs in the patches' domains, where they stop at
  // patch edges and outline the patches in the grown pattern; here `spots` discs of `radius`
  // (surface units, straight-line distance) are drawn on the surface around random cells,
  // given every cell's position.
  void seed_spots(const std::array<PatchField, 3>& cell_positions, std::uint32_t seed, int spots,
                  double radius);
  // A flat scene's start on the surface (a preset's rd.initial): a and b at the background,
  // `spots` discs of `radius` (surface units) at seed_a, seed_b around random cells, then each
  // cell times 1 +- noise, clamped to the model's invariant box (host/engine/rd_step.cpp's
  // noise).
  struct Start {
    double background_a = 1, background_b = 0, seed_a = 0.5, seed_b = 0.25;
    int spots = 0;
    double radius = 0, noise = 0;
    std::uint32_t seed = 1;
  };
  void seed_pattern(const std::array<PatchField, 3>& cell_positions, const Start& start);
  // One step dt; its two diffusion solves' sweeps and cycles summed, and the worse residual.
  DiffusionReport step();

  PatchField& a() { return a_; }
  PatchField& b() { return b_; }
  const PatchField& a() const { return a_; }
  const PatchField& b() const { return b_; }
  const SurfaceLaplacian& op() const { return op_; }
  const SurfaceRdParams& params() const { return params_; }
  // New parameters from the next step (a live change: rates, step, reaction).
  void set_params(const SurfaceRdParams& params) { params_ = params; }

 private:
  DiffusionReport diffuse(PatchField& x, double c);

  const SurfaceLaplacian& op_;
  const SurfaceMultigrid* multigrid_;
  SurfaceRdParams params_;
  PatchField a_, b_, rhs_;
};

}  // namespace ardcell
