#pragma once
// Dma: MFC-style transfers between main memory (Fields) and a worker's LocalStore.
//
// As on the Cell's SPE: a transfer moves at most 16 KiB, both addresses and the size are
// multiples of 128 bytes, each transfer carries a tag (0..31), and wait(tag) returns when every
// transfer with that tag has completed. On a CPU a transfer is a memcpy: issuing it records it
// and prefetches its source lines (software prefetch, so the next tile streams into the caches
// while the current one computes); wait(tag) performs the recorded copies of that tag. The
// queue is a fixed array: no allocation, ever.
//
// Box transfers copy each row of a box as one transfer, widened to whole 128-byte lines of the
// field's memory (fields pad and align their rows, runtime/field.h). The local copy of a box is
// a View in GLOBAL coordinates, so kernels run on it unchanged. A put writes whole lines too, so
// the box put must start and end on line boundaries (or at the end of the row): TilePlan cuts
// tiles there. With ARDCELL_CHECKS on, a transfer over 16 KiB or misaligned stops the program
// with a message naming the transfer.
#include <array>
#include <cstddef>
#include <cstdint>

#include "runtime/box.h"
#include "runtime/field.h"
#include "runtime/local_store.h"

namespace ardcell {

class Dma {
 public:
  static constexpr std::size_t kMaxTransferBytes = 16 * 1024;
  static constexpr std::size_t kAlignBytes = 128;
  static constexpr int kTags = 32;
  static constexpr int kQueueCapacity = 1024;
  // put_box into a field at least this large writes with non-temporal stores (a field of 1024^2
  // floats and up: a frame's fields no longer fit the caches, and streaming stores skip the
  // read-for-ownership of the destination lines).
  static constexpr std::size_t kStreamingPutFieldBytes = std::size_t(4) << 20;

  // Raw transfers (the MFC's mfc_get / mfc_put).
  void get(void* local, const void* remote, std::size_t bytes, int tag);
  void put(const void* local, void* remote, std::size_t bytes, int tag);
  // Completes every transfer issued with `tag`.
  void wait(int tag);
  void wait_all();
  int pending() const { return count_; }

  // Fetches `box` of `field` (box inside field.with_halo()) into a fresh buffer of `arena`.
  // Returns the local copy, valid once wait(tag) has returned.
  View<float> get_box(const FieldF& field, const Box2& box, SlotArena& arena, int tag);
  // A local buffer laid out as get_box would, without fetching (outputs computed in store).
  View<float> local_box(const FieldF& field, const Box2& box, SlotArena& arena) const {
    return local_box(field.origin().x - field.halo(), box, arena);
  }
  // The same, for rows whose first element is at x = row_start (scratch buffers that mirror no
  // field: the origin.x - halo of the fields the pass puts into).
  View<float> local_box(int row_start, const Box2& box, SlotArena& arena) const;
  // Writes `box` of the local copy `local` back into `field`.
  void put_box(View<const float> local, FieldF& field, const Box2& box, int tag);

  // Statistics since construction (bytes moved each way, number of transfers).
  std::uint64_t bytes_in() const { return bytes_in_; }
  std::uint64_t bytes_out() const { return bytes_out_; }
  std::uint64_t transfers() const { return transfers_; }

 private:
  struct Transfer {
    void* dst;
    const void* src;
    std::uint32_t bytes;
    std::int32_t tag;
    bool streaming;  // non-temporal stores (puts into large fields)
  };
  void enqueue(void* dst, const void* src, std::size_t bytes, int tag, const char* what,
               bool streaming = false);
  void complete(int index);

  std::array<Transfer, kQueueCapacity> queue_{};
  int count_ = 0;
  std::uint64_t bytes_in_ = 0, bytes_out_ = 0, transfers_ = 0;
};

}  // namespace ardcell
