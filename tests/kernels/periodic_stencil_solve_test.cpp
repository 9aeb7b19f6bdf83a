#include "kernels/periodic_stencil_solve.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include "kernels/generalized_diffusion.h"
#include "runtime/thread/thread_backend.h"
#include "tests/support/alloc_counter.h"

namespace ardcell {
namespace {

constexpr Int2 kSquare{64, 64};
constexpr Int2 kOdd{127, 93};  // odd, and neither a power of two (127 is prime)
constexpr int kHalo = 2;

// The reference system (I - delta K) x = b in double with the periodic wrap written out
// (independent of the FFT path: taps, modulo indexing).
class PeriodicSystem {
 public:
  PeriodicSystem(const Stencil5x5& k, double delta, Int2 n) : delta_(delta), n_(n) {
    for (int dy = -2; dy <= 2; ++dy)
      for (int dx = -2; dx <= 2; ++dx)
        if (k.at(dx, dy) != 0) taps_.push_back({dx, dy, k.at(dx, dy)});
    for (int dy = -2; dy <= 2; ++dy)
      for (int dx = -2; dx <= 2; ++dx) symmetric_ = symmetric_ && k.at(dx, dy) == k.at(-dx, -dy);
  }
  // A centrosymmetric stencil (even ranks only) makes a symmetric matrix.
  bool symmetric() const { return symmetric_; }
  std::size_t cells() const { return std::size_t(n_.x) * std::size_t(n_.y); }
  // y = (I - delta K) x.
  void apply(const std::vector<double>& x, std::vector<double>& y) const {
    y.resize(cells());
    for (int j = 0; j < n_.y; ++j)
      for (int i = 0; i < n_.x; ++i) {
        double kx = 0;
        for (const Tap& t : taps_) {
          const int xi = (i + t.dx + n_.x) % n_.x, yj = (j + t.dy + n_.y) % n_.y;
          kx += t.w * x[std::size_t(yj) * std::size_t(n_.x) + std::size_t(xi)];
        }
        const std::size_t c = std::size_t(j) * std::size_t(n_.x) + std::size_t(i);
        y[c] = x[c] - delta_ * kx;
      }
  }

 private:
  struct Tap {
    int dx, dy;
    double w;
  };
  double delta_;
  Int2 n_;
  std::vector<Tap> taps_;
  bool symmetric_ = true;
};

double dot(const std::vector<double>& a, const std::vector<double>& b) {
  double s = 0;
  for (std::size_t i = 0; i < a.size(); ++i) s += a[i] * b[i];
  return s;
}

// Restarted GMRES (modified Gram-Schmidt, Givens rotations), to a relative residual of `tol`:
// for the non-symmetric systems (odd ranks), which are well-conditioned in Table 2.
std::vector<double> gmres(const PeriodicSystem& a, const std::vector<double>& b, double tol,
                          std::size_t m = 150, int max_iterations = 30000) {
  const std::size_t n = b.size();
  std::vector<double> x(n, 0.0), r(n), w(n), g(m + 1), cs(m), sn(m), y(m);
  std::vector<std::vector<double>> v(m + 1, std::vector<double>(n));
  std::vector<double> hess((m + 1) * m);
  const auto h = [&](std::size_t i, std::size_t j) -> double& { return hess[i * m + j]; };
  const double bnorm = std::sqrt(dot(b, b));
  int iterations = 0;
  while (iterations < max_iterations) {
    a.apply(x, r);
    for (std::size_t i = 0; i < n; ++i) r[i] = b[i] - r[i];
    const double beta = std::sqrt(dot(r, r));
    if (beta <= tol * bnorm) return x;
    for (std::size_t i = 0; i < n; ++i) v[0][i] = r[i] / beta;
    std::fill(g.begin(), g.end(), 0.0);
    g[0] = beta;
    std::size_t k = 0;
    while (k < m && iterations < max_iterations) {
      a.apply(v[k], w);
      for (std::size_t i = 0; i <= k; ++i) {
        h(i, k) = dot(w, v[i]);
        for (std::size_t c = 0; c < n; ++c) w[c] -= h(i, k) * v[i][c];
      }
      h(k + 1, k) = std::sqrt(dot(w, w));
      if (h(k + 1, k) > 0)
        for (std::size_t c = 0; c < n; ++c) v[k + 1][c] = w[c] / h(k + 1, k);
      for (std::size_t i = 0; i < k; ++i) {
        const double t = cs[i] * h(i, k) + sn[i] * h(i + 1, k);
        h(i + 1, k) = -sn[i] * h(i, k) + cs[i] * h(i + 1, k);
        h(i, k) = t;
      }
      const double d = std::hypot(h(k, k), h(k + 1, k));
      cs[k] = h(k, k) / d;
      sn[k] = h(k + 1, k) / d;
      h(k, k) = d;
      h(k + 1, k) = 0;
      g[k + 1] = -sn[k] * g[k];
      g[k] *= cs[k];
      ++k, ++iterations;
      if (std::abs(g[k]) <= 0.1 * tol * bnorm) break;
    }
    for (std::size_t i = k; i-- > 0;) {
      double s = g[i];
      for (std::size_t j = i + 1; j < k; ++j) s -= h(i, j) * y[j];
      y[i] = s / h(i, i);
    }
    for (std::size_t j = 0; j < k; ++j)
      for (std::size_t c = 0; c < n; ++c) x[c] += y[j] * v[j][c];
  }
  ADD_FAILURE() << "GMRES did not reach " << tol << " in " << max_iterations << " iterations";
  return x;
}

// MINRES (Paige & Saunders, unpreconditioned) for the symmetric systems: (I - delta K) is
// indefinite for the rank-4 sequences (d) and (e) (backward hyperdiffusion, symbol up to +12),
// which rules out CG, and nearly singular (condition 1e3 to 1e4), where restarted GMRES
// crawls. Stops on its residual estimate; the caller checks the true residual.
std::vector<double> minres(const PeriodicSystem& a, const std::vector<double>& b, double tol,
                           int max_iterations = 200000) {
  const std::size_t n = b.size();
  std::vector<double> x(n, 0.0), r1 = b, r2 = b, y = b, v(n), w(n, 0.0), w1(n), w2(n, 0.0);
  const double beta1 = std::sqrt(dot(b, b));
  if (beta1 == 0) return x;
  double oldb = 0, beta = beta1, dbar = 0, epsln = 0, phibar = beta1, cs = -1, sn = 0;
  for (int it = 1; it <= max_iterations; ++it) {
    for (std::size_t i = 0; i < n; ++i) v[i] = y[i] / beta;
    a.apply(v, y);
    if (it >= 2)
      for (std::size_t i = 0; i < n; ++i) y[i] -= (beta / oldb) * r1[i];
    const double alfa = dot(v, y);
    for (std::size_t i = 0; i < n; ++i) y[i] -= (alfa / beta) * r2[i];
    r1.swap(r2);
    r2 = y;
    oldb = beta;
    beta = std::sqrt(dot(y, y));
    const double oldeps = epsln;
    const double delta = cs * dbar + sn * alfa;
    const double gbar = sn * dbar - cs * alfa;
    epsln = sn * beta;
    dbar = -cs * beta;
    const double gamma = std::max(std::hypot(gbar, beta), 1e-300);
    cs = gbar / gamma;
    sn = beta / gamma;
    const double phi = cs * phibar;
    phibar *= sn;
    w1.swap(w2);
    w2.swap(w);
    for (std::size_t i = 0; i < n; ++i) {
      w[i] = (v[i] - oldeps * w1[i] - delta * w2[i]) / gamma;
      x[i] += phi * w[i];
    }
    if (phibar <= tol * beta1 || beta == 0) break;
  }
  return x;
}

// (I - delta K) x = b to a true relative residual of 1e-12: MINRES or GMRES, then refinement
// on the residual (MINRES's estimate drifts from the true residual on these condition numbers).
std::vector<double> iterative_solve(const PeriodicSystem& a, const std::vector<double>& b) {
  constexpr double kTol = 1e-12;
  std::vector<double> x(b.size(), 0.0), r(b.size()), ax;
  const double bnorm = std::sqrt(dot(b, b));
  for (int pass = 0; pass < 8; ++pass) {
    a.apply(x, ax);
    for (std::size_t i = 0; i < b.size(); ++i) r[i] = b[i] - ax[i];
    if (std::sqrt(dot(r, r)) <= kTol * bnorm) return x;
    const std::vector<double> dx =
        a.symmetric() ? minres(a, r, 0.1 * kTol) : gmres(a, r, 0.1 * kTol);
    for (std::size_t i = 0; i < b.size(); ++i) x[i] += dx[i];
  }
  ADD_FAILURE() << "the iterative reference did not reach a residual of " << kTol;
  return x;
}

// A right-hand side with both smooth structure and noise in every mode; the halo holds NaN, so
// any read of it would show in the result.
FieldF make_rhs(Int2 n, unsigned seed) {
  FieldF f(n, kHalo);
  f.fill(std::numeric_limits<float>::quiet_NaN());
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> noise(-1.0f, 1.0f);
  for (int y = 0; y < n.y; ++y)
    for (int x = 0; x < n.x; ++x)
      f(x, y) = float(0.5 + std::sin(2 * std::numbers::pi * (2.0 * x / n.x + 1.0 * y / n.y))) +
                0.5f * noise(rng);
  return f;
}

std::vector<double> interior(const FieldF& f) {
  std::vector<double> v;
  v.reserve(std::size_t(f.nx()) * std::size_t(f.ny()));
  for (int y = 0; y < f.ny(); ++y)
    for (int x = 0; x < f.nx(); ++x) v.push_back(f(x, y));
  return v;
}

double max_abs(const std::vector<double>& v) {
  double m = 0;
  for (double e : v) m = std::max(m, std::abs(e));
  return m;
}

double max_abs_difference(const std::vector<double>& a, const std::vector<double>& b) {
  double m = 0;
  for (std::size_t i = 0; i < a.size(); ++i) m = std::max(m, std::abs(a[i] - b[i]));
  return m;
}

// The larger delta of each sequence: 5, where (I - delta K) is well-posed on both grids (the
// rank-4 ones are indefinite there but far from singular; problem() agrees, checked below).
constexpr double kDeltas[] = {0.1, 5.0};

TEST(PeriodicStencilSolve, SymbolIsStencilSymbolAtSignedWavenumbers) {
  for (const auto& seq : kTable2) {
    const Stencil5x5 k = assemble_generalized_stencil(seq.tensors);
    PeriodicStencilSolve solve(kOdd, k);
    ASSERT_EQ(solve.spectral_width(), kOdd.x / 2 + 1);
    for (int mx = 0; mx < solve.spectral_width(); ++mx)
      for (int my = 0; my < kOdd.y; ++my) {
        const double kx =
            2 * std::numbers::pi * PeriodicStencilSolve::signed_frequency(mx, kOdd.x) / kOdd.x;
        const double ky =
            2 * std::numbers::pi * PeriodicStencilSolve::signed_frequency(my, kOdd.y) / kOdd.y;
        EXPECT_NEAR(std::abs(solve.symbol(mx, my) - stencil_symbol(k, kx, ky)), 0.0, 1e-12)
            << seq.name << " (" << mx << ", " << my << ")";
      }
    // Column mx = 0 holds the modes (0, ky) and (0, -ky): their symbols are exact conjugates.
    for (int my = 1; my < kOdd.y; ++my)
      EXPECT_EQ(solve.symbol(0, my), std::conj(solve.symbol(0, kOdd.y - my))) << seq.name;
    EXPECT_EQ(solve.multiplier(3, 4, 0.5), 1.0 / (1.0 - 0.5 * solve.symbol(3, 4)));
  }
}

// (grid, Table 2 sequence, delta index into kDeltas): one test per system, so each one's time
// and error show.
using IterativeCase = std::tuple<int, int, int>;
class MatchesIterativeSolve : public ::testing::TestWithParam<IterativeCase> {};

TEST_P(MatchesIterativeSolve, OnTable2) {
  const auto [grid, sequence, delta_index] = GetParam();
  const Int2 n = grid == 0 ? kSquare : kOdd;
  const double delta = kDeltas[delta_index];
  const Stencil5x5 k = assemble_generalized_stencil(kTable2[sequence].tensors);
  PeriodicStencilSolve solve(n, k);
  ASSERT_EQ(solve.problem(delta), "");
  FieldF x = make_rhs(n, 11);
  const std::vector<double> b = interior(x);
  solve.solve(x, delta);
  const std::vector<double> got = interior(x);
  const std::vector<double> want = iterative_solve(PeriodicSystem(k, delta, n), b);
  const double err = max_abs_difference(got, want) / max_abs(want);
  EXPECT_LT(err, 1e-5);
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", err);
  RecordProperty("max_abs_error_over_max_abs_x", text);
  // The halo was not read (it is NaN) and not written.
  EXPECT_TRUE(std::isnan(x(-1, 0)) && std::isnan(x(n.x, n.y - 1)) && std::isnan(x(0, -2)));
}

INSTANTIATE_TEST_SUITE_P(PeriodicStencilSolve, MatchesIterativeSolve,
                         ::testing::Combine(::testing::Values(0, 1), ::testing::Range(0, 6),
                                            ::testing::Values(0, 1)),
                         [](const ::testing::TestParamInfo<IterativeCase>& info) {
                           // No structured binding: its commas would split the macro's arguments.
                           return std::string(kTable2[std::get<1>(info.param)].name) +
                                  (std::get<0>(info.param) == 0 ? "_64x64" : "_127x93") +
                                  (std::get<2>(info.param) == 0 ? "_delta0p1" : "_delta5");
                         });

TEST(PeriodicStencilSolve, ResidualGivesBackTheRightHandSide) {
  for (Int2 n : {kSquare, kOdd})
    for (const auto& seq : kTable2) {
      const Stencil5x5 k = assemble_generalized_stencil(seq.tensors);
      PeriodicStencilSolve solve(n, k);
      for (double delta : kDeltas) {
        SCOPED_TRACE(::testing::Message() << seq.name << " delta " << delta << " on " << n);
        FieldF x = make_rhs(n, 5);
        const std::vector<double> b = interior(x);
        solve.solve(x, delta);
        std::vector<double> ax;
        PeriodicSystem(k, delta, n).apply(interior(x), ax);
        // The normwise backward error: relative to ||I - delta K||_inf max |x| (float rounding of
        // x, 6e-8 |x|, shows in A x multiplied by up to the operator's norm).
        double taps = 0;
        for (double w : k.w) taps += std::abs(w);
        const double norm = 1.0 + delta * taps;
        const double backward = max_abs_difference(ax, b) / (norm * max_abs(interior(x)));
        EXPECT_LT(backward, 1e-5);
        // And plainly relative to the right-hand side at the small delta.
        if (delta < 1) {
          EXPECT_LT(max_abs_difference(ax, b) / max_abs(b), 1e-5);
        }
      }
    }
}

TEST(PeriodicStencilSolve, ConservesTheInteriorSumWhenTapsSumToZero) {
  for (Int2 n : {kSquare, kOdd})
    for (const auto& seq : kTable2) {
      const Stencil5x5 k = assemble_generalized_stencil(seq.tensors);
      ASSERT_NEAR(k.sum(), 0.0, 1e-12) << seq.name;
      PeriodicStencilSolve solve(n, k);
      for (double delta : kDeltas) {
        FieldF x = make_rhs(n, 3);
        const std::vector<double> before = interior(x);
        solve.solve(x, delta);
        const std::vector<double> after = interior(x);
        double s0 = 0, s1 = 0, magnitude = 0;
        for (double v : before) s0 += v, magnitude += std::abs(v);
        for (double v : after) s1 += v;
        // A float rounding of each cell: a few 1e-8 of sum |x|.
        EXPECT_NEAR(s1, s0, 1e-6 * magnitude) << seq.name << " delta " << delta << " on " << n;
      }
    }
}

TEST(PeriodicStencilSolve, SameBitsOnOneToFourWorkers) {
  // 300 x 257 so that every pass is big enough for the executor to cut it into bands.
  for (Int2 n : {kOdd, Int2{300, 257}})
    for (const auto& seq : {kTable2[2], kTable2[4]}) {  // (c): complex symbol; (e): rank 4
      const Stencil5x5 k = assemble_generalized_stencil(seq.tensors);
      FieldF reference = make_rhs(n, 9);
      {
        PeriodicStencilSolve serial(n, k);
        serial.solve(reference, 0.3);
      }
      for (int workers : {1, 2, 3, 4}) {
        ThreadBackendOptions o;
        o.workers = workers;
        ThreadBackend backend(o);
        RowExecutor ex(backend);
        PeriodicStencilSolve solve(n, k, ex);
        FieldF x = make_rhs(n, 9);
        solve.solve(x, 0.3);
        for (int y = 0; y < n.y; ++y)
          ASSERT_EQ(std::memcmp(x.row(y), reference.row(y), std::size_t(n.x) * sizeof(float)), 0)
              << seq.name << " on " << n << ", " << workers << " workers, row " << y;
      }
    }
}

TEST(PeriodicStencilSolve, PairGivesEachSolvesBitsOnOneToFourWorkers) {
  // Two transforms side by side on two workers, each split over the workers otherwise.
  const Int2 n{300, 257};
  const Stencil5x5 k = assemble_generalized_stencil(kTable2[2].tensors);
  FieldF want_a = make_rhs(n, 9), want_b = make_rhs(n, 10);
  {
    PeriodicStencilSolve serial(n, k);
    serial.solve(want_a, 0.3);
    serial.solve(want_b, 1.7);
  }
  for (int workers : {1, 2, 3, 4}) {
    ThreadBackendOptions o;
    o.workers = workers;
    ThreadBackend backend(o);
    RowExecutor ex(backend);
    PeriodicStencilSolve solve_a(n, k, ex), solve_b(n, k, ex);
    solve_a.set_delta(0.3);
    solve_b.set_delta(1.7);
    FieldF a = make_rhs(n, 9), b = make_rhs(n, 10);
    for (int repeat = 0; repeat < 2; ++repeat) {  // the second on warm scratch
      if (repeat == 1) a = make_rhs(n, 9), b = make_rhs(n, 10);
      PeriodicStencilSolve::solve_pair(solve_a, a, solve_b, b);
      for (int y = 0; y < n.y; ++y) {
        ASSERT_EQ(std::memcmp(a.row(y), want_a.row(y), std::size_t(n.x) * sizeof(float)), 0)
            << workers << " workers, A row " << y;
        ASSERT_EQ(std::memcmp(b.row(y), want_b.row(y), std::size_t(n.x) * sizeof(float)), 0)
            << workers << " workers, B row " << y;
      }
    }
  }
}

TEST(PeriodicStencilSolve, SecondSolveAllocatesNothing) {
  for (int workers : {0, 2}) {
    ThreadBackendOptions o;
    o.workers = std::max(1, workers);
    ThreadBackend backend(o);
    RowExecutor threads(backend);
    RowExecutor& ex = workers == 0 ? RowExecutor::serial() : threads;
    PeriodicStencilSolve solve(Int2{256, 200}, assemble_generalized_stencil(kTable2C), ex);
    PeriodicStencilSolve other(Int2{256, 200}, assemble_generalized_stencil(kTable2C), ex);
    FieldF x = make_rhs(Int2{256, 200}, 1), y = make_rhs(Int2{256, 200}, 2);
    solve.solve(x, 0.5);
    PeriodicStencilSolve::solve_pair(solve, x, other, y);
    const long before = g_allocations.load();
    solve.solve(x, 0.5);
    solve.solve(x, 2.0);  // a new delta: set_delta retabulates without allocating
    PeriodicStencilSolve::solve_pair(solve, x, other, y);
    EXPECT_EQ(g_allocations.load() - before, 0) << workers << " workers";
  }
}

TEST(PeriodicStencilSolve, ProblemNamesASingularDelta) {
  // K = minus the 5-point Laplacian: symbol 4 - 2 cos kx - 2 cos ky in [0, 8], so
  // 1 - delta symbol vanishes at delta = 1/4 on the modes with symbol 4, e.g. k = (pi/2, pi/2).
  const Stencil5x5 k = -1.0 * isotropic_stencil(1.0);
  PeriodicStencilSolve solve(kSquare, k);
  EXPECT_EQ(solve.problem(0.1), "");
  const std::string p = solve.problem(0.25);
  EXPECT_NE(p.find("delta = 0.25"), std::string::npos) << p;
  EXPECT_NE(p.find("min |1 - delta symbol| = 0 "), std::string::npos) << p;
  EXPECT_EQ(p.find('\n'), std::string::npos) << "one line: " << p;
  // The wavenumber named is one where the symbol is 4 (the first in scan order: (0, 32)).
  EXPECT_NE(p.find("(mx, my) = (0, 32)"), std::string::npos) << p;
  EXPECT_NE(solve.problem(1.0 / 8.0), "");  // symbol 8 at (pi, pi)
  EXPECT_NE(solve.problem(std::numeric_limits<double>::quiet_NaN()), "");
  EXPECT_NE(solve.problem(std::numeric_limits<double>::infinity()), "");

  // set_delta refuses it and keeps the previous delta; solve stays finite.
  solve.set_delta(0.1);
  EXPECT_THROW(solve.set_delta(0.25), std::invalid_argument);
  EXPECT_EQ(solve.delta(), 0.1);
  FieldF x = make_rhs(kSquare, 2);
  EXPECT_THROW(solve.solve(x, 0.25), std::invalid_argument);
  solve.solve(x);
  for (int y = 0; y < kSquare.y; ++y)
    for (int xx = 0; xx < kSquare.x; ++xx) ASSERT_TRUE(std::isfinite(x(xx, y)));

  // Table 2 at the deltas the other tests use are fine; (e) at delta 1 on 64 x 64 is not: a
  // mode has |1 - delta symbol| = 3.4e-6, under 1e-6 of max |1 - delta symbol| = 21.
  for (const auto& seq : kTable2) {
    PeriodicStencilSolve s(kSquare, assemble_generalized_stencil(seq.tensors));
    for (double delta : kDeltas) EXPECT_EQ(s.problem(delta), "") << seq.name << " " << delta;
  }
  PeriodicStencilSolve e(kSquare, assemble_generalized_stencil(kTable2E));
  EXPECT_NE(e.problem(1.0), "");
}

}  // namespace
}  // namespace ardcell
