#include "host/surface/surface_gray_scott.h"

#include <algorithm>
#include <random>

#include "host/surface/surface_multigrid.h"

namespace ardcell {

SurfaceRdParams gray_scott_for_length(double length) {
  SurfaceRdParams p;
  p.diffusion_a = 0.3 * length * length;
  p.diffusion_b = 0.15 * length * length;
  return p;
}

SurfaceGrayScott::SurfaceGrayScott(const SurfaceLaplacian& op, const SurfaceRdParams& params,
                                   const SurfaceMultigrid* multigrid)
    : op_(op),
      multigrid_(multigrid),
      params_(params),
      a_(op.grid().make_field(1.0)),
      b_(op.grid().make_field(0.0)),
      rhs_(op.grid().make_field()) {}

namespace {

// Calls f(c) for every cell c within `radius` (straight-line distance) of a random cell, for
// `spots` random cells drawn from rng.
template <class F>
void for_spot_cells(const PatchGrid& g, const std::array<PatchField, 3>& pos, int spots,
                    double radius, std::mt19937& rng, const F& f) {
  const int n = g.n();
  std::uniform_int_distribution<int> patch(0, g.patches() - 1), cell(0, n - 1);
  for (int s = 0; s < spots; ++s) {
    const std::size_t centre = g.index(patch(rng), cell(rng), cell(rng));
    for (int p = 0; p < g.patches(); ++p)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          const std::size_t c = g.index(p, i, j);
          double d2 = 0;
          for (const PatchField& x : pos) d2 += (x[c] - x[centre]) * (x[c] - x[centre]);
          if (d2 <= radius * radius) f(c);
        }
  }
}

}  // namespace

void SurfaceGrayScott::seed_spots(const std::array<PatchField, 3>& pos, std::uint32_t seed,
                                  int spots, double radius) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  a_.assign(a_.size(), 1.0);
  b_.assign(b_.size(), 0.0);
  for_spot_cells(op_.grid(), pos, spots, radius, rng, [&](std::size_t c) {
    a_[c] = 0.5 * (1 + 0.02 * (unit(rng) - 0.5));
    b_[c] = 0.25 * (1 + 0.02 * (unit(rng) - 0.5));
  });
}

void SurfaceGrayScott::seed_pattern(const std::array<PatchField, 3>& pos, const Start& start) {
  const PatchGrid& g = op_.grid();
  const int n = g.n();
  std::mt19937 rng(start.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  a_.assign(a_.size(), start.background_a);
  b_.assign(b_.size(), start.background_b);
  for_spot_cells(g, pos, start.spots, start.radius, rng, [&](std::size_t c) {
    a_[c] = start.seed_a;
    b_[c] = start.seed_b;
  });
  if (start.noise > 0) {
    const ConcentrationBox box = invariant_box(params_.reaction);
    for (int p = 0; p < g.patches(); ++p)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          const std::size_t c = g.index(p, i, j);
          const double ua = 2 * unit(rng) - 1, ub = 2 * unit(rng) - 1;
          a_[c] = std::clamp(a_[c] * (1 + start.noise * ua), box.a_lo, box.a_hi);
          b_[c] = std::clamp(b_[c] * (1 + start.noise * ub), box.b_lo, box.b_hi);
        }
  }
}

DiffusionReport SurfaceGrayScott::step() {
  const PatchGrid& g = op_.grid();
  const int n = g.n();
  const double dt = params_.dt;
  // The reaction per cell, patches side by side on the operator's executor.
  op_.executor().for_rows(g.patches(), n * n, [&](int p0, int p1) {
    for (int p = p0; p < p1; ++p)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          const std::size_t c = g.index(p, i, j);
          if (params_.scheme == SurfaceReaction::kForwardEuler) {
            double ra, rb;
            reaction_rates(params_.reaction, a_[c], b_[c], ra, rb);
            a_[c] += dt * ra;
            b_[c] += dt * rb;
          } else {
            const ImplicitResult r = implicit_reaction_cell(params_.reaction, dt, a_[c], b_[c]);
            a_[c] = r.a;
            b_[c] = r.b;
          }
        }
  });
  // The reaction's result is the right-hand side and the first guess of each solve.
  rhs_ = a_;
  const DiffusionReport ra = diffuse(a_, dt * params_.diffusion_a);
  rhs_ = b_;
  const DiffusionReport rb = diffuse(b_, dt * params_.diffusion_b);
  return {ra.sweeps + rb.sweeps, ra.cycles + rb.cycles, std::max(ra.residual, rb.residual)};
}

// x from rhs_ (x the first guess).
DiffusionReport SurfaceGrayScott::diffuse(PatchField& x, double c) {
  return multigrid_ ? multigrid_->implicit_diffusion(x, rhs_, c, params_.solve)
                    : op_.implicit_diffusion(x, rhs_, c, params_.solve);
}

}  // namespace ardcell
