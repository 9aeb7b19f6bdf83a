#include "host/live/frame_clock.h"

#include <gtest/gtest.h>

#include "tests/support/fake_time.h"

#include <csignal>

namespace ardcell {
namespace {

constexpr int64_t kMs = 1'000'000;

TEST(FrameClock, DeadlinesAreAbsoluteAndDoNotDrift) {
  FakeTime t;
  FrameClock clock(100.0, t);  // 10 ms period
  const int64_t start = t.now;
  for (int i = 0; i < 50; ++i) {
    clock.begin_frame();
    t.now += 3 * kMs;  // work
    clock.mark(FrameStage::kSimulate);
    EXPECT_FALSE(clock.end_frame_and_wait());
  }
  // 50 frames of 10 ms each, whatever the work time: the schedule is absolute.
  EXPECT_EQ(t.now - start, 50 * 10 * kMs);
  EXPECT_EQ(clock.misses(), 0);
  EXPECT_EQ(clock.frames(), 50);
  EXPECT_EQ(clock.stage(FrameStage::kSimulate).last_ns, 3 * kMs);
  EXPECT_EQ(clock.stage(FrameStage::kSimulate).count, 50);
}

TEST(FrameClock, InjectedSlowFrameCountsAsOneMiss) {
  FakeTime t;
  FrameClock clock(100.0, t);
  for (int i = 0; i < 20; ++i) {
    clock.begin_frame();
    t.now += (i == 7 ? 25 : 2) * kMs;  // frame 7 takes 2.5 periods
    const bool missed = clock.end_frame_and_wait();
    EXPECT_EQ(missed, i == 7) << "frame " << i;
  }
  EXPECT_EQ(clock.misses(), 1);
  // The frame after the miss gets a whole period again (no catch-up burst).
  clock.begin_frame();
  EXPECT_EQ(clock.slack_ns(), 10 * kMs);
}

TEST(FrameClock, FrameJustInsideTheDeadlineIsNotAMiss) {
  FakeTime t;
  FrameClock clock(50.0, t);  // 20 ms
  clock.begin_frame();
  t.now += 20 * kMs;
  EXPECT_FALSE(clock.end_frame_and_wait());
  clock.begin_frame();
  t.now += 20 * kMs + 1;
  EXPECT_TRUE(clock.end_frame_and_wait());
}

TEST(FrameClock, PercentilesOfWorkTime) {
  FakeTime t;
  FrameClock clock(10.0, t);  // 100 ms: nothing misses
  // 98 frames of 1 ms, 2 of 40 ms: p50 is ~1 ms, p99 ~40 ms.
  for (int i = 0; i < 100; ++i) {
    clock.begin_frame();
    t.now += (i % 50 == 49 ? 40 : 1) * kMs;
    clock.end_frame_and_wait();
  }
  const auto& h = clock.work_histogram();
  EXPECT_EQ(h.count(), 100);
  EXPECT_NEAR(double(h.percentile_ns(0.5)), 1.0 * kMs, DurationHistogram::kBucketNs);
  EXPECT_NEAR(double(h.percentile_ns(0.99)), 40.0 * kMs, DurationHistogram::kBucketNs);
  EXPECT_EQ(h.max_ns(), 40 * kMs);
  EXPECT_EQ(clock.recent_percentile_ns(0.5), 1 * kMs);
  EXPECT_EQ(clock.recent_percentile_ns(1.0), 40 * kMs);
  // Every interval is exactly the period.
  EXPECT_NEAR(clock.recent_fps(), 10.0, 1e-9);
  EXPECT_EQ(clock.misses(), 0);
}

TEST(FrameClock, UnpacedNeverSleepsNorMisses) {
  FakeTime t;
  FrameClock clock(0.0, t);
  for (int i = 0; i < 10; ++i) {
    clock.begin_frame();
    t.now += 100 * kMs;
    EXPECT_FALSE(clock.end_frame_and_wait());
  }
  EXPECT_EQ(t.sleeps, 0);
  EXPECT_EQ(clock.misses(), 0);
}

TEST(FrameClock, RealClockSleepsUntilAnAbsoluteDeadline) {
  MonotonicTime& t = MonotonicTime::instance();
  const int64_t deadline = t.now_ns() + 2 * kMs;
  t.sleep_until_ns(deadline);
  EXPECT_GE(t.now_ns(), deadline);
}

TEST(FrameClock, Sigusr1SetsTheReportFlag) {
  install_report_signal();
  EXPECT_FALSE(take_report_request());
  std::raise(SIGUSR1);
  EXPECT_TRUE(take_report_request());
  EXPECT_FALSE(take_report_request());
}

TEST(FrameClock, ReportNamesTheCounters) {
  FakeTime t;
  FrameClock clock(100.0, t);
  clock.begin_frame();
  t.now += 30 * kMs;
  clock.mark(FrameStage::kRender);
  clock.end_frame_and_wait();
  char buf[1024] = {};
  std::FILE* f = fmemopen(buf, sizeof buf - 1, "w");
  clock.print_report(f);
  std::fclose(f);
  const std::string text(buf);
  EXPECT_NE(text.find("frames 1, deadline misses 1"), std::string::npos) << text;
  EXPECT_NE(text.find("render 30.000/30.000"), std::string::npos) << text;
}

}  // namespace
}  // namespace ardcell
