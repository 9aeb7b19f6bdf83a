#include "runtime/local_store.h"

#include <cstdio>
#include <cstdlib>
#include <new>

#include "runtime/check.h"

namespace ardcell {

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
