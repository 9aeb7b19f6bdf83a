#include "host/surface/patch_grid.h"

#include <cmath>

namespace ardcell {

PatchGrid::PatchGrid(const PatchTopology& topo, int n, CornerGhosts corners)
    : n_(n), patches_(topo.patches) {
  const double h = 1.0 / n;
  auto cell_of = [&](double x) { return int(std::lround(x * n - 0.5)); };
  for (int p = 0; p < patches_; ++p) {
    for (int e = 0; e < 4; ++e) {
      const EdgeTransition& tr = topo.transition(p, e);
      if (tr.patch < 0)
        boundary_.push_back({p, e});
      else if (p < tr.patch || (p == tr.patch && e < tr.edge))
        shared_.push_back({p, e, tr.patch, tr.edge});
      for (int m = 0; m < n; ++m) {
        // Ghost (gi, gj) outside edge e and the cell (ii, ij) inside it.
        const auto [gi, gj, ii, ij] = edge_ring_cell(e, m, -1, n);
        if (tr.patch < 0) {
          copies_.push_back({index(p, gi, gj), index(p, ii, ij)});
          continue;
        }
        const auto y = tr.map_point({(gi + 0.5) * h, (gj + 0.5) * h});
        copies_.push_back({index(p, gi, gj), index(tr.patch, cell_of(y[0]), cell_of(y[1]))});
      }
    }
    for (int k = 0; k < 4; ++k) {
      const int ci = (k == 1 || k == 2) ? n - 1 : 0, cj = (k >= 2) ? n - 1 : 0;
      const int gi = (k == 1 || k == 2) ? n : -1, gj = (k >= 2) ? n : -1;
      const std::size_t dst = index(p, gi, gj);
      const std::size_t a = index(p, ci, gj), b = index(p, gi, cj), c = index(p, ci, cj);
      if (corners == CornerGhosts::kDiagonalExtrapolate && topo.regular_corner(p, k)) {
        const PatchPoint at = locate(topo, p, {(gi + 0.5) * h, (gj + 0.5) * h});
        if (at.patch >= 0) {
          corners_.push_back(
              {dst, index(at.patch, cell_of(at.x[0]), cell_of(at.x[1])), a, c, 1.0, 0.0, 0.0});
          continue;
        }
      }
      if (corners == CornerGhosts::kSeedAverage)
        corners_.push_back({dst, a, b, c, 0.5, 0.5, 0.0});
      else
        corners_.push_back({dst, a, b, c, 1.0, 1.0, -1.0});
    }
  }
}

void PatchGrid::exchange(PatchField& f) const {
  for (int p = 0; p < patches_; ++p) exchange(f, p);
}

// The constructor lays the copies out patch by patch (4 edges of n ghosts) and the corners four
// a patch; a corner reads its own patch's edge ghosts, filled just before.
void PatchGrid::exchange(PatchField& f, int p) const {
  const std::size_t per_patch = 4 * std::size_t(n_);
  for (std::size_t k = p * per_patch; k < (p + 1) * per_patch; ++k)
    f[copies_[k].dst] = f[copies_[k].src];
  for (std::size_t k = 4 * std::size_t(p); k < 4 * std::size_t(p) + 4; ++k) {
    const Corner& c = corners_[k];
    f[c.dst] = c.wa * f[c.a] + c.wb * f[c.b] + c.wc * f[c.c];
  }
}

}  // namespace ardcell
