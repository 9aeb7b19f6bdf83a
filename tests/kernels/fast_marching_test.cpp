// Fast marching against exact distances (a plane, a circle, a point) with first- and
// second-order error bounds that shrink with the grid as the order says; extension velocities
// (constant stays constant, an interface speed stays constant along the normals); orientation
// from a straight stroke is constant, from a circular stroke tangential.
#include "kernels/fast_marching.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

namespace ardcell {
namespace {

constexpr double kPi = 3.14159265358979323846;

struct Errors {
  double max = 0, mean = 0;
};

// Unit square on n x n cells (h = 1/n, centres at (i + 0.5) h). Cells where |exact| < band
// are sources initialised with the exact distance; the rest is marched. Errors are measured
// where `measure` holds.
Errors march_error(int n, int order, double band_cells,
                   const std::function<double(double, double)>& exact,
                   const std::function<bool(double, double)>& measure) {
  const double h = 1.0 / n;
  FieldF d({n, n}, 0);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const double e = exact((x + 0.5) * h, (y + 0.5) * h);
      d(x, y) = e < band_cells * h ? float(e) : kFarDistance;
    }
  FastMarchingWorkspace ws({n, n});
  FastMarchingParams p;
  p.h = h;
  p.order = order;
  fast_marching(d.view(), {}, box_of_size({n, n}), p, ws);
  Errors err;
  int count = 0;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const double px = (x + 0.5) * h, py = (y + 0.5) * h;
      if (!measure(px, py)) continue;
      const double e = std::fabs(d(x, y) - exact(px, py));
      err.max = std::max(err.max, e);
      err.mean += e;
      ++count;
    }
  err.mean /= count;
  return err;
}

// The error at n, 2n, 4n falls by about 2^order per halving of h.
void expect_order(const char* what, int order, double band_cells,
                  const std::function<double(double, double)>& exact,
                  const std::function<bool(double, double)>& measure, double min_rate,
                  double bound_coefficient) {
  double prev = 0;
  for (int n : {32, 64, 128}) {
    const Errors e = march_error(n, order, band_cells, exact, measure);
    const double h = 1.0 / n;
    SCOPED_TRACE(std::string(what) + " order " + std::to_string(order) + " n " + std::to_string(n));
    // Absolute bound: C h^order.
    EXPECT_LT(e.max, bound_coefficient * std::pow(h, order)) << e.max;
    if (prev > 0) {
      EXPECT_GT(prev / e.max, min_rate) << prev << " -> " << e.max;
    }
    prev = e.max;
  }
}

const auto everywhere = [](double, double) { return true; };

TEST(FastMarching, TiltedPlaneIsExactAwayFromTheEdges) {
  // Both upwind schemes are exact for a linear distance ((T - Tx)^2 + (T - Ty)^2 = h^2 holds
  // with T - Tx = h nx, T - Ty = h ny); only cells whose characteristic runs near the domain
  // edge, where the stencil is cut, see an error. Plane through (0.5, 0.43), normal at 30 deg.
  const double nx = std::cos(kPi / 6), ny = std::sin(kPi / 6);
  auto signed_distance = [=](double x, double y) { return (x - 0.5) * nx + (y - 0.43) * ny; };
  auto exact = [=](double x, double y) { return std::fabs(signed_distance(x, y)); };
  auto inside = [](double x, double y) { return x > 0.1 && x < 0.9 && y > 0.1 && y < 0.9; };
  auto measure = [=](double x, double y) {
    const double d = signed_distance(x, y);
    return inside(x, y) && inside(x - d * nx, y - d * ny);
  };
  for (int n : {64, 128})
    for (int order : {1, 2}) {
      const Errors e = march_error(n, order, order, exact, measure);
      EXPECT_LT(e.max, 0.01 / n) << "n " << n << " order " << order;
    }
}

TEST(FastMarching, GridAlignedPlaneIsExact) {
  auto exact = [](double x, double) { return std::fabs(x - 0.3037); };
  for (int order : {1, 2}) {
    const Errors e = march_error(64, order, 2.0, exact, everywhere);
    EXPECT_LT(e.max, 1e-6) << order;
  }
}

TEST(FastMarching, Circle) {
  // Distance to a circle of radius 0.3, measured outside and in the ring r > 0.15 inside
  // (the centre is a kink of the exact solution).
  auto exact = [](double x, double y) { return std::fabs(std::hypot(x - 0.5, y - 0.5) - 0.3); };
  auto measure = [](double x, double y) { return std::hypot(x - 0.5, y - 0.5) > 0.15; };
  expect_order("circle", 1, 1.0, exact, measure, 1.5, 1.0);
  expect_order("circle", 2, 2.0, exact, measure, 2.5, 3.0);
}

TEST(FastMarching, Point) {
  // A point source at (0.41, 0.37), exact inside a disc of fixed radius 0.1 (the usual
  // initialisation: the point itself is a rarefaction no finite stencil resolves).
  auto exact = [](double x, double y) { return std::hypot(x - 0.41, y - 0.37); };
  auto march = [&](int n, int order) { return march_error(n, order, 0.1 * n, exact, everywhere); };
  double prev1 = 0, prev2 = 0;
  for (int n : {32, 64, 128}) {
    const Errors e1 = march(n, 1), e2 = march(n, 2);
    const double h = 1.0 / n;
    EXPECT_LT(e1.max, 1.0 * h) << n;
    EXPECT_LT(e2.max, 6.0 * h * h) << n;
    EXPECT_LT(e2.max, e1.max) << n;
    if (prev1 > 0) {
      EXPECT_GT(prev1 / e1.max, 1.5) << n;
      EXPECT_GT(prev2 / e2.max, 2.8) << n;
    }
    prev1 = e1.max;
    prev2 = e2.max;
  }
}

TEST(FastMarching, NarrowBandStopsAtMaxDistance) {
  const int n = 64;
  FieldF d({n, n}, 0);
  d.fill(kFarDistance);
  d(10, 10) = 0;
  FastMarchingWorkspace ws({n, n});
  FastMarchingParams p;
  p.max_distance = 5;
  const int64_t accepted = fast_marching(d.view(), {}, box_of_size({n, n}), p, ws);
  EXPECT_GT(accepted, 50);
  EXPECT_LT(accepted, 140);  // about the disc of radius 5 (area 78)
  EXPECT_EQ(d(40, 40), kFarDistance);
  EXPECT_NEAR(d(13, 10), 3.0f, 1e-6);
}

TEST(FastMarching, ExtensionOfAConstantIsThatConstant) {
  const int n = 96;
  FieldF d({n, n}, 0), f({n, n}, 0), g({n, n}, 0);
  d.fill(kFarDistance);
  f.fill(-5);
  g.fill(-5);
  // An irregular source set: a diagonal line and a few blobs.
  for (int k = 10; k < 80; ++k) {
    d(k, k / 2 + 5) = 0;
    f(k, k / 2 + 5) = 1.0f;
    g(k, k / 2 + 5) = 0.7f;
  }
  d(70, 80) = 0;
  f(70, 80) = 1.0f;
  g(70, 80) = 0.7f;
  FastMarchingWorkspace ws({n, n});
  const View<float> values[2] = {f.view(), g.view()};
  fast_marching(d.view(), values, box_of_size({n, n}), {}, ws);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      ASSERT_EQ(f(x, y), 1.0f) << x << "," << y;  // (w1 + w2) / (w1 + w2) is exact
      ASSERT_NEAR(g(x, y), 0.7f, 2e-7f) << x << "," << y;
    }
}

TEST(FastMarching, InterfaceSpeedIsConstantAlongNormals) {
  // Speed F = cos(3 phi) given on a circle of radius 0.25; extended outward, F at (r, phi)
  // must stay cos(3 phi) along each normal (radial line), with a first-order error in h.
  // Second-order distances need sources two cells deep (the unsigned distance cannot tell
  // which side of the interface a stencil cell lies on).
  for (int order : {1, 2}) {
    double prev = 0;
    for (int n : {64, 128, 256}) {
      const double h = 1.0 / n;
      FieldF d({n, n}, 0), f({n, n}, 0);
      d.fill(kFarDistance);
      for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
          const double px = (x + 0.5) * h - 0.5, py = (y + 0.5) * h - 0.5;
          const double r = std::hypot(px, py);
          if (std::fabs(r - 0.25) < order * h) {
            d(x, y) = float(std::fabs(r - 0.25));
            f(x, y) = float(std::cos(3 * std::atan2(py, px)));
          }
        }
      FastMarchingWorkspace ws({n, n});
      const View<float> values[1] = {f.view()};
      FastMarchingParams p;
      p.h = h;
      p.order = order;
      fast_marching(d.view(), values, box_of_size({n, n}), p, ws);
      double err = 0;
      for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
          const double px = (x + 0.5) * h - 0.5, py = (y + 0.5) * h - 0.5;
          const double r = std::hypot(px, py);
          if (r < 0.27 || r > 0.45) continue;
          err = std::max(err, std::fabs(f(x, y) - std::cos(3 * std::atan2(py, px))));
        }
      SCOPED_TRACE("order " + std::to_string(order) + " n " + std::to_string(n));
      EXPECT_LT(err, 6 * h) << err;
      if (prev > 0) {
        EXPECT_GT(prev / err, 1.6) << prev << " -> " << err;
      }
      prev = err;
    }
  }
}

// Rasterises a polyline stroke: cells whose centre lies within `radius` cells of a segment
// get weight 1 and the segment's unit direction.
void rasterise(FieldF& w, FieldF& c, FieldF& s, const std::vector<std::pair<double, double>>& pts,
               double radius) {
  for (std::size_t k = 0; k + 1 < pts.size(); ++k) {
    const double ax = pts[k].first, ay = pts[k].second, bx = pts[k + 1].first,
                 by = pts[k + 1].second;
    const double len = std::hypot(bx - ax, by - ay);
    for (int y = 0; y < w.ny(); ++y)
      for (int x = 0; x < w.nx(); ++x) {
        const double px = x + 0.5, py = y + 0.5;
        double t = ((px - ax) * (bx - ax) + (py - ay) * (by - ay)) / (len * len);
        t = std::clamp(t, 0.0, 1.0);
        if (std::hypot(px - ax - t * (bx - ax), py - ay - t * (by - ay)) <= radius) {
          w(x, y) = 1;
          c(x, y) = float((bx - ax) / len);
          s(x, y) = float((by - ay) / len);
        }
      }
  }
}

double angle_error(double a, double b) {
  double d = std::fmod(std::fabs(a - b), 2 * kPi);
  return std::min(d, 2 * kPi - d);
}

TEST(Orientation, StraightStrokeGivesConstantTheta) {
  const int n = 128;
  for (int factor : {1, 4}) {
    FieldF w({n, n}, 0), c({n, n}, 0), s({n, n}, 0), theta({n, n}, 0);
    const double angle = 2.5;  // radians: a stroke pointing up-left, far from 0 / 2 pi
    rasterise(w, c, s, {{30, 90}, {30 + 60 * std::cos(angle), 90 + 60 * std::sin(angle)}}, 1.5);
    OrientationExtender ext({n, n}, factor);
    ASSERT_TRUE(ext.extend(w.view(), c.view(), s.view(), theta.view()));
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) ASSERT_LT(angle_error(theta(x, y), angle), 1e-4) << x << "," << y;
  }
}

TEST(Orientation, NoTearAtTwoPi) {
  // A stroke pointing along -x: theta = pi, whose neighbours in angle are -pi + eps. Extending
  // the angle itself would average pi and -pi to 0; (cos, sin) keeps pi everywhere.
  const int n = 64;
  FieldF w({n, n}, 0), c({n, n}, 0), s({n, n}, 0), theta({n, n}, 0);
  rasterise(w, c, s, {{50, 30}, {40, 30.3}, {30, 29.7}, {10, 30}}, 1.0);
  OrientationExtender ext({n, n}, 1);
  ASSERT_TRUE(ext.extend(w.view(), c.view(), s.view(), theta.view()));
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) ASSERT_LT(angle_error(theta(x, y), kPi), 0.08) << x << "," << y;
}

TEST(Orientation, CircularStrokeIsTangentialEverywhere) {
  const int n = 128;
  const double cx = 64, cy = 64, r = 30;
  std::vector<std::pair<double, double>> pts;
  for (int k = 0; k <= 200; ++k) {
    const double a = 2 * kPi * k / 200;
    pts.push_back({cx + r * std::cos(a), cy + r * std::sin(a)});  // counter-clockwise in (x, y)
  }
  for (int factor : {1, 2, 4}) {
    FieldF w({n, n}, 0), c({n, n}, 0), s({n, n}, 0), theta({n, n}, 0);
    rasterise(w, c, s, pts, 1.0);
    OrientationExtender ext({n, n}, factor);
    ASSERT_TRUE(ext.extend(w.view(), c.view(), s.view(), theta.view()));
    double worst = 0, sum = 0;
    int count = 0;
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        const double px = x + 0.5 - cx, py = y + 0.5 - cy;
        if (std::hypot(px, py) < 4.0 * factor) continue;  // all directions meet at the centre
        const double tangent = std::atan2(py, px) + kPi / 2;
        const double e = angle_error(theta(x, y), tangent);
        worst = std::max(worst, e);
        sum += e;
        ++count;
      }
    SCOPED_TRACE(factor);
    // First-order extension: a few cells where the fronts from opposite sides of the circle
    // collide (near the centre) or the domain edge cuts the stencil are off by up to ~12 deg;
    // the mean stays under 3 deg (the 200-segment polygon itself is off by up to 0.9 deg).
    EXPECT_LT(worst, 0.25) << "radians";
    EXPECT_LT(sum / count, 0.05) << "radians";
  }
}

TEST(Orientation, CoarseMatchesFullGrid) {
  const int n = 256;
  FieldF w({n, n}, 0), c({n, n}, 0), s({n, n}, 0), full({n, n}, 0), coarse({n, n}, 0);
  std::vector<std::pair<double, double>> spiral;
  for (int k = 0; k <= 300; ++k) {
    const double a = 6 * kPi * k / 300;
    spiral.push_back({128 + (10 + 3.5 * a) * std::cos(a), 128 + (10 + 3.5 * a) * std::sin(a)});
  }
  rasterise(w, c, s, spiral, 1.5);
  OrientationExtender e1({n, n}, 1), e4({n, n}, 4);
  ASSERT_TRUE(e1.extend(w.view(), c.view(), s.view(), full.view()));
  ASSERT_TRUE(e4.extend(w.view(), c.view(), s.view(), coarse.view()));
  double sum = 0;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      if (w(x, y) > 0) {
        EXPECT_EQ(full(x, y), coarse(x, y));  // source cells keep their angle
      }
      sum += angle_error(full(x, y), coarse(x, y));
    }
  EXPECT_LT(sum / (n * n), 0.1) << "mean angle difference, radians";
}

TEST(Orientation, NoSourceLeavesThetaAlone) {
  FieldF w({16, 16}, 0), c({16, 16}, 0), s({16, 16}, 0), theta({16, 16}, 0);
  theta.fill(0.25f);
  OrientationExtender ext({16, 16}, 2);
  EXPECT_FALSE(ext.extend(w.view(), c.view(), s.view(), theta.view()));
  EXPECT_EQ(theta(7, 7), 0.25f);
}

TEST(FastAtan2, MatchesStdAtan2) {
  double worst = 0;
  for (int k = 0; k < 10000; ++k) {
    const double a = -kPi + 2 * kPi * (k + 0.5) / 10000;
    for (double len : {1e-3, 1.0, 7.0}) {
      const float y = float(len * std::sin(a)), x = float(len * std::cos(a));
      worst = std::max(worst, angle_error(fast_atan2(y, x), std::atan2(y, x)));
    }
  }
  EXPECT_LT(worst, 2e-5);
  EXPECT_EQ(fast_atan2(0, 0), 0.f);
}

}  // namespace
}  // namespace ardcell
