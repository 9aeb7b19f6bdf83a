#pragma once
// The processes of one run through Open MPI (`mpirun -np N ardcell run ... --ranks WxH`): each
// rank runs one block of the grid (runtime/block_layout.h), its frame plan's halo exchange going
// through MpiHaloChannel, and rank 0 gathers the blocks for what is written. Nothing above
// runtime/ includes mpi.h: this header is the whole of MPI the rest of ardcell sees.
#include <cstddef>
#include <vector>

#include "runtime/block_layout.h"
#include "runtime/field.h"

namespace ardcell {

// MPI_Init on construction (threads: funneled, only the thread that made it calls MPI),
// MPI_Finalize on destruction; one per process.
class MpiWorld {
 public:
  MpiWorld();
  ~MpiWorld();
  MpiWorld(const MpiWorld&) = delete;
  MpiWorld& operator=(const MpiWorld&) = delete;

  int rank() const { return rank_; }
  int size() const { return size_; }
  // True on every rank when `flag` is true on any (all ranks call it together).
  bool any(bool flag) const;

 private:
  int rank_ = 0, size_ = 1;
};

// The frame plan's exchange between ranks: block b is rank b. One message per neighbouring rank
// and exchange (the boxes it owns of this block's halo, packed), non-blocking both ways; copies
// from this block itself (a periodic wrap) are made in place. Buffers are sized once.
class MpiHaloChannel final : public HaloChannel {
 public:
  MpiHaloChannel(const BlockLayout& layout, int width, const MpiWorld& world);
  int block() const override { return block_; }
  int width() const override { return exchange_.width(); }
  void exchange(FieldF& field) override;
  // Halo cells this rank receives per exchanged field.
  std::size_t cells_in() const { return exchange_.cells_into(block_); }

 private:
  struct Peer {
    int rank = 0;
    std::vector<HaloCopy> recv, send;  // boxes in this block's coordinates / the peer's
    std::vector<float> recv_buf, send_buf;
  };
  int block_ = 0;
  HaloExchange exchange_;
  std::vector<HaloCopy> self_;  // periodic copies from this block itself
  std::vector<Peer> peers_;
};

// Gathers the cells each rank owns (layout.owned) of its block field into `whole` (a field of
// the whole grid, halo >= 1) on rank 0; the other ranks pass nullptr. All ranks call it.
class BlockGather {
 public:
  BlockGather(const BlockLayout& layout, const MpiWorld& world);
  void gather(const FieldF& block, FieldF* whole);

 private:
  BlockLayout layout_;
  int rank_ = 0;
  std::vector<float> buffer_;
};

}  // namespace ardcell
