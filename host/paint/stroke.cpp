#include "host/paint/stroke.h"

#include <bit>

#include "runtime/check.h"

namespace ardcell {

StrokeRing::StrokeRing(std::size_t capacity) {
  ARDCELL_CHECK(capacity >= 2, "StrokeRing needs a capacity of at least 2");
  const std::size_t n = std::bit_ceil(capacity);
  slots_ = std::make_unique<StrokeSample[]>(n);
  mask_ = n - 1;
}

bool StrokeRing::push(const StrokeSample& s) {
  const std::size_t head = head_.load(std::memory_order_relaxed);
  const std::size_t tail = tail_.load(std::memory_order_acquire);
  if (head - tail > mask_) {
    dropped_.fetch_add(1, std::memory_order_relaxed);
    return false;
  }
  slots_[head & mask_] = s;
  head_.store(head + 1, std::memory_order_release);
  return true;
}

bool StrokeRing::pop(StrokeSample& s) {
  const std::size_t tail = tail_.load(std::memory_order_relaxed);
  const std::size_t head = head_.load(std::memory_order_acquire);
  if (tail == head) return false;
  s = slots_[tail & mask_];
  tail_.store(tail + 1, std::memory_order_release);
  return true;
}

std::size_t StrokeRing::pop_many(std::span<StrokeSample> out) {
  const std::size_t tail = tail_.load(std::memory_order_relaxed);
  const std::size_t head = head_.load(std::memory_order_acquire);
  std::size_t n = head - tail;
  if (n > out.size()) n = out.size();
  for (std::size_t i = 0; i < n; ++i) out[i] = slots_[(tail + i) & mask_];
  tail_.store(tail + n, std::memory_order_release);
  return n;
}

std::size_t StrokeRing::size() const {
  return head_.load(std::memory_order_acquire) - tail_.load(std::memory_order_acquire);
}

ReplayStrokeSource::ReplayStrokeSource(std::vector<StrokeSample> samples, std::string description,
                                       bool loop, double loop_gap)
    : samples_(std::move(samples)),
      description_(std::move(description)),
      loop_(loop),
      loop_gap_(loop_gap < 0 ? 0 : loop_gap) {
  if (!samples_.empty()) {
    t0_ = samples_.front().time;
    duration_ = samples_.back().time - t0_;
  }
}

void ReplayStrokeSource::restart(double now) {
  origin_ = now;
  next_ = 0;
}

bool ReplayStrokeSource::finished() const {
  return samples_.empty() || (!loop_ && next_ >= samples_.size());
}

std::size_t ReplayStrokeSource::poll(double now, std::span<StrokeSample> out) {
  std::size_t n = 0;
  while (n < out.size() && !samples_.empty()) {
    if (next_ >= samples_.size()) {
      if (!loop_) break;
      const double next_origin = origin_ + duration_ + loop_gap_;
      if (now < next_origin) break;
      origin_ = next_origin;
      next_ = 0;
    }
    const StrokeSample& s = samples_[next_];
    const double due = origin_ + (s.time - t0_);
    if (due > now) break;
    out[n] = s;
    out[n].time = due;
    ++n;
    ++next_;
  }
  return n;
}

}  // namespace ardcell
