#pragma once
// A clock that only moves when told: sleeping jumps straight to the deadline (counted). For the
// live loop's and the frame clock's tests.
#include <cstdint>

#include "host/live/frame_clock.h"

namespace ardcell {

class FakeTime final : public TimeSource {
 public:
  int64_t now_ns() override { return now; }
  void sleep_until_ns(int64_t deadline) override {
    ++sleeps;
    if (deadline > now) now = deadline;
  }
  int64_t now = 1'000'000'000;
  int sleeps = 0;
};

}  // namespace ardcell
