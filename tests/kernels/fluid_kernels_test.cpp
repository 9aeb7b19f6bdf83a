#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <utility>

#include "kernels/advect.h"
#include "kernels/project.h"
#include "kernels/sources.h"
#include "kernels/stam_sweeps.h"
#include "kernels/stencil_operator.h"
#include "runtime/boundary.h"

namespace ardcell {
namespace {

FieldF random_field(Int2 size, unsigned seed, float lo = -1.0f, float hi = 1.0f) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> dist(lo, hi);
  FieldF f(size, 1);
  for (int j = -1; j <= size.y; ++j)
    for (int i = -1; i <= size.x; ++i) f(i, j) = dist(rng);
  return f;
}

// A tile of `f` copied into a separate buffer (as the runtime's local store would hold it).
struct TileCopy {
  FieldF storage;
  View<float> view;
  TileCopy(const FieldF& f, Box2 box) : storage(box.size(), 0) {
    view = View<float>(storage.raw(), storage.stride(), box);
    copy_box(f.view(), view, box);
  }
};

TEST(Advect, ConstantFieldIsExact) {
  const Int2 n{33, 20};
  FieldF q0(n, 1), q(n, 1);
  q0.fill(0.7f);
  const FieldF u = random_field(n, 1, -50.0f, 50.0f), v = random_field(n, 2, -50.0f, 50.0f);
  for (bool periodic : {false, true}) {
    advect_scalar(q0.view(), u.view(), v.view(), q.view(), q.interior(), {0.3f, n, periodic});
    for (int j = 0; j < n.y; ++j)
      for (int i = 0; i < n.x; ++i) ASSERT_EQ(q(i, j), 0.7f);
    FieldF uo(n, 1), vo(n, 1), uc(n, 1), vc(n, 1);
    uc.fill(-2.0f);
    vc.fill(3.0f);
    advect_velocity(uc.view(), vc.view(), uo.view(), vo.view(), uo.interior(), {0.3f, n, periodic});
    for (int j = 0; j < n.y; ++j)
      for (int i = 0; i < n.x; ++i) ASSERT_TRUE(uo(i, j) == -2.0f && vo(i, j) == 3.0f);
  }
}

TEST(Advect, WholeCellShiftIsExactAndPeriodicWraps) {
  const Int2 n{16, 12};
  FieldF q0 = random_field(n, 3), q(n, 1), u(n, 1), v(n, 1);
  u.fill(2.0f);   // with dt/h = 1.5: 3 cells in +x
  v.fill(-1.0f);  // 1.5 cells in -y
  fill_boundary(q0.view(), n, BoundaryFill::periodic());
  advect_scalar(q0.view(), u.view(), v.view(), q.view(), q.interior(), {1.5f, n, true});
  for (int j = 0; j < n.y; ++j)
    for (int i = 0; i < n.x; ++i) {
      const int sx = (i - 3 + n.x) % n.x;
      const float expected =
          0.5f * (q0(sx, (j + 1) % n.y) + q0(sx, (j + 2) % n.y));  // y + 1.5 between two rows
      ASSERT_NEAR(q(i, j), expected, 1e-6f) << i << "," << j;
    }
}

TEST(Advect, BackTraceClampsAtWalls) {
  const Int2 n{8, 8};
  FieldF q0 = random_field(n, 4), q(n, 1), u(n, 1), v(n, 1);
  fill_boundary(q0.view(), n, BoundaryFill::copy());
  u.fill(100.0f);  // far beyond the left wall: the sample sits on the wall x = -0.5
  advect_scalar(q0.view(), u.view(), v.view(), q.view(), q.interior(), {1.0f, n, false});
  for (int j = 0; j < n.y; ++j)
    for (int i = 0; i < n.x; ++i) ASSERT_FLOAT_EQ(q(i, j), 0.5f * (q0(-1, j) + q0(0, j)));
}

// The multi-field advection shares one back-trace, vectorised 8 cells at a time where the build
// allows, with a scalar tail: every cell gets the same bits from either path (regions starting
// at each of 8 offsets put every cell once in a tail and otherwise in a vector), every field
// as its own call, and with q0 = {u, v} as advect_velocity - on whole fields (velocities large
// enough to hit the wall clamps, a NaN that must land on the wall) and on a tile copy.
TEST(Advect, SharedBackTraceAndVectorPathGiveTheSameBits) {
  const Int2 n{77, 45};
  const FieldF q0a = random_field(n, 21), q0b = random_field(n, 22, 0.0f, 1.0f),
               q0c = random_field(n, 23, -5.0f, 5.0f);
  FieldF u = random_field(n, 24, -3.0f, 3.0f), v = random_field(n, 25, -3.0f, 3.0f);
  u(10, 10) = std::nanf("");
  v(20, 30) = std::nanf("");
  const AdvectParams ap{7.7f, n, false};
  auto expect_bitwise = [](const View<float>& got, const FieldF& want, Box2 box, const char* what) {
    for (int y = box.min.y; y < box.max.y; ++y)
      for (int x = box.min.x; x < box.max.x; ++x) {
        const float g = got(x, y), w = want(x, y);
        ASSERT_EQ(std::memcmp(&g, &w, sizeof g), 0) << what << " at " << x << "," << y;
      }
  };
  // The reference: one field at a time, the regions' cells in 7-wide strips (all scalar tail).
  FieldF wa(n, 1), wb(n, 1), wc(n, 1), wu(n, 1), wv(n, 1);
  for (int x0 = 0; x0 < n.x; x0 += 7) {
    const Box2 strip{{x0, 0}, {std::min(x0 + 7, n.x), n.y}};
    advect_scalar(q0a.view(), u.view(), v.view(), wa.view(), strip, ap);
    advect_scalar(q0b.view(), u.view(), v.view(), wb.view(), strip, ap);
    advect_scalar(q0c.view(), u.view(), v.view(), wc.view(), strip, ap);
    advect_velocity(u.view(), v.view(), wu.view(), wv.view(), strip, ap);
  }
  for (int offset = 0; offset < 8; ++offset) {
    const Box2 region{{offset, 0}, n};  // vectors from `offset`, a tail of (77 - offset) % 8
    FieldF ga(n, 1), gb(n, 1), gc(n, 1);
    const View<const float> in[] = {q0a.view(), q0b.view(), q0c.view()};
    const View<float> out[] = {ga.view(), gb.view(), gc.view()};
    advect_fields(u.view(), v.view(), in, out, region, ap);
    expect_bitwise(ga.view(), wa, region, "field 0");
    expect_bitwise(gb.view(), wb, region, "field 1");
    expect_bitwise(gc.view(), wc, region, "field 2");

    FieldF gu(n, 1), gv(n, 1);
    advect_velocity(u.view(), v.view(), gu.view(), gv.view(), region, ap);
    expect_bitwise(gu.view(), wu, region, "velocity u");
    expect_bitwise(gv.view(), wv, region, "velocity v");
  }
  // Views of a tile copy (another origin and stride, clamps at the view): vector and tail agree.
  const Box2 core{{13, 6}, {50, 40}};
  const Box2 reach = core.grown(3).intersected(box_of_size(n).grown(1));
  TileCopy tq(q0a, reach), tu(u, reach), tv(v, reach);
  FieldF strips(n, 1), vectors(n, 1);
  const AdvectParams short_trace{1.5f, n, false};
  for (int x0 = core.min.x; x0 < core.max.x; x0 += 7) {
    const Box2 strip{{x0, core.min.y}, {std::min(x0 + 7, core.max.x), core.max.y}};
    advect_scalar(tq.view, tu.view, tv.view, strips.view(), strip, short_trace);
  }
  advect_scalar(tq.view, tu.view, tv.view, vectors.view(), core, short_trace);
  expect_bitwise(vectors.view(), strips, core, "tile copy");
}

// Every kernel gives the same cells on a tile copy (local store) as on the whole field.
// A smooth blob carried once across a periodic box at a fixed Courant number (0.4 cells per
// step along x, 0.3 along y), at three resolutions: semi-Lagrangian advection converges at first
// order (its interpolation error, h^2 per step, over 1/h steps), MacCormack's correction at
// second order, and its error is far smaller at every size.
TEST(Advect, MacCormackConvergesAtSecondOrder) {
  const auto error_after_crossing = [](int n, bool maccormack) {
    const Int2 size{n, n};
    const auto blob = [&](double x, double y) {
      const double sigma = n / 8.0;
      double sum = 0.0;  // periodic images
      for (int a = -1; a <= 1; ++a)
        for (int b = -1; b <= 1; ++b) {
          const double dx = x - n / 2.0 + a * n, dy = y - n / 2.0 + b * n;
          sum += std::exp(-(dx * dx + dy * dy) / (2 * sigma * sigma));
        }
      return sum;
    };
    FieldF q(size, 1), u(size, 1), v(size, 1), hat(size, 1), back(size, 1);
    u.fill(0.4f);
    v.fill(0.3f);
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) q(i, j) = float(blob(i, j));
    const AdvectParams forward{1.0f, size, true}, backward{-1.0f, size, true};
    const int steps = n * 5 / 2;  // x moves by n cells (once around), y by 0.75 n
    for (int s = 0; s < steps; ++s) {
      fill_boundary(q.view(), size, BoundaryFill::periodic());
      advect_scalar(q.view(), u.view(), v.view(), hat.view(), q.interior(), forward);
      if (maccormack) {
        fill_boundary(hat.view(), size, BoundaryFill::periodic());
        advect_scalar(hat.view(), u.view(), v.view(), back.view(), q.interior(), backward);
        const View<const float> q0[] = {q.view()}, h[] = {hat.view()}, b[] = {back.view()};
        const View<float> out[] = {hat.view()};
        maccormack_correct(u.view(), v.view(), q0, h, b, out, q.interior(), forward);
      }
      std::swap(q, hat);
    }
    double err2 = 0.0;
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const double d = q(i, j) - blob(i, j - 0.75 * n);
        err2 += d * d;
      }
    return std::sqrt(err2 / (double(n) * n));
  };
  double previous_sl = 0.0, previous_mc = 0.0;
  for (int n : {32, 64, 128}) {
    const double sl = error_after_crossing(n, false), mc = error_after_crossing(n, true);
    std::printf("n = %3d: semi-Lagrangian %.3e, MacCormack %.3e", n, sl, mc);
    if (previous_sl > 0.0)
      std::printf("  (orders %.2f, %.2f)", std::log2(previous_sl / sl),
                  std::log2(previous_mc / mc));
    std::printf("\n");
    EXPECT_LT(mc, (n == 32 ? 0.5 : 0.25) * sl) << n;
    if (previous_sl > 0.0) {
      EXPECT_LT(std::log2(previous_sl / sl), 1.4) << n;
      EXPECT_GT(std::log2(previous_mc / mc), 1.7) << n;
    }
    previous_sl = sl;
    previous_mc = mc;
  }
}

// The limiter: a square pulse carried by a shear keeps within [0, 1] (unlimited MacCormack
// overshoots at the pulse's edges), and a constant field stays exactly constant.
TEST(Advect, MacCormackLimiterCreatesNoExtremum) {
  const Int2 size{48, 40};
  FieldF q(size, 1), u(size, 1), v(size, 1), hat(size, 1), back(size, 1), out(size, 1);
  for (int j = -1; j <= size.y; ++j)
    for (int i = -1; i <= size.x; ++i) {
      u(i, j) = 0.8f * std::sin(0.2f * float(j));
      v(i, j) = 0.5f * std::cos(0.15f * float(i));
      q(i, j) = (i > 10 && i < 25 && j > 12 && j < 30) ? 1.0f : 0.0f;
    }
  const AdvectParams forward{1.3f, size, false}, backward{-1.3f, size, false};
  advect_scalar(q.view(), u.view(), v.view(), hat.view(), q.interior(), forward);
  fill_boundary(hat.view(), size, BoundaryFill::copy());
  advect_scalar(hat.view(), u.view(), v.view(), back.view(), q.interior(), backward);
  const View<const float> q0[] = {q.view()}, h[] = {hat.view()}, b[] = {back.view()};
  const View<float> o[] = {out.view()};
  maccormack_correct(u.view(), v.view(), q0, h, b, o, q.interior(), forward);
  float lo = 1.0f, hi = 0.0f, unlimited_lo = 1.0f, unlimited_hi = 0.0f;
  for (int j = 0; j < size.y; ++j)
    for (int i = 0; i < size.x; ++i) {
      lo = std::min(lo, out(i, j));
      hi = std::max(hi, out(i, j));
      const float raw = hat(i, j) + 0.5f * (q(i, j) - back(i, j));
      unlimited_lo = std::min(unlimited_lo, raw);
      unlimited_hi = std::max(unlimited_hi, raw);
    }
  EXPECT_GE(lo, 0.0f);
  EXPECT_LE(hi, 1.0f);
  EXPECT_TRUE(unlimited_lo < -0.01f || unlimited_hi > 1.01f) << unlimited_lo << " " << unlimited_hi;
  q.fill(0.625f);
  hat.fill(0.625f);
  back.fill(0.625f);
  maccormack_correct(u.view(), v.view(), q0, h, b, o, q.interior(), forward);
  for (int j = 0; j < size.y; ++j)
    for (int i = 0; i < size.x; ++i) ASSERT_EQ(out(i, j), 0.625f);
}

TEST(FluidKernels, TileEqualsWholeField) {
  const Int2 n{40, 30};
  const Box2 core{{12, 7}, {29, 19}};
  const FieldF q0 = random_field(n, 5), u = random_field(n, 6), v = random_field(n, 7);
  const FieldF x0 = random_field(n, 8), p = random_field(n, 9);
  const AdvectParams ap{2.0f, n, false};  // |u| <= 1: halo ceil(2) + 1 = 3
  const StamSweepParams sp{0.8f, 1.0f / 4.2f};
  const ProjectParams pp{1.0f / 40.0f};

  FieldF whole(n, 1), whole_v(n, 1);
  TileCopy tq(q0, core.grown(3)), tu(u, core.grown(3)), tv(v, core.grown(3));
  TileCopy tx0(x0, core.grown(1)), tp(p, core.grown(1)), tout(whole, core), tout_v(whole, core);
  auto expect_same = [&](const View<float>& tile, const FieldF& f, const char* what) {
    for (int y = core.min.y; y < core.max.y; ++y)
      for (int x = core.min.x; x < core.max.x; ++x)
        ASSERT_EQ(tile(x, y), f(x, y)) << what << " at " << x << "," << y;
  };

  advect_scalar(q0.view(), u.view(), v.view(), whole.view(), core, ap);
  advect_scalar(tq.view, tu.view, tv.view, tout.view, core, ap);
  expect_same(tout.view, whole, "advect_scalar");

  advect_velocity(u.view(), v.view(), whole.view(), whole_v.view(), core, ap);
  advect_velocity(tu.view, tv.view, tout.view, tout_v.view, core, ap);
  expect_same(tout.view, whole, "advect_velocity u");
  expect_same(tout_v.view, whole_v, "advect_velocity v");

  stam_jacobi_sweep(x0.view(), p.view(), whole.view(), core, sp);
  stam_jacobi_sweep(tx0.view, tp.view, tout.view, core, sp);
  expect_same(tout.view, whole, "stam_jacobi_sweep");

  FieldF gs = p;
  TileCopy tgs(p, core.grown(1));
  for (int color : {0, 1}) {
    stam_rbgs_half_sweep(x0.view(), gs.view(), core, color, sp);
    stam_rbgs_half_sweep(tx0.view, tgs.view, core, color, sp);
  }
  expect_same(tgs.view, gs, "stam_rbgs_half_sweep");

  pressure_rhs(u.view(), v.view(), whole.view(), core, pp);
  pressure_rhs(tu.view, tv.view, tout.view, core, pp);
  expect_same(tout.view, whole, "pressure_rhs");

  FieldF gu = u, gv = v;
  TileCopy tgu(u, core), tgv(v, core);
  subtract_gradient(p.view(), gu.view(), gv.view(), core, pp);
  subtract_gradient(tp.view, tgu.view, tgv.view, core, pp);
  expect_same(tgu.view, gu, "subtract_gradient u");
  expect_same(tgv.view, gv, "subtract_gradient v");
}

// The MAC path: face velocities from (u, v, p), then the dye carried by them. Exact for a
// constant field, identical on a tile, and the faces match their formula.
TEST(FluidKernels, FaceVelocitiesAndMacAdvection) {
  const Int2 n{30, 24};
  const float h = 1.0f / 30;
  const FieldF u = random_field(n, 20), v = random_field(n, 21), p = random_field(n, 22);
  FieldF uf(Int2{n.x + 1, n.y}, 1), vf(Int2{n.x, n.y + 1}, 1);
  face_velocities(u.view(), v.view(), p.view(), uf.view(), vf.view(), u.interior(), {h});
  EXPECT_FLOAT_EQ(uf(7, 5), 0.5f * (u(6, 5) + u(7, 5)) - (p(7, 5) - p(6, 5)) / h);
  EXPECT_FLOAT_EQ(uf(n.x, 3), 0.5f * (u(n.x - 1, 3) + u(n.x, 3)) - (p(n.x, 3) - p(n.x - 1, 3)) / h);
  EXPECT_FLOAT_EQ(vf(4, n.y), 0.5f * (v(4, n.y - 1) + v(4, n.y)) - (p(4, n.y) - p(4, n.y - 1)) / h);

  // Scale the faces to at most ~1.5 cells per step: dt/h = 0.05 with |uf| <= ~30.
  const AdvectParams ap{0.05f, n, false};
  FieldF q0(n, 1), q(n, 1);
  q0.fill(-0.3f);
  advect_scalar_mac(q0.view(), uf.view(), vf.view(), q.view(), q.interior(), ap);
  for (int j = 0; j < n.y; ++j)
    for (int i = 0; i < n.x; ++i) ASSERT_EQ(q(i, j), -0.3f);

  const FieldF r0 = random_field(n, 23);
  FieldF whole(n, 1);
  advect_scalar_mac(r0.view(), uf.view(), vf.view(), whole.view(), whole.interior(), ap);
  const Box2 core{{9, 4}, {21, 15}};
  const Box2 halo = core.grown(4);
  TileCopy tq(r0, halo), tout(whole, core);
  FieldF su(halo.size(), 0), sv(halo.size(), 0);
  View<float> tuf(su.raw(), su.stride(), halo), tvf(sv.raw(), sv.stride(), halo);
  copy_box(std::as_const(uf).view(), tuf, halo);
  copy_box(std::as_const(vf).view(), tvf, halo);
  advect_scalar_mac(tq.view, tuf, tvf, tout.view, core, ap);
  for (int y = core.min.y; y < core.max.y; ++y)
    for (int x = core.min.x; x < core.max.x; ++x) ASSERT_EQ(tout.view(x, y), whole(x, y));

  // Vectorised 8 cells at a time where the build allows, with a scalar tail: the same bits.
  // Faces fast enough to hit the wall clamps (dt/h 0.3), and a NaN that must land on a wall.
  FieldF fast_uf = uf, fast_vf = vf;
  fast_uf(12, 7) = std::nanf("");
  fast_vf(3, 19) = std::nanf("");
  const AdvectParams far{0.3f, n, false};
  FieldF strips(n, 1);
  for (int x0 = 0; x0 < n.x; x0 += 7) {  // 7 wide: every cell in a scalar tail
    const Box2 strip{{x0, 0}, {std::min(x0 + 7, n.x), n.y}};
    advect_scalar_mac(r0.view(), fast_uf.view(), fast_vf.view(), strips.view(), strip, far);
  }
  for (int offset = 0; offset < 8; ++offset) {
    FieldF vectors(n, 1);
    const Box2 region{{offset, 0}, n};
    advect_scalar_mac(r0.view(), fast_uf.view(), fast_vf.view(), vectors.view(), region, far);
    for (int y = 0; y < n.y; ++y)
      for (int x = offset; x < n.x; ++x) {
        const float g = vectors(x, y), w = strips(x, y);
        ASSERT_EQ(std::memcmp(&g, &w, sizeof g), 0)
            << "offset " << offset << " at " << x << "," << y;
      }
  }
}

TEST(FluidKernels, StamJacobiSweepFormula) {
  const Int2 n{6, 5};
  const FieldF x0 = random_field(n, 10), x = random_field(n, 11);
  FieldF out(n, 1);
  stam_jacobi_sweep(x0.view(), x.view(), out.view(), out.interior(), {0.5f, 0.25f});
  for (int j = 0; j < n.y; ++j)
    for (int i = 0; i < n.x; ++i)
      ASSERT_FLOAT_EQ(
          out(i, j),
          (x0(i, j) + 0.5f * (x(i - 1, j) + x(i + 1, j) + x(i, j - 1) + x(i, j + 1))) * 0.25f);
}

// The sweep (vectorised 16 cells at a time where the build allows, masked tails, neighbours
// shifted between vectors) is bit for bit the per-cell formula, for every width 1..50 at every
// start offset modulo 16, and writes nothing outside its region.
TEST(FluidKernels, StamJacobiSweepBitwiseAtEveryWidthAndOffset) {
  const Int2 n{70, 4};
  const FieldF x0 = random_field(n, 14), x = random_field(n, 15);
  const StamSweepParams p{0.37f, 1.0f / (1.0f + 4.0f * 0.37f)};
  for (int start = 0; start < 16; ++start)
    for (int width = 1; start + width <= n.x && width <= 50; ++width) {
      FieldF out(n, 1);
      out.fill(-7.0f);
      const Box2 region{{start, 1}, {start + width, 3}};
      stam_jacobi_sweep(x0.view(), x.view(), out.view(), region, p);
      for (int j = -1; j <= n.y; ++j)
        for (int i = -1; i <= n.x; ++i) {
          const float want =
              region.contains(Int2{i, j})
                  ? (x0(i, j) + p.a * (x(i - 1, j) + x(i + 1, j) + x(i, j - 1) + x(i, j + 1))) *
                        p.inv_c
                  : -7.0f;
          const float got = out(i, j);
          ASSERT_EQ(std::memcmp(&got, &want, sizeof got), 0)
              << "start " << start << " width " << width << " cell " << i << "," << j;
        }
    }
}

TEST(FluidKernels, RedBlackHalfSweepTouchesOnlyItsColour) {
  const Int2 n{7, 6};
  const FieldF x0 = random_field(n, 12), x = random_field(n, 13);
  FieldF y = x;
  stam_rbgs_half_sweep(x0.view(), y.view(), Box2{{1, 1}, {6, 5}}, 1, {1.0f, 0.25f});
  for (int j = 0; j < n.y; ++j)
    for (int i = 0; i < n.x; ++i) {
      const bool updated = (i + j) % 2 == 1 && i >= 1 && i < 6 && j >= 1 && j < 5;
      if (!updated)
        ASSERT_EQ(y(i, j), x(i, j)) << i << "," << j;
      else
        ASSERT_FLOAT_EQ(y(i, j),
                        (x0(i, j) + x(i - 1, j) + x(i + 1, j) + x(i, j - 1) + x(i, j + 1)) * 0.25f);
    }
}

TEST(FluidKernels, GradientOfLinearPressureAndDivergenceOfLinearFlow) {
  const Int2 n{10, 10};
  const float h = 0.1f;
  FieldF p(n, 1), u(n, 1), v(n, 1), rhs(n, 1);
  for (int j = -1; j <= n.y; ++j)
    for (int i = -1; i <= n.x; ++i) {
      p(i, j) = 3.0f * i * h - 2.0f * j * h;  // grad p = (3, -2)
      u(i, j) = 0.5f * i * h;                 // div u = 0.5 + 1.5 = 2
      v(i, j) = 1.5f * j * h;
    }
  pressure_rhs(u.view(), v.view(), rhs.view(), rhs.interior(), {h});
  FieldF u2(n, 1), v2(n, 1);
  subtract_gradient(p.view(), u2.view(), v2.view(), u2.interior(), {h});
  for (int j = 0; j < n.y; ++j)
    for (int i = 0; i < n.x; ++i) {
      ASSERT_NEAR(rhs(i, j), -h * h * 2.0f, 1e-6f);
      ASSERT_NEAR(u2(i, j), -3.0f, 1e-4f);
      ASSERT_NEAR(v2(i, j), 2.0f, 1e-4f);
    }
}

TEST(Sources, SplatAndAddScaled) {
  const Int2 n{21, 21};
  FieldF f(n, 1), s(n, 1);
  add_splat(f.view(), f.interior(), {10.0f, 10.0f, 2.0f, 3.0f});
  EXPECT_FLOAT_EQ(f(10, 10), 3.0f);
  EXPECT_FLOAT_EQ(f(12, 10), f(10, 8));
  EXPECT_NEAR(f(12, 10), 3.0f * std::exp(-1.0f), 1e-6f);
  EXPECT_EQ(f(0, 0), 0.0f);  // beyond 3 radii
  s.fill(2.0f);
  add_scaled(s.view(), f.view(), Box2{{0, 0}, {1, 1}}, 0.25f);
  EXPECT_FLOAT_EQ(f(0, 0), 0.5f);
  EXPECT_EQ(f(1, 0), 0.0f);
}

TEST(Sources, InflowStripesByHand) {
  FieldF dye({10, 4}, 1);
  dye.fill(0.5f);
  set_inflow_stripes(dye.view(), {10, 4}, 2, BoundarySide::kTop);  // 4 bands: i * 4 / 10
  const float want[10] = {0, 0, 0, 1, 1, 0, 0, 0, 1, 1};
  for (int i = 0; i < 10; ++i) EXPECT_EQ(dye(i, 3), want[i]) << i;
  EXPECT_EQ(dye(-1, 3), 0.5f);  // the ghosts and the rows below are left alone
  EXPECT_EQ(dye(10, 3), 0.5f);
  EXPECT_EQ(dye(4, 2), 0.5f);
  // Through the left column: 2 bands over 4 cells, j * 2 / 4.
  FieldF left({10, 4}, 1);
  left.fill(0.5f);
  set_inflow_stripes(left.view(), {10, 4}, 1, BoundarySide::kLeft);
  const float want_left[4] = {0, 0, 1, 1};
  for (int j = 0; j < 4; ++j) EXPECT_EQ(left(0, j), want_left[j]) << j;
  EXPECT_EQ(left(1, 0), 0.5f);
}

// fluid_step's boundary right-hand side: factor * scale * value on each kFixed (1) or kMirror
// (2) side, rounded to float per side, corners getting both of their sides.
TEST(StencilOperator, AddBoundaryValuesByHand) {
  const Int2 n{4, 3};
  FieldF b(n, 1);
  b.fill(1.0f);
  BoundaryFill fill = BoundaryFill::copy();   // bottom: copy, adds nothing
  fill.left = {EdgeRule::kFixed, 0.5f};       // 1 * 2 * 0.5 = 1
  fill.right = {EdgeRule::kMirror, 0.25f};    // 2 * 2 * 0.25 = 1
  fill.top = {EdgeRule::kMirror, -1.0f};      // 2 * 2 * -1 = -4
  fill.bottom = {EdgeRule::kPeriodic, 9.0f};  // no share
  add_boundary_values(b.view(), n, fill, 2.0);
  const float want[3][4] = {{2, 1, 1, 2}, {2, 1, 1, 2}, {-2, -3, -3, -2}};  // rows y = 0, 1, 2
  for (int y = 0; y < n.y; ++y)
    for (int x = 0; x < n.x; ++x) EXPECT_EQ(b(x, y), want[y][x]) << x << "," << y;
  EXPECT_EQ(b(-1, 0), 1.0f);  // ghosts untouched
  EXPECT_EQ(b(0, 3), 1.0f);

  // One cell wide: left and right both land on column 0; the amount is rounded once per side.
  FieldF c({1, 2}, 1);
  add_boundary_values(c.view(), {1, 2}, BoundaryFill::fixed(0.1f), 1.0 / 3.0);
  const float side = float(1.0 * (1.0 / 3.0) * double(0.1f));
  EXPECT_EQ(c(0, 0), ((0.0f + side) + side) + side);  // left, right, bottom
  EXPECT_EQ(c(0, 1), ((0.0f + side) + side) + side);  // left, right, top
}

}  // namespace
}  // namespace ardcell
