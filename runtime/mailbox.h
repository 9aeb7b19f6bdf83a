#pragma once
// Mailbox<T, N>: a single-producer single-consumer ring of N messages, the host<->worker
// channel (as the SPE's inbound and outbound mailboxes). No allocation and no lock: the two
// indices are atomics, and a blocked reader sleeps on the write index with C++20
// atomic::wait (a futex on Linux) after a bounded spin and yield (Wait), so an idle worker costs
// no CPU.
#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <thread>

namespace ardcell {

template <class T, std::size_t N>
class Mailbox {
  static_assert(N >= 2 && (N & (N - 1)) == 0, "Mailbox capacity must be a power of two");

 public:
  // Producer side. False when full (the caller decides whether to retry).
  bool try_push(const T& value) {
    const std::uint32_t w = write_.load(std::memory_order_relaxed);
    if (w - read_.load(std::memory_order_acquire) == N) return false;
    slots_[w & (N - 1)] = value;
    write_.store(w + 1, std::memory_order_release);
    write_.notify_one();
    return true;
  }
  // Producer side: waits (spinning, then yielding) while the ring is full.
  void push(const T& value) {
    while (!try_push(value)) std::this_thread::yield();
  }

  // Consumer side. Empty optional when there is nothing to read.
  std::optional<T> try_pop() {
    const std::uint32_t r = read_.load(std::memory_order_relaxed);
    if (r == write_.load(std::memory_order_acquire)) return std::nullopt;
    T value = slots_[r & (N - 1)];
    read_.store(r + 1, std::memory_order_release);
    return value;
  }
  // How a blocked consumer waits: `spins` pause instructions, then it yields the core until
  // `yield_for` has passed since it began waiting, then it sleeps on the futex. A spin catches
  // the next message of a busy pipeline at once; a long one steals the core from the thread that
  // would send it when cores are shared, where yielding hands it over (and on an idle core
  // returns at once, about a microsecond a round). The futex's sleep and wake-up cost tens of
  // microseconds (more in a VM, where the idle core halts): a wait shorter than yield_for never
  // pays it.
  struct Wait {
    int spins = 256;
    std::chrono::microseconds yield_for{0};
  };
  // Consumer side: blocks until a message arrives.
  T pop(Wait wait = {}) {
    std::chrono::steady_clock::time_point yield_until{};
    for (int round = 0;; ++round) {
      const std::uint32_t r = read_.load(std::memory_order_relaxed);
      const std::uint32_t w = write_.load(std::memory_order_acquire);
      if (r != w) {
        T value = slots_[r & (N - 1)];
        read_.store(r + 1, std::memory_order_release);
        return value;
      }
      if (round < wait.spins) {
#if defined(__x86_64__) || defined(__i386__)
        __builtin_ia32_pause();
#endif
        continue;
      }
      // The clock is read every 16 yields (a vDSO call, tens of nanoseconds, against a yield's
      // microsecond).
      const int yields = round - wait.spins;
      if (yields == 0) yield_until = std::chrono::steady_clock::now() + wait.yield_for;
      if (yields % 16 != 0 || std::chrono::steady_clock::now() < yield_until)
        std::this_thread::yield();
      else
        write_.wait(w, std::memory_order_acquire);
    }
  }
  std::size_t size() const {
    return write_.load(std::memory_order_acquire) - read_.load(std::memory_order_acquire);
  }

 private:
  alignas(64) std::atomic<std::uint32_t> write_{0};
  alignas(64) std::atomic<std::uint32_t> read_{0};
  alignas(64) T slots_[N]{};
};

}  // namespace ardcell
