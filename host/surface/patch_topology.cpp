#include "host/surface/patch_topology.h"

#include <string>
#include <unordered_map>

namespace ardcell {
namespace {

// Start corner, direction and outward normal of each edge of the unit square.
constexpr int kCorner[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
constexpr int kDir[4][2] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};
constexpr int kOut[4][2] = {{0, -1}, {1, 0}, {0, 1}, {-1, 0}};

std::array<int, 4> quarter_turn_matrix(int r) {
  switch (r & 3) {
    case 0:
      return {1, 0, 0, 1};
    case 1:
      return {0, -1, 1, 0};
    case 2:
      return {-1, 0, 0, -1};
    default:
      return {0, 1, -1, 0};
  }
}

}  // namespace

std::array<int, 4> EdgeTransition::rotation() const { return quarter_turn_matrix(quarter_turns); }

std::array<double, 2> EdgeTransition::map_point(std::array<double, 2> x) const {
  const auto v = map_vector(x);
  return {v[0] + t[0], v[1] + t[1]};
}

std::array<double, 2> EdgeTransition::map_vector(std::array<double, 2> v) const {
  const auto r = rotation();
  return {r[0] * v[0] + r[1] * v[1], r[2] * v[0] + r[3] * v[1]};
}

std::array<double, 3> EdgeTransition::map_tensor(std::array<double, 3> a) const {
  const auto r = rotation();
  // (R a R^T) with a = [[a11, a12], [a12, a22]].
  const double m00 = r[0] * a[0] + r[1] * a[1], m01 = r[0] * a[1] + r[1] * a[2];
  const double m10 = r[2] * a[0] + r[3] * a[1], m11 = r[2] * a[1] + r[3] * a[2];
  return {m00 * r[0] + m01 * r[1], m00 * r[2] + m01 * r[3], m10 * r[2] + m11 * r[3]};
}

EdgeRingCell edge_ring_cell(int e, int m, int lo, int hi) {
  switch (e) {
    case 0:
      return {m, lo, m, lo + 1};
    case 1:
      return {hi, m, hi - 1, m};
    case 2:
      return {m, hi, m, hi - 1};
    default:
      return {lo, m, lo + 1, m};
  }
}

EdgeTransition make_transition(int neighbour, int e, int f) {
  EdgeTransition tr;
  tr.patch = neighbour;
  tr.edge = f;
  // R = -(d_f d_e^T + o_f o_e^T)
  const int r00 = -(kDir[f][0] * kDir[e][0] + kOut[f][0] * kOut[e][0]);
  const int r01 = -(kDir[f][0] * kDir[e][1] + kOut[f][0] * kOut[e][1]);
  const int r10 = -(kDir[f][1] * kDir[e][0] + kOut[f][1] * kOut[e][0]);
  for (int q = 0; q < 4; ++q) {
    const auto m = quarter_turn_matrix(q);
    if (m[0] == r00 && m[1] == r01 && m[2] == r10) tr.quarter_turns = q;
  }
  const auto m = quarter_turn_matrix(tr.quarter_turns);
  const int rc0 = m[0] * kCorner[e][0] + m[1] * kCorner[e][1];
  const int rc1 = m[2] * kCorner[e][0] + m[3] * kCorner[e][1];
  tr.t = {kCorner[f][0] + kDir[f][0] - rc0, kCorner[f][1] + kDir[f][1] - rc1};
  return tr;
}

std::vector<int> patch_pieces(const PatchTopology& topo) {
  std::vector<int> piece(std::size_t(topo.patches), -1), stack;
  int pieces = 0;
  for (int start = 0; start < topo.patches; ++start) {
    if (piece[std::size_t(start)] >= 0) continue;
    piece[std::size_t(start)] = pieces;
    stack.assign(1, start);
    while (!stack.empty()) {
      const int p = stack.back();
      stack.pop_back();
      for (int e = 0; e < 4; ++e) {
        const int q = topo.transition(p, e).patch;
        if (q >= 0 && piece[std::size_t(q)] < 0) piece[std::size_t(q)] = pieces, stack.push_back(q);
      }
    }
    ++pieces;
  }
  return piece;
}

Status build_patch_topology(const PolyMesh& quads, PatchTopology& out) {
  out = PatchTopology{};
  const int faces = quads.face_count();
  out.patches = faces;
  out.across.assign(std::size_t(4) * faces, EdgeTransition{});
  out.corner_vertex.resize(faces);
  out.valence.assign(quads.points.size(), 0);
  out.boundary_vertex.assign(quads.points.size(), false);
  std::unordered_map<std::uint64_t, int> half_edge;  // directed (a, b) -> 4 face + edge
  half_edge.reserve(std::size_t(4) * faces);
  auto key = [](int a, int b) {
    return (std::uint64_t(std::uint32_t(a)) << 32) | std::uint32_t(b);
  };
  for (int f = 0; f < faces; ++f) {
    if (quads.face_size(f) != 4)
      return Status::error("face " + std::to_string(f + 1) + " is not a quad (" +
                           std::to_string(quads.face_size(f)) + " vertices)");
    const int* v = quads.face(f);
    for (int k = 0; k < 4; ++k) {
      out.corner_vertex[f][k] = v[k];
      ++out.valence[v[k]];
      half_edge[key(v[k], v[(k + 1) % 4])] = 4 * f + k;
    }
  }
  for (int f = 0; f < faces; ++f) {
    const int* v = quads.face(f);
    for (int k = 0; k < 4; ++k) {
      const auto it = half_edge.find(key(v[(k + 1) % 4], v[k]));
      if (it == half_edge.end()) {
        out.boundary_vertex[v[k]] = true;
        out.boundary_vertex[v[(k + 1) % 4]] = true;
        continue;
      }
      out.across[4 * f + k] = make_transition(it->second / 4, k, it->second % 4);
    }
  }
  return Status::ok();
}

PatchPoint locate(const PatchTopology& topo, int p, std::array<double, 2> x) {
  PatchPoint at{p, x, 0};
  for (int crossing = 0; crossing < 3; ++crossing) {
    int e = -1;
    if (at.x[1] < 0)
      e = 0;
    else if (at.x[0] > 1)
      e = 1;
    else if (at.x[1] > 1)
      e = 2;
    else if (at.x[0] < 0)
      e = 3;
    if (e < 0) return at;
    if (crossing == 2) break;
    const EdgeTransition& tr = topo.transition(at.patch, e);
    if (tr.patch < 0) break;
    at.x = tr.map_point(at.x);
    at.patch = tr.patch;
    at.quarter_turns = (at.quarter_turns + tr.quarter_turns) & 3;
  }
  return PatchPoint{};
}

}  // namespace ardcell
