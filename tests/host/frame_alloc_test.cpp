// No heap allocation during a steady-state frame: global operator new is replaced in this
// test program and counted while frames run, on every schedule.
#include <gtest/gtest.h>

// The replacements below pair malloc with free by design; GCC cannot see that across them.
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"

#include <atomic>
#include <cstdlib>
#include <new>

#include "host/table1.h"

namespace {
std::atomic<long> g_allocations{0};
}  // namespace

void* operator new(std::size_t n) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t n) { return operator new(n); }
void* operator new(std::size_t n, std::align_val_t a) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  const std::size_t al = static_cast<std::size_t>(a);
  if (void* p = std::aligned_alloc(al, (n + al - 1) / al * al)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t n, std::align_val_t a) { return operator new(n, a); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }

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
