#include "host/live/remote_log.h"

#include <array>

#include "host/config/status.h"

namespace ardcell {

namespace {
constexpr int64_t kSecondNs = 1'000'000'000;
}

RemoteLog::RemoteLog(std::FILE* out, TimeSource* time)
    : out_(out), time_(time ? *time : MonotonicTime::instance()) {
  window_start_ns_ = time_.now_ns();
}

RemoteLog::~RemoteLog() { finish(); }

void RemoteLog::finish() {
  std::lock_guard lock(mutex_);
  print_summary();
}

void RemoteLog::print_summary() {
  if (window_dropped_ == 0) return;
  if (out_) {
    std::fprintf(
        out_, "osc: %lld more lines caused by remote commands not logged (at most %d a second)\n",
        static_cast<long long>(window_dropped_), kMaxLinesPerSecond);
    std::fflush(out_);
  }
  ++printed_;
  window_dropped_ = 0;
}

void RemoteLog::roll_window(int64_t now_ns) {
  if (now_ns - window_start_ns_ < kSecondNs) return;
  print_summary();
  window_start_ns_ = now_ns;
  window_lines_ = 0;
}

void RemoteLog::tick() {
  const int64_t now = time_.now_ns();
  std::lock_guard lock(mutex_);
  roll_window(now);
}

void RemoteLog::line(std::string_view who, std::string_view text) {
  const int64_t now = time_.now_ns();
  std::lock_guard lock(mutex_);
  roll_window(now);
  if (window_lines_ >= kMaxLinesPerSecond) {
    ++window_dropped_;
    ++dropped_;
    return;
  }
  ++window_lines_;
  ++printed_;
  if (!out_) return;
  std::array<char, kMaxLineChars * 4 + 4> escaped;
  escaped_prefix(text, kMaxLineChars, escaped);
  std::fprintf(out_, "%.*s: %s\n", int(who.size()), who.data(), escaped.data());
  std::fflush(out_);
}

int64_t RemoteLog::printed() const {
  std::lock_guard lock(mutex_);
  return printed_;
}

int64_t RemoteLog::dropped() const {
  std::lock_guard lock(mutex_);
  return dropped_;
}

}  // namespace ardcell
