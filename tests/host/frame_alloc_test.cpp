// No heap allocation during a steady-state frame: global operator new is replaced in this
// test program and counted while frames run, on every schedule.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>

#include "host/table1.h"

#include "tests/support/alloc_counter.h"

namespace ardcell {
namespace {

TEST(FrameAlloc, SteadyStateFramesDoNotAllocate) {
  for (Table1Schedule s :
       {Table1Schedule::kSerial, Table1Schedule::kStream, Table1Schedule::kBlocked}) {
    for (bool rd : {false, true}) {
      Table1Options o;
      o.n = 64;
      o.rd = rd;
      o.schedule = s;
      o.workers = 2;
      Table1Workload w(o);
      w.step();  // first frame: nothing should allocate either, but it is not the steady state
      const long before = g_allocations.load();
      for (int i = 0; i < 5; ++i) w.step();
      EXPECT_EQ(g_allocations.load() - before, 0)
          << table1_schedule_name(s) << (rd ? " ard" : " fluid");
    }
  }
}

TEST(FrameAlloc, TheCounterSeesAllocations) {
  const long before = g_allocations.load();
  auto* p = new int(3);
  EXPECT_EQ(g_allocations.load() - before, 1);
  delete p;
}

}  // namespace
}  // namespace ardcell
