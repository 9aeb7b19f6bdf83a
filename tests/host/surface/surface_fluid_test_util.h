#pragma once
// Shared by the surface fluid tests: a fluid on a procedural surface, the test meshes, the
// torus's rotation as a parametric field, and visitors of the MAC faces.
#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "host/surface/patch_metric.h"
#include "host/surface/procedural_mesh.h"
#include "host/surface/surface_fluid.h"
#include "runtime/row_executor.h"

namespace ardcell::surface_fluid_test {

struct Sim {
  LimitSurface surface;
  std::unique_ptr<SurfaceLaplacian> op;
  std::unique_ptr<SurfaceMultigrid> mg;
  std::unique_ptr<SurfaceFluid> fluid;
};

inline std::unique_ptr<Sim> make_sim(PolyMesh mesh, int n, const SurfaceFluidParams& params,
                                     RowExecutor* executor = nullptr) {
  auto s = std::make_unique<Sim>();
  // A surface that does not build fails the test (gtest reports the exception).
  if (const Status built = LimitSurface::build(std::move(mesh), {}, s->surface); !built)
    throw std::runtime_error("make_sim: " + built.message());
  const PatchMetric metric = sample_limit_metric(s->surface, n);
  s->op = std::make_unique<SurfaceLaplacian>(s->surface.topology(), metric);
  if (executor) s->op->set_executor(*executor);
  s->mg = std::make_unique<SurfaceMultigrid>(s->surface, *s->op);
  s->fluid = std::make_unique<SurfaceFluid>(s->surface, metric, *s->op, *s->mg, params);
  return s;
}

inline SurfaceFluidParams quiet() {
  SurfaceFluidParams p;
  p.force = FluidForce::kNone;
  p.source_rate = 0;
  return p;
}

inline PolyMesh cube() { return rotate_faces(cube_mesh(2), 5); }
inline PolyMesh torus() { return rotate_faces(torus_mesh(8, 4, 2.0, 0.8), 3); }

// A cube and a torus beside it: a surface in two pieces.
inline PolyMesh two_pieces() {
  PolyMesh two = cube_mesh(1);
  const PolyMesh other = torus_mesh(4, 3, 2.0, 0.8);
  const int base = int(two.points.size());
  for (const auto& q : other.points) two.points.push_back({q[0] + 5, q[1], q[2]});
  for (int f = 0; f < other.face_count(); ++f) {
    const int* v = other.face(f);
    two.add_face({v[0] + base, v[1] + base, v[2] + base, v[3] + base});
  }
  return two;
}

// The cube-sphere's control mesh with one quad of its top taken out: an open surface whose
// boundary (4 edges) runs through an extraordinary corner.
inline PolyMesh open_box() {
  const PolyMesh cube = cube_mesh(2);
  PolyMesh open;
  open.points = cube.points;
  bool cut = false;
  for (int f = 0; f < cube.face_count(); ++f) {
    const int* v = cube.face(f);
    bool top = true;
    for (int c = 0; c < 4; ++c) top = top && cube.points[std::size_t(v[c])][2] > 0.99;
    if (top && !cut) {
      cut = true;
      continue;
    }
    open.add_face({v[0], v[1], v[2], v[3]});
  }
  return rotate_faces(open, 5);
}

// The rigid rotation of the torus about its axis as the limit surface's parametric field along
// the ring of 8 patches: on every face (ghosts included) the component along the patch's
// around-direction is +-1 (1 patch a unit time), the other 0.
inline void torus_rotation(const LimitSurface& surface, SurfaceFluid& f) {
  const int n = f.n();
  LimitSample s;
  for (int p = 0; p < f.patches(); ++p) {
    surface.evaluate(p, 0.5, 0.5, s);
    const double rho = std::hypot(s.p[0], s.p[1]);
    const std::array<double, 3> around{-s.p[1] / rho, s.p[0] / rho, 0};
    const auto unit_dot = [&](const std::array<double, 3>& t) {
      return (t[0] * around[0] + t[1] * around[1]) / std::hypot(t[0], t[1], t[2]);
    };
    const double a1 = unit_dot(s.du), a2 = unit_dot(s.dv);
    const double v[2] = {std::abs(a1) > std::abs(a2) ? std::copysign(1.0, a1) : 0.0,
                         std::abs(a1) > std::abs(a2) ? 0.0 : std::copysign(1.0, a2)};
    for (int j = -1; j <= n; ++j)
      for (int i = -1; i <= n + 1; ++i) f.u1(p, i, j) = v[0], f.u2(p, j, i) = v[1];
  }
}

// Visits every patch face (not the ghosts): comp 0 the x1-faces, 1 the x2-faces, with their
// point.
template <class F>
void for_faces(int patches, int n, const F& f) {
  const double h = 1.0 / n;
  for (int p = 0; p < patches; ++p) {
    for (int j = 0; j < n; ++j)
      for (int i = 0; i <= n; ++i) f(p, 0, i, j, i * h, (j + 0.5) * h);
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i < n; ++i) f(p, 1, i, j, (i + 0.5) * h, j * h);
  }
}

// The dye's smallest and largest cell (not the ghosts).
inline std::array<double, 2> dye_range(const SurfaceFluid& f) {
  const PatchGrid& g = f.op().grid();
  double lo = INFINITY, hi = -INFINITY;
  for (int p = 0; p < g.patches(); ++p)
    for (int j = 0; j < g.n(); ++j)
      for (int i = 0; i < g.n(); ++i) {
        lo = std::min(lo, f.dye()[g.index(p, i, j)]);
        hi = std::max(hi, f.dye()[g.index(p, i, j)]);
      }
  return {lo, hi};
}

inline double& face(SurfaceFluid& f, int p, int comp, int i, int j) {
  return comp == 0 ? f.u1(p, i, j) : f.u2(p, i, j);
}

inline void random_velocity(SurfaceFluid& f, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for_faces(f.patches(), f.n(),
            [&](int p, int c, int i, int j, double, double) { face(f, p, c, i, j) = u(rng); });
  f.stitch_velocity();
}

}  // namespace ardcell::surface_fluid_test
