#include <gtest/gtest.h>

#include <cmath>

#include "host/engine/engine.h"
#include "host/engine/rd_step.h"
#include "host/scenes/scene_registry.h"

namespace ardcell {
namespace {

const char* const kRdScenes[] = {"space-cookie-3",
                                 "space-cookie-4",
                                 "space-cookie-5",
                                 "space-cookie-8",
                                 "cavity-advect",
                                 "cavity-gray-scott",
                                 "cavity-fhn",
                                 "cavity-barkley",
                                 "obstacle-advect",
                                 "obstacle-ard-gray-scott",
                                 "obstacle-ard-fhn",
                                 "obstacle-ard-barkley",
                                 "obstacle-rd-gray-scott",
                                 "obstacle-rd-fhn",
                                 "obstacle-rd-barkley",
                                 "pearson",
                                 "seed001",
                                 "turing-spots",
                                 "meinhardt-spots"};

TEST(RdScenes, EveryFigurePresetIsRegisteredValidAndDescribed) {
  for (const char* name : kRdScenes) {
    const SceneEntry* e = builtin_scenes().find(name);
    ASSERT_NE(e, nullptr) << name;
    EXPECT_FALSE(e->description.empty()) << name;
    EXPECT_EQ(e->description.find('\n'), std::string::npos) << name;
    const SceneConfig s = e->make();
    EXPECT_EQ(s.name, name);
    EXPECT_TRUE(s.rd.enabled) << name;
    EXPECT_EQ(rd_config_problem(s), "") << name;
  }
}

TEST(RdScenes, PearsonAndSeed001MatchTheirSpecifications) {
  const SceneConfig p = builtin_scenes().find("pearson")->make();
  EXPECT_EQ(p.size, (Int2{256, 256}));
  EXPECT_DOUBLE_EQ(p.domain_width, 2.5);
  EXPECT_DOUBLE_EQ(p.rd.diffusion_a, 2e-5);
  EXPECT_DOUBLE_EQ(p.rd.diffusion_b, 1e-5);
  EXPECT_EQ(p.rd.boundary, BoundaryKind::kPeriodic);
  EXPECT_FLOAT_EQ(p.rd.seed_a, 0.5f);
  EXPECT_FLOAT_EQ(p.rd.seed_b, 0.25f);
  EXPECT_DOUBLE_EQ(p.rd.noise, 0.01);
  const SceneConfig s = builtin_scenes().find("seed001")->make();
  EXPECT_EQ(s.size, (Int2{400, 400}));
  EXPECT_EQ(s.rd.scheme, RdScheme::kExplicit9);
  EXPECT_FLOAT_EQ(s.rd.reaction.F, 0.055f);
  EXPECT_FLOAT_EQ(s.rd.reaction.k, 0.062f);
  EXPECT_DOUBLE_EQ(s.rd.diffusion_a, 1.0);
  EXPECT_DOUBLE_EQ(s.rd.diffusion_b, 0.5);
  EXPECT_EQ(s.rd.seed_cells, 10);
  const SceneConfig c = builtin_scenes().find("space-cookie-5")->make();
  EXPECT_EQ(c.rd.anisotropy.kind, AnisotropyKind::kCosineLobes);
  EXPECT_EQ(c.rd.anisotropy.lobes, 5);
}

// The engine runs RD with and without the fluid: chemicals allocated, finite, in range, and
// the flow carries them (ARD differs from RD alone in the same cavity).
TEST(RdScenes, EngineRunsRdWithAndWithoutFluid) {
  auto shrink = [](SceneConfig s) {
    s.size = {32, 32};
    s.rd.spots = 4;
    return s;
  };
  SceneConfig ard = shrink(builtin_scenes().find("cavity-gray-scott")->make());
  SceneConfig rd_only = ard;
  rd_only.rd.advect = false;
  Engine with_flow(ard), without_flow(rd_only);
  ASSERT_FALSE(with_flow.state().A.empty());
  ASSERT_FALSE(with_flow.state().B.empty());
  for (int i = 0; i < 20; ++i) {
    with_flow.step();
    without_flow.step();
  }
  double diff = 0;
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 32; ++x) {
      const float a = with_flow.state().A(x, y), b = with_flow.state().B(x, y);
      ASSERT_TRUE(std::isfinite(a) && std::isfinite(b));
      EXPECT_GE(a, -1e-3f);
      EXPECT_LE(a, 1.001f);
      EXPECT_GE(b, -1e-3f);
      diff = std::max(diff, std::abs(double(b) - without_flow.state().B(x, y)));
    }
  EXPECT_GT(diff, 1e-3);

  SceneConfig alone = shrink(builtin_scenes().find("space-cookie-4")->make());
  Engine e(alone);
  const float before = e.state().B(16, 16);
  for (int i = 0; i < 5; ++i) e.step();
  EXPECT_NE(e.state().B(16, 16), before);
  e.reset();
  EXPECT_EQ(e.state().B(16, 16), before);
  EXPECT_EQ(e.state().step, 0);
}

}  // namespace
}  // namespace ardcell
