#include "runtime/dma.h"

#include <gtest/gtest.h>

#include <cstring>

namespace ardcell {
namespace {

FieldF numbered(Int2 size, int halo) {
  FieldF f(size, halo);
  for (int y = -halo; y < size.y + halo; ++y)
    for (int x = -halo; x < size.x + halo; ++x) f(x, y) = float(1000 * y + x);
  return f;
}

TEST(Dma, GetBoxCopiesTheBoxInGlobalCoordinatesOnWait) {
  const FieldF f = numbered({100, 40}, 1);
  LocalStore store(64 * 1024);
  Dma dma;
  SlotArena arena(store, 0);
  const Box2 box{{13, -1}, {77, 9}};
  View<float> local = dma.get_box(f, box, arena, 3);
  EXPECT_EQ(local.box(), box);
  EXPECT_GT(dma.pending(), 0);
  dma.wait(3);
  EXPECT_EQ(dma.pending(), 0);
  for (int y = box.min.y; y < box.max.y; ++y)
    for (int x = box.min.x; x < box.max.x; ++x) ASSERT_EQ(local(x, y), f(x, y));
  EXPECT_EQ(dma.bytes_in(), local_copy_bytes(box, 1));
}

TEST(Dma, WaitCompletesOnlyItsTag) {
  FieldF f = numbered({64, 4}, 1);
  LocalStore store(16 * 1024);
  Dma dma;
  SlotArena a0(store, 0), a1(store, 1);
  View<float> l0 = dma.get_box(f, Box2{{-1, 0}, {31, 2}}, a0, 0);
  View<float> l1 = dma.get_box(f, Box2{{-1, 2}, {31, 4}}, a1, 1);
  l1(5, 2) = -7.0f;  // not landed yet: the transfer overwrites it on wait(1)
  dma.wait(0);
  EXPECT_EQ(l0(5, 1), f(5, 1));
  EXPECT_EQ(l1(5, 2), -7.0f);
  dma.wait(1);
  EXPECT_EQ(l1(5, 2), f(5, 2));
}

TEST(Dma, PutBoxWritesOnlyTheBox) {
  FieldF f = numbered({100, 10}, 1);
  const FieldF before = f;
  LocalStore store(64 * 1024);
  Dma dma;
  SlotArena arena(store, 0);
  const Box2 box{{31, 2}, {63, 5}};  // line-exact for halo 1
  View<float> local = dma.local_box(f, box, arena);
  for (int y = box.min.y; y < box.max.y; ++y)
    for (int x = box.min.x; x < box.max.x; ++x) local(x, y) = -1.0f;
  dma.put_box(local, f, box, 2);
  dma.wait_all();
  for (int y = -1; y < 11; ++y)
    for (int x = -1; x < 101; ++x)
      ASSERT_EQ(f(x, y), box.contains(Int2{x, y}) ? -1.0f : before(x, y)) << x << "," << y;
}

#if defined(ARDCELL_CHECKS) && ARDCELL_CHECKS
TEST(DmaDeathTest, RejectsTransfersOver16KiB) {
  alignas(128) static float local[8192];
  alignas(128) static float remote[8192];
  Dma dma;
  EXPECT_DEATH(dma.get(local, remote, 16 * 1024 + 128, 0), "Dma get rejected: larger than 16 KiB");
}

TEST(DmaDeathTest, RejectsMisalignedTransfers) {
  alignas(128) static float local[256];
  alignas(128) static float remote[256];
  Dma dma;
  EXPECT_DEATH(dma.get(local + 1, remote, 128, 0), "local address not 128-byte aligned");
  EXPECT_DEATH(dma.put(local, remote + 4, 128, 0), "remote address not 128-byte aligned");
  EXPECT_DEATH(dma.get(local, remote, 100, 0), "size not a positive multiple of 128 bytes");
}
#endif

TEST(DmaDeathTest, PutThatWouldSplitALineIsRefused) {
  FieldF f({100, 4}, 1);
  LocalStore store(64 * 1024);
  Dma dma;
  SlotArena arena(store, 0);
  const Box2 box{{10, 0}, {40, 2}};
  View<float> local = dma.local_box(f, box, arena);
  EXPECT_DEATH(dma.put_box(local, f, box, 0), "must start and end on 128-byte lines");
}

}  // namespace
}  // namespace ardcell
