// Seed 001's per-step scheme skipping quiescent cells (kernels/explicit_rd.h QuiescentBox,
// CpuDevice::explicit_rd): stepping only the cells that can change gives the bits of stepping
// every cell, on the serial and threads back ends, periodic (a pattern across the edge, which the
// ring brings in) and with Neumann walls, through the background's settling (A = 1 reaches the
// fixed point in 2 steps: the box shrinks from the whole grid to the pattern at once, and the
// other pair's cells must still be overwritten), a change of D_A (a new fixed point) and a stroke
// written between steps (restart()). Meanwhile the region a step computes shrinks to the pattern
// once the background has settled.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cstdint>

#include "host/engine/device.h"
#include "kernels/generalized_diffusion.h"
#include "runtime/boundary.h"
#include "runtime/row_executor.h"
#include "runtime/thread/thread_backend.h"
#include "tests/support/field_compare.h"

namespace ardcell {
namespace {

constexpr Int2 kGrid{256, 192};

// Seed 001's square of B in a background of A = 1, B = 0, centred at (cx, cy), wrapped.
void add_square(FieldF& a, FieldF& b, int cx, int cy) {
  for (int y = cy - 3; y < cy + 3; ++y)
    for (int x = cx - 3; x < cx + 3; ++x) {
      const int wx = (x + kGrid.x) % kGrid.x, wy = (y + kGrid.y) % kGrid.y;
      a(wx, wy) = 0.5f;
      b(wx, wy) = 0.25f;
    }
}

struct Pair {
  FieldF a{kGrid, 1}, b{kGrid, 1}, a_out{kGrid, 1}, b_out{kGrid, 1};
  bool periodic = true;
  explicit Pair(bool periodic_grid) : periodic(periodic_grid) {
    a.fill(1.0f);
    add_square(a, b, 254, 40);  // across the x = 0 edge
  }
  void fill_ring() {
    for (FieldF* f : {&a, &b})
      if (periodic)
        fill_periodic_halo(*f);
      else
        fill_boundary(f->view(), kGrid, BoundaryFill::copy());
  }
  void step(Device& device, const ExplicitRdParams& p, QuiescentBox* quiet) {
    fill_ring();
    device.explicit_rd(a, b, a_out, b_out, Device::ExplicitScheme::kGrayScott9, p, quiet, 0);
    device.swap(a, a_out);
    device.swap(b, b_out);
  }
};

void expect_skipping_keeps_the_bits(RowExecutor& ex, bool periodic) {
  CpuDevice device(ex);
  device.reserve(kGrid);
  ExplicitRdParams p{};  // seed 001: F 0.055, k 0.062, dt 1, DA 1, DB 0.5
  Pair every(periodic), skipping(periodic);
  QuiescentBox quiet;
  const int64_t all = box_of_size(kGrid).area();
  int64_t smallest = all;
  for (int step = 0; step < 70; ++step) {
    if (step == 40) {
      // A stroke between steps, far from the pattern: the fields were written, so restart().
      add_square(every.a, every.b, 128, 150);
      add_square(skipping.a, skipping.b, 128, 150);
      quiet.restart();
    }
    // A live change of D_A moves the fixed point (A 1.00000036 -> 1.00000048): no restart()
    // needed, the box sees new parameters.
    if (step == 20) p.diffusion_a = 0.8f;
    if (quiet.known()) {
      skipping.fill_ring();
      const Box2 region = quiet.region(skipping.a.view(), skipping.b.view(), box_of_size(kGrid));
      if (step > 4 && step < 20) smallest = std::min(smallest, region.area());
    }
    every.step(device, p, nullptr);
    skipping.step(device, p, &quiet);
    ASSERT_TRUE(same_cells_in(every.a, skipping.a, box_of_size(kGrid))) << "A, step " << step;
    ASSERT_TRUE(same_cells_in(every.b, skipping.b, box_of_size(kGrid))) << "B, step " << step;
  }
  // The settled background is skipped: a step computes the rows of the pattern and of the tail
  // its diffusion spreads a cell a step until B underflows (the box spans the width, the pattern
  // lying across x = 0), under a third of the grid.
  EXPECT_LT(smallest, all / 3);
}

TEST(QuiescentSteps, SkippingGivesTheBitsOfEveryCellSerial) {
  expect_skipping_keeps_the_bits(RowExecutor::serial(), true);
}

TEST(QuiescentSteps, SkippingGivesTheBitsOfEveryCellOnTwoWorkers) {
  ThreadBackend threads({2, 512 * 1024, false});
  RowExecutor ex(threads);
  expect_skipping_keeps_the_bits(ex, true);
}

TEST(QuiescentSteps, SkippingGivesTheBitsOfEveryCellWithNeumannWalls) {
  expect_skipping_keeps_the_bits(RowExecutor::serial(), false);
}

// A block's halo columns (explicit_rd's grow): once both pairs are known to hold the fixed point
// there, no row of them is stepped, except rows within one of a differing cell of the state's
// columns (the interior's edge column, the stepped ones and the one beyond), the rows the other
// pair differs in (overwritten), and the first or last row next to a differing cell of the halo
// row just above or below; a column not stepped keeps what the other pair held there.
TEST(QuiescentSteps, HaloColumnsStepOnlyRowsThatCanChange) {
  QuiescentBox quiet;
  ASSERT_TRUE(quiet.skips(GrayScott9Params{}));
  const Box2 inner{{0, 0}, {32, 24}};
  FieldF a = FieldF::over(inner, 5), b = FieldF::over(inner, 5);
  a.fill(quiet.fixed_a());
  b.fill(quiet.fixed_b());
  const auto rows = [&](int side, int grow) {
    return quiet.side_rows(a.view(), b.view(), side, inner, grow);
  };
  const auto step = [&](int grow, Int2 left_written) {
    quiet.begin_sides(a.view(), b.view(), inner, grow);
    quiet.side_stepped(0, left_written);
    quiet.side_stepped(1, {});
    quiet.stepped({}, {}, grow);
  };
  // An exchange of 5 cells found nothing; its first step wrote rows 5..6 of the left columns.
  quiet.halo_exchanged();
  step(4, {5, 7});
  EXPECT_EQ(rows(0, 3), (Int2{4, 8}));  // the state's rows, one row either side
  EXPECT_LE(rows(1, 3).y, rows(1, 3).x);
  step(3, {});
  EXPECT_EQ(rows(0, 2), (Int2{5, 7}));  // the other pair's rows, which this step overwrites
  step(2, {});
  // Column 3 was not stepped: the state there is what the other pair held, rows 5..6.
  EXPECT_EQ(rows(0, 2), (Int2{4, 8}));
  step(2, {});  // and the pair that is the state now holds the fixed point there
  EXPECT_LE(rows(0, 2).y, rows(0, 2).x);
  // A new exchange wrote a differing cell in column 3 (read by column 2) and one in the halo row
  // above the left columns; one above the interior, next to neither side, counts for none.
  a(-3, 12) = 0.5f;
  a(-2, -1) = 0.5f;
  a(16, -1) = 0.5f;
  b(34, 24) = 0.25f;  // below the right columns
  quiet.halo_exchanged();
  quiet.begin_sides(a.view(), b.view(), inner, 2);
  EXPECT_EQ(rows(0, 2), (Int2{0, 14}));  // rows 0 and 11..13, as one interval
  EXPECT_EQ(rows(1, 2), (Int2{23, 24}));
  // An exchange one cell deep serves a step of no halo column (a frame's last, odd step); what it
  // wrote into column 1 is that pair's when it next is the pair a step overwrites.
  a.fill(quiet.fixed_a());
  b.fill(quiet.fixed_b());
  quiet.halo_exchanged();
  step(2, {});
  step(2, {});
  a(-1, 18) = 0.5f;
  quiet.halo_exchanged();
  step(0, {});
  a(-1, 18) = quiet.fixed_a();  // the next exchange's state: quiet again
  quiet.halo_exchanged();
  quiet.begin_sides(a.view(), b.view(), inner, 4);
  EXPECT_EQ(rows(0, 4), (Int2{18, 19}));

  // The interior's column next to the halo: the rows of the interior's box where it reaches the
  // side; before anything is known, every row.
  QuiescentBox fresh;
  ASSERT_TRUE(fresh.skips(GrayScott9Params{}));
  fresh.halo_exchanged();
  fresh.begin_sides(a.view(), b.view(), inner, 4);
  for (int side = 0; side < 2; ++side) fresh.side_stepped(side, {});
  fresh.stepped({{0, 3}, {4, 9}}, {}, 4);
  EXPECT_EQ(fresh.side_rows(a.view(), b.view(), 0, inner, 3), (Int2{2, 10}));
  EXPECT_LE(fresh.side_rows(a.view(), b.view(), 1, inner, 3).y,
            fresh.side_rows(a.view(), b.view(), 1, inner, 3).x);
  fresh.restart();
  EXPECT_EQ(fresh.side_rows(a.view(), b.view(), 1, inner, 3), (Int2{0, 24}));
}

TEST(QuiescentSteps, FindsSeed001sFixedPoint) {
  QuiescentBox quiet;
  ASSERT_TRUE(quiet.skips(GrayScott9Params{}));
  // The background's float fixed point: A just above 1 (1 + 3 ulp), B exactly 0.
  EXPECT_EQ(quiet.fixed_a(), 1.0f + 3.0f * 0x1p-23f);
  EXPECT_EQ(std::bit_cast<uint32_t>(quiet.fixed_b()), 0u);
  // An update that runs away from (1, 0) has none, and nothing is skipped.
  GrayScott9Params unstable;
  unstable.dt = 1e30f;
  EXPECT_FALSE(quiet.skips(unstable));
}

}  // namespace
}  // namespace ardcell
