#pragma once
// LocalStore: a worker's fixed arena, as an SPE's local store (256 KiB on the Cell; by default
// here two of a core's L2 caches, one per double-buffer slot: machine_local_store_bytes). Allocated
// once when the worker starts; a tile program lays its buffers out in it with a bump cursor, reset
// per tile. It is split into two halves (slots) for double buffering: tile i+1 is fetched into one
// slot while tile i computes in the other.
#include <cstddef>
#include <cstdint>
#include <memory>

#include "runtime/box.h"
#include "runtime/field.h"

namespace ardcell {

// The Cell SPE's local store: the Cell-faithful size (`--store-kib spe`).
inline constexpr std::size_t kSpeLocalStoreBytes = 256 * 1024;

// The local store a worker gets by default: twice this machine's L2 cache per core (from
// /sys/devices/system/cpu/cpu0/cache, else sysconf), so that each double-buffer slot - the tile
// computing - fits the core's L2; a multiple of 256 bytes in [64 KiB, 16 MiB]; the SPE's
// 256 KiB where the machine does not say. Read once. Measured on the 512 KiB-L2 EPYC,
// Table 1 blocked fluid+RD 512^2: 31 FPS with 256 KiB, 47 with 512 KiB, 59-67 with 1 MiB.
std::size_t machine_local_store_bytes();

// The machine's last-level data cache (the whole of it, as its cores share it), from sysfs, else
// sysconf; 8 MiB where the machine does not say. Read once. What a pass over several fields must
// exceed before streaming them through memory once per sweep costs more than blocking the sweeps.
std::size_t machine_last_level_cache_bytes();

class LocalStore {
 public:
  static constexpr int kSlots = 2;
  explicit LocalStore(std::size_t capacity_bytes = machine_local_store_bytes());
  LocalStore(const LocalStore&) = delete;
  LocalStore& operator=(const LocalStore&) = delete;

  std::size_t capacity() const { return capacity_; }
  std::size_t slot_bytes() const { return slot_bytes_; }
  std::byte* base() const { return data_.get(); }
  // Start of double-buffer slot s (0 or 1), 128-byte aligned.
  std::byte* slot(int s) const;

 private:
  struct FreeDeleter {
    void operator()(std::byte* p) const { std::free(p); }
  };
  std::size_t capacity_;
  std::size_t slot_bytes_;
  std::unique_ptr<std::byte, FreeDeleter> data_;
};

// Bump allocator over one slot of a LocalStore. Hands out 128-byte aligned buffers; running out
// is a broken tile plan and stops with a message naming the sizes.
class SlotArena {
 public:
  SlotArena(const LocalStore& store, int slot)
      : begin_(store.slot(slot)), end_(begin_ + store.slot_bytes()), cursor_(begin_) {}
  std::byte* allocate(std::size_t bytes);
  std::size_t used() const { return std::size_t(cursor_ - begin_); }

 private:
  std::byte* begin_;
  std::byte* end_;
  std::byte* cursor_;
};

// Bytes a local copy of `box` takes when its rows are fetched as whole 128-byte lines of a
// field whose row starts are 128-byte aligned and whose halo is `field_halo` (see Dma).
std::size_t local_copy_bytes(const Box2& box, int field_halo);

}  // namespace ardcell
