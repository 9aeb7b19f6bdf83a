#pragma once
// RemoteLog: every log line a remote sender can cause (`ardcell live --osc`): the messages the
// OSC server rejects, and what the live loop says about the commands it accepted (preset
// switches and the errors of a switched preset, screenshots, recordings, out-of-range values).
// A sender can send thousands of messages a second and each may print a line, so at most
// kMaxLinesPerSecond are printed in any second; the rest are counted and one line sums them up
// once that second is over. Every line is escaped and cut to kMaxLineChars, and a sender's own
// text within it to kMaxEchoedChars (escaped_prefix), so nothing a sender writes reaches the
// terminal or the journal beyond a short, printable prefix. One RemoteLog is shared by the OSC
// receive thread and the loop (thread-safe); printing a line allocates nothing.
#include <cstdint>
#include <cstdio>
#include <mutex>
#include <string_view>

#include "host/live/frame_clock.h"

namespace ardcell {

class RemoteLog {
 public:
  static constexpr int kMaxLinesPerSecond = 5;
  static constexpr std::size_t kMaxEchoedChars = 40;  // of a sender's text within a line
  static constexpr std::size_t kMaxLineChars = 200;

  // `out`: where lines go (nullptr: nowhere, still counted); `time`: the clock of the
  // per-second limit (default: the monotonic clock).
  explicit RemoteLog(std::FILE* out = stderr, TimeSource* time = nullptr);
  ~RemoteLog();  // sums up what the last second dropped
  RemoteLog(const RemoteLog&) = delete;
  RemoteLog& operator=(const RemoteLog&) = delete;

  // Prints "<who>: <text>" unless this second's lines are spent; then counts it.
  void line(std::string_view who, std::string_view text);
  // Prints the count of a second that is over ("osc: 37 more lines ... not logged"). line()
  // does it too; the live loop calls this each frame so that a flood's count appears as soon
  // as it ends, not at the next line.
  void tick();
  // Prints the count not yet summed up, even mid-second: the loop is ending (the destructor
  // does it too; `ardcell live` may end with _Exit, which runs no destructor).
  void finish();

  int64_t printed() const;  // lines printed, summaries included
  int64_t dropped() const;  // lines not printed, in all

 private:
  void roll_window(int64_t now_ns);  // with mutex_ held
  void print_summary();              // with mutex_ held
  std::FILE* out_;
  TimeSource& time_;
  mutable std::mutex mutex_;
  int64_t window_start_ns_ = 0;
  int window_lines_ = 0;
  int64_t window_dropped_ = 0;
  int64_t printed_ = 0, dropped_ = 0;
};

}  // namespace ardcell
