#include "runtime/thread/thread_backend.h"

#include <pthread.h>
#include <sched.h>

#include <algorithm>

#include "runtime/check.h"

namespace ardcell {
namespace {
// A waiting side spins kSpin pauses (about 50 ns each on the EPYC), then yields kYields times,
// then sleeps on the futex. Passes of a small grid last tens of microseconds: on idle cores the
// yields return at once and the waiter picks the next message up without a sleep and wake-up
// (which costs more than the pass); on shared cores they hand the core to the thread being
// waited for instead of spinning it away.
constexpr int kSpin = 256, kYields = 64;
}  // namespace

struct ThreadBackend::Worker {
  Worker(int index, std::size_t store_bytes) : store(store_bytes) { ctx.worker = index; }
  int index = 0;
  int count = 1;
  LocalStore store;
  Dma dma;
  WorkerContext ctx;
  Mailbox<Command, 64> inbox;
  Mailbox<int, 64> outbox;
  std::thread thread;
};

ThreadBackend::ThreadBackend(const ThreadBackendOptions& options)
    : store_bytes_(options.local_store_bytes), host_is_worker_(options.host_is_worker) {
  int n = options.workers;
  if (n <= 0) n = std::max(1u, std::thread::hardware_concurrency());
  const int cores = int(std::max(1u, std::thread::hardware_concurrency()));
  workers_.reserve(std::size_t(n));
  for (int i = 0; i < n; ++i) {
    auto w = std::make_unique<Worker>(i, store_bytes_);
    w->index = i;
    w->count = n;
    w->ctx.store = &w->store;
    w->ctx.dma = &w->dma;
    workers_.push_back(std::move(w));
  }
  // The host thread is worker 0: pin it to core 0 too (restored in the destructor). Left
  // unpinned, the scheduler's wake-affine placement pulls it onto the core of the pinned worker
  // whose completion wakes it, and the two then share one core while the other idles.
  if (options.pin && host_is_worker_ && n > 1) {
    cpu_set_t set;
    CPU_ZERO(&set);
    CPU_SET(0, &set);
    host_pinned_ = pthread_getaffinity_np(pthread_self(), sizeof(host_mask_), &host_mask_) == 0 &&
                   pthread_setaffinity_np(pthread_self(), sizeof(set), &set) == 0;
  }
  for (auto& w : workers_) {
    if (host_is_worker_ && w->index == 0) continue;
    w->thread = std::thread(run_worker, std::ref(*w));
    if (options.pin) {
      cpu_set_t set;
      CPU_ZERO(&set);
      CPU_SET(w->index % cores, &set);
      // Pinning is a performance hint: a container without the right keeps the default mask.
      (void)pthread_setaffinity_np(w->thread.native_handle(), sizeof(set), &set);
    }
  }
}

ThreadBackend::~ThreadBackend() {
  sync();
  for (auto& w : workers_)
    if (w->thread.joinable()) w->inbox.push(Command{});
  for (auto& w : workers_)
    if (w->thread.joinable()) w->thread.join();
  if (host_pinned_) (void)pthread_setaffinity_np(pthread_self(), sizeof(host_mask_), &host_mask_);
}

void ThreadBackend::dispatch(const Pass& pass, std::span<const Tile> tiles) {
  ARDCELL_CHECK(pass.fetch != nullptr && pass.compute != nullptr,
                "threads back end needs a tile program (fetch and compute)");
  ARDCELL_CHECK(outstanding_ < kMaxOutstanding, "threads back end: too many passes before sync");
  const Command cmd{&pass, tiles.data(), tiles.size()};
  for (auto& w : workers_)
    if (w->thread.joinable()) w->inbox.push(cmd);
  if (host_is_worker_) host_queue_[std::size_t(outstanding_)] = cmd;
  ++outstanding_;
}

void ThreadBackend::sync() {
  if (host_is_worker_)
    for (int i = 0; i < outstanding_; ++i) run_share(*workers_[0], host_queue_[std::size_t(i)]);
  for (; outstanding_ > 0; --outstanding_)
    for (auto& w : workers_)
      if (w->thread.joinable()) (void)w->outbox.pop(kSpin, kYields);
}

std::uint64_t ThreadBackend::dma_bytes() const {
  std::uint64_t total = 0;
  for (const auto& w : workers_) total += w->dma.bytes_in() + w->dma.bytes_out();
  return total;
}

void ThreadBackend::run_worker(Worker& w) {
  for (;;) {
    const Command cmd = w.inbox.pop(kSpin, kYields);
    if (cmd.pass == nullptr) return;
    run_share(w, cmd);
    w.outbox.push(w.index);
  }
}

// Runs the w-th contiguous share of the tiles, double-buffered: tile i+1 is fetched into the
// other slot before tile i computes.
void ThreadBackend::run_share(Worker& w, const Command& cmd) {
  const Pass& pass = *cmd.pass;
  const std::size_t begin = cmd.count * std::size_t(w.index) / std::size_t(w.count);
  const std::size_t end = cmd.count * std::size_t(w.index + 1) / std::size_t(w.count);
  if (begin >= end) return;
  pass.fetch(pass.program, cmd.tiles[begin], 0, w.ctx);
  for (std::size_t i = begin; i < end; ++i) {
    const int slot = int((i - begin) & 1);
    if (i + 1 < end) pass.fetch(pass.program, cmd.tiles[i + 1], slot ^ 1, w.ctx);
    pass.compute(pass.program, cmd.tiles[i], slot, w.ctx);
  }
  w.dma.wait_all();
}

}  // namespace ardcell
