#include "host/scenes/adaptive_quality.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

namespace ardcell {
namespace {

constexpr int64_t kPeriod = 16'666'667;

// An artificial load model: the frame costs a fixed part plus a part per sweep and per RD cell.
int64_t work_for(const QualityLevel& q, int64_t extra_ns) {
  return 2'000'000 + int64_t(q.sweeps) * 600'000 + int64_t(4'000'000 * q.rd_scale * q.rd_scale) +
         extra_ns;
}

TEST(AdaptiveQuality, LowersSweepsUnderLoadAndRestoresAfter) {
  AdaptiveQuality aq({.min_sweeps = 4, .max_sweeps = 20, .min_rd_scale = 0.5});
  ASSERT_EQ(aq.level().sweeps, 20);
  // Full quality costs 18 ms: over the 16.7 ms period.
  for (int f = 0; f < 200; ++f) aq.update(work_for(aq.level(), 0), kPeriod);
  const QualityLevel settled = aq.level();
  EXPECT_LT(settled.sweeps, 20);
  EXPECT_GE(settled.sweeps, 4);
  EXPECT_LE(work_for(settled, 0), int64_t(0.85 * kPeriod));
  EXPECT_EQ(settled.rd_scale, 1.0);  // sweeps alone were enough

  // Artificial load of 8 ms more: sweeps hit the floor, then resolution goes down.
  for (int f = 0; f < 200; ++f) aq.update(work_for(aq.level(), 8'000'000), kPeriod);
  EXPECT_EQ(aq.level().sweeps, 4);
  EXPECT_LT(aq.level().rd_scale, 1.0);
  EXPECT_GE(aq.level().rd_scale, 0.5);

  // Load gone and the frame is cheap: everything comes back, within bounds.
  for (int f = 0; f < 2000; ++f) aq.update(1'000'000, kPeriod);
  EXPECT_EQ(aq.level().sweeps, 20);
  EXPECT_EQ(aq.level().rd_scale, 1.0);
  EXPECT_GT(aq.lowered(), 0);
  EXPECT_GT(aq.raised(), 0);
}

TEST(AdaptiveQuality, ResolutionMovesOnAFixedLadder) {
  // Rungs are exact powers of the step, so a simulation can preallocate one grid per rung.
  const std::vector<double> ladder = rd_scale_ladder(0.5);
  ASSERT_EQ(ladder.size(), 3u);
  EXPECT_EQ(ladder[0], 1.0);
  EXPECT_EQ(ladder[1], 0.75);
  EXPECT_EQ(ladder[2], 0.5625);
  EXPECT_EQ(rd_scale_ladder(1.0).size(), 1u);
  EXPECT_EQ(rd_scale_ladder(0.125).back(), 0.75 * 0.75 * 0.75 * 0.75 * 0.75 * 0.75 * 0.75);

  AdaptiveQuality aq({.min_sweeps = 4, .max_sweeps = 4, .min_rd_scale = 0.5}, {.raise_after = 1});
  std::vector<double> seen;
  for (int f = 0; f < 6; ++f) {
    aq.update(kPeriod * 2, kPeriod);
    seen.push_back(aq.level().rd_scale);
  }
  for (int f = 0; f < 6; ++f) {
    aq.update(0, kPeriod);
    seen.push_back(aq.level().rd_scale);
  }
  for (double s : seen) {
    EXPECT_NE(std::find(ladder.begin(), ladder.end(), s), ladder.end()) << s;
  }
  EXPECT_EQ(seen[5], 0.5625);
  EXPECT_EQ(aq.level().rd_rung, 0);
  EXPECT_EQ(aq.level().rd_scale, 1.0);

  // Narrower bounds later: the level climbs back inside them.
  for (int f = 0; f < 6; ++f) aq.update(kPeriod * 2, kPeriod);
  aq.set_bounds({.min_sweeps = 4, .max_sweeps = 4, .min_rd_scale = 0.7});
  EXPECT_EQ(aq.level().rd_scale, 0.75);
  EXPECT_EQ(aq.level().rd_rung, 1);
}

TEST(AdaptiveQuality, NeverLeavesTheBounds) {
  AdaptiveQuality aq({.min_sweeps = 6, .max_sweeps = 12, .min_rd_scale = 0.75});
  for (int f = 0; f < 500; ++f) {
    aq.update(f % 7 == 0 ? 1'000'000'000 : 1, kPeriod);
    EXPECT_GE(aq.level().sweeps, 6);
    EXPECT_LE(aq.level().sweeps, 12);
    EXPECT_GE(aq.level().rd_scale, 0.75);
    EXPECT_LE(aq.level().rd_scale, 1.0);
  }
}

TEST(AdaptiveQuality, HysteresisWaitsForSustainedSlack) {
  AdaptiveQuality aq({.min_sweeps = 2, .max_sweeps = 20}, {.raise_after = 30});
  aq.update(kPeriod * 2, kPeriod);
  const int lowered = aq.level().sweeps;
  ASSERT_LT(lowered, 20);
  for (int f = 0; f < 29; ++f) EXPECT_FALSE(aq.update(0, kPeriod));
  EXPECT_EQ(aq.level().sweeps, lowered);
  EXPECT_TRUE(aq.update(0, kPeriod));
  EXPECT_GT(aq.level().sweeps, lowered);
}

TEST(AdaptiveQuality, DisabledOrUnpacedKeepsFullQuality) {
  AdaptiveQuality off({.min_sweeps = 2, .max_sweeps = 20, .adaptive = false});
  EXPECT_FALSE(off.update(kPeriod * 10, kPeriod));
  EXPECT_EQ(off.level().sweeps, 20);
  AdaptiveQuality unpaced({.min_sweeps = 2, .max_sweeps = 20});
  EXPECT_FALSE(unpaced.update(kPeriod * 10, 0));
  EXPECT_EQ(unpaced.level().sweeps, 20);
}

}  // namespace
}  // namespace ardcell
