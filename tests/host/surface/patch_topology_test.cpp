// Edge transitions: the round trip across every edge is the identity, for points and vectors;
// the limit surface and its metric agree across every edge after the transition.
#include "host/surface/patch_topology.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "host/surface/limit_surface.h"
#include "host/surface/patch_metric.h"
#include "host/surface/procedural_mesh.h"

namespace ardcell {
namespace {

void expect_round_trip(const EdgeTransition& there, const EdgeTransition& back) {
  for (double x : {-0.25, 0.0, 0.3, 1.0, 1.2})
    for (double y : {-0.1, 0.5, 1.0}) {
      const auto p = back.map_point(there.map_point({x, y}));
      EXPECT_NEAR(p[0], x, 1e-15);
      EXPECT_NEAR(p[1], y, 1e-15);
      const auto v = back.map_vector(there.map_vector({x, y}));
      EXPECT_EQ(v[0], x);
      EXPECT_EQ(v[1], y);
    }
}

TEST(EdgeTransition, RoundTripIsTheIdentityForEveryEdgePair) {
  for (int e = 0; e < 4; ++e)
    for (int f = 0; f < 4; ++f) {
      const EdgeTransition there = make_transition(1, e, f);
      expect_round_trip(there, make_transition(0, f, e));
      // The shared edge maps onto the neighbour's edge, reversed; outside goes inside.
      const double s = 0.3;
      double c[4][2] = {{s, 0}, {1, s}, {1 - s, 1}, {0, 1 - s}};
      const double g[4][2] = {{1 - s, 0}, {1, 1 - s}, {s, 1}, {0, s}};
      const auto y = there.map_point({c[e][0], c[e][1]});
      EXPECT_NEAR(y[0], g[f][0], 1e-15) << e << " " << f;
      EXPECT_NEAR(y[1], g[f][1], 1e-15) << e << " " << f;
    }
}

// The seed's Sec. 2: the point map across edge e_i into the neighbour's edge e_j is
// phi_<e_i,e_j> o T_e_i with <e_i, e_j> = (4 + e_i - (e_j + 2) % 4) % 4, which is ours. Its
// Jacobian, which carries vectors, is a rotation by -<e_i,e_j> quarter turns: the printed
// "M_i = R_{i pi/2}, counterclockwise" turns the wrong way for odd i.
TEST(EdgeTransition, PointMapIsTheSeedsAndItsJacobianTurnsClockwise) {
  using Map = std::array<double, 2> (*)(double, double);
  const Map phi[4] = {[](double x, double y) {
                        return std::array<double, 2>{x, y};
                      },
                      [](double x, double y) {
                        return std::array<double, 2>{y, 1 - x};
                      },
                      [](double x, double y) {
                        return std::array<double, 2>{1 - x, 1 - y};
                      },
                      [](double x, double y) {
                        return std::array<double, 2>{1 - y, x};
                      }};
  const Map shift[4] = {[](double x, double y) {
                          return std::array<double, 2>{x, y + 1};
                        },
                        [](double x, double y) {
                          return std::array<double, 2>{x - 1, y};
                        },
                        [](double x, double y) {
                          return std::array<double, 2>{x, y - 1};
                        },
                        [](double x, double y) {
                          return std::array<double, 2>{x + 1, y};
                        }};
  for (int e = 0; e < 4; ++e)
    for (int f = 0; f < 4; ++f) {
      const int t = (4 + e - (f + 2) % 4) % 4;
      const EdgeTransition tr = make_transition(1, e, f);
      for (double x : {-0.1, 0.3, 1.1})
        for (double y : {-0.2, 0.6, 1.05}) {
          const auto s = shift[e](x, y);
          const auto want = phi[t](s[0], s[1]);
          const auto got = tr.map_point({x, y});
          EXPECT_NEAR(got[0], want[0], 1e-15);
          EXPECT_NEAR(got[1], want[1], 1e-15);
        }
      EXPECT_EQ(tr.quarter_turns, (4 - t) % 4) << e << " " << f;
    }
}

TEST(PatchTopology, NeighboursAgreeOnEveryEdge) {
  for (const PolyMesh& mesh :
       {rotate_faces(cube_mesh(2), 7), rotate_faces(torus_mesh(8, 6, 2, 0.7), 3)}) {
    PatchTopology topo;
    ASSERT_TRUE(build_patch_topology(mesh, topo));
    for (int p = 0; p < topo.patches; ++p)
      for (int e = 0; e < 4; ++e) {
        const EdgeTransition& tr = topo.transition(p, e);
        ASSERT_GE(tr.patch, 0);
        const EdgeTransition& back = topo.transition(tr.patch, tr.edge);
        EXPECT_EQ(back.patch, p);
        EXPECT_EQ(back.edge, e);
        EXPECT_EQ((tr.quarter_turns + back.quarter_turns) % 4, 0);
        expect_round_trip(tr, back);
      }
  }
}

// Max over edge points of |X_p - X_q| and the relative metric jump |g_p - R^T g_q R| / |g_p|,
// binned by the parameter distance d from the nearest extraordinary corner.
struct Continuity {
  double position = 0;
  double metric_far = 0;     // d >= 1/4 (and everywhere on a surface without extraordinary corners)
  double metric_mid = 0;     // 1/16 <= d < 1/4
  double metric_near = 0;    // 1/64 <= d < 1/16
  double metric_vertex = 0;  // d < 1/64
};

Continuity measure(const LimitSurface& s) {
  const PatchTopology& topo = s.topology();
  Continuity c;
  const int samples = 256;
  LimitSample a, b;
  for (int p = 0; p < topo.patches; ++p)
    for (int e = 0; e < 4; ++e) {
      const EdgeTransition& tr = topo.transition(p, e);
      const EdgeTransition back = make_transition(p, tr.edge, e);
      for (int k = 0; k < samples; ++k) {
        const double t = (k + 0.5) / samples;
        const double edge_pt[4][2] = {{t, 0}, {1, t}, {1 - t, 1}, {0, 1 - t}};
        const std::array<double, 2> x{edge_pt[e][0], edge_pt[e][1]};
        const auto y = tr.map_point(x);
        s.evaluate(p, x[0], x[1], a);
        s.evaluate(tr.patch, y[0], y[1], b);
        for (int i = 0; i < 3; ++i) c.position = std::max(c.position, std::abs(a.p[i] - b.p[i]));
        const MetricSample mp = metric_from_tangents(a.du, a.dv);
        const MetricSample mq = metric_from_tangents(b.du, b.dv);
        const auto g = back.map_tensor({mq.g11, mq.g12, mq.g22});
        const double scale = std::max(mp.g11, mp.g22);
        const double err =
            std::max({std::abs(g[0] - mp.g11), std::abs(g[1] - mp.g12), std::abs(g[2] - mp.g22)}) /
            scale;
        // Distance to the nearer end of the edge, when that end is extraordinary.
        const int k0 = e, k1 = (e + 1) % 4;
        double d = 1;
        if (!topo.regular_corner(p, k0)) d = std::min(d, t);
        if (!topo.regular_corner(p, k1)) d = std::min(d, 1 - t);
        double& bin = d >= 0.25       ? c.metric_far
                      : d >= 1.0 / 16 ? c.metric_mid
                      : d >= 1.0 / 64 ? c.metric_near
                                      : c.metric_vertex;
        bin = std::max(bin, err);
      }
    }
  return c;
}

TEST(LimitSurfaceContinuity, TorusIsContinuousEverywhere) {
  LimitSurface s;
  ASSERT_TRUE(LimitSurface::build(rotate_faces(torus_mesh(8, 6, 2, 0.7), 11), {}, s));
  const Continuity c = measure(s);
  std::printf("torus 8x6: position %.2e, metric %.2e\n", c.position, c.metric_far);
  EXPECT_LT(c.position, 1e-12);
  EXPECT_LT(c.metric_far, 1e-6);
  EXPECT_EQ(c.metric_near + c.metric_vertex, 0.0);
}

TEST(LimitSurfaceContinuity, CubeSphereAwayFromExtraordinaryVertices) {
  for (int level : {2, 4, 6, 8}) {
    LimitSurfaceOptions opt;
    opt.approx_level = level;
    LimitSurface s;
    ASSERT_TRUE(LimitSurface::build(rotate_faces(cube_mesh(2), 5), opt, s));
    const Continuity c = measure(s);
    std::printf(
        "cube-sphere k=2, Bfr approximation level %d: position %.2e; metric jump "
        "d >= 1/4: %.2e, [1/16, 1/4): %.2e, [1/64, 1/16): %.2e, d < 1/64: %.2e\n",
        level, c.position, c.metric_far, c.metric_mid, c.metric_near, c.metric_vertex);
    EXPECT_LT(c.position, 1e-12);
    EXPECT_LT(c.metric_far, 1e-6);
  }
}

TEST(PatchMetric, GhostRingCarriesTheNeighbourMetric) {
  LimitSurface s;
  ASSERT_TRUE(LimitSurface::build(rotate_faces(cube_mesh(2), 9), {}, s));
  const int n = 8;
  const PatchMetric m = sample_limit_metric(s, n);
  // Each ring sample is the neighbour's metric at the same surface point (half a cell inside
  // the neighbour), evaluated there and carried into this patch's frame.
  const int last = m.side() - 1;
  double worst = 0;
  LimitSample a;
  for (int p = 0; p < s.patches(); ++p)
    for (int e = 0; e < 4; ++e)
      for (int k = 1; k < last; ++k) {
        const int ring[4][2] = {{k, 0}, {last, k}, {k, last}, {0, k}};
        const int ra = ring[e][0], rb = ring[e][1];
        const EdgeTransition& tr = s.topology().transition(p, e);
        const auto y = tr.map_point({m.coordinate(ra), m.coordinate(rb)});
        ASSERT_GE(y[0], 0);
        ASSERT_LE(y[0], 1);
        ASSERT_GE(y[1], 0);
        ASSERT_LE(y[1], 1);
        s.evaluate(tr.patch, y[0], y[1], a);
        const MetricSample q = metric_from_tangents(a.du, a.dv);
        const auto g = make_transition(p, tr.edge, e).map_tensor({q.g11, q.g12, q.g22});
        const MetricSample& got = m.at(p, ra, rb);
        worst = std::max({worst, std::abs(got.g11 - g[0]) / q.g11, std::abs(got.g12 - g[1]) / q.g11,
                          std::abs(got.g22 - g[2]) / q.g11,
                          std::abs(got.sqrt_g - q.sqrt_g) / q.sqrt_g});
        // The inverse metric is the inverse of the metric.
        EXPECT_NEAR(got.gi11 * got.g11 + got.gi12 * got.g12, 1.0, 1e-9);
        EXPECT_NEAR(got.gi11 * got.g12 + got.gi12 * got.g22, 0.0, 1e-9 * got.gi11 * got.g11);
      }
  EXPECT_LT(worst, 1e-12);
}

}  // namespace
}  // namespace ardcell
