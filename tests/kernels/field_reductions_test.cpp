// kernels/field_reductions.h against hand computations, and the property the frame relies on:
// the partials do not depend on how the rows are cut into bands.
#include "kernels/field_reductions.h"

#include <gtest/gtest.h>

#include <random>
#include <vector>

namespace ardcell {
namespace {

FieldF small_field() {
  FieldF f({3, 2}, 1);
  f.fill(100.0f);  // the halo must not be read
  f(0, 0) = 0.25f, f(1, 0) = -1.0f, f(2, 0) = 2.0f;
  f(0, 1) = 0.5f, f(1, 1) = 0.75f, f(2, 1) = 0.125f;
  return f;
}

TEST(FieldReductions, RowSumsRangesAndWeightsByHand) {
  const FieldF f = small_field();
  std::vector<double> sum(2), lo(2), hi(2);
  row_sums(f.view(), 3, 0, 2, sum.data());
  EXPECT_EQ(sum[0], 1.25);
  EXPECT_EQ(sum[1], 1.375);
  row_ranges(f.view(), 3, 0, 2, sum.data(), lo.data(), hi.data());
  EXPECT_EQ(sum[0], 1.25);
  EXPECT_EQ(lo[0], -1.0);
  EXPECT_EQ(hi[0], 2.0);
  EXPECT_EQ(lo[1], 0.125);
  EXPECT_EQ(hi[1], 0.75);
  // (f - 0)(1 - f): 0.1875 + (-2) + (-2) in row 0; 0.25 + 0.1875 + 0.109375 in row 1.
  row_mass_weights(f.view(), 3, 0, 2, 0.0f, 1.0f, sum.data());
  EXPECT_EQ(sum[0], -3.8125);
  EXPECT_EQ(sum[1], 0.546875);

  Field<uint8_t> mask({3, 2}, 0);
  mask(1, 0) = 1, mask(2, 0) = 1, mask(0, 1) = 1;
  row_masked_sums(f.view(), mask.view(), 3, 0, 2, sum.data());
  EXPECT_EQ(sum[0], 1.0);
  EXPECT_EQ(sum[1], 0.5);
}

TEST(FieldReductions, RestoreMassRowsByHandAndClamps) {
  FieldF f = small_field();
  // k = 1 on [0, 1]: q + q (1 - q), clamped to [0, 1].
  restore_mass_rows(f.view(), 3, 1, 2, 1.0, 0.0f, 1.0f);
  EXPECT_EQ(f(0, 1), 0.75f);
  EXPECT_EQ(f(1, 1), 0.9375f);
  EXPECT_EQ(f(2, 1), 0.125f + 0.109375f);
  EXPECT_EQ(f(1, 0), -1.0f);  // row 0 is outside the band
  restore_mass_rows(f.view(), 3, 0, 1, 1.0, 0.0f, 1.0f);
  EXPECT_EQ(f(0, 0), 0.4375f);
  EXPECT_EQ(f(1, 0), 0.0f);  // -1 + (-2), clamped to lo
  EXPECT_EQ(f(2, 0), 0.0f);  // 2 + (-2): a weight outside [lo, hi] pulls back in
}

TEST(FieldReductions, PartialsDoNotDependOnTheBands) {
  FieldF f({37, 23}, 1);
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> d(-1.0f, 1.0f);
  for (int y = 0; y < 23; ++y)
    for (int x = 0; x < 37; ++x) f(x, y) = d(rng);
  std::vector<double> whole(23), banded(23, -7.0);
  row_mass_weights(f.view(), 37, 0, 23, -0.5f, 0.5f, whole.data());
  for (int y0 = 0; y0 < 23; y0 += 5)
    row_mass_weights(f.view(), 37, y0, std::min(23, y0 + 5), -0.5f, 0.5f, banded.data());
  EXPECT_EQ(whole, banded);
}

}  // namespace
}  // namespace ardcell
