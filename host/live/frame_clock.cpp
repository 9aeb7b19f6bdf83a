#include "host/live/frame_clock.h"

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <ctime>

namespace ardcell {

int64_t MonotonicTime::now_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return int64_t(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

void MonotonicTime::sleep_until_ns(int64_t deadline_ns) {
  timespec ts{};
  ts.tv_sec = time_t(deadline_ns / 1'000'000'000);
  ts.tv_nsec = long(deadline_ns % 1'000'000'000);
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
  }
}

MonotonicTime& MonotonicTime::instance() {
  static MonotonicTime time;
  return time;
}

void DurationHistogram::add(int64_t ns) {
  if (ns < 0) ns = 0;
  const int64_t b = std::min<int64_t>(ns / kBucketNs, kBuckets);
  ++buckets_[size_t(b)];
  ++count_;
  sum_ns_ += ns;
  max_ns_ = std::max(max_ns_, ns);
}

void DurationHistogram::clear() { *this = DurationHistogram(); }

int64_t DurationHistogram::percentile_ns(double q) const {
  if (count_ == 0) return 0;
  const double target = std::clamp(q, 0.0, 1.0) * double(count_);
  int64_t seen = 0;
  for (int b = 0; b <= kBuckets; ++b) {
    seen += buckets_[size_t(b)];
    if (double(seen) >= target && seen > 0)
      return b == kBuckets ? max_ns_ : std::min<int64_t>((b + 1) * kBucketNs, max_ns_);
  }
  return max_ns_;
}

std::string_view frame_stage_name(FrameStage stage) {
  switch (stage) {
    case FrameStage::kInput:
      return "input";
    case FrameStage::kSimulate:
      return "simulate";
    case FrameStage::kRender:
      return "render";
    case FrameStage::kPresent:
      return "present";
    case FrameStage::kRecord:
      return "record";
    case FrameStage::kCount:
      break;
  }
  return "?";
}

FrameClock::FrameClock(double fps, TimeSource& time) : time_(time) { set_fps(fps); }

void FrameClock::set_fps(double fps) {
  fps_ = fps > 0 ? fps : 0;
  period_ns_ = fps_ > 0 ? int64_t(1e9 / fps_ + 0.5) : 0;
  scheduled_ = false;  // the next frame starts a fresh schedule
}

void FrameClock::begin_frame() {
  const int64_t now = time_.now_ns();
  if (!scheduled_) {
    deadline_ns_ = now + period_ns_;
    scheduled_ = true;
  }
  if (last_begin_ns_ >= 0) {
    const int64_t interval = now - last_begin_ns_;
    interval_.add(interval);
    recent_interval_[size_t(interval_next_)] = interval;
    interval_next_ = (interval_next_ + 1) % kRecent;
    interval_count_ = std::min(interval_count_ + 1, kRecent);
  }
  last_begin_ns_ = now;
  frame_begin_ns_ = now;
  last_mark_ns_ = now;
}

void FrameClock::mark(FrameStage stage) {
  const int64_t now = time_.now_ns();
  StageTiming& s = stages_[size_t(stage)];
  const int64_t d = now - last_mark_ns_;
  s.last_ns = d;
  s.max_ns = std::max(s.max_ns, d);
  s.total_ns += d;
  ++s.count;
  last_mark_ns_ = now;
}

int64_t FrameClock::slack_ns() {
  if (period_ns_ == 0) return INT64_MAX;
  return deadline_ns_ - time_.now_ns();
}

bool FrameClock::end_frame_and_wait() {
  const int64_t now = time_.now_ns();
  last_work_ns_ = now - frame_begin_ns_;
  work_.add(last_work_ns_);
  recent_work_[size_t(recent_next_)] = last_work_ns_;
  recent_next_ = (recent_next_ + 1) % kRecent;
  recent_count_ = std::min(recent_count_ + 1, kRecent);
  ++frames_;
  if (period_ns_ == 0) return false;
  bool missed = false;
  if (now > deadline_ns_) {
    ++misses_;
    missed = true;
    deadline_ns_ = now;  // restart the schedule: the next frame gets a whole period
  } else {
    time_.sleep_until_ns(deadline_ns_);
  }
  deadline_ns_ += period_ns_;
  return missed;
}

int64_t FrameClock::recent_percentile_ns(double q) const {
  if (recent_count_ == 0) return 0;
  std::array<int64_t, kRecent> sorted;
  std::copy_n(recent_work_.begin(), recent_count_, sorted.begin());
  const int n = recent_count_;
  const int k = std::clamp(int(q * double(n - 1) + 0.5), 0, n - 1);
  std::nth_element(sorted.begin(), sorted.begin() + k, sorted.begin() + n);
  return sorted[size_t(k)];
}

double FrameClock::recent_fps() const {
  const int n = interval_count_;
  if (n == 0) return 0;
  int64_t total = 0;
  for (int i = 0; i < n; ++i) total += recent_interval_[size_t(i)];
  return total > 0 ? 1e9 * double(n) / double(total) : 0;
}

void FrameClock::reset_counters() {
  frames_ = misses_ = 0;
  work_.clear();
  interval_.clear();
  stages_ = {};
  recent_count_ = recent_next_ = interval_count_ = interval_next_ = 0;
  last_begin_ns_ = -1;
}

void FrameClock::print_report(std::FILE* out) const {
  const double ms = 1e-6;
  std::fprintf(out,
               "frames %lld, deadline misses %lld at %.1f fps target; work p50 %.3f ms p99 %.3f "
               "ms max %.3f ms; interval p50 %.3f ms p99 %.3f ms\n",
               (long long)frames_, (long long)misses_, fps_, work_.percentile_ns(0.5) * ms,
               work_.percentile_ns(0.99) * ms, work_.max_ns() * ms,
               interval_.percentile_ns(0.5) * ms, interval_.percentile_ns(0.99) * ms);
  std::fprintf(out, "stages (mean/max ms):");
  for (int i = 0; i < kStages; ++i) {
    const StageTiming& s = stages_[size_t(i)];
    if (s.count == 0) continue;
    const std::string_view name = frame_stage_name(FrameStage(i));
    std::fprintf(out, " %.*s %.3f/%.3f", int(name.size()), name.data(),
                 double(s.total_ns) / double(s.count) * ms, s.max_ns * ms);
  }
  std::fprintf(out, "\n");
  std::fflush(out);
}

namespace {
volatile std::sig_atomic_t g_report_requested = 0;
extern "C" void on_report_signal(int) { g_report_requested = 1; }
}  // namespace

void install_report_signal() {
  struct sigaction sa {};
  sa.sa_handler = on_report_signal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESTART;
  sigaction(SIGUSR1, &sa, nullptr);
}

bool take_report_request() {
  if (!g_report_requested) return false;
  g_report_requested = 0;
  return true;
}

void request_report() { g_report_requested = 1; }

}  // namespace ardcell
