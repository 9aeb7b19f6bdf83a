#include "host/surface/procedural_mesh.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <set>

namespace ardcell {

namespace {

// A side of an axis-aligned cube: the fixed axis, at its low (0) or high (1) end, and two
// in-face axes (u, v) with u x v outward.
struct CubeSide {
  int axis, at, u, v;
};
constexpr CubeSide kCubeSides[6] = {{0, 0, 2, 1}, {0, 1, 1, 2}, {1, 0, 0, 2},
                                    {1, 1, 2, 0}, {2, 0, 1, 0}, {2, 1, 0, 1}};

}  // namespace

PolyMesh box_mesh(int nx, int ny, int nz) {
  const std::array<int, 3> cells{nx, ny, nz};
  const double unit = 2.0 / std::max({nx, ny, nz});
  PolyMesh m;
  std::map<std::array<int, 3>, int> ids;  // lattice point -> vertex
  auto vertex = [&](std::array<int, 3> q) {
    auto [it, added] = ids.emplace(q, int(m.points.size()));
    if (added)
      m.points.push_back(
          {unit * (q[0] - 0.5 * nx), unit * (q[1] - 0.5 * ny), unit * (q[2] - 0.5 * nz)});
    return it->second;
  };
  for (const CubeSide& s : kCubeSides)
    for (int b = 0; b < cells[std::size_t(s.v)]; ++b)
      for (int a = 0; a < cells[std::size_t(s.u)]; ++a) {
        auto point = [&](int da, int db) {
          std::array<int, 3> q{};
          q[std::size_t(s.axis)] = s.at * cells[std::size_t(s.axis)];
          q[std::size_t(s.u)] = a + da;
          q[std::size_t(s.v)] = b + db;
          return vertex(q);
        };
        m.add_face({point(0, 0), point(1, 0), point(1, 1), point(0, 1)});
      }
  return m;
}

PolyMesh cube_mesh(int k) { return box_mesh(k, k, k); }

PolyMesh torus_mesh(int around, int tube, double R, double r) {
  PolyMesh m;
  const double two_pi = 2 * std::numbers::pi;
  for (int a = 0; a < around; ++a)
    for (int t = 0; t < tube; ++t) {
      const double phi = two_pi * a / around, theta = two_pi * t / tube;
      const double rho = R + r * std::cos(theta);
      m.points.push_back({rho * std::cos(phi), rho * std::sin(phi), r * std::sin(theta)});
    }
  auto id = [&](int a, int t) { return (a % around) * tube + (t % tube); };
  for (int a = 0; a < around; ++a)
    for (int t = 0; t < tube; ++t)
      m.add_face({id(a, t), id(a + 1, t), id(a + 1, t + 1), id(a, t + 1)});
  return m;
}

PolyMesh genus2_mesh(double size) {
  using Cell = std::array<int, 3>;
  std::set<Cell> cubes;
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 5; ++x)
      if (!(y == 1 && (x == 1 || x == 3))) cubes.insert({x, y, 0});
  PolyMesh m;
  std::map<Cell, int> ids;
  auto vertex = [&](Cell q) {
    auto [it, added] = ids.emplace(q, int(m.points.size()));
    if (added) m.points.push_back({size * (q[0] - 2.5), size * (q[1] - 1.5), size * (q[2] - 0.5)});
    return it->second;
  };
  // Every side of a cube that no other cube covers is a face of the surface.
  for (const Cell& c : cubes)
    for (const CubeSide& s : kCubeSides) {
      Cell beyond = c;
      beyond[std::size_t(s.axis)] += s.at ? 1 : -1;
      if (cubes.count(beyond)) continue;
      auto point = [&](int du, int dv) {
        Cell q = c;
        q[std::size_t(s.axis)] += s.at;
        q[std::size_t(s.u)] += du;
        q[std::size_t(s.v)] += dv;
        return vertex(q);
      };
      m.add_face({point(0, 0), point(1, 0), point(1, 1), point(0, 1)});
    }
  return m;
}

PolyMesh rotate_faces(const PolyMesh& mesh, std::uint32_t seed) {
  PolyMesh out = mesh;
  std::uint32_t state = seed * 2654435761u + 1;
  for (int f = 0; f < mesh.face_count(); ++f) {
    state = state * 1664525u + 1013904223u;
    const int n = mesh.face_size(f), shift = int(state >> 30) % n;
    for (int k = 0; k < n; ++k)
      out.face_vertices[out.face_offsets[f] + k] = mesh.face(f)[(k + shift) % n];
  }
  return out;
}

}  // namespace ardcell
