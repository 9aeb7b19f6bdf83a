// Every OpenCL twin (kernels/cl/*.cl) against its C++ serial kernel on PoCL, at awkward sizes
// (not multiples of the tile or of a work-group) and over awkward regions.
//
// Norm: normwise relative error in the max norm over the written region,
//   err = max_cells |cl - cpp| / max(max_cells |cpp|, 1e-30),
// required <= 1e-5. Cells outside the region (halo and padding included) must be untouched:
// exact equality.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include "kernels/cl/opencl_kernels.h"
#include "kernels/reaction.h"

namespace ardcell {
namespace {

constexpr double kTolerance = 1e-5;

struct Fixture {
  std::unique_ptr<OpenClContext> ctx;
  std::unique_ptr<OpenClKernels> cl;
};

Fixture& device() {
  static Fixture f = [] {
    Fixture fx;
    std::string error;
    fx.ctx = OpenClContext::open(0, &error);
    if (fx.ctx) fx.cl = OpenClKernels::create(*fx.ctx, &error);
    if (!fx.cl) ADD_FAILURE() << error;
    return fx;
  }();
  return f;
}

void fill_random(FieldF& f, float lo, float hi, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> d(lo, hi);
  for (std::size_t i = 0; i < f.raw_size(); ++i) f.raw()[i] = d(rng);
}

// Normwise relative max-norm error over `region`; also checks every cell outside it is
// bit-identical to `before`.
double relative_error(const FieldF& cl, const FieldF& cpp, const FieldF& before, Box2 region) {
  double diff = 0, ref = 0;
  for (int y = -cl.halo(); y < cl.ny() + cl.halo(); ++y)
    for (int x = -cl.halo(); x < cl.nx() + cl.halo(); ++x) {
      if (region.contains(Int2{x, y})) {
        diff = std::max(diff, std::abs(double(cl(x, y)) - double(cpp(x, y))));
        ref = std::max(ref, std::abs(double(cpp(x, y))));
      } else if (cl(x, y) != before(x, y)) {
        ADD_FAILURE() << "cell (" << x << ", " << y << ") outside " << region << " was written";
        return 1.0;
      }
    }
  return diff / std::max(ref, 1e-30);
}

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
  for (Int2 size : {Int2{37, 23}, Int2{129, 65}, Int2{1, 1}}) {
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

}  // namespace
}  // namespace ardcell
