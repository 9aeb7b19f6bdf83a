#pragma once
// FrameClock: paces the live loop at a target rate with absolute deadlines
// (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME)), so sleep error never accumulates, and keeps
// the real-time counters: per-stage timings, deadline misses, p50/p99 of the frame work time and
// of the frame-to-frame interval. All storage is fixed-size: nothing allocates after
// construction, so the clock may run inside a steady-state frame.
#include <array>
#include <atomic>
#include <cstdint>
#include <cstdio>
#include <string_view>

namespace ardcell {

// Where time comes from. The real one is CLOCK_MONOTONIC; tests substitute a fake that they
// advance by hand, so that "slow" frames are exact and no test depends on the machine's speed.
class TimeSource {
 public:
  virtual ~TimeSource() = default;
  virtual int64_t now_ns() = 0;
  // Blocks until now_ns() >= deadline_ns (absolute).
  virtual void sleep_until_ns(int64_t deadline_ns) = 0;
};

// CLOCK_MONOTONIC with clock_nanosleep(TIMER_ABSTIME), retried on EINTR.
class MonotonicTime final : public TimeSource {
 public:
  int64_t now_ns() override;
  void sleep_until_ns(int64_t deadline_ns) override;
  static MonotonicTime& instance();
};

// Percentiles over a fixed histogram of durations: 20 us buckets up to 200 ms, then overflow.
class DurationHistogram {
 public:
  static constexpr int64_t kBucketNs = 20'000;
  static constexpr int kBuckets = 10'000;
  void add(int64_t ns);
  void clear();
  int64_t count() const { return count_; }
  // The smallest bucket upper edge below which a fraction q of the samples lie (ns); 0 if empty.
  int64_t percentile_ns(double q) const;
  int64_t max_ns() const { return max_ns_; }
  double mean_ns() const { return count_ ? double(sum_ns_) / double(count_) : 0.0; }

 private:
  std::array<uint32_t, kBuckets + 1> buckets_{};
  int64_t count_ = 0;
  int64_t sum_ns_ = 0;
  int64_t max_ns_ = 0;
};

// The stages of a live frame, timed separately.
enum class FrameStage : uint8_t { kInput, kSimulate, kRender, kPresent, kRecord, kCount };
std::string_view frame_stage_name(FrameStage stage);

struct StageTiming {
  int64_t last_ns = 0;
  int64_t max_ns = 0;
  int64_t total_ns = 0;
  int64_t count = 0;
};

class FrameClock {
 public:
  static constexpr int kStages = int(FrameStage::kCount);
  static constexpr int kRecent = 128;  // frames in the short window the HUD shows

  // fps <= 0: run unpaced (as fast as possible; no deadlines, no misses).
  explicit FrameClock(double fps, TimeSource& time = MonotonicTime::instance());

  void set_fps(double fps);
  double fps() const { return fps_; }
  int64_t period_ns() const { return period_ns_; }

  // Opens a frame: stage timings of this frame are measured from here.
  void begin_frame();
  // Closes the current stage (the time since the previous mark or begin_frame()).
  void mark(FrameStage stage);
  // Closes the frame: records its work time, counts a miss when the work ran past the frame's
  // deadline, then sleeps until the next deadline. After a miss the schedule restarts from now,
  // so one slow frame costs one miss, not a burst of catch-up frames. Returns true on a miss.
  bool end_frame_and_wait();

  // Nanoseconds left before the current frame's deadline (negative when already late);
  // adaptive quality uses it to act before a miss.
  int64_t slack_ns();
  // When the current frame began, and the time spent in it so far.
  int64_t frame_begin_ns() const { return frame_begin_ns_; }
  int64_t elapsed_in_frame_ns() { return time_.now_ns() - frame_begin_ns_; }
  // Work time of the last finished frame.
  int64_t last_work_ns() const { return last_work_ns_; }

  int64_t frames() const { return frames_; }
  int64_t misses() const { return misses_; }
  const DurationHistogram& work_histogram() const { return work_; }
  const DurationHistogram& interval_histogram() const { return interval_; }
  const StageTiming& stage(FrameStage s) const { return stages_[int(s)]; }
  // p50/p99 of the work time over the last kRecent frames (for the HUD), and their rate.
  int64_t recent_percentile_ns(double q) const;
  double recent_fps() const;

  // One block of text: frames, misses, fps, p50/p99 work and interval, per-stage means.
  void print_report(std::FILE* out) const;
  void reset_counters();

 private:
  TimeSource& time_;
  double fps_ = 0;
  int64_t period_ns_ = 0;
  int64_t deadline_ns_ = 0;  // absolute deadline of the frame in progress
  int64_t frame_begin_ns_ = 0;
  int64_t last_mark_ns_ = 0;
  int64_t last_begin_ns_ = -1;  // previous frame's begin, for the interval
  int64_t last_work_ns_ = 0;
  int64_t frames_ = 0;
  int64_t misses_ = 0;
  bool scheduled_ = false;
  DurationHistogram work_;
  DurationHistogram interval_;
  std::array<StageTiming, kStages> stages_{};
  std::array<int64_t, kRecent> recent_work_{};
  std::array<int64_t, kRecent> recent_interval_{};
  int recent_next_ = 0;
  int recent_count_ = 0;
  int interval_next_ = 0;
  int interval_count_ = 0;
};

// SIGUSR1 asks a running loop to print its report. The handler only sets a flag
// (async-signal-safe); the loop calls take_report_request() once per frame.
void install_report_signal();
bool take_report_request();
// For tests and for other signal sources: the same as receiving SIGUSR1.
void request_report();

}  // namespace ardcell
