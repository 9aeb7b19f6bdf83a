// Fig. 4's space cookies: each preset (space-cookie-3, -4, -5, -8), loaded from its embedded file
// and run through the engine at its own size for its own frame count, ends as a cookie with
// j-fold structure:
//   bounded: no cell with B above kThreshold on the domain's edge, and the cookie (those cells
//   with any holes filled) covers under kMaxCoverage of the domain;
//   j-fold: the radius of the cookie's outline, sampled at kAngles angles around its centroid,
//   has its largest angular Fourier power (harmonics 1 to kHarmonics) at harmonic j, at least
//   kMargin times the next largest.
// Under AddressSanitizer (the CI's build, where a frame costs about 6 times as much) the run
// stops at frame kSanitizedFrames, where the cookie has already formed: at frame 100 harmonic j
// leads the next by 9.4-10.1 times in power, at the preset's last frame (200) by 5.0-16.7.
// The measure is checked first on drawn shapes of known symmetry, where a wrong harmonic fails.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <complex>
#include <cstdio>
#include <string>
#include <vector>

#include "host/engine/engine.h"
#include "host/scenes/preset.h"
#include "tests/support/sanitizers.h"

namespace ardcell {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr float kThreshold = 0.1f;  // B: 0 outside a cookie, 0.2-0.45 inside
constexpr double kMaxCoverage = 0.4;
constexpr int kAngles = 256;
constexpr int kHarmonics = 16;
constexpr double kMargin = 2.0;
constexpr int kSanitizedFrames = 100;

struct CookieShape {
  bool touches_edge = false;
  double coverage = 0;        // cookie cells / all cells
  std::vector<double> power;  // power[m]: harmonic m of the outline radius, m = 0..kHarmonics
  int dominant = 0;           // the m >= 1 of the largest power
  double margin = 0;          // power[dominant] / the next largest power[m >= 1]
};

// `inside(x, y)`: the cell belongs to the pattern. The cookie is every cell not reachable from
// the edge through cells outside the pattern (holes filled); its outline radius r(angle) is the
// distance from its centroid to the farthest cookie cell along the ray.
template <class Inside>
CookieShape measure_cookie(Int2 n, Inside inside) {
  CookieShape c;
  std::vector<uint8_t> outside(size_t(n.x) * n.y, 0);
  std::vector<Int2> stack;
  auto at = [&](int x, int y) { return size_t(y) * n.x + x; };
  auto seed = [&](int x, int y) {
    if (inside(x, y)) {
      c.touches_edge = true;
    } else if (!outside[at(x, y)]) {
      outside[at(x, y)] = 1;
      stack.push_back({x, y});
    }
  };
  for (int x = 0; x < n.x; ++x) seed(x, 0), seed(x, n.y - 1);
  for (int y = 0; y < n.y; ++y) seed(0, y), seed(n.x - 1, y);
  while (!stack.empty()) {
    const Int2 p = stack.back();
    stack.pop_back();
    const Int2 next[] = {{p.x - 1, p.y}, {p.x + 1, p.y}, {p.x, p.y - 1}, {p.x, p.y + 1}};
    for (const Int2 q : next)
      if (q.x >= 0 && q.y >= 0 && q.x < n.x && q.y < n.y && !outside[at(q.x, q.y)] &&
          !inside(q.x, q.y)) {
        outside[at(q.x, q.y)] = 1;
        stack.push_back(q);
      }
  }
  double cells = 0, sx = 0, sy = 0;
  for (int y = 0; y < n.y; ++y)
    for (int x = 0; x < n.x; ++x)
      if (!outside[at(x, y)]) cells += 1, sx += x, sy += y;
  c.coverage = cells / (double(n.x) * n.y);
  if (cells == 0) return c;
  const double cx = sx / cells, cy = sy / cells;
  const double reach = std::hypot(double(n.x), double(n.y));
  std::vector<std::complex<double>> sum(kHarmonics + 1);
  for (int i = 0; i < kAngles; ++i) {
    const double t = 2 * kPi * i / kAngles;
    double r = 0;
    for (double s = 0; s < reach; s += 0.25) {
      const int x = int(std::lround(cx + s * std::cos(t))),
                y = int(std::lround(cy + s * std::sin(t)));
      if (x < 0 || y < 0 || x >= n.x || y >= n.y) break;
      if (!outside[at(x, y)]) r = s;
    }
    for (int m = 0; m <= kHarmonics; ++m) sum[m] += r * std::polar(1.0, -m * t);
  }
  c.power.resize(kHarmonics + 1);
  for (int m = 0; m <= kHarmonics; ++m) c.power[m] = std::norm(sum[m] / double(kAngles));
  c.dominant = 1;
  for (int m = 2; m <= kHarmonics; ++m)
    if (c.power[m] > c.power[c.dominant]) c.dominant = m;
  double next = 0;
  for (int m = 1; m <= kHarmonics; ++m)
    if (m != c.dominant) next = std::max(next, c.power[m]);
  c.margin = next > 0 ? c.power[c.dominant] / next : INFINITY;
  return c;
}

// A drawn star r = R (1 + a cos(j (angle - phase))) at (cx, cy) on an n x n grid, with a hole
// of radius `hole` at its centre.
CookieShape drawn_star(int n, double cx, double cy, double R, int j, double a, double phase,
                       double hole = 0) {
  return measure_cookie({n, n}, [=](int x, int y) {
    const double dx = x - cx, dy = y - cy, r = std::hypot(dx, dy);
    return r >= hole && r <= R * (1 + a * std::cos(j * (std::atan2(dy, dx) - phase)));
  });
}

TEST(SpaceCookieMeasure, FindsTheFoldOfADrawnStarAndNoOther) {
  for (const int j : {3, 4, 5, 8}) {
    // Off the grid's centre, turned, with a hole (filled: only the outline counts).
    const CookieShape c = drawn_star(160, 83.3, 76.9, 35, j, 0.1, 0.3, 12);
    EXPECT_FALSE(c.touches_edge) << j;
    EXPECT_EQ(c.dominant, j);
    EXPECT_GT(c.margin, 10.0) << j;
    for (const int wrong : {3, 4, 5, 8})
      if (wrong != j) {
        EXPECT_LT(c.power[wrong], c.power[j] / 10) << j << " as " << wrong;
      }
  }
  // An ellipse is 2-fold; a disc has no fold worth the name.
  const CookieShape ellipse = measure_cookie({160, 160}, [](int x, int y) {
    const double dx = (x - 80) / 40.0, dy = (y - 80) / 25.0;
    return dx * dx + dy * dy <= 1;
  });
  EXPECT_EQ(ellipse.dominant, 2);
  const CookieShape disc = drawn_star(160, 80, 80, 40, 1, 0, 0);
  const CookieShape square = drawn_star(160, 80, 80, 40, 4, 0.1, 0);
  EXPECT_LT(disc.power[disc.dominant], square.power[4] / 100);  // the raster's own steps
}

TEST(SpaceCookieMeasure, ALabyrinthOrAFilledDomainIsNotBounded) {
  const CookieShape filled = measure_cookie({64, 64}, [](int, int) { return true; });
  EXPECT_TRUE(filled.touches_edge);
  EXPECT_DOUBLE_EQ(filled.coverage, 1.0);
  // Stripes reaching every edge (a labyrinth's cut): unbounded, whatever their folds.
  const CookieShape stripes =
      measure_cookie({64, 64}, [](int x, int y) { return (x / 4 + y / 4) % 2 == 0; });
  EXPECT_TRUE(stripes.touches_edge);
  // A ring is bounded and its hole counts as cookie.
  const CookieShape ring = measure_cookie({64, 64}, [](int x, int y) {
    const double r = std::hypot(x - 31.5, y - 31.5);
    return r >= 10 && r <= 14;
  });
  EXPECT_FALSE(ring.touches_edge);
  EXPECT_NEAR(ring.coverage, kPi * 14 * 14 / (64 * 64), 0.005);
}

class SpaceCookie : public ::testing::TestWithParam<int> {};

TEST_P(SpaceCookie, EndsAsABoundedCookieWithItsLobesFold) {
  const int j = GetParam();
  const std::string name = "space-cookie-" + std::to_string(j);
  Preset preset;
  ASSERT_TRUE(load_preset(name, preset).is_ok()) << name;
  const SceneConfig& scene = preset.scene;
  ASSERT_EQ(scene.rd.initial, RdInitialPattern::kCentreDisc) << name;
  ASSERT_EQ(scene.rd.anisotropy.lobes, j) << name;
  const auto start = std::chrono::steady_clock::now();
  // Serial: the same bits as the threads back end (engine_backend_parity_test), and no workers
  // to contend with the tests ctest runs beside this one.
  Engine engine(scene, {EngineOptions::Backend::kSerial, 1});
  const int steps = int(scene.default_steps);
  const int frames = ARDCELL_TEST_ASAN ? std::min(steps, kSanitizedFrames) : steps;
  for (int f = 0; f < frames; ++f) engine.step();
  const SimState& s = engine.state();
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const CookieShape c =
      measure_cookie(s.size, [&](int x, int y) { return s.B(x, y) > kThreshold; });
  std::printf(
      "%s: %d frames of %dx%d in %.2f s; coverage %.3f, edge %s; fold %d, margin %.1f;"
      " power",
      name.c_str(), frames, scene.size.x, scene.size.y, seconds, c.coverage,
      c.touches_edge ? "touched" : "clear", c.dominant, c.margin);
  for (size_t m = 1; m < c.power.size(); ++m) std::printf(" %zu:%.3g", m, c.power[m]);
  std::printf("\n");
  EXPECT_FALSE(c.touches_edge) << name << ": the pattern reaches the domain's edge";
  EXPECT_GT(c.coverage, 0.02) << name << ": no cookie grew";
  EXPECT_LT(c.coverage, kMaxCoverage) << name;
  EXPECT_EQ(c.dominant, j) << name;
  EXPECT_GE(c.margin, kMargin) << name;
  ASSERT_EQ(c.power.size(), size_t(kHarmonics + 1)) << name;
  for (const int other : {3, 4, 5, 8}) {
    if (other != j) {
      EXPECT_LT(c.power[other] * kMargin, c.power[j]) << name << " reads as " << other << "-fold";
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Lobes, SpaceCookie, ::testing::Values(3, 4, 5, 8));

}  // namespace
}  // namespace ardcell
