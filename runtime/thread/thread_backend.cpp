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
  std::thread thread;
};

namespace {

constexpr std::uint64_t kClaimMask = (std::uint64_t(1) << 24) - 1;

// Waits, spinning, then yielding, until `done` holds `target`.
void wait_for(const std::atomic<std::size_t>& done, std::size_t target) {
  for (int spin = 0; done.load(std::memory_order_acquire) != target; ++spin) {
    if (spin < kSpin) {
#if defined(__x86_64__) || defined(__i386__)
      __builtin_ia32_pause();
#endif
    } else {
      std::this_thread::yield();
    }
  }
}

}  // namespace

ThreadBackend::ThreadBackend(const ThreadBackendOptions& options)
    : store_bytes_(options.local_store_bytes), host_is_worker_(options.host_is_worker) {
  int n = options.workers;
  if (n <= 0) n = std::max(1u, std::thread::hardware_concurrency());
  const int cores = int(std::max(1u, std::thread::hardware_concurrency()));
  workers_.reserve(std::size_t(n));
  for (Slot& slot : slots_) {
    slot.claims = std::make_unique<std::atomic<std::uint64_t>[]>(std::size_t(n));
    for (int i = 0; i < n; ++i) slot.claims[std::size_t(i)].store(0, std::memory_order_relaxed);
  }
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
    w->thread = std::thread(run_worker, std::ref(*this), std::ref(*w));
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
  stop_.store(true, std::memory_order_release);
  issued_.fetch_add(1, std::memory_order_release);  // wakes the sleepers; they see stop_
  issued_.notify_all();
  for (auto& w : workers_)
    if (w->thread.joinable()) w->thread.join();
  if (host_pinned_) (void)pthread_setaffinity_np(pthread_self(), sizeof(host_mask_), &host_mask_);
}

void ThreadBackend::dispatch(const Pass& pass, std::span<const Tile> tiles) {
  ARDCELL_CHECK(pass.compute != nullptr, "threads back end needs a tile program (compute)");
  const std::uint64_t d = issued_.load(std::memory_order_relaxed);
  ARDCELL_CHECK(d - synced_ < kMaxOutstanding, "threads back end: too many passes before sync");
  ARDCELL_CHECK(tiles.size() <= kClaimMask, "threads back end: too many tiles in one pass");
  Slot& slot = slots_[d % kMaxOutstanding];
  slot.pass.store(&pass, std::memory_order_relaxed);
  slot.tiles.store(tiles.data(), std::memory_order_relaxed);
  slot.count.store(tiles.size(), std::memory_order_relaxed);
  slot.done.store(0, std::memory_order_relaxed);
  // Tagging the claim counters with this dispatch retires the slot's previous one: a worker
  // still holding it fails every claim from now on.
  const std::uint64_t tag = (d + 1) << kClaimBits;
  for (std::size_t s = 0; s < workers_.size(); ++s)
    slot.claims[s].store(tag, std::memory_order_relaxed);
  issued_.store(d + 1, std::memory_order_release);
  issued_.notify_all();
}

void ThreadBackend::sync() {
  const std::uint64_t issued = issued_.load(std::memory_order_relaxed);
  for (std::uint64_t d = synced_; d < issued; ++d) {
    if (host_is_worker_) run_share(*workers_[0], d);
    const Slot& slot = slots_[d % kMaxOutstanding];
    wait_for(slot.done, slot.count.load(std::memory_order_relaxed));
  }
  synced_ = issued;
}

std::uint64_t ThreadBackend::dma_bytes() const {
  std::uint64_t total = 0;
  for (const auto& w : workers_) total += w->dma.bytes_in() + w->dma.bytes_out();
  return total;
}

void ThreadBackend::run_worker(ThreadBackend& b, Worker& w) {
  std::uint64_t seen = 0;
  for (;;) {
    std::uint64_t issued = b.issued_.load(std::memory_order_acquire);
    for (int spin = 0; issued == seen; ++spin) {
      if (spin < kSpin) {
#if defined(__x86_64__) || defined(__i386__)
        __builtin_ia32_pause();
#endif
      } else if (spin < kSpin + kYields) {
        std::this_thread::yield();
      } else {
        b.issued_.wait(seen, std::memory_order_acquire);
      }
      issued = b.issued_.load(std::memory_order_acquire);
    }
    if (b.stop_.load(std::memory_order_acquire)) return;
    // Dispatches older than the slots are done: the host reused their slot.
    if (issued - seen > kMaxOutstanding) seen = issued - kMaxOutstanding;
    for (; seen < issued; ++seen) b.run_share(w, seen);
  }
}

// Worker w runs the contiguous w-th share of the tiles first (the cells it wrote in the last pass
// are in its own caches), then helps with the other shares. Double-buffered: the next tile is
// claimed and fetched into the other slot before the current one computes. The tiles it
// finished count as done once its puts have completed.
void ThreadBackend::run_share(Worker& w, std::uint64_t d) {
  Slot& slot = slots_[d % kMaxOutstanding];
  const std::uint64_t tag = (d + 1) << kClaimBits;
  const std::size_t n = std::size_t(w.count);
  // Read before any claim; a claim that succeeds proves the slot still held dispatch d (the host
  // reuses a slot only once all of its tiles were claimed and done).
  const Pass* pass = slot.pass.load(std::memory_order_relaxed);
  const Tile* tiles = slot.tiles.load(std::memory_order_relaxed);
  const std::size_t count = slot.count.load(std::memory_order_relaxed);
  std::size_t share = 0;  // shares visited so far, starting with the worker's own
  const auto claim = [&]() -> std::size_t {
    for (; share < n; ++share) {
      const std::size_t s = (std::size_t(w.index) + share) % n;
      const std::size_t begin = count * s / n, end = count * (s + 1) / n;
      std::uint64_t v = slot.claims[s].load(std::memory_order_acquire);
      while ((v & ~kClaimMask) == tag && begin + (v & kClaimMask) < end) {
        if (slot.claims[s].compare_exchange_weak(v, v + 1, std::memory_order_acq_rel))
          return begin + std::size_t(v & kClaimMask);
      }
      if ((v & ~kClaimMask) != tag) return count;  // a later dispatch owns the slot
    }
    return count;
  };
  // Nothing of *pass may be read before a claim succeeds: the pass of a dispatch this worker
  // woke too late for may be gone.
  std::size_t i = claim();
  if (i >= count) return;
  std::size_t finished = 0;
  if (!pass->fetch) {
    // In place: nothing to fetch ahead, so a tile is claimed only when the worker can start it
    // (a look-ahead claim would take the last tiles of the others' shares from idle workers).
    for (; i < count; i = claim()) {
      pass->compute(pass->program, tiles[i], 0, w.ctx);
      ++finished;
    }
    slot.done.fetch_add(finished, std::memory_order_release);
    return;
  }
  pass->fetch(pass->program, tiles[i], 0, w.ctx);
  for (int buffer = 0;; buffer ^= 1) {
    const std::size_t j = claim();
    if (j < count) pass->fetch(pass->program, tiles[j], buffer ^ 1, w.ctx);
    pass->compute(pass->program, tiles[i], buffer, w.ctx);
    ++finished;
    if (j >= count) break;
    i = j;
  }
  w.dma.wait_all();
  slot.done.fetch_add(finished, std::memory_order_release);
}

}  // namespace ardcell
