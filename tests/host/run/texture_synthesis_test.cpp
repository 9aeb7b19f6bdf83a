// Coarse-to-fine synthesis (host/run/texture_synthesis.h): periodic bilinear prolongation
// (constants exact, a cosine within the interpolation error, mass times the cell ratio, the
// wrap at the edges), the levels' parsing, the periodic-preset rule, and a two-level run on
// `pearson` that ends at the final size, finite and the same bits every time.
#include "host/run/texture_synthesis.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstring>
#include <numbers>
#include <random>

#include "host/scenes/preset.h"

namespace ardcell {
namespace {

double sum(const FieldF& f) {
  double s = 0;
  for (int y = 0; y < f.ny(); ++y)
    for (int x = 0; x < f.nx(); ++x) s += f(x, y);
  return s;
}

TEST(TextureSynthesis, ProlongsAConstantExactly) {
  FieldF coarse({8, 6}, 1), fine({16, 12}, 1);
  for (int y = 0; y < 6; ++y)
    for (int x = 0; x < 8; ++x) coarse(x, y) = 2.5f;
  prolong_periodic(coarse, fine);
  for (int y = 0; y < 12; ++y)
    for (int x = 0; x < 16; ++x) ASSERT_EQ(fine(x, y), 2.5f) << x << "," << y;
}

TEST(TextureSynthesis, ReproducesACosineWithinTheInterpolationError) {
  constexpr int nc = 32, nf = 64;
  const double k = 2 * std::numbers::pi;
  // Cell centres at (i + 0.5) / n of a unit periodic domain.
  FieldF coarse({nc, nc}, 1), fine({nf, nf}, 1);
  for (int y = 0; y < nc; ++y)
    for (int x = 0; x < nc; ++x)
      coarse(x, y) = float(std::cos(k * (x + 0.5) / nc) * std::cos(2 * k * (y + 0.5) / nc));
  prolong_periodic(coarse, fine);
  // Bilinear error <= h^2 / 8 (|f_xx| + |f_yy|) with h = 1 / nc: (1 + 4) k^2 / (8 nc^2).
  const double bound = 5 * k * k / (8.0 * nc * nc);
  double worst = 0;
  for (int y = 0; y < nf; ++y)
    for (int x = 0; x < nf; ++x) {
      const double want = std::cos(k * (x + 0.5) / nf) * std::cos(2 * k * (y + 0.5) / nf);
      worst = std::max(worst, std::abs(fine(x, y) - want));
    }
  EXPECT_LT(worst, bound);
  EXPECT_GT(worst, 0.0);  // it is an interpolation, not a copy of the analytic field
}

TEST(TextureSynthesis, DoublingScalesTheTotalMassByFour) {
  FieldF coarse({16, 8}, 1), fine({32, 16}, 1);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 16; ++x) coarse(x, y) = u(rng);
  prolong_periodic(coarse, fine);
  // Each coarse cell gives weights 3/4 + 1/4 + 3/4 + 1/4 = 2 per axis: the mean is kept.
  EXPECT_NEAR(sum(fine), 4 * sum(coarse), 1e-4 * sum(coarse));
}

TEST(TextureSynthesis, ProlongationWrapsAroundTheEdges) {
  FieldF coarse({8, 8}, 1), fine({16, 16}, 1);
  coarse(0, 0) = 1.0f;
  prolong_periodic(coarse, fine);
  // Fine cell 0 sits at -0.25 coarse: 3/4 of coarse 0, 1/4 of coarse 7 (wrapped).
  EXPECT_FLOAT_EQ(fine(0, 0), 0.75f * 0.75f);
  EXPECT_FLOAT_EQ(fine(15, 0), 0.25f * 0.75f);
  EXPECT_FLOAT_EQ(fine(0, 15), 0.75f * 0.25f);
  EXPECT_FLOAT_EQ(fine(15, 15), 0.25f * 0.25f);
  EXPECT_FLOAT_EQ(fine(1, 0), 0.75f * 0.75f);
  EXPECT_EQ(fine(3, 3), 0.0f);
  EXPECT_NEAR(sum(fine), 4.0, 1e-6);
}

TEST(TextureSynthesis, ParsesLevels) {
  std::vector<int> levels;
  ASSERT_TRUE(parse_texture_levels("64,128,256,512", levels));
  EXPECT_EQ(levels, (std::vector<int>{64, 128, 256, 512}));
  ASSERT_TRUE(parse_texture_levels("8", levels));
  EXPECT_EQ(levels, (std::vector<int>{8}));
  for (const char* bad :
       {"", "64,", ",64", "64,32", "64,64", "4,16", "16,abc", "16;32", "-16", "16,70000", "1e2"}) {
    const Status s = parse_texture_levels(bad, levels);
    EXPECT_FALSE(s) << bad;
    if (!s) {
      EXPECT_EQ(s.message().find('\n'), std::string::npos) << s.message();
    }
  }
  EXPECT_NE(parse_texture_levels("64,32", levels).message().find("increasing"), std::string::npos);
  EXPECT_EQ(doubling_levels(64, 512), (std::vector<int>{64, 128, 256, 512}));
  EXPECT_EQ(doubling_levels(64, 300), (std::vector<int>{64, 128, 256, 300}));
  EXPECT_EQ(doubling_levels(32, 32), (std::vector<int>{32}));
  EXPECT_EQ(format_levels({16, 32}), "16,32");
}

TEST(TextureSynthesis, NeedsAPeriodicReactionDiffusionScene) {
  Preset pearson, cavity;
  ASSERT_TRUE(load_preset("pearson", pearson));
  ASSERT_TRUE(load_preset("cavity-gray-scott", cavity));
  EXPECT_TRUE(check_texture_scene(pearson.scene));
  const Status s = check_texture_scene(cavity.scene);
  ASSERT_FALSE(s);
  EXPECT_EQ(s.message(), "texture needs a periodic preset: rd.boundary = periodic, got dirichlet");
  SceneConfig no_rd = pearson.scene;
  no_rd.rd.enabled = false;
  EXPECT_FALSE(check_texture_scene(no_rd));
  TextureOptions options;
  options.levels = {16};
  TextureResult result;
  EXPECT_FALSE(synthesize_texture(cavity.scene, options, result));
}

TextureResult synthesize_pearson(const std::atomic<bool>* stop = nullptr) {
  Preset p;
  EXPECT_TRUE(load_preset("pearson", p));
  TextureOptions options;
  options.levels = {16, 32};
  options.frames_per_level = 3;
  options.engine.backend = EngineOptions::Backend::kThreads;
  options.engine.workers = 2;
  options.stop = stop;
  TextureResult result;
  const Status s = synthesize_texture(p.scene, options, result);
  EXPECT_TRUE(s) << s.message();
  return result;
}

bool same_bits(const FieldF& a, const FieldF& b) {
  if (a.size() != b.size()) return false;
  for (int y = 0; y < a.ny(); ++y)
    if (std::memcmp(a.row(y), b.row(y), sizeof(float) * std::size_t(a.nx())) != 0) return false;
  return true;
}

TEST(TextureSynthesis, TwoLevelsOnPearsonEndFiniteAtTheFinalSizeAndRepeat) {
  const TextureResult first = synthesize_pearson();
  EXPECT_FALSE(first.stopped_early);
  EXPECT_EQ(first.levels_done, 2);
  EXPECT_EQ(first.frames, 6);
  ASSERT_EQ(first.state.A.size(), (Int2{32, 32}));
  ASSERT_EQ(first.state.B.size(), (Int2{32, 32}));
  double lo = 1e9, hi = -1e9;
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 32; ++x) {
      ASSERT_TRUE(std::isfinite(first.state.A(x, y)));
      ASSERT_TRUE(std::isfinite(first.state.B(x, y)));
      lo = std::min(lo, double(first.state.B(x, y)));
      hi = std::max(hi, double(first.state.B(x, y)));
    }
  EXPECT_GT(hi, lo);  // the seed square survived the prolongation
  const TextureResult second = synthesize_pearson();
  EXPECT_TRUE(same_bits(first.state.A, second.state.A));
  EXPECT_TRUE(same_bits(first.state.B, second.state.B));
}

TEST(TextureSynthesis, AStopRequestEndsItUnfinished) {
  const std::atomic<bool> stop{true};
  const TextureResult r = synthesize_pearson(&stop);
  EXPECT_TRUE(r.stopped_early);
  EXPECT_EQ(r.levels_done, 0);
  EXPECT_EQ(r.frames, 0);
}

}  // namespace
}  // namespace ardcell
