#include "runtime/local_store.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <new>
#include <string>

#include "runtime/check.h"

namespace ardcell {

namespace {

// The first line of a sysfs file ("" when unreadable).
std::string read_line(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  return line;
}

// "512K", "1M", "2048" (bytes) -> bytes; 0 when not a size.
std::size_t parse_cache_size(const std::string& s) {
  char* end = nullptr;
  const unsigned long long v = std::strtoull(s.c_str(), &end, 10);
  if (end == s.c_str()) return 0;
  if (*end == 'K') return std::size_t(v) << 10;
  if (*end == 'M') return std::size_t(v) << 20;
  return std::size_t(v);
}

// CPUs in a list like "0", "0-1", "0,4" or "0-3,8-11".
int cpu_count(const std::string& list) {
  int count = 0;
  const char* p = list.c_str();
  while (*p) {
    char* end = nullptr;
    const long a = std::strtol(p, &end, 10);
    if (end == p) break;
    long b = a;
    if (*end == '-') b = std::strtol(end + 1, &end, 10);
    count += int(std::max(1L, b - a + 1));
    p = *end == ',' ? end + 1 : end;
    if (*end != ',') break;
  }
  return std::max(1, count);
}

// L2 bytes per core, 0 when unknown.
std::size_t l2_per_core() {
  for (int i = 0; i < 8; ++i) {
    const std::string dir = "/sys/devices/system/cpu/cpu0/cache/index" + std::to_string(i) + "/";
    if (read_line(dir + "level") != "2" || read_line(dir + "type") == "Instruction") continue;
    if (const std::size_t bytes = parse_cache_size(read_line(dir + "size")))
      return bytes / std::size_t(cpu_count(read_line(dir + "shared_cpu_list")));
  }
#if defined(_SC_LEVEL2_CACHE_SIZE)
  const long bytes = sysconf(_SC_LEVEL2_CACHE_SIZE);
  if (bytes > 0) return std::size_t(bytes);
#endif
  return 0;
}

// The largest data cache level's size (not divided among the cores sharing it), 0 when unknown.
std::size_t last_level_cache() {
  std::size_t bytes = 0;
  int deepest = 0;
  for (int i = 0; i < 8; ++i) {
    const std::string dir = "/sys/devices/system/cpu/cpu0/cache/index" + std::to_string(i) + "/";
    const std::string level = read_line(dir + "level");
    if (level.empty() || read_line(dir + "type") == "Instruction") continue;
    const int l = std::atoi(level.c_str());
    const std::size_t size = parse_cache_size(read_line(dir + "size"));
    if (l > deepest && size > 0) {
      deepest = l;
      bytes = size;
    }
  }
  if (bytes > 0) return bytes;
#if defined(_SC_LEVEL3_CACHE_SIZE)
  if (const long l3 = sysconf(_SC_LEVEL3_CACHE_SIZE); l3 > 0) return std::size_t(l3);
#endif
  return 0;
}

}  // namespace

std::size_t machine_last_level_cache_bytes() {
  static const std::size_t bytes = [] {
    const std::size_t llc = last_level_cache();
    return llc > 0 ? llc : std::size_t(8) << 20;
  }();
  return bytes;
}

std::size_t machine_local_store_bytes() {
  static const std::size_t bytes = [] {
    const std::size_t l2 = l2_per_core();
    if (l2 == 0) return kSpeLocalStoreBytes;
    // Each of the two double-buffer slots one L2: the tile computing stays in the core's cache.
    const std::size_t clamped = std::clamp<std::size_t>(2 * l2, 64 << 10, 16 << 20);
    return clamped / (2 * kRowAlignBytes) * (2 * kRowAlignBytes);
  }();
  return bytes;
}

LocalStore::LocalStore(std::size_t capacity_bytes) : capacity_(capacity_bytes) {
  ARDCELL_CHECK(capacity_bytes >= 2 * kRowAlignBytes && capacity_bytes % (2 * kRowAlignBytes) == 0,
                "LocalStore capacity must be a positive multiple of 256 bytes");
  slot_bytes_ = capacity_ / kSlots;
  void* p = std::aligned_alloc(kRowAlignBytes, capacity_);
  if (!p) throw std::bad_alloc();
  data_.reset(static_cast<std::byte*>(p));
}

std::byte* LocalStore::slot(int s) const {
  ARDCELL_DCHECK(s >= 0 && s < kSlots, "LocalStore slot out of range");
  return data_.get() + std::size_t(s) * slot_bytes_;
}

std::byte* SlotArena::allocate(std::size_t bytes) {
  const std::size_t rounded = (bytes + kRowAlignBytes - 1) / kRowAlignBytes * kRowAlignBytes;
  if (rounded > std::size_t(end_ - cursor_)) {
    std::fprintf(stderr, "ardcell: local store slot overflow: %zu bytes asked, %zu of %zu free\n",
                 rounded, std::size_t(end_ - cursor_), std::size_t(end_ - begin_));
    std::abort();
  }
  std::byte* p = cursor_;
  cursor_ += rounded;
  return p;
}

std::size_t local_copy_bytes(const Box2& box, int field_halo) {
  if (box.empty()) return 0;
  constexpr int kLine = int(kRowAlignBytes / sizeof(float));
  const int a0 = (box.min.x + field_halo) / kLine * kLine;
  const int a1 = (box.max.x + field_halo + kLine - 1) / kLine * kLine;
  return std::size_t(a1 - a0) * sizeof(float) * std::size_t(box.height());
}

}  // namespace ardcell
