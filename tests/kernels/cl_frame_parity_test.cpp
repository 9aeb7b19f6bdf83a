// The OpenCL twins the frame needs to run with every field on the device (fluid_step,
// rd_step, the solvers): MAC face velocities and advection, obstacle fills, whole-field copies,
// boundary right-hand sides, the row reductions (mass bookkeeping, residuals, null space), the
// explicit reaction-diffusion steps and the inflow stripes, each against its C++ kernel on PoCL
// (norms and helpers: tests/support/cl_parity.h). Reductions compare the per-row partials:
// bit for bit where the device has doubles (the C++ sums in double), else within the norm.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "kernels/advect.h"
#include "kernels/cl/opencl_kernels.h"
#include "kernels/explicit_rd.h"
#include "kernels/field_reductions.h"
#include "kernels/generalized_rd.h"
#include "kernels/project.h"
#include "kernels/reaction.h"
#include "kernels/sources.h"
#include "kernels/stencil_operator.h"
#include "kernels/stencil_sweeps.h"
#include "runtime/boundary.h"
#include "tests/support/cl_parity.h"

namespace ardcell {
namespace {

using namespace cl_parity;  // NOLINT: the shared helpers of every parity test

// Partials of the device against the C++ ones over rows [y0, y1): the same bits with doubles on
// the device, else within the relative max norm.
void expect_partials(const std::vector<double>& cl, const std::vector<double>& cpp, int y0, int y1,
                     bool exact, const char* what) {
  double diff = 0, ref = 0;
  for (int j = y0; j < y1; ++j) {
    if (exact) {
      ASSERT_EQ(cl[j], cpp[j]) << what << " row " << j;
    }
    diff = std::max(diff, std::abs(cl[j] - cpp[j]));
    ref = std::max(ref, std::abs(cpp[j]));
  }
  EXPECT_LE(diff / std::max(ref, 1e-30), kTolerance) << what;
}

bool device_has_doubles(OpenClKernels& cl) { return cl.row_partials(1).real_bytes == 8; }

// A solid disc at a random centre and radius (seeded), plus a few isolated solid cells (no
// fluid neighbour for some of them: those become 0). Halo 1, the halo fluid.
Field<uint8_t> disc_mask(Int2 size, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> ux(0.0f, float(size.x)), uy(0.0f, float(size.y));
  std::uniform_real_distribution<float> ur(0.5f, 0.4f * float(std::min(size.x, size.y)) + 1.0f);
  const float cx = ux(rng), cy = uy(rng), r = ur(rng);
  Field<uint8_t> solid(size, 1);
  for (int y = 0; y < size.y; ++y)
    for (int x = 0; x < size.x; ++x)
      if ((float(x) - cx) * (float(x) - cx) + (float(y) - cy) * (float(y) - cy) <= r * r)
        solid(x, y) = 1;
  std::uniform_int_distribution<int> px(0, size.x - 1), py(0, size.y - 1);
  for (int i = 0; i < 5; ++i) solid(px(rng), py(rng)) = 1;
  return solid;
}

// ---- Fluid: faces, MAC advection, obstacles, copies, boundary values, inflow -----------------

TEST(ClFrameParity, FaceVelocities) {
  Fixture& d = device();
  ASSERT_TRUE(d.cl);
  Dev dev{*d.ctx};
  const ProjectParams p{1.0f / 37.0f};
  for (Int2 size : kSizes)
    for (const Box2& region : regions_of(size)) {
      FieldF u(size, 1), v(size, 1), pr(size, 1);
      fill_random(u, -1, 1, 40);
      fill_random(v, -1, 1, 41);
      fill_random(pr, -1, 1, 42);
      FieldF uf(Int2{size.x + 1, size.y}, 1), vf(Int2{size.x, size.y + 1}, 1);
      fill_random(uf, -1, 1, 43);
      fill_random(vf, -1, 1, 44);
      FieldF uf_ref = uf, vf_ref = vf;
      face_velocities(u.view(), v.view(), pr.view(), uf_ref.view(), vf_ref.view(), region, p);
      DeviceField du = dev.up(u), dv = dev.up(v), dp = dev.up(pr), duf = dev.up(uf),
                  dvf = dev.up(vf);
      d.cl->face_velocities(du, dv, dp, duf, dvf, region, p);
      const Box2 ufaces{region.min, {region.max.x + 1, region.max.y}};
      const Box2 vfaces{region.min, {region.max.x, region.max.y + 1}};
      EXPECT_LE(relative_error(dev.down(duf), uf_ref, uf, ufaces), kTolerance) << size << region;
      EXPECT_LE(relative_error(dev.down(dvf), vf_ref, vf, vfaces), kTolerance) << size << region;
    }
}

TEST(ClFrameParity, MacAdvectionWallsAndPeriodic) {
  Fixture& d = device();
  ASSERT_TRUE(d.cl);
  Dev dev{*d.ctx};
  for (Int2 size : kSizes)
    for (const Box2& region : regions_of(size))
      for (bool periodic : {false, true}) {
        // Smooth fields and a few cells per step (see ClParity.AdvectionWallsAndPeriodic), the
        // faces from a smooth velocity and pressure as the frame makes them.
        const AdvectParams ap{2.5f, size, periodic};
        FieldF q0(size, 1), u(size, 1), v(size, 1), pr(size, 1), q(size, 1);
        fill_smooth(q0, 0.5f, 0.4f, 1.0f);
        fill_smooth(u, 0.0f, 3.0f, 2.0f);
        fill_smooth(v, 0.0f, 3.0f, 3.0f);
        fill_smooth(pr, 0.0f, 0.05f, 0.5f);
        fill_random(q, 0, 1, 45);
        FieldF uf(Int2{size.x + 1, size.y}, 1), vf(Int2{size.x, size.y + 1}, 1);
        face_velocities(u.view(), v.view(), pr.view(), uf.view(), vf.view(), u.interior(), {1.0f});
        if (periodic) {
          // The ghost rows of uf and ghost columns of vf, wrapped (advect.h).
          for (int x = -1; x <= size.x + 1; ++x) {
            uf(x, -1) = uf(x, size.y - 1);
            uf(x, size.y) = uf(x, 0);
          }
          for (int y = -1; y <= size.y + 1; ++y) {
            vf(-1, y) = vf(size.x - 1, y);
            vf(size.x, y) = vf(0, y);
          }
        }
        FieldF q_ref = q;
        advect_scalar_mac(q0.view(), uf.view(), vf.view(), q_ref.view(), region, ap);
        DeviceField dq0 = dev.up(q0), duf = dev.up(uf), dvf = dev.up(vf), dq = dev.up(q);
        d.cl->advect_scalar_mac(dq0, duf, dvf, dq, region, ap);
        EXPECT_LE(relative_error(dev.down(dq), q_ref, q, region), kTolerance)
            << size << region << periodic;
      }
}

TEST(ClFrameParity, FillObstacleEveryRuleOnARandomDisc) {
  Fixture& d = device();
  ASSERT_TRUE(d.cl);
  Dev dev{*d.ctx};
  unsigned seed = 50;
  for (Int2 size : kSizes)
    for (const Box2& region : regions_of(size)) {
      const Field<uint8_t> solid = disc_mask(size, seed++);
      const DeviceField dsolid = upload_mask(*d.ctx, solid);
      for (ObstacleRule rule : {ObstacleRule::kCopy, ObstacleRule::kNoSlip, ObstacleRule::kZero}) {
        SCOPED_TRACE(::testing::Message() << size << region << " rule " << int(rule));
        FieldF f(size, 1);
        fill_random(f, -1, 1, seed++);
        FieldF ref = f;
        fill_obstacle(ref.view(), solid.view(), region, rule);
        DeviceField df = dev.up(f);
        d.cl->fill_obstacle(df, dsolid, region, rule);
        EXPECT_LE(relative_error(dev.down(df), ref, f, region), kTolerance);
      }
    }
}

TEST(ClFrameParity, UploadMaskIsOneWhereSolid) {
  Fixture& d = device();
  ASSERT_TRUE(d.cl);
  Dev dev{*d.ctx};
  for (int halo : {0, 1}) {
    Field<uint8_t> mask({13, 7}, halo);
    mask(3, 2) = 1;
    mask(12, 6) = 7;
    if (halo) mask(-1, 4) = 1;
    const FieldF got = dev.down(upload_mask(*d.ctx, mask));
    ASSERT_EQ(got.size(), mask.size());
    ASSERT_EQ(got.halo(), 1);
    for (int y = -1; y <= 7; ++y)
      for (int x = -1; x <= 13; ++x) {
        const bool in = mask.with_halo().contains(Int2{x, y}) && mask(x, y) != 0;
        EXPECT_EQ(got(x, y), in ? 1.0f : 0.0f) << x << "," << y;
      }
  }
}

TEST(ClFrameParity, CopyFieldCopiesTheWholeAllocation) {
  Fixture& d = device();
  ASSERT_TRUE(d.cl);
  Dev dev{*d.ctx};
  for (Int2 size : kSizes) {
    FieldF a(size, 1), b(size, 1);
    fill_random(a, -1, 1, 60);
    fill_random(b, -1, 1, 61);
    const DeviceField da = dev.up(a);
    DeviceField db = dev.up(b);
    d.cl->copy_field(da, db);
    const FieldF got = dev.down(db);
    ASSERT_EQ(std::memcmp(got.raw(), a.raw(), a.raw_size() * sizeof(float)), 0) << size;
  }
}

TEST(ClFrameParity, AddBoundaryValuesEveryRule) {
  Fixture& d = device();
  ASSERT_TRUE(d.cl);
  Dev dev{*d.ctx};
  BoundaryFill mixed = BoundaryFill::copy();
  mixed.left = {EdgeRule::kMirror, 0.3f};
  mixed.right = {EdgeRule::kFixed, -1.7f};
  mixed.top = {EdgeRule::kMirror, 1.0f};
  BoundaryFill periodic_x = BoundaryFill::periodic();
  periodic_x.bottom = {EdgeRule::kFixed, 0.25f};
  BoundaryFill parabolic = BoundaryFill::no_slip(0.0f);
  parabolic.left = {EdgeRule::kParabolic, 1.5f};
  parabolic.top = {EdgeRule::kParabolic, -0.7f};
  const std::pair<const char*, BoundaryFill> fills[] = {
      {"copy", BoundaryFill::copy()},       {"fixed", BoundaryFill::fixed(0.25f)},
      {"lid", BoundaryFill::no_slip(1.0f)}, {"mixed", mixed},
      {"periodic-x", periodic_x},           {"parabolic", parabolic}};
  for (Int2 size : {Int2{37, 23}, Int2{129, 65}, Int2{1, 1}, Int2{1, 6}, Int2{6, 1}, Int2{2, 2}})
    for (const auto& [name, fill] : fills)
      for (double scale : {1.0, 0.37}) {
        SCOPED_TRACE(::testing::Message() << name << " " << size << " scale " << scale);
        FieldF b(size, 1);
        fill_random(b, -1, 1, 62);
        FieldF ref = b;
        add_boundary_values(ref.view(), size, fill, scale);
        DeviceField db = dev.up(b);
        d.cl->add_boundary_values(db, fill, scale);
        const FieldF got = dev.down(db);
        // The same float additions in the same order: bit for bit.
        for (std::size_t i = 0; i < b.raw_size(); ++i) ASSERT_EQ(got.raw()[i], ref.raw()[i]) << i;
      }
}

TEST(ClFrameParity, InflowStripes) {
  Fixture& d = device();
  ASSERT_TRUE(d.cl);
  Dev dev{*d.ctx};
  for (Int2 size : kSizes)
    for (int stripes : {1, 3, 7}) {
      FieldF dye(size, 1);
      fill_random(dye, -1, 1, 63);
      for (BoundarySide side :
           {BoundarySide::kLeft, BoundarySide::kRight, BoundarySide::kBottom, BoundarySide::kTop}) {
        FieldF ref = dye;
        set_inflow_stripes(ref.view(), size, stripes, side);
        DeviceField dd = dev.up(dye);
        d.cl->set_inflow_stripes(dd, stripes, side);
        const FieldF got = dev.down(dd);
        for (std::size_t i = 0; i < got.raw_size(); ++i)
          ASSERT_EQ(got.raw()[i], ref.raw()[i]) << size << stripes << int(side);
      }
    }
}

// ---- Reductions ------------------------------------------------------------------------------

std::vector<std::pair<int, int>> bands_of(Int2 size) {
  return {{0, size.y}, {size.y / 3, std::max(size.y / 3, size.y - 1)}};
}

TEST(ClFrameParity, RowSumsRangesAndMassWeights) {
  Fixture& d = device();
  ASSERT_TRUE(d.cl);
  Dev dev{*d.ctx};
  const bool exact = device_has_doubles(*d.cl);
  for (Int2 size : kSizes)
    for (auto [y0, y1] : bands_of(size)) {
      SCOPED_TRACE(::testing::Message() << size << " rows " << y0 << ".." << y1);
      FieldF f(size, 1);
      fill_random(f, 0.1f, 0.9f, 70);
      const DeviceField df = dev.up(f);
      const int ny = size.y;
      std::vector<double> cpp(ny, -1.0), lo(ny, -1.0), hi(ny, -1.0), got(ny, -1.0);
      ClRowPartials ps = d.cl->row_partials(ny), plo = d.cl->row_partials(ny),
                    phi = d.cl->row_partials(ny);

      row_sums(f.view(), size.x, y0, y1, cpp.data());
      d.cl->row_sums(df, y0, y1, ps);
      ps.read(*d.ctx, y0, y1, got.data());
      expect_partials(got, cpp, y0, y1, exact, "row_sums");
      double total = 0.0;
      for (int j = y0; j < y1; ++j) total += cpp[j];
      if (exact) {
        EXPECT_EQ(ps.sum(*d.ctx, y0, y1), total);
      }

      row_ranges(f.view(), size.x, y0, y1, cpp.data(), lo.data(), hi.data());
      d.cl->row_ranges(df, y0, y1, ps, plo, phi);
      ps.read(*d.ctx, y0, y1, got.data());
      expect_partials(got, cpp, y0, y1, exact, "row_ranges sum");
      plo.read(*d.ctx, y0, y1, got.data());
      expect_partials(got, lo, y0, y1, true, "row_ranges lo");  // float values: exact anyway
      phi.read(*d.ctx, y0, y1, got.data());
      expect_partials(got, hi, y0, y1, true, "row_ranges hi");

      const float wlo = 0.15f, whi = 0.85f;  // some cells outside: negative weights
      row_mass_weights(f.view(), size.x, y0, y1, wlo, whi, cpp.data());
      d.cl->row_mass_weights(df, y0, y1, wlo, whi, ps);
      ps.read(*d.ctx, y0, y1, got.data());
      expect_partials(got, cpp, y0, y1, exact, "row_mass_weights");

      for (double k : {0.37, -2.5e3}) {  // a gentle push, and one that clamps
        FieldF ref = f;
        restore_mass_rows(ref.view(), size.x, y0, y1, k, wlo, whi);
        DeviceField dg = dev.up(f);
        d.cl->restore_mass_rows(dg, y0, y1, k, wlo, whi);
        EXPECT_LE(relative_error(dev.down(dg), ref, f, Box2{{0, y0}, {size.x, y1}}), kTolerance)
            << k;
      }
    }
}

TEST(ClFrameParity, MaskedSumsSumsOfSquaresAndResidual) {
  Fixture& d = device();
  ASSERT_TRUE(d.cl);
  Dev dev{*d.ctx};
  const bool exact = device_has_doubles(*d.cl);
  const BoundaryKind kinds[] = {BoundaryKind::kPeriodic, BoundaryKind::kNeumann,
                                BoundaryKind::kDirichlet};
  for (Int2 size : {Int2{127, 93}, Int2{6, 5}, Int2{1, 1}, Int2{5, 1}}) {
    const int ny = size.y;
    FieldF f(size, 1);
    fill_random(f, -1, 1, 80);
    const DeviceField df = dev.up(f);
    std::vector<double> cpp(ny, -1.0), got(ny, -1.0);
    ClRowPartials partials = d.cl->row_partials(ny);

    const Field<uint8_t> mask = disc_mask(size, 81);
    row_masked_sums(f.view(), mask.view(), size.x, 0, ny, cpp.data());
    d.cl->row_masked_sums(df, upload_mask(*d.ctx, mask), 0, ny, partials);
    partials.read(*d.ctx, 0, ny, got.data());
    expect_partials(got, cpp, 0, ny, exact, "row_masked_sums");

    const double squares = stencil::norm2_squared(f);
    d.cl->row_sums_of_squares(df, 0, ny, partials);
    if (exact) {
      EXPECT_EQ(partials.sum(*d.ctx, 0, ny), squares);
    }
    EXPECT_LE(std::abs(partials.sum(*d.ctx, 0, ny) - squares), kTolerance * squares);

    for (BoundaryKind bx : kinds)
      for (BoundaryKind by : kinds) {
        SCOPED_TRACE(::testing::Message() << size << " boundaries " << int(bx) << int(by));
        FieldF k(size, 1), b(size, 1), x(size, 1), r(size, 1);
        fill_random(k, 0.1f, 2.0f, 82);
        fill_random(b, -1, 1, 83);
        fill_random(x, -1, 1, 84);
        fill_random(r, -1, 1, 85);
        const StencilOperator op = assemble_stencil_operator(size, 1.0, 0.8, &k, bx, by);
        ClStencilOperator dop = ClStencilOperator::allocate(*d.ctx, size, bx, by);
        dop.upload(*d.ctx, op);
        const DeviceField db = dev.up(b), dx = dev.up(x);
        FieldF r_ref = r;
        const double total = stencil::residual(op, b, x, &r_ref);
        DeviceField dr = dev.up(r);
        d.cl->residual(dop, db, dx, &dr, partials);
        const double cl_total = partials.sum(*d.ctx, 0, ny);
        if (exact) {
          EXPECT_EQ(cl_total, total);
        }
        EXPECT_LE(std::abs(cl_total - total), kTolerance * total);
        EXPECT_LE(relative_error(dev.down(dr), r_ref, r, box_of_size(size)), kTolerance);
        // Without r: the same sums, nothing written.
        d.cl->residual(dop, db, dx, nullptr, partials);
        EXPECT_EQ(partials.sum(*d.ctx, 0, ny), cl_total);
        EXPECT_EQ(stencil::residual(op, b, x, nullptr), total);
      }
  }
}

// NullSpace::remove_mean on a singular (pure Neumann, then Neumann with isolated solid cells)
// Poisson operator, from the device's masked sums and mean removal.
TEST(ClFrameParity, NullSpaceRemoveMean) {
  Fixture& d = device();
  ASSERT_TRUE(d.cl);
  Dev dev{*d.ctx};
  for (Int2 size : {Int2{127, 93}, Int2{6, 5}})
    for (bool with_solids : {false, true}) {
      SCOPED_TRACE(::testing::Message() << size << (with_solids ? " with solids" : ""));
      StencilOperator op = assemble_stencil_operator(
          size, 0.0, 1.0, nullptr, BoundaryKind::kNeumann, BoundaryKind::kNeumann);
      if (with_solids) isolate_solid_cells(op, disc_mask(size, 90), 0.0);
      stencil::NullSpace null_space(size);
      null_space.analyse(op);
      ASSERT_TRUE(null_space.singular());
      FieldF f(size, 1);
      fill_random(f, 0.5f, 1.5f, 91);  // a large mean: the subtraction matters
      FieldF ref = f;
      null_space.remove_mean(ref);

      const DeviceField mask = upload_mask(*d.ctx, null_space.mask());
      DeviceField df = dev.up(f);
      ClRowPartials partials = d.cl->row_partials(size.y);
      d.cl->row_masked_sums(df, mask, 0, size.y, partials);
      const float mean = float(partials.sum(*d.ctx, 0, size.y) / double(null_space.count()));
      d.cl->subtract_masked(df, mask, mean);
      EXPECT_LE(relative_error(dev.down(df), ref, f, box_of_size(size)), kTolerance);
    }
}

// ---- Explicit reaction-diffusion -------------------------------------------------------------

TEST(ClFrameParity, ExplicitRd5And9EveryModel) {
  Fixture& d = device();
  ASSERT_TRUE(d.cl);
  Dev dev{*d.ctx};
  for (ReactionModel model : {ReactionModel::kGrayScott, ReactionModel::kTuring,
                              ReactionModel::kMeinhardt, ReactionModel::kFitzHughNagumo,
                              ReactionModel::kBarkley, ReactionModel::kBarkleyTurbulent}) {
    ExplicitRdParams p;
    p.reaction.model = model;
    p.dt = 0.05f;
    p.diffusion_a = 0.2f;
    p.diffusion_b = 0.1f;
    const ConcentrationBox r = typical_range(p.reaction);
    for (Int2 size : kSizes)
      for (const Box2& region : regions_of(size))
        for (bool nine : {false, true}) {
          SCOPED_TRACE(::testing::Message() << reaction_model_name(model) << " " << size << region
                                            << (nine ? " 9-point" : " 5-point"));
          FieldF a(size, 1), b(size, 1), a_out(size, 1), b_out(size, 1);
          fill_random(a, float(r.a_lo), float(r.a_hi), 100);
          fill_random(b, float(r.b_lo), float(r.b_hi), 101);
          fill_random(a_out, -1, 1, 102);
          fill_random(b_out, -1, 1, 103);
          FieldF a_ref = a_out, b_ref = b_out;
          if (nine)
            explicit_rd9_tile(a.view(), b.view(), a_ref.view(), b_ref.view(), region, p);
          else
            explicit_rd5_tile(a.view(), b.view(), a_ref.view(), b_ref.view(), region, p);
          const DeviceField da = dev.up(a), db = dev.up(b);
          DeviceField dao = dev.up(a_out), dbo = dev.up(b_out);
          if (nine)
            d.cl->explicit_rd9(da, db, dao, dbo, region, p);
          else
            d.cl->explicit_rd5(da, db, dao, dbo, region, p);
          EXPECT_LE(relative_error(dev.down(dao), a_ref, a_out, region), kTolerance);
          EXPECT_LE(relative_error(dev.down(dbo), b_ref, b_out, region), kTolerance);
        }
  }
}

// Seed 003's Eqn 27 with each of Table 2's stencils: the taps' symmetry groups uploaded
// (stencil_groups) and added in GeneralizedTaps' order in float, so the same bits as the C++.
TEST(ClFrameParity, GeneralizedRdEveryTable2Stencil) {
  Fixture& d = device();
  ASSERT_TRUE(d.cl);
  Dev dev{*d.ctx};
  for (const NamedTensorSequence& seq : kTable2)
    for (ReactionModel model : {ReactionModel::kGrayScott, ReactionModel::kTuring}) {
      SCOPED_TRACE(::testing::Message() << seq.name << " " << reaction_model_name(model));
      const Int2 size{37, 23};
      const GeneralizedTaps taps(assemble_generalized_stencil(seq.tensors));
      GeneralizedRdParams p;
      p.reaction.model = model;
      p.dt = 0.1f;
      p.scale_a = 0.2f;
      p.scale_b = 0.1f;
      const ConcentrationBox r = typical_range(p.reaction);
      FieldF a(size, 2), b(size, 2), a_ref(size, 2), b_ref(size, 2);
      fill_random(a, float(r.a_lo), float(r.a_hi), 120);
      fill_random(b, float(r.b_lo), float(r.b_hi), 121);
      std::vector<float> scratch(generalized_rd_scratch_floats(size.x));
      generalized_rd_rows(taps, a.view(), b.view(), a_ref.view(), b_ref.view(), size, 0, size.y, p,
                          scratch.data());
      const DeviceField da = dev.up(a), db = dev.up(b);
      DeviceField dao = dev.up(a_ref), dbo = dev.up(b_ref);
      const OpenClBuffer groups = d.cl->stencil_groups(taps);
      d.cl->generalized_rd(da, db, dao, dbo, groups, p);
      const FieldF a_got = dev.down(dao), b_got = dev.down(dbo);
      for (int y = 0; y < size.y; ++y)
        for (int x = 0; x < size.x; ++x) {
          ASSERT_EQ(a_got(x, y), a_ref(x, y)) << x << "," << y;
          ASSERT_EQ(b_got(x, y), b_ref(x, y)) << x << "," << y;
        }
    }
}

// Seed 003's per-cell rank-2 tensor field (Table 1's last row): every field kind and the two
// reactions the presets use, with and without the Gray-Scott parameter map; the same float
// arithmetic in the same order, so the same bits.
TEST(ClFrameParity, TensorFieldRdEveryFieldKind) {
  Fixture& d = device();
  ASSERT_TRUE(d.cl);
  Dev dev{*d.ctx};
  for (TensorFieldKind kind :
       {TensorFieldKind::kUniform, TensorFieldKind::kVortex, TensorFieldKind::kRadial})
    for (ReactionModel model : {ReactionModel::kGrayScott, ReactionModel::kTuring})
      for (Int2 size : {Int2{37, 23}, Int2{64, 48}}) {
        SCOPED_TRACE(::testing::Message()
                     << int(kind) << " " << reaction_model_name(model) << " " << size);
        const Rank2FaceField faces = rank2_tensor_field(size, kind, 0.3, 0.07);
        GeneralizedRdParams p;
        p.reaction.model = model;
        p.dt = 0.1f;
        p.scale_a = 1.0f;
        p.scale_b = 0.5f;
        if (model == ReactionModel::kGrayScott) p.f_step = 0.001f, p.k_step = 0.0005f;
        const ConcentrationBox r = typical_range(p.reaction);
        FieldF a(size, 1), b(size, 1), a_ref(size, 1), b_ref(size, 1);
        fill_random(a, float(r.a_lo), float(r.a_hi), 110);
        fill_random(b, float(r.b_lo), float(r.b_hi), 111);
        tensor_field_rd_rows(faces, a.view(), b.view(), a_ref.view(), b_ref.view(), size, 0, size.y,
                             p);
        const DeviceField da = dev.up(a), db = dev.up(b);
        DeviceField dao = dev.up(a_ref), dbo = dev.up(b_ref);
        const DeviceField fxx = dev.up(faces.x_xx), fxy = dev.up(faces.x_xy),
                          gxy = dev.up(faces.y_xy), gyy = dev.up(faces.y_yy);
        d.cl->tensor_field_rd(da, db, dao, dbo, fxx, fxy, gxy, gyy, p);
        const FieldF a_got = dev.down(dao), b_got = dev.down(dbo);
        for (int y = 0; y < size.y; ++y)
          for (int x = 0; x < size.x; ++x) {
            ASSERT_EQ(a_got(x, y), a_ref(x, y)) << x << "," << y;
            ASSERT_EQ(b_got(x, y), b_ref(x, y)) << x << "," << y;
          }
      }
}

TEST(ClFrameParity, GrayScott9Explicit) {
  Fixture& d = device();
  ASSERT_TRUE(d.cl);
  Dev dev{*d.ctx};
  const GrayScott9Params p{0.037f, 0.06f, 1.0f, 1.0f, 0.5f};
  for (Int2 size : kSizes)
    for (const Box2& region : regions_of(size)) {
      FieldF a(size, 1), b(size, 1), a_out(size, 1), b_out(size, 1);
      fill_random(a, 0, 1, 110);
      fill_random(b, 0, 0.5f, 111);
      fill_random(a_out, -1, 1, 112);
      fill_random(b_out, -1, 1, 113);
      FieldF a_ref = a_out, b_ref = b_out;
      std::vector<float> scratch(2 * std::size_t(region.width() + 2));
      gray_scott9_explicit_tile(a.view(), b.view(), a_ref.view(), b_ref.view(), region, p,
                                scratch.data());
      const DeviceField da = dev.up(a), db = dev.up(b);
      DeviceField dao = dev.up(a_out), dbo = dev.up(b_out);
      d.cl->gray_scott9_explicit(da, db, dao, dbo, region, p);
      // Each multiply-add fused as the C++ writes it: on PoCL, the C++ bits.
      const double bound = is_pocl(*d.ctx) ? 0.0 : kTolerance;
      EXPECT_LE(relative_error(dev.down(dao), a_ref, a_out, region), bound) << size << region;
      EXPECT_LE(relative_error(dev.down(dbo), b_ref, b_out, region), bound) << size << region;
    }
}

}  // namespace
}  // namespace ardcell
