// Seed 003's Table 1, last row at rank 2 (rd.generalized.field): the flux-form kernel against the
// homogeneous Gaussian stencil (Eqn 29) for a uniform tensor, its conservation on the periodic
// grid, bands of rows, the developed pattern's orientation along the field, and the refusals.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <vector>

#include "host/engine/engine.h"
#include "host/engine/rd_step.h"
#include "host/scenes/preset.h"
#include "kernels/generalized_rd.h"
#include "tests/support/field_compare.h"
#include "tests/support/preset_params.h"
#include "tests/support/uniform_tensor.h"

namespace ardcell {
namespace {

// A uniform tensor: the flux form is Eqn 29's 9-point stencil (the corners D_xy / 2) summed in
// another order, so one step (Turing reaction and clamp included) agrees to float rounding: a
// few ulps of the values (<= 12), asserted 4e-6.
TEST(TensorFieldRdKernel, UniformFieldIsTheGaussianStencil) {
  const Int2 size{37, 29};
  const float xx = 0.8f, xy = 0.3f, yy = 0.5f;
  const FieldF a = random_field(size, 1, 1, 2.0f, 6.0f), b = random_field(size, 1, 2, 2.0f, 6.0f);
  FieldF a1(size, 1), b1(size, 1), a2(size, 1), b2(size, 1);
  GeneralizedRdParams p;
  p.reaction.model = ReactionModel::kTuring;
  p.reaction.turing_s = 1.0f / 16.0f;
  p.reaction.turing_beta = 12.0f;
  p.reaction.turing_supply = 15.0f;
  p.dt = 0.1f;
  p.scale_a = 0.1f;
  p.scale_b = 0.05f;
  p.a_lo = p.b_lo = 0.0f;
  p.a_hi = p.b_hi = 12.0f;
  tensor_field_rd_rows(uniform_tensor_faces(size, xx, xy, yy), a.view(), b.view(), a1.view(),
                       b1.view(), size, 0, size.y, p);
  std::vector<float> scratch(generalized_rd_scratch_floats(size.x));
  generalized_rd_rows(GeneralizedTaps(gaussian_stencil(xx, xy, yy)), a.view(), b.view(), a2.view(),
                      b2.view(), size, 0, size.y, p, scratch.data());
  double worst = 0;
  for (int y = 0; y < size.y; ++y)
    for (int x = 0; x < size.x; ++x)
      worst = std::max(
          {worst, double(std::abs(a1(x, y) - a2(x, y))), double(std::abs(b1(x, y) - b2(x, y)))});
  std::printf("uniform field against Eqn 29's stencil: max |difference| %.3g\n", worst);
  EXPECT_LT(worst, 4e-6);
}

// Diffusion alone with the vortex field on a periodic grid: the face fluxes cancel in pairs, so
// the total changes by rounding only (the step's float additions), however long it runs.
TEST(TensorFieldRdKernel, ConservesTheTotalOnAPeriodicGrid) {
  const Int2 size{48, 40};
  const Rank2FaceField d = rank2_tensor_field(size, TensorFieldKind::kVortex, 2.0, 0.5);
  FieldF a = random_field(size, 1, 3, 0.0f, 1.0f), b = random_field(size, 1, 4, 0.0f, 1.0f);
  FieldF a_out(size, 1), b_out(size, 1);
  const double before = interior_sum(a);
  GeneralizedRdParams p;
  p.scale_a = p.scale_b = 0.08f;
  for (int i = 0; i < 500; ++i) {
    tensor_field_rd_rows(d, a.view(), b.view(), a_out.view(), b_out.view(), size, 0, size.y, p);
    std::swap(a, a_out);
    std::swap(b, b_out);
  }
  const double drift = std::abs(interior_sum(a) - before) / before;
  double lo = 1, hi = 0;
  for (int y = 0; y < size.y; ++y)
    for (int x = 0; x < size.x; ++x) {
      lo = std::min(lo, double(a(x, y)));
      hi = std::max(hi, double(a(x, y)));
    }
  std::printf(
      "vortex field, 500 steps of diffusion: relative drift of the total %.3g, range "
      "[%.4f, %.4f]\n",
      drift, lo, hi);
  EXPECT_LT(drift, 1e-5);
  EXPECT_LT(hi - lo, 0.5) << "diffusion smooths the noise";
}

TEST(TensorFieldRdKernel, BandsOfRowsGiveTheSameBits) {
  const Int2 size{33, 27};
  const Rank2FaceField d = rank2_tensor_field(size, TensorFieldKind::kRadial, 1.5, 0.2);
  const FieldF a = random_field(size, 1, 5, 0.0f, 1.0f), b = random_field(size, 1, 6, 0.0f, 0.5f);
  GeneralizedRdParams p;
  p.reaction.model = ReactionModel::kGrayScott;
  p.reaction.F = 0.04f;
  p.reaction.k = 0.06f;
  p.dt = 1.0f;
  p.scale_a = 0.2f;
  p.scale_b = 0.1f;
  FieldF a1(size, 1), b1(size, 1), a2(size, 1), b2(size, 1);
  tensor_field_rd_rows(d, a.view(), b.view(), a1.view(), b1.view(), size, 0, size.y, p);
  for (const auto& [y0, y1] : {std::pair{0, 1}, {1, 7}, {7, 20}, {20, 27}})
    tensor_field_rd_rows(d, a.view(), b.view(), a2.view(), b2.view(), size, y0, y1, p);
  for (int y = 0; y < size.y; ++y) {
    EXPECT_EQ(std::memcmp(a1.row(y), a2.row(y), sizeof(float) * size.x), 0) << "row " << y;
    EXPECT_EQ(std::memcmp(b1.row(y), b2.row(y), sizeof(float) * size.x), 0) << "row " << y;
  }
}

// The power of A's gradient along the radius over that along the tangent, over the annulus
// 8 cells from the centre to 4 from the edge: stripes along circles have radial gradients.
double radial_over_tangential(const FieldF& f) {
  const Int2 n = f.size();
  double radial = 0, tangential = 0;
  for (int y = 1; y + 1 < n.y; ++y)
    for (int x = 1; x + 1 < n.x; ++x) {
      const double rx = x + 0.5 - 0.5 * n.x, ry = y + 0.5 - 0.5 * n.y, r = std::hypot(rx, ry);
      if (r < 8 || r > 0.5 * std::min(n.x, n.y) - 4) continue;
      const double gx = 0.5 * (f(x + 1, y) - f(x - 1, y)), gy = 0.5 * (f(x, y + 1) - f(x, y - 1));
      const double gr = (gx * rx + gy * ry) / r, gt = (-gx * ry + gy * rx) / r;
      radial += gr * gr;
      tangential += gt * gt;
    }
  return radial / tangential;
}

// After `frames` frames on an n x n grid.
double developed_ratio(TensorFieldKind kind, const char* preset = "mcgraw-turing-vortex",
                       RdStepStats* stats = nullptr, int n = 96, int frames = 30) {
  SceneConfig scene = builtin_preset_scene(preset);
  scene.size = {n, n};
  scene.domain_width = n * scene.rd.cell_size;
  scene.rd.generalized.field = kind;
  Engine engine(scene);  // threads
  for (int i = 0; i < frames; ++i) engine.step();
  if (stats && engine.rd_stats()) *stats = *engine.rd_stats();
  return radial_over_tangential(engine.state().A);
}

TEST(TensorFieldRdEngine, StripesFollowTheField) {
  const double vortex = developed_ratio(TensorFieldKind::kVortex);
  const double radial = developed_ratio(TensorFieldKind::kRadial);
  std::printf("radial / tangential gradient power: vortex %.3f, radial %.3f\n", vortex, radial);
  EXPECT_GT(vortex, 1.5) << "vortex: stripes along circles";
  EXPECT_LT(radial, 1 / 1.5) << "radial: stripes along rays";
}

// The semi-implicit step (Eqn 28 by BiCGSTAB, kernels/tensor_field_solve.h) at 16 times the
// explicit step: the same orientation, every solve to rd.diffusion_solver's tolerance.
TEST(TensorFieldRdEngine, SemiImplicitStripesFollowTheField) {
  const SceneConfig preset = builtin_preset_scene("mcgraw-turing-radial");
  ASSERT_EQ(preset.rd.scheme, RdScheme::kSemiImplicit);
  RdStepStats sv, sr;
  // 48^2 and 15 frames: the solves are most of the test's time under the sanitizers.
  const double vortex =
      developed_ratio(TensorFieldKind::kVortex, "mcgraw-turing-radial", &sv, 48, 15);
  const double radial =
      developed_ratio(TensorFieldKind::kRadial, "mcgraw-turing-radial", &sr, 48, 15);
  std::printf(
      "semi-implicit, radial / tangential gradient power: vortex %.3f, radial %.3f; last solves "
      "%d and %d steps, residuals %.2g and %.2g\n",
      vortex, radial, sr.diffusion_iterations_a, sr.diffusion_iterations_b, sr.diffusion_residual_a,
      sr.diffusion_residual_b);
  EXPECT_GT(vortex, 1.5) << "vortex: stripes along circles";
  EXPECT_LT(radial, 1 / 1.5) << "radial: stripes along rays";
  for (const RdStepStats& s : {sv, sr}) {
    EXPECT_LE(s.diffusion_residual_a, preset.rd.diffusion_solver.tolerance);
    EXPECT_LE(s.diffusion_residual_b, preset.rd.diffusion_solver.tolerance);
    EXPECT_GT(s.diffusion_iterations_b, 0);
  }
}

// rd.scheme implicit with the field: Eqn 6's reaction (Newton per cell), then the same BiCGSTAB
// solve, every frame's solves to the tolerance and every value finite and within the clamp.
TEST(TensorFieldRdEngine, ImplicitSchemeSolvesToTheTolerance) {
  SceneConfig scene = builtin_preset_scene("mcgraw-turing-radial");
  scene.size = {64, 64};
  scene.domain_width = 64 * scene.rd.cell_size;
  scene.rd.scheme = RdScheme::kImplicit;
  Engine engine(scene);
  for (int i = 0; i < 10; ++i) {
    engine.step();
    ASSERT_TRUE(engine.rd_stats());
    const RdStepStats& s = *engine.rd_stats();
    EXPECT_LE(s.diffusion_residual_a, scene.rd.diffusion_solver.tolerance) << "frame " << i;
    EXPECT_LE(s.diffusion_residual_b, scene.rd.diffusion_solver.tolerance) << "frame " << i;
  }
  const ConcentrationBox box = typical_range(scene.rd.reaction);
  const SimState& st = engine.state();
  float lo = st.A(0, 0), hi = lo;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      ASSERT_TRUE(std::isfinite(st.A(x, y)) && std::isfinite(st.B(x, y))) << x << " " << y;
      ASSERT_GE(st.A(x, y), float(box.a_lo));
      ASSERT_LE(st.A(x, y), float(box.a_hi));
      lo = std::min(lo, st.A(x, y));
      hi = std::max(hi, st.A(x, y));
    }
  EXPECT_GT(hi - lo, 0.1f) << "the Turing instability grows from the noise";
}

TEST(TensorFieldRdEngine, RefusesWhatTheFieldCannotRun) {
  EXPECT_EQ(rd_config_problem(builtin_preset_scene("mcgraw-turing-vortex")), "");
  SceneConfig scene = builtin_preset_scene("mcgraw-turing-vortex");
  for (RdScheme s : {RdScheme::kSemiImplicit, RdScheme::kImplicit}) {
    scene.rd.scheme = s;
    EXPECT_EQ(rd_config_problem(scene), "") << "the solve is BiCGSTAB's";
  }
  scene = builtin_preset_scene("mcgraw-turing-vortex");
  scene.rd.generalized.tensors.xxyy = 1;
  EXPECT_NE(rd_config_problem(scene).find("the tensor field is rank 2"), std::string::npos);
  scene = builtin_preset_scene("mcgraw-turing-vortex");
  scene.rd.generalized.d_across = -1;
  EXPECT_NE(rd_config_problem(scene).find("d_across"), std::string::npos);
  scene = builtin_preset_scene("mcgraw-turing-vortex");
  scene.rd.boundary = BoundaryKind::kNeumann;
  EXPECT_NE(rd_config_problem(scene).find("periodic"), std::string::npos);
  // A new field rebuilds the engine.
  scene = builtin_preset_scene("mcgraw-turing-vortex");
  scene.size = {32, 32};
  Engine engine(scene);
  SceneConfig next = scene;
  next.rd.generalized.field = TensorFieldKind::kRadial;
  const Status s = engine.update_parameters(next);
  ASSERT_FALSE(s);
  EXPECT_NE(s.message().find("rd.generalized.field"), std::string::npos);
}

}  // namespace
}  // namespace ardcell
