#include "runtime/local_store.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <string>

#include <cstdint>

namespace ardcell {
namespace {

TEST(LocalStore, TwoAlignedSlotsOfHalfTheCapacity) {
  LocalStore store(kSpeLocalStoreBytes);
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

// The default local store holds one L2 cache per core in each of its two slots, the L2 read here
// independently of the runtime's parser: the first level-2 data or unified cache of cpu0 divided
// among the CPUs sharing it.
TEST(LocalStore, DefaultSlotIsOneL2PerCore) {
  const std::size_t bytes = machine_local_store_bytes();
  EXPECT_EQ(bytes % 256, 0u);
  EXPECT_GE(bytes, std::size_t(64) << 10);
  EXPECT_LE(bytes, std::size_t(16) << 20);
  LocalStore store;  // the default constructor takes it
  EXPECT_EQ(store.capacity(), bytes);
  for (int i = 0; i < 8; ++i) {
    const std::string dir = "/sys/devices/system/cpu/cpu0/cache/index" + std::to_string(i) + "/";
    std::ifstream level(dir + "level"), type(dir + "type"), size(dir + "size"),
        shared(dir + "shared_cpu_map");
    int l = 0;
    std::string t, s, map;
    if (!(level >> l) || l != 2 || !(type >> t) || t == "Instruction" || !(size >> s)) continue;
    std::size_t l2 = std::stoul(s) * (s.back() == 'K' ? 1024 : s.back() == 'M' ? 1 << 20 : 1);
    // shared_cpu_map is a hex mask: count its bits.
    int sharing = 0;
    if (shared >> map)
      for (char c : map)
        if (std::isxdigit(static_cast<unsigned char>(c)))
          sharing += __builtin_popcount(unsigned(std::stoi(std::string(1, c), nullptr, 16)));
    if (sharing > 0) l2 /= std::size_t(sharing);
    const std::size_t expected =
        std::clamp<std::size_t>(2 * l2, std::size_t(64) << 10, std::size_t(16) << 20) / 256 * 256;
    EXPECT_EQ(bytes, expected) << dir;
    return;
  }
  GTEST_SKIP() << "this machine does not describe its L2 cache in sysfs";
}

}  // namespace
}  // namespace ardcell
