#include "host/engine/table1.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

namespace ardcell {
namespace {

bool same_cells(const FieldF& a, const FieldF& b) {
  const Box2 box = a.with_halo();
  for (int y = box.min.y; y < box.max.y; ++y)
    if (std::memcmp(a.row(y) + box.min.x, b.row(y) + box.min.x,
                    std::size_t(box.width()) * sizeof(float)) != 0)
      return false;
  return true;
}

Table1Options small(Table1Schedule s, bool rd) {
  Table1Options o;
  o.n = 32;
  o.rd = rd;
  o.schedule = s;
  o.workers = 2;
  return o;
}

TEST(Table1, ScheduleNamesRoundTrip) {
  for (Table1Schedule s :
       {Table1Schedule::kSerial, Table1Schedule::kStream, Table1Schedule::kBlocked}) {
    Table1Schedule back{};
    ASSERT_TRUE(parse_table1_schedule(table1_schedule_name(s), back));
    EXPECT_EQ(back, s);
  }
  Table1Schedule s{};
  EXPECT_FALSE(parse_table1_schedule("fast", s));
}

// 100 frames of fluid + RD: every schedule gives the same fields bit for bit, and a second run
// of one schedule repeats itself exactly.
TEST(Table1, HundredFramesAgreeBitwiseAcrossSchedules) {
  Table1Workload serial(small(Table1Schedule::kSerial, true));
  Table1Workload stream(small(Table1Schedule::kStream, true));
  Table1Workload blocked(small(Table1Schedule::kBlocked, true));
  for (int i = 0; i < 100; ++i) {
    serial.step();
    stream.step();
    blocked.step();
  }
  EXPECT_EQ(serial.frame(), 100);
  for (const Table1Workload* w : {&stream, &blocked}) {
    EXPECT_TRUE(same_cells(w->u(), serial.u()));
    EXPECT_TRUE(same_cells(w->v(), serial.v()));
    EXPECT_TRUE(same_cells(w->dye(), serial.dye()));
    EXPECT_TRUE(same_cells(w->a(), serial.a()));
    EXPECT_TRUE(same_cells(w->b(), serial.b()));
  }
  blocked.reset();
  for (int i = 0; i < 100; ++i) blocked.step();
  EXPECT_TRUE(same_cells(blocked.b(), serial.b()));
  EXPECT_TRUE(same_cells(blocked.u(), serial.u()));
}

// Physical sanity of the workload itself: finite, dye injected and bounded, concentrations in
// [0, 1], the projected velocity nearly divergence-free, walls respected (Stam's set_bnd).
TEST(Table1, FieldsStayPhysical) {
  Table1Workload w(small(Table1Schedule::kBlocked, true));
  for (int i = 0; i < 60; ++i) w.step();
  const int n = w.grid().x;
  double dye = 0, div2 = 0, vel2 = 0;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      ASSERT_TRUE(std::isfinite(w.u()(x, y)) && std::isfinite(w.v()(x, y)));
      ASSERT_GE(w.a()(x, y), 0.0f);
      ASSERT_LE(w.a()(x, y), 1.0f);
      ASSERT_GE(w.b()(x, y), 0.0f);
      ASSERT_LE(w.b()(x, y), 1.0f);
      dye += w.dye()(x, y);
      vel2 += double(w.u()(x, y)) * w.u()(x, y) + double(w.v()(x, y)) * w.v()(x, y);
      if (x > 0 && y > 0 && x < n - 1 && y < n - 1) {
        const double d =
            0.5 * (w.u()(x + 1, y) - w.u()(x - 1, y) + w.v()(x, y + 1) - w.v()(x, y - 1));
        div2 += d * d;
      }
    }
  EXPECT_GT(dye, 0.0);
  EXPECT_GT(vel2, 0.0);
  // 20 Jacobi sweeps leave some divergence, but far below the velocity's own gradients.
  EXPECT_LT(div2, 0.1 * vel2);
  for (int y = 0; y < n; ++y) {
    EXPECT_EQ(w.u()(-1, y), -w.u()(0, y));  // Stam b = 1: u mirrored at the side walls
    EXPECT_EQ(w.v()(y, -1), -w.v()(y, 0));  // b = 2: v mirrored at bottom and top
    EXPECT_EQ(w.dye()(-1, y), w.dye()(0, y));
  }
}

TEST(Table1, FluidAloneAllocatesNoRdFieldsAndCountsBytes) {
  Table1Workload w(small(Table1Schedule::kBlocked, false));
  EXPECT_TRUE(w.a().empty());
  EXPECT_DOUBLE_EQ(w.bytes_per_frame(), 32.0 * 32 * Table1Constants::kFluidBytesPerCell);
  Table1Workload ard(small(Table1Schedule::kBlocked, true));
  EXPECT_DOUBLE_EQ(
      ard.bytes_per_frame(),
      32.0 * 32 * (Table1Constants::kFluidBytesPerCell + Table1Constants::kRdBytesPerCell));
  w.step();
  EXPECT_GT(w.dye()(10, 10), 0.0f);
}

}  // namespace
}  // namespace ardcell
