#pragma once
// For the tests of the rate-limited remote log (host/live/remote_log.h): a clock that moves only
// when the test moves it, so "one second" is exact, and the lines written to a log file so far.
#include <atomic>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "host/live/frame_clock.h"

namespace ardcell {

// Atomic: the OSC receive thread and the loop may both read it.
class ManualTime final : public TimeSource {
 public:
  int64_t now_ns() override { return now.load(); }
  void sleep_until_ns(int64_t deadline_ns) override {
    if (deadline_ns > now.load()) now.store(deadline_ns);
  }
  std::atomic<int64_t> now{1'000'000'000};
};

// Every line written to `log` (a tmpfile()) so far, newlines kept.
inline std::vector<std::string> logged_lines(std::FILE* log) {
  std::fflush(log);
  std::rewind(log);
  std::vector<std::string> out;
  char buf[4096];
  while (std::fgets(buf, sizeof buf, log)) out.emplace_back(buf);
  std::fseek(log, 0, SEEK_END);
  return out;
}

}  // namespace ardcell
