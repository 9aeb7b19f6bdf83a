#include "host/surface/procedural_mesh.h"

#include <cmath>
#include <map>
#include <numbers>

namespace ardcell {

PolyMesh cube_mesh(int k) {
  PolyMesh m;
  std::map<std::array<int, 3>, int> ids;  // lattice point (in units of 2/k) -> vertex
  auto vertex = [&](std::array<int, 3> q) {
    auto [it, added] = ids.emplace(q, int(m.points.size()));
    if (added) m.points.push_back({2.0 * q[0] / k - 1, 2.0 * q[1] / k - 1, 2.0 * q[2] / k - 1});
    return it->second;
  };
  // Each face: a fixed axis at 0 or k and two in-face axes (u, v) with u x v outward.
  struct Side {
    int axis, at, u, v;
  };
  const Side sides[6] = {{0, 0, 2, 1}, {0, 1, 1, 2}, {1, 0, 0, 2},
                         {1, 1, 2, 0}, {2, 0, 1, 0}, {2, 1, 0, 1}};
  for (const Side& s : sides)
    for (int b = 0; b < k; ++b)
      for (int a = 0; a < k; ++a) {
        auto point = [&](int da, int db) {
          std::array<int, 3> q{};
          q[s.axis] = s.at * k;
          q[s.u] = a + da;
          q[s.v] = b + db;
          return vertex(q);
        };
        m.add_face({point(0, 0), point(1, 0), point(1, 1), point(0, 1)});
      }
  return m;
}

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
