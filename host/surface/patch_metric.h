#pragma once
// The metric of every patch on the seed's dense sample grid (seed 004, Sec. 2: g_ij =
// <X_xi, X_xj>, G = det g, g^11 = g_22 / G, g^22 = g_11 / G, g^12 = -g_12 / G; Sec. 4.1 and
// 7.1: a (2N+3) x (2N+3) grid), computed once.
//
// Sample (a, b), 0 <= a, b <= 2N+2, sits at x = ((a - 1) h/2, (b - 1) h/2), h = 1/N: odd
// indices on cell faces and corners, even ones on cell centres, a = 0 and a = 2N+2 on the ghost
// ring half a cell outside. Cell (i, j) (0-based) is sample (2i+2, 2j+2); the face between
// cells i-1 and i is a = 2i+1.
//
// Inside [0,1]^2 the samples are evaluated on the patch. The ghost ring is the neighbour's
// metric carried over by the transition (g and g^-1 as R g R^T, sqrt(G) unchanged: the seed's
// "swap g^11 and g^22 and negate g^12" for odd turns is this for a quarter turn); on a boundary
// edge the edge sample is copied; the four ring corners are the mean of the two ring samples
// beside them (the seed's rule for corner cells). The Laplace-Beltrami stencil reads no ring
// sample; the ring is there for gradient and advection stencils that read the ghost cells.
#include <array>
#include <vector>

#include "host/config/status.h"
#include "host/surface/limit_surface.h"
#include "host/surface/patch_grid.h"
#include "host/surface/patch_topology.h"

namespace ardcell {

struct MetricSample {
  double g11 = 1, g12 = 0, g22 = 1;     // g_ij
  double sqrt_g = 1;                    // sqrt(G)
  double gi11 = 1, gi12 = 0, gi22 = 1;  // g^ij
};

// The metric of the tangents X_x1 = du, X_x2 = dv.
MetricSample metric_from_tangents(const std::array<double, 3>& du, const std::array<double, 3>& dv);

class PatchMetric {
 public:
  PatchMetric() = default;
  PatchMetric(int n, int patches)
      : n_(n), patches_(patches), samples_(std::size_t(patches) * side() * side()) {}

  int n() const { return n_; }
  int patches() const { return patches_; }
  int side() const { return 2 * n_ + 3; }
  MetricSample& at(int p, int a, int b) {
    return samples_[(std::size_t(p) * side() + b) * side() + a];
  }
  const MetricSample& at(int p, int a, int b) const {
    return samples_[(std::size_t(p) * side() + b) * side() + a];
  }
  // The parameter of sample index a.
  double coordinate(int a) const { return (a - 1) * 0.5 / n_; }

  // Fills the ghost ring of every patch from its neighbours (see above).
  void fill_ghost_ring(const PatchTopology& topo);

  // Every sample the Laplace-Beltrami operator reads (cell centres and faces) has a finite,
  // positive sqrt(G); one line naming the first patch and point where not (a degenerate
  // control mesh: coincident vertices, a folded face). The cell corners are not read: at an
  // extraordinary vertex of valence 3 the limit parametrisation has G = 0 there.
  Status check_nondegenerate() const;

 private:
  int n_ = 0, patches_ = 0;
  std::vector<MetricSample> samples_;
};

// Samples the limit surface's metric for N x N cells per patch.
PatchMetric sample_limit_metric(const LimitSurface& surface, int n);

// The limit surface's position at every cell centre, as x, y, z fields (ghosts 0).
std::array<PatchField, 3> cell_positions(const LimitSurface& surface, const PatchGrid& grid);

// Every patch a flat square of side `scale` (g = scale^2 I), for tests.
PatchMetric flat_metric(const PatchTopology& topo, int n, double scale);

}  // namespace ardcell
