#include "host/surface/coarse_aggregation.h"

#include <algorithm>
#include <cmath>

#include "runtime/check.h"

namespace ardcell {

namespace {

// For each patch, the patches that share a corner vertex with it (itself included), ascending.
std::vector<std::vector<int>> vertex_neighbours(const PatchTopology& topo) {
  std::vector<std::vector<int>> around(topo.valence.size());
  for (int p = 0; p < topo.patches; ++p)
    for (int v : topo.corner_vertex[std::size_t(p)]) around[std::size_t(v)].push_back(p);
  std::vector<std::vector<int>> near(std::size_t(topo.patches));
  for (int p = 0; p < topo.patches; ++p) {
    std::vector<int>& n = near[std::size_t(p)];
    for (int v : topo.corner_vertex[std::size_t(p)])
      n.insert(n.end(), around[std::size_t(v)].begin(), around[std::size_t(v)].end());
    std::sort(n.begin(), n.end());
    n.erase(std::unique(n.begin(), n.end()), n.end());
  }
  return near;
}

void size_vectors(SparseLevel& l) {
  l.b.assign(std::size_t(l.cells), 0.0);
  l.x.assign(std::size_t(l.cells), 0.0);
  l.r.assign(std::size_t(l.cells), 0.0);
}

}  // namespace

SparseLevel probe_patch_level(const SurfaceLaplacian& op, const PatchTopology& topo,
                              const std::vector<int>& pieces) {
  const PatchGrid& g = op.grid();
  ARDCELL_CHECK(g.n() == 1 && g.patches() == topo.patches,
                "probe_patch_level: a grid of one cell a patch of this topology");
  const int n = topo.patches;
  const std::vector<std::vector<int>> near = vertex_neighbours(topo);
  // Distance-2 colouring: q takes the least colour that no patch near a patch near q has.
  std::vector<int> colour(std::size_t(n), -1), seen;
  int colours = 0;
  for (int q = 0; q < n; ++q) {
    seen.assign(std::size_t(colours) + 1, 0);
    for (int r : near[std::size_t(q)])
      for (int t : near[std::size_t(r)])
        if (colour[std::size_t(t)] >= 0) seen[std::size_t(colour[std::size_t(t)])] = 1;
    int c = 0;
    while (seen[std::size_t(c)]) ++c;
    colour[std::size_t(q)] = c;
    colours = std::max(colours, c + 1);
  }
  SparseLevel l;
  l.cells = n;
  l.start.assign(std::size_t(n) + 1, 0);
  for (int r = 0; r < n; ++r)
    l.start[std::size_t(r) + 1] = l.start[std::size_t(r)] + int(near[std::size_t(r)].size());
  l.col.resize(std::size_t(l.start.back()));
  l.lap.assign(l.col.size(), 0.0);
  for (int r = 0; r < n; ++r)
    std::copy(near[std::size_t(r)].begin(), near[std::size_t(r)].end(),
              l.col.begin() + l.start[std::size_t(r)]);
  PatchField unit = g.make_field(), lap = g.make_field();
  for (int c = 0; c < colours; ++c) {
    std::fill(unit.begin(), unit.end(), 0.0);
    for (int q = 0; q < n; ++q)
      if (colour[std::size_t(q)] == c) unit[g.index(q, 0, 0)] = 1;
    op.apply(unit, lap);
    for (int r = 0; r < n; ++r)
      for (int k = l.start[std::size_t(r)]; k < l.start[std::size_t(r) + 1]; ++k)
        if (colour[std::size_t(l.col[std::size_t(k)])] == c)
          l.lap[std::size_t(k)] = lap[g.index(r, 0, 0)];
  }
  l.area.resize(std::size_t(n));
  for (int p = 0; p < n; ++p) l.area[std::size_t(p)] = op.cell_area(p, 0, 0);
  l.piece = pieces;
  size_vectors(l);
  return l;
}

SparseLevel aggregate_level(SparseLevel& fine) {
  const int n = fine.cells;
  std::vector<int>& agg = fine.coarse;
  agg.assign(std::size_t(n), -1);
  int count = 0;
  // A cell whose neighbours are all free seeds an aggregate of itself and them.
  for (int i = 0; i < n; ++i) {
    if (agg[std::size_t(i)] >= 0) continue;
    bool free = true;
    for (int k = fine.start[std::size_t(i)]; k < fine.start[std::size_t(i) + 1] && free; ++k)
      free = agg[std::size_t(fine.col[std::size_t(k)])] < 0;
    if (!free) continue;
    for (int k = fine.start[std::size_t(i)]; k < fine.start[std::size_t(i) + 1]; ++k)
      agg[std::size_t(fine.col[std::size_t(k)])] = count;
    agg[std::size_t(i)] = count++;
  }
  // The others join the aggregate of the neighbour most strongly coupled to them.
  for (int i = 0; i < n; ++i) {
    if (agg[std::size_t(i)] >= 0) continue;
    int best = -1;
    double strongest = -1;
    for (int k = fine.start[std::size_t(i)]; k < fine.start[std::size_t(i) + 1]; ++k) {
      const int j = fine.col[std::size_t(k)];
      if (j != i && agg[std::size_t(j)] >= 0 && std::abs(fine.lap[std::size_t(k)]) > strongest) {
        strongest = std::abs(fine.lap[std::size_t(k)]);
        best = agg[std::size_t(j)];
      }
    }
    agg[std::size_t(i)] = best >= 0 ? best : count++;
  }
  // The Galerkin operator, a coarse row at a time: its cells' rows weighted by their areas,
  // their columns gathered by aggregate.
  SparseLevel c;
  c.cells = count;
  c.area.assign(std::size_t(count), 0.0);
  c.piece.assign(std::size_t(count), 0);
  std::vector<int> first(std::size_t(count) + 1, 0);
  std::vector<int> members(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) ++first[std::size_t(agg[std::size_t(i)]) + 1];
  for (int I = 0; I < count; ++I) first[std::size_t(I) + 1] += first[std::size_t(I)];
  std::vector<int> fill(first.begin(), first.end() - 1);
  for (int i = 0; i < n; ++i) members[std::size_t(fill[std::size_t(agg[std::size_t(i)])]++)] = i;
  std::vector<double> row(std::size_t(count), 0.0);
  std::vector<int> touched;
  c.start.assign(1, 0);
  for (int I = 0; I < count; ++I) {
    touched.clear();
    double area = 0;
    for (int m = first[std::size_t(I)]; m < first[std::size_t(I) + 1]; ++m) {
      const int i = members[std::size_t(m)];
      const double a = fine.area[std::size_t(i)];
      area += a;
      c.piece[std::size_t(I)] = fine.piece[std::size_t(i)];
      for (int k = fine.start[std::size_t(i)]; k < fine.start[std::size_t(i) + 1]; ++k) {
        const int J = agg[std::size_t(fine.col[std::size_t(k)])];
        if (std::find(touched.begin(), touched.end(), J) == touched.end()) touched.push_back(J);
        row[std::size_t(J)] += a * fine.lap[std::size_t(k)];
      }
    }
    std::sort(touched.begin(), touched.end());
    c.area[std::size_t(I)] = area;
    // An aggregate with no neighbour holds a whole piece: its row is lap's of a constant, 0 but
    // for rounding, which a sweep would divide by. It is exactly 0 (the sweeps leave such a
    // cell alone; the bordered solve fixes its constant).
    const bool alone = touched.size() == 1;
    for (int J : touched) {
      c.col.push_back(J);
      c.lap.push_back(alone ? 0.0 : row[std::size_t(J)] / area);
      row[std::size_t(J)] = 0;
    }
    c.start.push_back(int(c.col.size()));
  }
  size_vectors(c);
  return c;
}

void sparse_sweeps(const SparseLevel& l, double a, double s, int sweeps) {
  for (int sweep = 0; sweep < sweeps; ++sweep) {
    for (int i = 0; i < l.cells; ++i) {
      double m_x = a * l.x[std::size_t(i)], diagonal = a, off = 0;
      for (int k = l.start[std::size_t(i)]; k < l.start[std::size_t(i) + 1]; ++k) {
        const int j = l.col[std::size_t(k)];
        const double e = s * l.lap[std::size_t(k)];
        m_x += e * l.x[std::size_t(j)];
        if (j == i)
          diagonal += e;
        else
          off += std::abs(e);
      }
      const double d = diagonal < 0 ? diagonal - off : diagonal + off;
      // A row of zeros (a piece of one cell: a lone patch, or an aggregate holding its piece)
      // has nothing to solve in the Poisson problem: x stays.
      l.r[std::size_t(i)] =
          d == 0 ? l.x[std::size_t(i)] : l.x[std::size_t(i)] + (l.b[std::size_t(i)] - m_x) / d;
    }
    std::swap(l.x, l.r);
  }
}

void sparse_residual(const SparseLevel& l, double a, double s) {
  for (int i = 0; i < l.cells; ++i) {
    double m_x = a * l.x[std::size_t(i)];
    for (int k = l.start[std::size_t(i)]; k < l.start[std::size_t(i) + 1]; ++k)
      m_x += s * l.lap[std::size_t(k)] * l.x[std::size_t(l.col[std::size_t(k)])];
    l.r[std::size_t(i)] = l.b[std::size_t(i)] - m_x;
  }
}

}  // namespace ardcell
