// Stable fluids on patched surfaces (host/surface/surface_fluid.h), transport: the MAC ghosts
// are the neighbour's field in this patch's frame, the projection leaves the solver's residual as
// the divergence, free-slip walls on an open surface, a rotation of the torus carries dye once
// around and back and carries itself across patch edges. Forces, viscosity, the dye and workers:
// surface_fluid_forces_test.cpp.
#include "host/surface/surface_fluid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <vector>

#include "host/surface/patch_metric.h"
#include "tests/host/surface/surface_fluid_test_util.h"

namespace ardcell {
namespace {

using namespace surface_fluid_test;

// The contravariant components of a's tangential part, with tangents X_1, X_2.
std::array<double, 2> tangential(const std::array<double, 3>& a, const std::array<double, 3>& x1,
                                 const std::array<double, 3>& x2) {
  const MetricSample m = metric_from_tangents(x1, x2);
  const double d1 = a[0] * x1[0] + a[1] * x1[1] + a[2] * x1[2];
  const double d2 = a[0] * x2[0] + a[1] * x2[1] + a[2] * x2[2];
  return {m.gi11 * d1 + m.gi12 * d2, m.gi12 * d1 + m.gi22 * d2};
}

// Every ghost face, edges and corners: (comp, i, j, point, the corner it is beyond or -1).
template <class F>
void for_ghosts(int n, const F& f) {
  const double h = 1.0 / n;
  const auto at = [&](int c, int i, int j, int corner) {
    f(c, i, j, c == 0 ? i * h : (i + 0.5) * h, c == 0 ? (j + 0.5) * h : j * h, corner);
  };
  for (int j = 0; j < n; ++j) at(0, -1, j, -1), at(0, n + 1, j, -1);
  for (int i = 0; i <= n; ++i) at(0, i, -1, -1), at(0, i, n, -1);
  for (int i = 0; i < n; ++i) at(1, i, -1, -1), at(1, i, n + 1, -1);
  for (int j = 0; j <= n; ++j) at(1, -1, j, -1), at(1, n, j, -1);
  at(0, -1, -1, 0), at(0, n + 1, -1, 1), at(0, n + 1, n, 2), at(0, -1, n, 3);
  at(1, -1, -1, 0), at(1, n, -1, 1), at(1, n, n + 1, 2), at(1, -1, n + 1, 3);
}

// A ghost face is the neighbour's field seen in this patch's frame: with the tangential part of a
// constant vector on every face, each ghost of p at point x (in p's extended plane) holds the
// components of that field in p's frame there, X_p,k = sum_j X_q,j R_jk by the chain rule through
// the transition (tested against the limit surface, not against the exchange's own tables), at
// every edge ghost and every regular corner ghost of a cube-sphere and a torus whose faces meet
// with every quarter turn. Then the round trip: random faces, exchanged; every edge ghost of q,
// carried back across its edge by q's own transition, is the face of p it came from (component
// and sign from that transition's rotation).
TEST(SurfaceFluid, MacGhostsAreTheNeighboursFieldAndRoundTrip) {
  const std::array<double, 3> a{0.3, -0.5, 0.8};
  for (PolyMesh mesh : {cube(), torus()}) {
    const int n = 4;
    auto sim = make_sim(std::move(mesh), n, quiet());
    SurfaceFluid& f = *sim->fluid;
    const PatchTopology& topo = sim->surface.topology();
    LimitSample s;
    for_faces(f.patches(), n, [&](int p, int c, int i, int j, double x0, double x1) {
      sim->surface.evaluate(p, x0, x1, s);
      face(f, p, c, i, j) = tangential(a, s.du, s.dv)[c];
    });
    f.exchange_velocity();
    double worst = 0;
    int checked = 0;
    for (int p = 0; p < f.patches(); ++p)
      for_ghosts(n, [&](int c, int i, int j, double x0, double x1, int corner) {
        if (corner >= 0 && !topo.regular_corner(p, corner)) return;  // extrapolated
        const PatchPoint q = locate(topo, p, {x0, x1});
        ASSERT_GE(q.patch, 0);
        sim->surface.evaluate(q.patch, q.x[0], q.x[1], s);
        EdgeTransition turn;
        turn.quarter_turns = q.quarter_turns;
        const auto r = turn.rotation();
        std::array<double, 3> xp1, xp2;
        for (int k = 0; k < 3; ++k) {
          xp1[k] = s.du[k] * r[0] + s.dv[k] * r[2];
          xp2[k] = s.du[k] * r[1] + s.dv[k] * r[3];
        }
        const double expected = tangential(a, xp1, xp2)[c];
        worst = std::max(worst, std::abs(face(f, p, c, i, j) - expected));
        ++checked;
      });
    EXPECT_LT(worst, 1e-9) << "ghosts checked: " << checked;
    std::printf("patches %d: %d ghost faces, worst %.2g\n", f.patches(), checked, worst);

    random_velocity(f, 11);
    f.exchange_velocity();
    int trips = 0;
    for (int q = 0; q < f.patches(); ++q)
      for_ghosts(n, [&](int c, int i, int j, double x0, double x1, int corner) {
        if (corner >= 0) return;
        const int e = x1 < 0 ? 0 : x0 > 1 ? 1 : x1 > 1 ? 2 : 3;
        const EdgeTransition& tr = topo.transition(q, e);
        ASSERT_GE(tr.patch, 0);
        const auto y = tr.map_point({x0, x1});
        const auto r = tr.rotation();
        const int d = r[c] != 0 ? 0 : 1;  // v_p = R v_q: component c of q is R_dc u_p^d
        const int fi = int(std::lround(d == 0 ? y[0] * n : y[0] * n - 0.5));
        const int fj = int(std::lround(d == 0 ? y[1] * n - 0.5 : y[1] * n));
        EXPECT_EQ(face(f, q, c, i, j), r[2 * d + c] * face(f, tr.patch, d, fi, fj));
        ++trips;
      });
    EXPECT_EQ(trips, f.patches() * 4 * (2 * n + 1));
  }
}

// A random field's divergence is of the order of its size over a cell (|u| N); after the
// projection the divergence left is the Poisson solve's residual (div grad = lap): max |div u|
// over what it was is the solver's relative residual, at most the tolerance 1e-6; a second
// projection changes the field by no more than that. On a surface of two pieces (a cube-sphere
// and a torus) as on one: lap's null space is then a constant on each piece.
TEST(SurfaceFluid, ProjectionRemovesTheDivergence) {
  const char* names[] = {"cube-sphere", "torus", "two pieces"};
  for (int n : {8, 16})
    for (int shape : {0, 1, 2}) {
      auto sim = make_sim(shape == 0 ? cube() : shape == 1 ? torus() : two_pieces(), n, quiet());
      SurfaceFluid& f = *sim->fluid;
      random_velocity(f, 3);
      double largest = 0;
      for (double v : f.velocity()) largest = std::max(largest, std::abs(v));
      const double before = f.max_divergence();
      const FluidReport r = f.project();
      const double after = f.max_divergence();
      std::printf(
          "%s N=%d: max |div u| %.3g (%.2f |u| N) -> %.3g (%.3g of it; solver residual %.3g) "
          "in %d V-cycles\n",
          names[shape], n, before, before / (largest * n), after, after / before, r.residual,
          r.cycles);
      EXPECT_GT(before, 0.5 * largest * n);
      EXPECT_LE(r.residual, f.params().projection.tolerance);
      EXPECT_LE(after, f.params().projection.tolerance * before);
      EXPECT_NEAR(after / before, r.residual, 0.01 * r.residual);
      EXPECT_LE(r.cycles, 40);
      const std::vector<double> once = f.velocity();
      f.project();
      double change = 0, size = 0;
      for (std::size_t k = 0; k < once.size(); ++k) {
        change = std::max(change, std::abs(f.velocity()[k] - once[k]));
        size = std::max(size, std::abs(once[k]));
      }
      EXPECT_LE(change, 1e-4 * size);
    }
}

// The torus's rotation about its axis, sampled as the limit surface's parametric field along the
// ring of 8 patches (1 patch a unit time, every face's component from its patch's orientation),
// carries a blob of dye once around in 8 time units: the error after the full turn falls as N
// grows (8/3 cells a step, 3N steps: bilinear interpolation's diffusion, which grows with the
// number of steps, is what the error measures), and half-way round the blob is elsewhere.
// The seed's trace velocity ubar = g^-1 u (FluidTrace::kSeedInverseMetric; g is far from the
// identity on the torus's patches) does not bring it back.
TEST(SurfaceFluid, RotationCarriesDyeAroundAndBack) {
  double errors[3] = {0, 0, 0};
  int at = 0;
  for (int n : {8, 16, -16}) {  // N = 32: 0.043 (1.9x less again); -16: the seed's trace
    SurfaceFluidParams params = quiet();
    if (n < 0) n = -n, params.trace = FluidTrace::kSeedInverseMetric;
    params.dt = 8.0 / (3 * n);
    auto sim = make_sim(torus(), n, params);
    SurfaceFluid& f = *sim->fluid;
    const LimitSurface& surface = sim->surface;
    torus_rotation(surface, f);
    const PatchGrid& g = f.op().grid();
    const auto positions = cell_positions(surface, g);
    const std::array<double, 3> centre = surface.position(0, 0.5, 0.5);
    PatchField& dye = f.dye();
    for (std::size_t k = 0; k < dye.size(); ++k) {
      const double d2 = std::pow(positions[0][k] - centre[0], 2) +
                        std::pow(positions[1][k] - centre[1], 2) +
                        std::pow(positions[2][k] - centre[2], 2);
      dye[k] = std::exp(-d2);
    }
    const PatchField start = dye;
    const auto error = [&] {
      double e = 0, norm = 0;
      for (int p = 0; p < g.patches(); ++p)
        for (int j = 0; j < n; ++j)
          for (int i = 0; i < n; ++i) {
            const std::size_t k = g.index(p, i, j);
            e += f.op().cell_area(p, i, j) * std::pow(dye[k] - start[k], 2);
            norm += f.op().cell_area(p, i, j) * start[k] * start[k];
          }
      return std::sqrt(e / norm);
    };
    const int steps = int(std::lround(8 / params.dt));
    for (int k = 0; k < steps / 2; ++k) f.advect_dye();
    const double halfway = error();
    for (int k = steps / 2; k < steps; ++k) f.advect_dye();
    errors[at++] = error();
    std::printf(
        "N=%d%s: %d steps, relative L2 error half-way %.3f, after the turn %.4f; "
        "max |div u| of the field %.3g\n",
        n, params.trace == FluidTrace::kSeedInverseMetric ? " (seed's ubar)" : "", steps, halfway,
        errors[at - 1], f.max_divergence());
    EXPECT_GT(halfway, 1.0);
  }
  EXPECT_LT(errors[0], 0.25);
  EXPECT_LT(errors[1], 0.65 * errors[0]);
  EXPECT_GT(errors[2], 0.5);
}

// The velocity advected by itself across patch edges comes back in each patch's own frame (the
// quarter turns of the trace undone): the torus's rigid rotation, 1 patch a unit time, is +-1 on
// one component in every patch whose faces meet with every quarter turn; 6 steps of 8/3 cells
// carry every face's value from the neighbouring patch (one edge crossed, any turn), and the
// field stays itself (bilinear samples of a field constant in each frame: to rounding). A vector
// turned the wrong way round (turns instead of -turns) comes back reversed after an odd turn.
TEST(SurfaceFluid, SelfAdvectedRotationStaysItselfAcrossPatchEdges) {
  for (int n : {8, 16}) {
    SurfaceFluidParams params = quiet();
    params.dt = 8.0 / (3 * n);
    auto sim = make_sim(torus(), n, params);
    SurfaceFluid& f = *sim->fluid;
    torus_rotation(sim->surface, f);
    const std::vector<double> start = f.velocity();
    double worst = 0;
    int faces = 0;
    for (int k = 0; k < 6; ++k) {
      f.advect_velocity();
      for_faces(f.patches(), n, [&](int p, int c, int i, int j, double, double) {
        const double now = face(f, p, c, i, j);
        const double was = c == 0 ? start[&f.u1(p, i, j) - f.velocity().data()]
                                  : start[&f.u2(p, i, j) - f.velocity().data()];
        worst = std::max(worst, std::abs(now - was));
        ++faces;
      });
    }
    std::printf("N=%d: rotation self-advected 6 steps (%d face values): max |u - u0| %.3g\n", n,
                faces, worst);
    EXPECT_LT(worst, 1e-12);
  }
}

// An open surface (the cube-sphere with one quad cut out of its top): the boundary faces carry
// no flux after the projection, the ghosts beyond them mirror the field (the normal component
// reversed: a free-slip wall), and the divergence left is the solver's residual, at the
// boundary cells too.
TEST(SurfaceFluid, OpenSurfaceHasFreeSlipWalls) {
  const int n = 8;
  auto sim = make_sim(open_box(), n, quiet());
  SurfaceFluid& f = *sim->fluid;
  const auto& edges = f.op().grid().boundary_edges();
  ASSERT_EQ(edges.size(), 4u);
  random_velocity(f, 13);
  const double before = f.max_divergence();
  const FluidReport r = f.project();
  const double after = f.max_divergence();
  f.exchange_velocity();
  double wall = 0, mirror = 0, inside = 0;
  for (const auto& [p, e] : edges)
    for (int m = 0; m < n; ++m) {
      // Along edge e: the boundary face (normal component), the ghost beyond it and its mirror,
      // and a tangential ghost with its mirror (the faces at the corners extrapolate).
      double b, g, gm, t, tm;
      switch (e) {
        case 0:
          b = f.u2(p, m, 0), g = f.u2(p, m, -1), gm = -f.u2(p, m, 1);
          t = f.u1(p, m, -1), tm = f.u1(p, m, 0);
          break;
        case 1:
          b = f.u1(p, n, m), g = f.u1(p, n + 1, m), gm = -f.u1(p, n - 1, m);
          t = f.u2(p, n, m), tm = f.u2(p, n - 1, m);
          break;
        case 2:
          b = f.u2(p, m, n), g = f.u2(p, m, n + 1), gm = -f.u2(p, m, n - 1);
          t = f.u1(p, m, n), tm = f.u1(p, m, n - 1);
          break;
        default:
          b = f.u1(p, 0, m), g = f.u1(p, -1, m), gm = -f.u1(p, 1, m);
          t = f.u2(p, -1, m), tm = f.u2(p, 0, m);
          break;
      }
      wall = std::max(wall, std::abs(b));
      mirror = std::max({mirror, std::abs(g - gm), std::abs(t - tm)});
      inside = std::max(inside, std::abs(tm));
    }
  std::printf(
      "open cube-sphere (%d patches, %zu boundary edges): max |div u| %.3g -> %.3g (residual "
      "%.3g, %d V-cycles); boundary flux %.3g, ghosts off their mirror by %.3g\n",
      f.patches(), edges.size(), before, after, r.residual, r.cycles, wall, mirror);
  EXPECT_EQ(wall, 0.0);
  EXPECT_EQ(mirror, 0.0);
  EXPECT_GT(inside, 0.01);  // the wall's tangential flow is not 0
  EXPECT_LE(r.residual, f.params().projection.tolerance);
  EXPECT_LE(after, f.params().projection.tolerance * before);
}

}  // namespace
}  // namespace ardcell
