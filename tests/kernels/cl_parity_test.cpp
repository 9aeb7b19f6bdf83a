// Every OpenCL twin (kernels/cl/*.cl) against its C++ serial kernel on PoCL (norms and helpers:
// tests/support/cl_parity.h; the frame's later twins: cl_frame_parity_test.cpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include "kernels/advect.h"
#include "kernels/aniso_diffusion.h"
#include "kernels/anisotropy.h"
#include "kernels/cl/opencl_diffusion.h"
#include "kernels/cl/opencl_kernels.h"
#include "kernels/imex_rd.h"
#include "kernels/project.h"
#include "kernels/reaction.h"
#include "kernels/reaction_table.h"
#include "kernels/sources.h"
#include "kernels/stam_sweeps.h"
#include "kernels/stencil_operator.h"
#include "kernels/stencil_sweeps.h"
#include "runtime/boundary.h"
#include "tests/support/cl_parity.h"

namespace ardcell {
namespace {

using namespace cl_parity;  // NOLINT: the shared helpers of every parity test

struct ReactionCase {
  ReactionParams params;
  float a_lo, a_hi, b_lo, b_hi;
  float dt;
};

std::vector<ReactionCase> reaction_cases() {
  std::vector<ReactionCase> cases;
  ReactionParams p;
  p.model = ReactionModel::kGrayScott;
  cases.push_back({p, 0.0f, 1.0f, 0.0f, 1.0f, 1.0f});
  cases.push_back({p, -0.2f, 1.2f, -0.1f, 1.3f, 25.0f});  // clamped inputs, a long step
  p.model = ReactionModel::kTuring;
  cases.push_back({p, 0.0f, 12.0f, 0.0f, 12.0f, 0.5f});
  p.model = ReactionModel::kMeinhardt;
  cases.push_back({p, 0.0f, 6.0f, 0.1f, 6.0f, 0.5f});
  p.model = ReactionModel::kFitzHughNagumo;
  cases.push_back({p, -1.5f, 1.5f, -1.0f, 1.0f, 0.1f});
  p.model = ReactionModel::kBarkley;
  cases.push_back({p, 0.0f, 1.0f, 0.0f, 1.0f, 0.01f});
  p.model = ReactionModel::kBarkleyTurbulent;
  cases.push_back({p, 0.0f, 1.0f, 0.0f, 1.0f, 0.01f});
  return cases;
}

TEST(ClParity, ReactionImplicitEveryModelAtAwkwardSizes) {
  Fixture& d = device();
  ASSERT_TRUE(d.cl);
  for (Int2 size : {Int2{37, 23}, Int2{127, 93}, Int2{129, 65}, Int2{1, 1}}) {
    for (const Box2& region : {box_of_size(size), Box2{{size.x / 3, size.y / 2}, size}}) {
      for (const ReactionCase& rc : reaction_cases()) {
        SCOPED_TRACE(std::string(reaction_model_name(rc.params.model)));
        FieldF a(size, 1), b(size, 1);
        fill_random(a, rc.a_lo, rc.a_hi, 1);
        fill_random(b, rc.b_lo, rc.b_hi, 2);
        FieldF a_ref = a, b_ref = b;
        reaction_implicit_tile(a.view(), b.view(), a_ref.view(), b_ref.view(), region, rc.params,
                               rc.dt);
        // On the device, in place (outputs alias inputs), as the frame runs it.
        DeviceField da = d.ctx->allocate_like(a), db = d.ctx->allocate_like(b);
        d.ctx->upload(a, da);
        d.ctx->upload(b, db);
        d.cl->reaction_implicit(da, db, da, db, region, rc.params, rc.dt);
        FieldF a_cl(size, 1), b_cl(size, 1);
        d.ctx->download(da, a_cl);
        d.ctx->download(db, b_cl);
        EXPECT_LE(relative_error(a_cl, a_ref, a, region), kTolerance) << size << region;
        EXPECT_LE(relative_error(b_cl, b_ref, b, region), kTolerance) << size << region;
      }
    }
  }
}

TEST(ClParity, ParameterChangesAreArgumentsNotRebuilds) {
  Fixture& d = device();
  ASSERT_TRUE(d.cl);
  const int builds = d.ctx->build_count();
  FieldF a({40, 9}, 1), b({40, 9}, 1);
  fill_random(a, 0, 1, 3);
  fill_random(b, 0, 1, 4);
  DeviceField da = d.ctx->allocate_like(a), db = d.ctx->allocate_like(b);
  ReactionParams p;
  for (float F : {0.02f, 0.04f, 0.06f}) {
    p.F = F;
    d.cl->reaction_implicit(da, db, da, db, a.interior(), p, 1.0f);
  }
  d.ctx->finish();
  EXPECT_EQ(OpenClKernels::create(*d.ctx, nullptr) != nullptr, true);
  EXPECT_EQ(d.ctx->build_count(), builds);
}

// The second-order schemes' per-cell kernels: the trapezoidal reaction (every model, in place
// as the frame runs it) and SBDF1/2's right-hand side with its history.
TEST(ClParity, ReactionTrapezoidalEveryModel) {
  Fixture& d = device();
  ASSERT_TRUE(d.cl);
  for (Int2 size : {Int2{37, 23}, Int2{127, 93}}) {
    for (const Box2& region : {box_of_size(size), Box2{{size.x / 3, size.y / 2}, size}}) {
      for (const ReactionCase& rc : reaction_cases()) {
        SCOPED_TRACE(std::string(reaction_model_name(rc.params.model)));
        FieldF a(size, 1), b(size, 1);
        fill_random(a, rc.a_lo, rc.a_hi, 5);
        fill_random(b, rc.b_lo, rc.b_hi, 6);
        FieldF a_ref = a, b_ref = b;
        reaction_trapezoidal_tile(a.view(), b.view(), a_ref.view(), b_ref.view(), region, rc.params,
                                  rc.dt);
        DeviceField da = d.ctx->allocate_like(a), db = d.ctx->allocate_like(b);
        d.ctx->upload(a, da);
        d.ctx->upload(b, db);
        d.cl->reaction_trapezoidal(da, db, da, db, region, rc.params, rc.dt);
        FieldF a_cl(size, 1), b_cl(size, 1);
        d.ctx->download(da, a_cl);
        d.ctx->download(db, b_cl);
        EXPECT_LE(relative_error(a_cl, a_ref, a, region), kTolerance) << size << region;
        EXPECT_LE(relative_error(b_cl, b_ref, b, region), kTolerance) << size << region;
      }
    }
  }
}

TEST(ClParity, SbdfRightHandSideBothOrdersEveryModel) {
  Fixture& d = device();
  ASSERT_TRUE(d.cl);
  const Int2 size{45, 31};
  const Box2 region{{3, 2}, {40, 31}};
  for (const ReactionCase& rc : reaction_cases()) {
    for (int order : {1, 2}) {
      for (bool react : {true, false}) {
        SCOPED_TRACE(::testing::Message() << reaction_model_name(rc.params.model) << " order "
                                          << order << (react ? "" : " no reaction"));
        FieldF a(size, 1), b(size, 1), ap(size, 1), bp(size, 1);
        fill_random(a, rc.a_lo, rc.a_hi, 7);
        fill_random(b, rc.b_lo, rc.b_hi, 8);
        fill_random(ap, rc.a_lo, rc.a_hi, 9);
        fill_random(bp, rc.b_lo, rc.b_hi, 10);
        const FieldF a0 = a, b0 = b;
        const SbdfRhsParams p{rc.params, rc.dt, order, react};
        FieldF ar = a, br = b, apr = ap, bpr = bp;
        sbdf_rhs_tile(ar.view(), br.view(), apr.view(), bpr.view(), region, p);
        DeviceField da = d.ctx->allocate_like(a), db = d.ctx->allocate_like(b);
        DeviceField dap = d.ctx->allocate_like(a), dbp = d.ctx->allocate_like(b);
        d.ctx->upload(a, da);
        d.ctx->upload(b, db);
        d.ctx->upload(ap, dap);
        d.ctx->upload(bp, dbp);
        d.cl->sbdf_rhs(da, db, dap, dbp, region, p);
        FieldF a_cl(size, 1), b_cl(size, 1), ap_cl(size, 1), bp_cl(size, 1);
        d.ctx->download(da, a_cl);
        d.ctx->download(db, b_cl);
        d.ctx->download(dap, ap_cl);
        d.ctx->download(dbp, bp_cl);
        EXPECT_LE(relative_error(a_cl, ar, a0, region), kTolerance);
        EXPECT_LE(relative_error(b_cl, br, b0, region), kTolerance);
        EXPECT_LE(relative_error(ap_cl, apr, ap, region), 0.0);  // the history is a copy
        EXPECT_LE(relative_error(bp_cl, bpr, bp, region), 0.0);
      }
    }
  }
}

// ---- Fluid kernels and boundary fills -------------------------------------------------------

// Runs `body` with big tiles (a few per work-group) and with small ones (many per work-group,
// so the double-buffered walk and partial edge tiles are exercised).
template <class Body>
void for_each_tiling(OpenClKernels& cl, Body&& body) {
  const ClTiling saved = cl.tiling();
  // 128 work-items per group (the GPU choice), 64, and one (the CPU choice, default_tiling).
  for (ClTiling t : {ClTiling{}, ClTiling{64, 16, 64, 4}, ClTiling{8, 4, 64, 1},
                     ClTiling{8, 4, 1, 1}, default_tiling(cl.context().device())}) {
    cl.tiling() = t;
    SCOPED_TRACE(::testing::Message() << "tile " << t.tile_w << "x" << t.tile_h);
    body();
  }
  cl.tiling() = saved;
}

std::vector<std::pair<const char*, BoundaryFill>> every_boundary() {
  BoundaryFill mixed = BoundaryFill::copy();
  mixed.left = mixed.right = {EdgeRule::kPeriodic, 0.0f};
  mixed.top = {EdgeRule::kFixed, 0.7f};
  BoundaryFill channel = BoundaryFill::no_slip(0.0f);  // a parabolic inflow on two sides
  channel.left = {EdgeRule::kParabolic, 1.5f};
  channel.bottom = {EdgeRule::kParabolic, -0.4f};
  return {{"copy", BoundaryFill::copy()},         {"channel", channel},
          {"fixed", BoundaryFill::fixed(0.25f)},  {"stam-u", BoundaryFill::stam(1)},
          {"stam-v", BoundaryFill::stam(2)},      {"lid", BoundaryFill::no_slip(1.0f)},
          {"periodic", BoundaryFill::periodic()}, {"periodic-x", mixed}};
}

TEST(ClParity, BoundaryFillEveryKind) {
  Fixture& d = device();
  ASSERT_TRUE(d.cl);
  Dev dev{*d.ctx};
  for (Int2 size : kSizes)
    for (const auto& [name, fill] : every_boundary()) {
      SCOPED_TRACE(name);
      FieldF f(size, 1);
      fill_random(f, -1, 1, 5);
      FieldF ref = f;
      fill_boundary(ref.view(), size, fill);
      DeviceField df = dev.up(f);
      d.cl->fill_boundary(df, fill);
      const FieldF got = dev.down(df);
      // Copies and averages: bit-for-bit.
      for (std::size_t i = 0; i < f.raw_size(); ++i) ASSERT_EQ(got.raw()[i], ref.raw()[i]) << i;
    }
}

TEST(ClParity, StamJacobiAndRedBlackSweeps) {
  Fixture& d = device();
  ASSERT_TRUE(d.cl);
  Dev dev{*d.ctx};
  const StamSweepParams p{0.37f, 1.0f / (1.0f + 4.0f * 0.37f)};
  for_each_tiling(*d.cl, [&] {
    for (Int2 size : kSizes)
      for (const Box2& region : regions_of(size)) {
        FieldF x0(size, 1), x(size, 1), out(size, 1);
        fill_random(x0, -1, 1, 6);
        fill_random(x, -1, 1, 7);
        fill_random(out, -1, 1, 8);
        FieldF ref = out;
        stam_jacobi_sweep(x0.view(), x.view(), ref.view(), region, p);
        DeviceField dx0 = dev.up(x0), dx = dev.up(x), dout = dev.up(out);
        d.cl->stam_jacobi_sweep(dx0, dx, dout, region, p);
        EXPECT_LE(relative_error(dev.down(dout), ref, out, region), kTolerance) << size << region;

        for (int color : {0, 1}) {
          FieldF rb = x;
          stam_rbgs_half_sweep(x0.view(), rb.view(), region, color, p);
          DeviceField drb = dev.up(x);
          d.cl->stam_rbgs_half_sweep(dx0, drb, region, color, p);
          EXPECT_LE(relative_error(dev.down(drb), rb, x, region), kTolerance) << color;
        }
      }
  });
}

// k sweeps in one residency == k x (sweep + fill), at tiles smaller and larger than k.
// The Cell's 20 sweeps per residency, cut to what the device's local memory holds: the tile
// of the chosen depth fits (a GPU's 48 KiB holds 4 sweeps; the launch would otherwise fail with
// CL_OUT_OF_RESOURCES) and is at least half of the cells a residency computes.
TEST(ClParity, BlockedSweepsFitTheLocalMemory) {
  Fixture& d = device();
  ASSERT_TRUE(d.cl);
  for (int wanted : {1, 4, 20, 64}) {
    const int k = d.cl->blocked_sweeps(wanted);
    const Int2 t = d.cl->blocked_tile(k);
    SCOPED_TRACE(::testing::Message() << "wanted " << wanted << " k " << k << " tile " << t);
    EXPECT_GE(k, 1);
    EXPECT_LE(k, wanted);
    ASSERT_GT(t.x, 0);
    EXPECT_LE(5 * sizeof(float) * std::size_t(t.x + 2 * k) * std::size_t(t.y + 2 * k),
              d.ctx->device().local_mem_bytes);
    if (k > 1) {
      EXPECT_GE(2 * t.x * t.y, (t.x + 2 * k) * (t.y + 2 * k));
    }
  }
}

TEST(ClParity, TemporallyBlockedJacobiEqualsSweepBySweep) {
  Fixture& d = device();
  ASSERT_TRUE(d.cl);
  Dev dev{*d.ctx};
  const StamSweepParams p{0.8f, 1.0f / (1.0f + 4.0f * 0.8f)};
  for (Int2 size : kSizes)
    for (const auto& [name, fill] : every_boundary()) {
      if (fill.left.rule == EdgeRule::kPeriodic) continue;  // sweep by sweep (stream) only
      for (int k : {1, 3, 8})
        for (Int2 tile : {Int2{8, 4}, Int2{32, 16}, d.cl->blocked_tile(k)}) {
          SCOPED_TRACE(::testing::Message() << name << " k " << k << " tile " << tile);
          FieldF rhs(size, 1), x(size, 1);
          fill_random(rhs, -1, 1, 20);
          fill_random(x, -1, 1, 21);
          fill_boundary(rhs.view(), size, fill);
          fill_boundary(x.view(), size, fill);
          FieldF a = x, b(size, 1);
          for (int s = 0; s < k; ++s) {
            stam_jacobi_sweep(rhs.view(), a.view(), b.view(), rhs.interior(), p);
            fill_boundary(b.view(), size, fill);
            std::swap(a, b);
          }
          DeviceField drhs = dev.up(rhs), dx = dev.up(x), dout = dev.up(FieldF(size, 1));
          d.cl->stam_jacobi_blocked(drhs, dx, dout, k, p, fill, tile);
          const FieldF got = dev.down(dout);
          EXPECT_LE(relative_error(got, a, got, rhs.with_halo()), kTolerance);
        }
    }
}

TEST(ClParity, DivergenceAndGradient) {
  Fixture& d = device();
  ASSERT_TRUE(d.cl);
  Dev dev{*d.ctx};
  const ProjectParams p{1.0f / 37.0f};
  for_each_tiling(*d.cl, [&] {
    for (Int2 size : kSizes)
      for (const Box2& region : regions_of(size)) {
        FieldF u(size, 1), v(size, 1), rhs(size, 1), pr(size, 1);
        fill_random(u, -1, 1, 9);
        fill_random(v, -1, 1, 10);
        fill_random(rhs, -1, 1, 11);
        fill_random(pr, -1, 1, 12);
        FieldF rhs_ref = rhs;
        pressure_rhs(u.view(), v.view(), rhs_ref.view(), region, p);
        DeviceField du = dev.up(u), dv = dev.up(v), drhs = dev.up(rhs), dp = dev.up(pr);
        d.cl->pressure_rhs(du, dv, drhs, region, p);
        EXPECT_LE(relative_error(dev.down(drhs), rhs_ref, rhs, region), kTolerance);

        // The cut-cell form, open fractions in [0, 1] with some faces shut.
        FieldF ox(Int2{size.x + 1, size.y}, 1), oy(Int2{size.x, size.y + 1}, 1);
        fill_random(ox, -0.5f, 1, 13);
        fill_random(oy, -0.5f, 1, 14);
        for (FieldF* o : {&ox, &oy})
          for (std::size_t i = 0; i < o->raw_size(); ++i) o->raw()[i] = std::max(0.0f, o->raw()[i]);
        FieldF cut_ref = rhs;
        pressure_rhs_cut(u.view(), v.view(), ox.view(), oy.view(), cut_ref.view(), region, p);
        DeviceField dcut = dev.up(rhs), dox = dev.up(ox), doy = dev.up(oy);
        d.cl->pressure_rhs_cut(du, dv, dox, doy, dcut, region, p);
        EXPECT_LE(relative_error(dev.down(dcut), cut_ref, rhs, region), kTolerance);

        FieldF u_ref = u, v_ref = v;
        subtract_gradient(pr.view(), u_ref.view(), v_ref.view(), region, p);
        d.cl->subtract_gradient(dp, du, dv, region, p);
        EXPECT_LE(relative_error(dev.down(du), u_ref, u, region), kTolerance);
        EXPECT_LE(relative_error(dev.down(dv), v_ref, v, region), kTolerance);
      }
  });
}

TEST(ClParity, AdvectionWallsAndPeriodic) {
  Fixture& d = device();
  ASSERT_TRUE(d.cl);
  Dev dev{*d.ctx};
  for (Int2 size : kSizes)
    for (const Box2& region : regions_of(size))
      for (bool periodic : {false, true}) {
        // Velocities of a few cells per step, so back-traces cross walls and wrap. Smooth
        // fields, as a flow carries: on white noise a one-ulp change of the back-traced point
        // (an fma the C++ compiler may contract) moves the result by ulp * |grad q|, which
        // noise makes arbitrarily large.
        const AdvectParams p{2.5f, size, periodic};
        FieldF q0(size, 1), u(size, 1), v(size, 1), q(size, 1);
        fill_smooth(q0, 0.5f, 0.4f, 1.0f);
        fill_smooth(u, 0.0f, 3.0f, 2.0f);
        fill_smooth(v, 0.0f, 3.0f, 3.0f);
        fill_random(q, 0, 1, 16);
        FieldF q_ref = q;
        advect_scalar(q0.view(), u.view(), v.view(), q_ref.view(), region, p);
        DeviceField dq0 = dev.up(q0), du = dev.up(u), dv = dev.up(v), dq = dev.up(q);
        d.cl->advect_scalar(dq0, du, dv, dq, region, p);
        EXPECT_LE(relative_error(dev.down(dq), q_ref, q, region), kTolerance) << periodic;

        // Three scalars on one back-trace: bit for bit three single advections on the device.
        FieldF q0b(size, 1), q0c(size, 1);
        fill_smooth(q0b, 0.2f, 0.1f, 1.5f);
        fill_smooth(q0c, 0.7f, 0.3f, 2.5f);
        DeviceField dq0b = dev.up(q0b), dq0c = dev.up(q0c);
        DeviceField ea = dev.up(q), eb = dev.up(q), ec = dev.up(q);
        d.cl->advect_scalar(dq0b, du, dv, eb, region, p);
        d.cl->advect_scalar(dq0c, du, dv, ec, region, p);
        DeviceField ta = dev.up(q), tb = dev.up(q), tc = dev.up(q);
        d.cl->advect_scalar3(dq0, dq0b, dq0c, du, dv, ta, tb, tc, region, p);
        const FieldF single_a = dev.down(dq), fused_a = dev.down(ta);
        const FieldF single_b = dev.down(eb), fused_b = dev.down(tb);
        const FieldF single_c = dev.down(ec), fused_c = dev.down(tc);
        for (int y = region.min.y; y < region.max.y; ++y)
          for (int x = region.min.x; x < region.max.x; ++x) {
            ASSERT_EQ(fused_a(x, y), single_a(x, y)) << x << "," << y;
            ASSERT_EQ(fused_b(x, y), single_b(x, y)) << x << "," << y;
            ASSERT_EQ(fused_c(x, y), single_c(x, y)) << x << "," << y;
          }

        FieldF uo(size, 1), vo(size, 1);
        FieldF uo_ref = uo, vo_ref = vo;
        advect_velocity(u.view(), v.view(), uo_ref.view(), vo_ref.view(), region, p);
        DeviceField duo = dev.up(uo), dvo = dev.up(vo);
        d.cl->advect_velocity(du, dv, duo, dvo, region, p);
        EXPECT_LE(relative_error(dev.down(duo), uo_ref, uo, region), kTolerance);
        EXPECT_LE(relative_error(dev.down(dvo), vo_ref, vo, region), kTolerance);
      }
}

// MacCormack's limited correction, by cell-centred and by face velocities, into a separate field
// and in place over q_hat (as the engine runs it).
TEST(ClParity, MacCormackCorrection) {
  Fixture& d = device();
  ASSERT_TRUE(d.cl);
  Dev dev{*d.ctx};
  for (Int2 size : kSizes)
    for (const Box2& region : regions_of(size))
      for (bool periodic : {false, true})
        for (bool mac : {false, true}) {
          const AdvectParams p{2.5f, size, periodic};
          FieldF q0(size, 1), hat(size, 1), back(size, 1), q(size, 1);
          fill_smooth(q0, 0.5f, 0.4f, 1.0f);
          fill_smooth(hat, 0.5f, 0.4f, 1.1f);
          fill_smooth(back, 0.5f, 0.4f, 0.9f);
          fill_random(q, 0, 1, 17);
          const Int2 usize = mac ? Int2{size.x + 1, size.y} : size;
          const Int2 vsize = mac ? Int2{size.x, size.y + 1} : size;
          FieldF u(usize, 1), v(vsize, 1);
          // No velocity of round-off size at a cell centre: the limiter's bounds jump where a
          // departure point crosses a cell edge, so a back-trace of 1e-15 cells lands on either
          // side depending on the last bit (as it would on one back end run twice with another
          // rounding).
          fill_smooth(u, 0.0f, 3.0f, 2.3f);
          fill_smooth(v, 0.0f, 3.0f, 3.7f);
          FieldF q_ref = q, hat_ref = hat;
          if (mac) {
            maccormack_correct_mac(q0.view(), hat.view(), back.view(), u.view(), v.view(),
                                   q_ref.view(), region, p);
            maccormack_correct_mac(q0.view(), hat_ref.view(), back.view(), u.view(), v.view(),
                                   hat_ref.view(), region, p);
          } else {
            const View<const float> in[] = {q0.view()}, h[] = {hat.view()}, b[] = {back.view()};
            const View<float> out[] = {q_ref.view()};
            maccormack_correct(u.view(), v.view(), in, h, b, out, region, p);
            const View<const float> h2[] = {hat_ref.view()};
            const View<float> out2[] = {hat_ref.view()};
            maccormack_correct(u.view(), v.view(), in, h2, b, out2, region, p);
          }
          DeviceField dq0 = dev.up(q0), dhat = dev.up(hat), dback = dev.up(back), dq = dev.up(q);
          DeviceField du = dev.up(u), dv = dev.up(v);
          d.cl->maccormack_correct(dq0, dhat, dback, du, dv, dq, region, p, mac);
          EXPECT_LE(relative_error(dev.down(dq), q_ref, q, region), kTolerance)
              << size.x << "x" << size.y << " periodic " << periodic << " mac " << mac;
          d.cl->maccormack_correct(dq0, dhat, dback, du, dv, dhat, region, p, mac);
          EXPECT_LE(relative_error(dev.down(dhat), hat_ref, hat, region), kTolerance)
              << "in place, " << size.x << "x" << size.y << " periodic " << periodic << " mac "
              << mac;
        }
}

TEST(ClParity, SourcesAndSplats) {
  Fixture& d = device();
  ASSERT_TRUE(d.cl);
  Dev dev{*d.ctx};
  for (Int2 size : kSizes)
    for (const Box2& region : regions_of(size)) {
      FieldF s(size, 1), x(size, 1);
      fill_random(s, -1, 1, 17);
      fill_random(x, -1, 1, 18);
      FieldF x_ref = x;
      add_scaled(s.view(), x_ref.view(), region, 0.125f);
      const SplatParams splat{float(size.x) * 0.4f, float(size.y) * 0.6f, 3.5f, 2.0f};
      add_splat(x_ref.view(), region, splat);
      DeviceField ds = dev.up(s), dx = dev.up(x);
      d.cl->add_scaled(ds, dx, region, 0.125f);
      d.cl->add_splat(dx, region, splat);
      EXPECT_LE(relative_error(dev.down(dx), x_ref, x, region), kTolerance) << size << region;
    }
}

// ---- Reaction-diffusion: the table reaction, anisotropy (Eqns 15, 16, polar), the Eqn 17/19
// operator, its Jacobi and red-black sweeps, and the whole implicit diffusion step.

const Int2 kRdSizes[] = {{127, 93}, {6, 5}, {1, 1}};
const BoundaryKind kBoundaryKinds[] = {BoundaryKind::kPeriodic, BoundaryKind::kNeumann,
                                       BoundaryKind::kDirichlet};

TEST(ClParity, ReactionTableEveryModel) {
  Fixture& d = device();
  ASSERT_TRUE(d.cl);
  Dev dev{*d.ctx};
  ClReactionTable table_cl;
  for (const ReactionCase& rc : reaction_cases()) {
    SCOPED_TRACE(std::string(reaction_model_name(rc.params.model)));
    const ReactionTable table(rc.params, rc.dt, typical_range(rc.params), 33);
    table_cl.upload(*d.ctx, table.view());
    for (Int2 size : {Int2{127, 93}, Int2{5, 3}})
      for (const Box2& region : regions_of(size)) {
        // Inputs reach past the table's range (clamped there).
        const ConcentrationBox r = typical_range(rc.params);
        const double pad_a = 0.1 * (r.a_hi - r.a_lo), pad_b = 0.1 * (r.b_hi - r.b_lo);
        FieldF a(size, 1), b(size, 1);
        fill_random(a, float(r.a_lo - pad_a), float(r.a_hi + pad_a), 30);
        fill_random(b, float(r.b_lo - pad_b), float(r.b_hi + pad_b), 31);
        FieldF a_ref = a, b_ref = b;
        reaction_table_tile(a.view(), b.view(), a_ref.view(), b_ref.view(), region, table.view());
        DeviceField da = dev.up(a), db = dev.up(b);
        d.cl->reaction_table(da, db, da, db, region, table_cl);  // in place, as a frame runs it
        EXPECT_LE(relative_error(dev.down(da), a_ref, a, region), kTolerance) << size << region;
        EXPECT_LE(relative_error(dev.down(db), b_ref, b, region), kTolerance) << size << region;
      }
  }
}

std::vector<std::pair<const char*, AnisotropyParams>> every_anisotropy() {
  AnisotropyParams iso;
  iso.kind = AnisotropyKind::kIsotropic;
  iso.isotropic_value = 0.7f;
  AnisotropyParams wk;
  wk.kind = AnisotropyKind::kWitkinKass;
  wk.a1 = 1.0f;
  wk.a2 = 0.2f;
  wk.theta0 = 0.3f;
  AnisotropyParams one_lobe;
  one_lobe.kind = AnisotropyKind::kCosineLobes;
  one_lobe.lobes = 1;
  one_lobe.lobe_speed[0] = 0.9f;
  AnisotropyParams five_lobes = one_lobe;
  five_lobes.lobes = 5;
  for (int n = 0; n < 5; ++n) five_lobes.lobe_speed[n] = 0.2f * float(n + 1);
  five_lobes.theta0 = -2.0f;
  AnisotropyParams polar;
  polar.kind = AnisotropyKind::kPolarSamples;
  polar.samples = 7;
  for (int i = 0; i < 7; ++i) polar.sample[i] = 0.1f + 0.15f * float(i);
  return {{"isotropic", iso},
          {"witkin-kass", wk},
          {"one lobe", one_lobe},
          {"five lobes", five_lobes},
          {"polar", polar}};
}

// A smooth field with a flat block (zero gradient: theta = 0 there), halo filled.
FieldF chemical(Int2 size) {
  FieldF a(size, 1);
  fill_smooth(a, 0.5f, 0.4f, 0.7f);
  for (int y = size.y / 4; y < size.y / 2; ++y)
    for (int x = size.x / 4; x < size.x / 2; ++x) a(x, y) = 0.25f;
  return a;
}

TEST(ClParity, ConductivityEveryAnisotropy) {
  Fixture& d = device();
  ASSERT_TRUE(d.cl);
  Dev dev{*d.ctx};
  for (Int2 size : kRdSizes)
    for (const Box2& region : {box_of_size(size), Box2{{size.x / 3, 0}, {size.x, size.y / 2}}})
      for (const auto& [name, params] : every_anisotropy())
        for (bool per_cell : {false, true}) {
          SCOPED_TRACE(::testing::Message() << name << (per_cell ? " theta0 field" : ""));
          const FieldF a = chemical(size);
          FieldF theta0(size, 1), k(size, 1);
          fill_random(theta0, -4.0f, 8.0f, 32);  // beyond [0, 2 pi): wrapped
          fill_random(k, -1, 1, 33);
          FieldF k_ref = k;
          conductivity_tile(a.view(), per_cell ? theta0.view() : View<const float>{}, k_ref.view(),
                            region, params);
          DeviceField da = dev.up(a), dtheta0 = dev.up(theta0), dk = dev.up(k);
          d.cl->conductivity(da, per_cell ? &dtheta0 : nullptr, dk, region, params);
          EXPECT_LE(relative_error(dev.down(dk), k_ref, k, region), kTolerance) << size << region;
        }
}

TEST(ClParity, StencilOperatorAssemblyEveryBoundary) {
  Fixture& d = device();
  ASSERT_TRUE(d.cl);
  Dev dev{*d.ctx};
  for (Int2 size : kRdSizes)
    for (BoundaryKind bx : kBoundaryKinds)
      for (BoundaryKind by : kBoundaryKinds)
        for (bool with_k : {false, true})
          for (auto [identity, scale] : {std::pair{1.0f, 0.37f}, std::pair{0.0f, 1.0f}}) {
            SCOPED_TRACE(::testing::Message() << size << " boundaries " << int(bx) << int(by)
                                              << (with_k ? " k" : "") << " identity " << identity);
            FieldF k(size, 1);
            fill_random(k, 0.1f, 2.0f, 34);
            const StencilOperator ref =
                assemble_stencil_operator(size, identity, scale, with_k ? &k : nullptr, bx, by);
            ClStencilOperator op = ClStencilOperator::allocate(*d.ctx, size, bx, by);
            const DeviceField dk = dev.up(k);
            d.cl->assemble_stencil_operator(op, identity, scale, with_k ? &dk : nullptr);
            EXPECT_LE(region_error(dev.down(op.diag), ref.diag, ref.diag.interior()), kTolerance);
            EXPECT_LE(region_error(dev.down(op.wx), ref.wx, ref.wx.interior()), kTolerance);
            EXPECT_LE(region_error(dev.down(op.wy), ref.wy, ref.wy.interior()), kTolerance);
          }
}

// On the same (host-assembled) operator: one Jacobi sweep, y = A x, and three red-black sweeps
// (127 x 93 is odd both ways: periodic edges then couple cells of one colour).
TEST(ClParity, StencilJacobiRedBlackAndApplyEveryBoundary) {
  Fixture& d = device();
  ASSERT_TRUE(d.cl);
  Dev dev{*d.ctx};
  for (Int2 size : kRdSizes)
    for (BoundaryKind bx : kBoundaryKinds)
      for (BoundaryKind by : kBoundaryKinds) {
        SCOPED_TRACE(::testing::Message() << size << " boundaries " << int(bx) << int(by));
        FieldF k(size, 1), b(size, 1), x(size, 1), out(size, 1);
        fill_random(k, 0.1f, 2.0f, 35);
        fill_random(b, -1, 1, 36);
        fill_random(x, -1, 1, 37);
        fill_random(out, -1, 1, 38);
        const StencilOperator op = assemble_stencil_operator(size, 1.0, 0.8, &k, bx, by);
        ClStencilOperator dop = ClStencilOperator::allocate(*d.ctx, size, bx, by);
        dop.upload(*d.ctx, op);
        const DeviceField db = dev.up(b), dx = dev.up(x);

        FieldF jac = out;
        stencil::jacobi_sweep(op, b, x, jac);
        DeviceField dout = dev.up(out);
        d.cl->stencil_jacobi_sweep(dop, db, dx, dout);
        EXPECT_LE(relative_error(dev.down(dout), jac, out, box_of_size(size)), kTolerance);

        FieldF ax = out;
        apply_stencil_operator(op, x, ax);
        DeviceField dax = dev.up(out);
        d.cl->apply_stencil_operator(dop, dx, dax);
        EXPECT_LE(relative_error(dev.down(dax), ax, out, box_of_size(size)), kTolerance);

        FieldF rb = x;
        DeviceField drb = dev.up(x);
        for (int sweep = 0; sweep < 3; ++sweep) {
          stencil::rbgs_sweep(op, b, rb);
          d.cl->stencil_rbgs_half_sweep(dop, db, drb, 0);
          d.cl->stencil_rbgs_half_sweep(dop, db, drb, 1);
        }
        EXPECT_LE(relative_error(dev.down(drb), rb, x, box_of_size(size)), kTolerance);
      }
}

// The whole implicit step, conductivity included: ImplicitDiffusion (Jacobi or red-black, fixed
// sweeps) against OpenClDiffusion fed by the conductivity kernel.
TEST(ClParity, ImplicitDiffusionStepIsotropicAndAnisotropic) {
  Fixture& d = device();
  ASSERT_TRUE(d.cl);
  Dev dev{*d.ctx};
  AnisotropyParams wk;
  wk.kind = AnisotropyKind::kWitkinKass;
  wk.a1 = 1.0f;
  wk.a2 = 0.1f;
  for (Int2 size : {Int2{127, 93}, Int2{6, 5}})
    for (BoundaryKind boundary : kBoundaryKinds)
      for (SolverKind kind : {SolverKind::kJacobi, SolverKind::kRedBlackGaussSeidel})
        for (bool crank : {false, true})
          for (bool anisotropic : {false, true}) {
            SCOPED_TRACE(::testing::Message()
                         << size << " boundary " << int(boundary) << " " << solver_kind_name(kind)
                         << (crank ? " CN" : "") << (anisotropic ? " witkin-kass" : " isotropic"));
            const DiffusionStep step{2.5, 0.3f, crank};
            FieldF a = chemical(size);
            fill_boundary(a.view(), size,
                          boundary == BoundaryKind::kPeriodic  ? BoundaryFill::periodic()
                          : boundary == BoundaryKind::kNeumann ? BoundaryFill::copy()
                                                               : BoundaryFill::fixed(0.3f));
            FieldF k(size, 1);
            conductivity_tile(a.view(), {}, k.view(), a.interior(), wk);
            const SolverSettings solver{kind, 12, 0.0};
            ImplicitDiffusion cpu(size, boundary, solver);
            FieldF ref = a;
            cpu.step(ref, anisotropic ? &k : nullptr, step);

            OpenClDiffusion gpu(*d.cl, size, boundary, solver);
            DeviceField da = dev.up(a), dk = dev.up(FieldF(size, 1));
            d.cl->conductivity(da, nullptr, dk, a.interior(), wk);
            gpu.step(da, anisotropic ? &dk : nullptr, step);
            EXPECT_LE(relative_error(dev.down(da), ref, a, a.interior()), kTolerance);
          }
}

// Every RD parameter is a kernel argument or a buffer write: none rebuilds the program.
TEST(ClParity, RdParameterChangesRebuildNothing) {
  Fixture& d = device();
  ASSERT_TRUE(d.cl);
  Dev dev{*d.ctx};
  const Int2 size{40, 9};
  DeviceField a = dev.up(chemical(size)), b = dev.up(chemical(size)), k = dev.up(FieldF(size, 1));
  const int builds = d.ctx->build_count();
  ClReactionTable table;
  OpenClDiffusion diffusion(*d.cl, size, BoundaryKind::kNeumann, {SolverKind::kJacobi, 4, 0.0});
  for (const auto& [name, params] : every_anisotropy()) {
    d.cl->conductivity(a, nullptr, k, box_of_size(size), params);
    for (float rate : {0.5f, 2.0f}) diffusion.step(a, &k, DiffusionStep{rate, 0.0f, false});
  }
  diffusion.set_limits(9, 0.0);
  diffusion.step(a, nullptr, DiffusionStep{1.0, 0.0f, true});
  for (float F : {0.03f, 0.05f}) {
    ReactionParams p;
    p.F = F;
    const ReactionTable t(p, 1.0, typical_range(p), 8);
    table.upload(*d.ctx, t.view());
    d.cl->reaction_table(a, b, a, b, box_of_size(size), table);
  }
  d.ctx->finish();
  EXPECT_EQ(d.ctx->build_count(), builds);
}

}  // namespace
}  // namespace ardcell
