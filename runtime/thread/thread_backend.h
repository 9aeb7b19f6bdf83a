#pragma once
// The threads back end: one worker per accelerator queue (an SPE each), pinned to a core, each
// with its own LocalStore and Dma (worker 0 may be the host thread itself, see host_is_worker).
//
// dispatch() fills one of kMaxOutstanding slots and publishes it by bumping a dispatch counter
// that idle workers wait on (spin, then yield, then a futex sleep). Worker w runs the contiguous
// w-th share of the slot's tiles, then helps with the others' (each share has a claim counter,
// so a descheduled worker's tiles go to the others; a tile's result does not depend on who
// computes it), with the double-buffered tile program: the next tile is claimed and fetched
// before the current one computes. sync() runs the host's share and waits only for tiles that
// were claimed: it never waits for a worker that has not started, so a pass costs no more than
// its work when another process holds a core (a kiosk's browser, a parallel test run). A
// worker that wakes late finds the claim counters tagged with a newer dispatch and skips.
// Nothing on this path allocates or locks.
#include <sched.h>

#include <array>
#include <atomic>
#include <cstddef>
#include <memory>
#include <span>
#include <thread>
#include <vector>

#include "runtime/backend.h"
#include "runtime/dma.h"
#include "runtime/local_store.h"

namespace ardcell {

struct ThreadBackendOptions {
  int workers = 0;  // 0: one per hardware thread
  std::size_t local_store_bytes = machine_local_store_bytes();
  // Pin worker w to core w % cores, and a host thread that is worker 0 to core 0 for the back
  // end's lifetime (silently unpinned where not permitted).
  bool pin = true;
  // The calling (host) thread runs worker 0's share inside sync(), so `workers` threads of
  // work need only workers - 1 helper threads: on a 2-core machine the host does not sit idle
  // on a core of its own while two workers share the other.
  bool host_is_worker = true;
};

class ThreadBackend final : public Backend {
 public:
  explicit ThreadBackend(const ThreadBackendOptions& options = {});
  ~ThreadBackend() override;
  ThreadBackend(const ThreadBackend&) = delete;
  ThreadBackend& operator=(const ThreadBackend&) = delete;

  const char* name() const override { return "threads"; }
  int workers() const override { return int(workers_.size()); }
  void dispatch(const Pass& pass, std::span<const Tile> tiles) override;
  void sync() override;

  // Bytes each worker's Dma has moved (in + out), summed; for the benchmark's counters.
  std::uint64_t dma_bytes() const;
  std::size_t local_store_bytes() const { return store_bytes_; }

 private:
  static constexpr int kMaxOutstanding = 64;
  // A claim counter: the dispatch it belongs to (high bits) and the tiles of its share claimed so
  // far (low kClaimBits bits).
  static constexpr int kClaimBits = 24;
  struct Slot {
    std::atomic<const Pass*> pass{nullptr};
    std::atomic<const Tile*> tiles{nullptr};
    std::atomic<std::size_t> count{0};
    std::atomic<std::size_t> done{0};                      // tiles finished (puts completed)
    std::unique_ptr<std::atomic<std::uint64_t>[]> claims;  // one per share
  };
  struct Worker;
  static void run_worker(ThreadBackend& backend, Worker& w);
  // Worker w's part of dispatch `d` (0-based): its share, then the others' unclaimed tiles.
  void run_share(Worker& w, std::uint64_t d);

  std::size_t store_bytes_;
  std::vector<std::unique_ptr<Worker>> workers_;
  bool host_is_worker_ = true;
  bool host_pinned_ = false;  // the host thread was pinned to core 0; host_mask_ is its old mask
  cpu_set_t host_mask_{};
  std::array<Slot, kMaxOutstanding> slots_;
  std::atomic<std::uint64_t> issued_{0};  // dispatches published
  std::uint64_t synced_ = 0;              // dispatches sync() has completed
  std::atomic<bool> stop_{false};
};

}  // namespace ardcell
