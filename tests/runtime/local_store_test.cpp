#include "runtime/local_store.h"

#include <gtest/gtest.h>

#include <cstdint>

namespace ardcell {
namespace {

TEST(LocalStore, TwoAlignedSlotsOfHalfTheCapacity) {
  LocalStore store;
  EXPECT_EQ(store.capacity(), 256u * 1024);
  EXPECT_EQ(store.slot_bytes(), 128u * 1024);
  EXPECT_EQ(store.slot(1) - store.slot(0), std::ptrdiff_t(store.slot_bytes()));
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(store.slot(0)) % 128, 0u);
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(store.slot(1)) % 128, 0u);
}

TEST(LocalStore, ArenaHandsOutAlignedDisjointBuffersInsideItsSlot) {
  LocalStore store(8 * 1024);
  SlotArena arena(store, 1);
  std::byte* a = arena.allocate(1);
  std::byte* b = arena.allocate(300);
  std::byte* c = arena.allocate(128);
  EXPECT_EQ(b - a, 128);
  EXPECT_EQ(c - b, 384);
  EXPECT_EQ(arena.used(), 640u);
  EXPECT_GE(a, store.slot(1));
  EXPECT_LE(c + 128, store.slot(1) + store.slot_bytes());
}

TEST(LocalStoreDeathTest, ArenaOverflowNamesTheSizes) {
  LocalStore store(1024);
  SlotArena arena(store, 0);
  EXPECT_DEATH(arena.allocate(4096), "local store slot overflow: 4096 bytes asked");
}

TEST(LocalStore, LocalCopyBytesCountsWholeLines) {
  // Cells [-1, 31) of a halo-1 field are exactly one line per row.
  EXPECT_EQ(local_copy_bytes(Box2{{-1, 0}, {31, 2}}, 1), 2u * 128);
  // [0, 31) starts mid-line but still fits the same line.
  EXPECT_EQ(local_copy_bytes(Box2{{0, 0}, {31, 1}}, 1), 128u);
  // [30, 40) straddles two lines.
  EXPECT_EQ(local_copy_bytes(Box2{{30, 0}, {40, 1}}, 1), 256u);
}

}  // namespace
}  // namespace ardcell
