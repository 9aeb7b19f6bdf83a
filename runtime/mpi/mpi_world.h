#pragma once
// The processes of one run through Open MPI (`mpirun -np N ardcell run ... --ranks WxH`, and the
// screens of `ardcell live --wall WxH`): each rank runs one block of the grid
// (runtime/block_layout.h), its frame plan's halo exchange going through MpiHaloChannel, and
// rank 0 gathers the blocks for what is written; a wall's screens also share their input and
// wait for each other through MpiWorld's collectives. Nothing above
// runtime/ includes mpi.h: this header is the whole of MPI the rest of ardcell sees.
#include <cstddef>
#include <memory>
#include <span>
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
  // The sum over the ranks of `value`, on every rank (all ranks call it together).
  double sum(double value) const;
  // The least of `lo` and the greatest of `hi` over the ranks, on every rank.
  void min_max(float& lo, float& hi) const;
  // Returns when every rank has called it.
  void barrier() const;
  // Every rank's `bytes` bytes at `mine`, in rank order, into `all` (size() * bytes), on every
  // rank. No allocation.
  void all_gather(const void* mine, std::size_t bytes, void* all) const;
  // Rank 0's `bytes` bytes at `data` into `data` on every other rank. No allocation.
  void broadcast(void* data, std::size_t bytes) const;
  // Every rank's `mine` (any length), in rank order, concatenated on rank 0 (`all`, resized;
  // `counts`: each rank's length); the other ranks' `all` is left alone.
  void gather_to_root(std::span<const unsigned char> mine, std::vector<unsigned char>& all,
                      std::vector<int>& counts) const;

 private:
  int rank_ = 0, size_ = 1;
};

// The frame plan's exchange between ranks: block b is rank b. begin packs, for each neighbouring
// rank, the boxes it owns of this block's halo, every field's in one message, and posts the
// non-blocking receives and sends; copies from this block itself (a periodic wrap) are made in
// place. finish waits for the messages and unpacks them: in between, the caller's workers compute
// what reads no halo. Open MPI has no progress thread: the messages move inside MPI calls, so
// the host thread, when it computes tiles too, calls progress (MPI_Testall) between them
// (FramePlan::run, Backend::help). Buffers grow in the first frame only.
class MpiHaloChannel final : public HaloChannel {
 public:
  static constexpr std::size_t kMaxFields = 16;  // fields of one exchange step
  MpiHaloChannel(const BlockLayout& layout, int width, const MpiWorld& world);
  ~MpiHaloChannel() override;
  int block() const override { return block_; }
  int width() const override { return exchange_.width(); }
  bool periodic_x() const override { return exchange_.periodic_x(); }
  bool periodic_y() const override { return exchange_.periodic_y(); }
  bool fills_any(const Box2& box) const override { return exchange_.fills_any(block_, box); }
  void begin(std::span<const HaloField> fields) override;
  void progress() override;
  void finish() override;
  // MPI_Allgatherv of the blocks' cells; its buffer (the whole grid) is made at the first call.
  void gather_all(const FieldF& field, FieldF& whole) override;
  // MPI_Allgather of every rank's values, added in rank order on each.
  void sum(std::span<double> values) override;
  // Halo cells this rank receives per exchanged field.
  std::size_t cells_in() const { return exchange_.cells_into(block_); }
  // Since construction or reset_stats: the bytes this rank sent, and the seconds its host thread
  // spent in exchanges (packing, messages, waiting for its neighbours, unpacking; the wait in
  // finish overlaps the workers' inner tiles, so not all of it is time lost).
  double bytes_sent() const { return bytes_sent_; }
  double seconds() const { return double(ns_) * 1e-9; }
  void reset_stats() {
    bytes_sent_ = 0;
    ns_ = 0;
  }

 private:
  struct Peer {
    int rank = 0;
    std::vector<HaloCopy> recv, send;            // boxes in this block's coordinates / the peer's
    std::size_t recv_count = 0, send_count = 0;  // floats of the step in flight (all its fields)
    std::vector<float> recv_buf, send_buf;
  };
  struct Requests;  // MPI's request handles (mpi.h stays in the .cpp)
  int block_ = 0;
  HaloExchange exchange_;
  std::vector<HaloCopy> self_;  // periodic copies from this block itself
  std::vector<Peer> peers_;
  std::vector<HaloField> fields_;  // of the exchange in flight
  std::unique_ptr<Requests> requests_;
  std::vector<int> gather_counts_, gather_offsets_;  // floats of each rank's block, in rank order
  std::vector<float> gathered_;
  std::vector<double> sums_;  // every rank's values of a sum(), kMaxSums a rank
  double bytes_sent_ = 0;
  long long ns_ = 0;
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
