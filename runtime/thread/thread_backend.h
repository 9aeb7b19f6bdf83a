#pragma once
// The threads back end: one worker per accelerator queue (an SPE each), pinned to a core, each
// with its own LocalStore and Dma, fed through a Mailbox (worker 0 may be the host thread
// itself, see host_is_worker). dispatch() posts the pass to
// every worker's inbound mailbox; worker w runs the contiguous w-th share of the tiles, then
// helps with the others' (each share has an atomic claim counter, so a descheduled worker's
// tiles go to the others; a tile's result does not depend on who computes it), with the
// double-buffered tile program: the next tile is claimed and fetched before the current one
// computes. sync() collects one completion per worker
// per dispatch from the outbound mailboxes. Nothing on this path allocates or locks.
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
#include "runtime/mailbox.h"

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
  void help(HostProgress progress) override;

  // Bytes each worker's Dma has moved (in + out), summed; for the benchmark's counters.
  std::uint64_t dma_bytes() const;
  std::size_t local_store_bytes() const { return store_bytes_; }

 private:
  struct Command {
    const Pass* pass = nullptr;  // null: stop
    const Tile* tiles = nullptr;
    std::size_t count = 0;
    std::atomic<std::size_t>* next = nullptr;  // per share: tiles of it claimed so far
  };
  struct Worker;
  static void run_worker(Worker& w);

  std::size_t store_bytes_;
  // Worker w's part of cmd; the host calls progress.poll after each tile it computes.
  static void run_share(Worker& w, const Command& cmd, HostProgress progress = {});

  std::vector<std::unique_ptr<Worker>> workers_;
  bool host_is_worker_ = true;
  bool host_pinned_ = false;  // the host thread was pinned to core 0; host_mask_ is its old mask
  cpu_set_t host_mask_{};
  static constexpr int kMaxOutstanding = 64;
  std::array<Command, kMaxOutstanding> host_queue_{};  // worker 0's share when the host runs it
  // Claim counters, one per share (worker) per dispatch between two syncs.
  std::unique_ptr<std::atomic<std::size_t>[]> claims_;
  int outstanding_ = 0;  // dispatches not yet collected by sync()
  int host_ran_ = 0;     // of those, the ones whose host share help() has run
};

}  // namespace ardcell
