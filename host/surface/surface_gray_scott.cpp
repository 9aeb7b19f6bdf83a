#include "host/surface/surface_gray_scott.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <vector>

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
// `spots` random cells drawn from rng, each spot's cells in increasing index (the order of a scan
// over every cell, which f's own draws from rng depend on). The cells are binned once into a
// uniform 3D grid of bins `radius` wide, so a spot tests the cells of the 27 bins around it, not
// every cell (the elephant's 16674 patches: 30 s of scans before).
template <class F>
void for_spot_cells(const PatchGrid& g, const std::array<PatchField, 3>& pos, int spots,
                    double radius, std::mt19937& rng, const F& f) {
  const int n = g.n();
  std::vector<std::size_t> cells;
  cells.reserve(std::size_t(g.patches()) * n * n);
  std::array<double, 3> lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
  for (int p = 0; p < g.patches(); ++p)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const std::size_t c = g.index(p, i, j);
        cells.push_back(c);
        for (int a = 0; a < 3; ++a)
          lo[a] = std::min(lo[a], pos[a][c]), hi[a] = std::max(hi[a], pos[a][c]);
      }
  // Bins of at least `radius` (fewer along an axis when the cells would outnumber them).
  std::array<int, 3> bins;
  const double limit = std::cbrt(double(cells.size())) + 1;
  for (int a = 0; a < 3; ++a) {
    const double extent = hi[a] - lo[a];
    // (1 - 1e-9): a bin a little wider than radius, so that rounding in bin_of never puts a
    // cell at exactly radius two bins away.
    const double count = extent / radius * (1 - 1e-9);
    bins[a] = std::isfinite(count) && count > 1 ? int(std::min(count, limit)) : 1;
  }
  const auto bin_of = [&](int a, double x) {
    const double at = (x - lo[a]) / (hi[a] - lo[a]) * bins[a];
    return bins[a] == 1 || !std::isfinite(at) ? 0 : std::clamp(int(at), 0, bins[a] - 1);
  };
  const auto bin_index = [&](int bx, int by, int bz) {
    return (std::size_t(bz) * bins[1] + std::size_t(by)) * bins[0] + std::size_t(bx);
  };
  // The cells of each bin, contiguous (a counting sort): first[b] .. first[b + 1] in `binned`,
  // in increasing index within a bin.
  const std::size_t bin_count = std::size_t(bins[0]) * std::size_t(bins[1]) * std::size_t(bins[2]);
  std::vector<std::size_t> first(bin_count + 1, 0), binned(cells.size());
  std::vector<std::size_t> bin_of_cell(cells.size());
  for (std::size_t k = 0; k < cells.size(); ++k) {
    const std::size_t c = cells[k];
    bin_of_cell[k] = bin_index(bin_of(0, pos[0][c]), bin_of(1, pos[1][c]), bin_of(2, pos[2][c]));
    ++first[bin_of_cell[k] + 1];
  }
  for (std::size_t b = 1; b < first.size(); ++b) first[b] += first[b - 1];
  {
    std::vector<std::size_t> next(first.begin(), first.end() - 1);
    for (std::size_t k = 0; k < cells.size(); ++k) binned[next[bin_of_cell[k]]++] = cells[k];
  }
  std::uniform_int_distribution<int> patch(0, g.patches() - 1), cell(0, n - 1);
  std::vector<std::size_t> near;
  for (int s = 0; s < spots; ++s) {
    const std::size_t centre = g.index(patch(rng), cell(rng), cell(rng));
    int at[3];
    for (int a = 0; a < 3; ++a) at[a] = bin_of(a, pos[a][centre]);
    near.clear();
    for (int bz = std::max(0, at[2] - 1); bz <= std::min(bins[2] - 1, at[2] + 1); ++bz)
      for (int by = std::max(0, at[1] - 1); by <= std::min(bins[1] - 1, at[1] + 1); ++by)
        for (int bx = std::max(0, at[0] - 1); bx <= std::min(bins[0] - 1, at[0] + 1); ++bx) {
          const std::size_t b = bin_index(bx, by, bz);
          for (std::size_t k = first[b]; k < first[b + 1]; ++k) {
            const std::size_t c = binned[k];
            double d2 = 0;
            for (const PatchField& x : pos) d2 += (x[c] - x[centre]) * (x[c] - x[centre]);
            if (d2 <= radius * radius) near.push_back(c);
          }
        }
    std::sort(near.begin(), near.end());
    for (std::size_t c : near) f(c);
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
