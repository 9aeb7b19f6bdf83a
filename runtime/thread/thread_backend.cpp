#include "runtime/thread/thread_backend.h"

#include <pthread.h>
#include <sched.h>

#include <algorithm>
#include <chrono>

#include "runtime/check.h"

namespace ardcell {
namespace {
// A waiting side spins kSpins pauses (about 10 us), then yields the core until kYieldFor has
// passed, then sleeps on the futex. kYieldFor is about what a futex wake-up costs on a KVM guest
// (0.1 ms: an IPI to a halted vCPU), the classic spin-then-block choice that never pays more than
// twice the better of the two. Longer is worse where threads are not pinned (`ardcell live`):
// two threads yielding to each other stay runnable on one core, cache-hot, and the scheduler
// does not move one to the idle core (with 1 ms, cavity at 512^2 on two unpinned workers ran at
// 0.5-0.8x one core in some runs). On idle cores a yield returns at once; on shared cores it hands
// the core to the thread being waited for instead of spinning it away.
constexpr int kSpins = 256;
constexpr std::chrono::microseconds kYieldFor{100};
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
  claims_ =
      std::make_unique<std::atomic<std::size_t>[]>(std::size_t(kMaxOutstanding) * std::size_t(n));
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
  ARDCELL_CHECK(pass.compute != nullptr, "threads back end needs a tile program (compute)");
  ARDCELL_CHECK(outstanding_ < kMaxOutstanding, "threads back end: too many passes before sync");
  std::atomic<std::size_t>* next = &claims_[std::size_t(outstanding_) * workers_.size()];
  for (std::size_t s = 0; s < workers_.size(); ++s)
    next[s].store(0, std::memory_order_relaxed);  // published to the workers by the push
  const Command cmd{&pass, tiles.data(), tiles.size(), next};
  for (auto& w : workers_)
    if (w->thread.joinable()) w->inbox.push(cmd);
  if (host_is_worker_) host_queue_[std::size_t(outstanding_)] = cmd;
  ++outstanding_;
}

void ThreadBackend::help(HostProgress progress) {
  if (!host_is_worker_) return;
  for (; host_ran_ < outstanding_; ++host_ran_)
    run_share(*workers_[0], host_queue_[std::size_t(host_ran_)], progress);
}

void ThreadBackend::sync() {
  help({});
  host_ran_ = 0;
  for (; outstanding_ > 0; --outstanding_)
    for (auto& w : workers_)
      if (w->thread.joinable()) (void)w->outbox.pop({kSpins, kYieldFor});
}

std::uint64_t ThreadBackend::dma_bytes() const {
  std::uint64_t total = 0;
  for (const auto& w : workers_) total += w->dma.bytes_in() + w->dma.bytes_out();
  return total;
}

void ThreadBackend::run_worker(Worker& w) {
  for (;;) {
    const Command cmd = w.inbox.pop({kSpins, kYieldFor});
    if (cmd.pass == nullptr) return;
    run_share(w, cmd);
    w.outbox.push(w.index);
  }
}

// Worker w runs the contiguous w-th share of the tiles first (the cells it wrote in the last pass
// are in its own caches), then helps with the other shares: every share has a claim counter, so
// a descheduled worker's tiles go to the others. Double-buffered: the next tile is claimed and
// fetched into the other slot before the current one computes.
void ThreadBackend::run_share(Worker& w, const Command& cmd, HostProgress progress) {
  const Pass& pass = *cmd.pass;
  const std::size_t n = std::size_t(w.count);
  std::size_t share = 0;  // shares visited so far, starting with the worker's own
  const auto claim = [&]() -> std::size_t {
    for (; share < n; ++share) {
      const std::size_t s = (std::size_t(w.index) + share) % n;
      const std::size_t begin = cmd.count * s / n, end = cmd.count * (s + 1) / n;
      const std::size_t i = begin + cmd.next[s].fetch_add(1, std::memory_order_relaxed);
      if (i < end) return i;
    }
    return cmd.count;
  };
  std::size_t i = claim();
  if (i >= cmd.count) return;
  if (!pass.fetch) {
    // In place: nothing to fetch ahead, so a tile is claimed only when the worker can start it
    // (a look-ahead claim would take the last tiles of the others' shares from idle workers).
    for (; i < cmd.count; i = claim()) {
      pass.compute(pass.program, cmd.tiles[i], 0, w.ctx);
      if (progress.poll) progress.poll(progress.user);
    }
    return;
  }
  pass.fetch(pass.program, cmd.tiles[i], 0, w.ctx);
  for (int slot = 0;; slot ^= 1) {
    const std::size_t j = claim();
    if (j < cmd.count) pass.fetch(pass.program, cmd.tiles[j], slot ^ 1, w.ctx);
    pass.compute(pass.program, cmd.tiles[i], slot, w.ctx);
    if (progress.poll) progress.poll(progress.user);
    if (j >= cmd.count) break;
    i = j;
  }
  w.dma.wait_all();
}

}  // namespace ardcell
