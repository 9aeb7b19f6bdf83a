#pragma once
// Cell fields over all patches of a surface: N x N cells per patch with one ghost ring
// (seed 004, Sec. 4.1, Fig. 5-6; Sec. 7.1's layout, one (N+2) x (N+2) block per patch), and the
// exchange that fills the ring from the neighbours through the edge transitions.
//
// Edge ghosts are the neighbour's cells (a transition maps cell centres onto cell centres).
// Corner ghosts (the seed: "the average of the two boundary cells adjacent to each corner
// cell"):
//   kSeedAverage         - that average, everywhere;
//   kDiagonalExtrapolate - at a regular corner (an interior vertex of valence 4) the diagonal
//                          patch's cell, exact; at an extraordinary or boundary vertex, where no
//                          cell lies beyond the corner, the bilinear extrapolation
//                          g1 + g2 - c from the two edge ghosts and the corner cell, which is
//                          second-order where the seed's average is first-order.
// A boundary edge (open mesh) copies the cell inside it: no flux through the boundary.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "host/surface/patch_topology.h"
#include "runtime/field.h"

namespace ardcell {

enum class CornerGhosts : std::uint8_t { kSeedAverage, kDiagonalExtrapolate };

using PatchField = std::vector<double>;

class PatchGrid {
 public:
  PatchGrid() = default;
  PatchGrid(const PatchTopology& topo, int n, CornerGhosts corners);

  int n() const { return n_; }
  int patches() const { return patches_; }
  int stride() const { return n_ + 2; }
  std::size_t patch_cells() const { return std::size_t(stride()) * stride(); }
  PatchField make_field(double value = 0) const {
    return PatchField(patch_cells() * patches_, value);
  }
  // Cell (i, j) of patch p, -1 <= i, j <= N.
  std::size_t index(int p, int i, int j) const {
    return p * patch_cells() + std::size_t(j + 1) * stride() + (i + 1);
  }
  View<double> view(PatchField& f, int p) const {
    return View<double>(f.data() + p * patch_cells(), stride(), Box2{{-1, -1}, {n_ + 1, n_ + 1}});
  }
  View<const double> view(const PatchField& f, int p) const {
    return View<const double>(f.data() + p * patch_cells(), stride(),
                              Box2{{-1, -1}, {n_ + 1, n_ + 1}});
  }

  // The mean of the four cells around corner (i, j) of patch p, 0 <= i, j <= N (ghosts included:
  // after an exchange, the patches that share a corner give it the same value).
  double corner_mean(const PatchField& f, int p, int i, int j) const {
    return 0.25 * (f[index(p, i - 1, j - 1)] + f[index(p, i, j - 1)] + f[index(p, i - 1, j)] +
                   f[index(p, i, j)]);
  }

  // Fills every ghost cell (edges, then corners).
  void exchange(PatchField& f) const;
  // Fills patch p's ghost cells only: it reads the neighbours' interiors and its own ghosts, so
  // the patches' exchanges can run side by side (while no interior is written).
  void exchange(PatchField& f, int p) const;

  // The shared patch edges, each once: outward fluxes of the N faces of (p, e) and of (q, f)
  // (the same faces in reverse order). See SurfaceLaplacian.
  struct SharedEdge {
    int p, e, q, f;
  };
  const std::vector<SharedEdge>& shared_edges() const { return shared_; }
  const std::vector<std::pair<int, int>>& boundary_edges() const { return boundary_; }

 private:
  struct Copy {
    std::size_t dst, src;
  };
  struct Corner {
    std::size_t dst, a, b, c;
    double wa, wb, wc;
  };
  int n_ = 0, patches_ = 0;
  std::vector<Copy> copies_;
  std::vector<Corner> corners_;
  std::vector<SharedEdge> shared_;
  std::vector<std::pair<int, int>> boundary_;
};

}  // namespace ardcell
