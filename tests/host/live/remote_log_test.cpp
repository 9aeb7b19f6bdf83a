// RemoteLog: the lines a remote sender can cause are limited to kMaxLinesPerSecond in any second,
// the rest summed up in one line once that second is over, and each line is escaped and cut
// short, so no sender's text reaches the log beyond a short printable prefix.
#include "host/live/remote_log.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <vector>

#include "tests/support/remote_log_capture.h"

namespace ardcell {
namespace {

TEST(RemoteLog, AFloodPrintsAFewLinesASecondThenOneLineCountingTheRest) {
  ManualTime time;
  std::FILE* f = std::tmpfile();
  ASSERT_NE(f, nullptr);
  {
    RemoteLog log(f, &time);
    for (int i = 0; i < 1000; ++i) log.line("live", "screenshot shot-" + std::to_string(i));
    EXPECT_EQ(logged_lines(f).size(), size_t(RemoteLog::kMaxLinesPerSecond));
    EXPECT_EQ(log.dropped(), 1000 - RemoteLog::kMaxLinesPerSecond);
    log.tick();  // the second is not over: no summary yet
    EXPECT_EQ(logged_lines(f).size(), size_t(RemoteLog::kMaxLinesPerSecond));
    time.now += 1'000'000'000;
    log.tick();
    std::vector<std::string> lines = logged_lines(f);
    ASSERT_EQ(lines.size(), size_t(RemoteLog::kMaxLinesPerSecond + 1));
    EXPECT_EQ(lines.front(), "live: screenshot shot-0\n");
    EXPECT_EQ(lines.back(), "osc: 995 more lines caused by remote commands not logged (at most " +
                                std::to_string(RemoteLog::kMaxLinesPerSecond) + " a second)\n");
    // A new second prints again; what it drops is summed up when the log ends.
    for (int i = 0; i < 7; ++i) log.line("osc", "rejected");
  }
  const std::vector<std::string> lines = logged_lines(f);
  ASSERT_EQ(lines.size(), size_t(2 * RemoteLog::kMaxLinesPerSecond + 2));
  EXPECT_EQ(lines.back().rfind("osc: 2 more lines caused by remote commands not logged", 0), 0u)
      << lines.back();
  std::fclose(f);
}

TEST(RemoteLog, FinishSumsUpMidSecond) {
  ManualTime time;
  std::FILE* f = std::tmpfile();
  ASSERT_NE(f, nullptr);
  RemoteLog log(f, &time);
  for (int i = 0; i < 8; ++i) log.line("osc", "rejected");
  log.finish();  // the loop ends before the second is over
  std::vector<std::string> lines = logged_lines(f);
  ASSERT_EQ(lines.size(), size_t(RemoteLog::kMaxLinesPerSecond + 1));
  EXPECT_EQ(lines.back().rfind("osc: 3 more lines caused by remote commands not logged", 0), 0u)
      << lines.back();
  log.finish();  // nothing more to say
  EXPECT_EQ(logged_lines(f).size(), lines.size());
  std::fclose(f);
}

TEST(RemoteLog, LinesAreEscapedAndCutShort) {
  ManualTime time;
  std::FILE* f = std::tmpfile();
  ASSERT_NE(f, nullptr);
  RemoteLog log(f, &time);
  log.line("live", "keeping cavity: \x1b[2J\nsecond line\\" + std::string(1000, 'A'));
  const std::vector<std::string> lines = logged_lines(f);
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_EQ(lines[0].find('\x1b'), std::string::npos) << lines[0];
  EXPECT_NE(lines[0].find("keeping cavity: \\x1b[2J\\x0asecond line\\x5cAAA"), std::string::npos)
      << lines[0];
  EXPECT_LT(lines[0].size(), RemoteLog::kMaxLineChars + 20);
  EXPECT_EQ(lines[0].substr(lines[0].size() - 5), "A...\n");
  std::fclose(f);
}

}  // namespace
}  // namespace ardcell
