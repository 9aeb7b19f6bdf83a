#include "host/surface/patch_metric.h"

#include <cmath>
#include <cstdio>
#include <string>

namespace ardcell {

MetricSample metric_from_tangents(const std::array<double, 3>& du,
                                  const std::array<double, 3>& dv) {
  MetricSample m;
  m.g11 = du[0] * du[0] + du[1] * du[1] + du[2] * du[2];
  m.g12 = du[0] * dv[0] + du[1] * dv[1] + du[2] * dv[2];
  m.g22 = dv[0] * dv[0] + dv[1] * dv[1] + dv[2] * dv[2];
  const double det = m.g11 * m.g22 - m.g12 * m.g12;
  m.sqrt_g = std::sqrt(det);
  m.gi11 = m.g22 / det;
  m.gi12 = -m.g12 / det;
  m.gi22 = m.g11 / det;
  return m;
}

void PatchMetric::fill_ghost_ring(const PatchTopology& topo) {
  const int last = side() - 1;  // 2N + 2
  for (int p = 0; p < patches_; ++p) {
    for (int e = 0; e < 4; ++e) {
      const EdgeTransition& tr = topo.transition(p, e);
      for (int s = 1; s < last; ++s) {
        // The ring sample (a, b) and the edge sample (ia, ib) inside it.
        const auto [a, b, ia, ib] = edge_ring_cell(e, s, 0, last);
        if (tr.patch < 0) {
          at(p, a, b) = at(p, ia, ib);
          continue;
        }
        // The ring sample's position in the neighbour: an interior sample half a cell inside.
        const auto y = tr.map_point({coordinate(a), coordinate(b)});
        const int qa = int(std::lround(y[0] * 2 * n_ + 1)),
                  qb = int(std::lround(y[1] * 2 * n_ + 1));
        const MetricSample& src = at(tr.patch, qa, qb);
        // Reverse transition (q -> p) carries q's tensors into p's frame.
        const EdgeTransition back = make_transition(p, tr.edge, e);
        MetricSample m;
        const auto g = back.map_tensor({src.g11, src.g12, src.g22});
        const auto gi = back.map_tensor({src.gi11, src.gi12, src.gi22});
        m.g11 = g[0], m.g12 = g[1], m.g22 = g[2];
        m.gi11 = gi[0], m.gi12 = gi[1], m.gi22 = gi[2];
        m.sqrt_g = src.sqrt_g;
        at(p, a, b) = m;
      }
    }
    const int ring[4][2] = {{0, 0}, {last, 0}, {last, last}, {0, last}};
    for (const auto& c : ring) {
      const int a = c[0], b = c[1];
      const MetricSample& m1 = at(p, a == 0 ? 1 : last - 1, b);
      const MetricSample& m2 = at(p, a, b == 0 ? 1 : last - 1);
      MetricSample m;
      m.g11 = 0.5 * (m1.g11 + m2.g11), m.g12 = 0.5 * (m1.g12 + m2.g12);
      m.g22 = 0.5 * (m1.g22 + m2.g22), m.sqrt_g = 0.5 * (m1.sqrt_g + m2.sqrt_g);
      m.gi11 = 0.5 * (m1.gi11 + m2.gi11), m.gi12 = 0.5 * (m1.gi12 + m2.gi12);
      m.gi22 = 0.5 * (m1.gi22 + m2.gi22);
      at(p, a, b) = m;
    }
  }
}

Status PatchMetric::check_nondegenerate() const {
  for (int p = 0; p < patches_; ++p)
    for (int b = 1; b < side() - 1; ++b)
      for (int a = 1; a < side() - 1; ++a) {
        if (a % 2 == 1 && b % 2 == 1) continue;  // a cell corner
        const MetricSample& m = at(p, a, b);
        if (std::isfinite(m.sqrt_g) && m.sqrt_g > 0 && std::isfinite(m.gi11) &&
            std::isfinite(m.gi12) && std::isfinite(m.gi22))
          continue;
        char where[96];
        std::snprintf(where, sizeof where, "patch %d at (%.4g, %.4g)", p + 1, coordinate(a),
                      coordinate(b));
        return Status::error(std::string("the limit surface is degenerate (no tangent plane) in ") +
                             where + ": coincident or folded control points?");
      }
  return Status::ok();
}

PatchMetric sample_limit_metric(const LimitSurface& surface, int n) {
  PatchMetric metric(n, surface.patches());
  const int last = metric.side() - 1;
  LimitSample s;
  for (int p = 0; p < surface.patches(); ++p)
    for (int b = 1; b < last; ++b)
      for (int a = 1; a < last; ++a) {
        surface.evaluate(p, metric.coordinate(a), metric.coordinate(b), s);
        metric.at(p, a, b) = metric_from_tangents(s.du, s.dv);
      }
  metric.fill_ghost_ring(surface.topology());
  return metric;
}

std::array<PatchField, 3> cell_positions(const LimitSurface& surface, const PatchGrid& grid) {
  std::array<PatchField, 3> out{grid.make_field(), grid.make_field(), grid.make_field()};
  const int n = grid.n();
  for (int p = 0; p < grid.patches(); ++p)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const auto x = surface.position(p, (i + 0.5) / n, (j + 0.5) / n);
        for (int k = 0; k < 3; ++k) out[k][grid.index(p, i, j)] = x[k];
      }
  return out;
}

PatchMetric flat_metric(const PatchTopology& topo, int n, double scale) {
  PatchMetric metric(n, topo.patches);
  MetricSample m;
  m.g11 = m.g22 = scale * scale;
  m.sqrt_g = scale * scale;
  m.gi11 = m.gi22 = 1 / (scale * scale);
  for (int p = 0; p < topo.patches; ++p)
    for (int b = 0; b < metric.side(); ++b)
      for (int a = 0; a < metric.side(); ++a) metric.at(p, a, b) = m;
  return metric;
}

}  // namespace ardcell
