// The stroke recording format round-trips exactly, rejects bad lines with the file and line,
// is written atomically; the SPSC ring and the replay source keep order and timing.
#include "host/paint/stroke_io.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <thread>

namespace ardcell {
namespace {

std::filesystem::path temp_dir() {
  auto d = std::filesystem::temp_directory_path() / "ardcell_stroke_io_test";
  std::filesystem::create_directories(d);
  return d;
}

TEST(StrokeIo, RoundTripsExactly) {
  std::vector<StrokeSample> samples;
  for (int i = 0; i < 50; ++i) {
    StrokeSample s;
    s.time = 0.01 * i;
    s.x = 0.1f + 0.013f * i;
    s.y = 0.9f - 0.007f * i;
    s.pressure = float(i % 10) / 9.f;
    s.tilt_x = float(i) - 25.f;
    s.tilt_y = -3.5f;
    s.buttons = uint32_t(i % 4);
    s.in_range = i % 7 != 0;
    s.eraser = i % 11 == 0;
    samples.push_back(s);
  }
  const std::string path = (temp_dir() / "round.jsonl").string();
  std::string error;
  ASSERT_TRUE(write_stroke_file(path, samples, error)) << error;
  EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
  std::vector<StrokeSample> back;
  ASSERT_TRUE(read_stroke_file(path, back, error)) << error;
  EXPECT_EQ(back, samples);
}

TEST(StrokeIo, DefaultsAndComments) {
  StrokeSample s;
  std::string error;
  ASSERT_TRUE(stroke_sample_from_json(R"({"t": 1.5, "x": 0.25, "y": 0.75})", s, error)) << error;
  EXPECT_EQ(s.time, 1.5);
  EXPECT_EQ(s.x, 0.25f);
  EXPECT_TRUE(s.in_range);
  EXPECT_EQ(s.buttons, 0u);
  const std::string path = (temp_dir() / "comments.jsonl").string();
  std::ofstream(path) << "# a comment\n\n{\"t\":0,\"x\":0,\"y\":0,\"buttons\":1}\n";
  std::vector<StrokeSample> v;
  ASSERT_TRUE(read_stroke_file(path, v, error)) << error;
  ASSERT_EQ(v.size(), 1u);
  EXPECT_TRUE(v[0].touching());
}

TEST(StrokeIo, BadLinesNameFileAndLine) {
  struct Case {
    const char* text;
    const char* expect;
  };
  const Case cases[] = {
      {"{\"t\":0,\"x\":0}\n", ":1: missing key \"y\""},
      {"{\"t\":0,\"x\":0,\"y\":0}\nnot json\n", ":2: expected one JSON object per line"},
      {"{\"t\":0,\"x\":\"a\",\"y\":0}\n", ":1: key \"x\" must be a number"},
      {"{\"t\":0,\"x\":0,\"y\":0,\"pressure\":2}\n", ":1: key \"pressure\" must be in [0, 1]"},
      {"{\"t\":0,\"x\":0,\"y\":0,\"buttons\":-1}\n", ":1: key \"buttons\""},
      {"{\"t\":0,\"x\":0,\"y\":0,\"eraser\":1}\n", ":1: key \"eraser\" must be true or false"},
      {"{\"t\":1,\"x\":0,\"y\":0}\n{\"t\":0.5,\"x\":0,\"y\":0}\n", ":2: time 0.5"},
  };
  const std::string path = (temp_dir() / "bad.jsonl").string();
  for (const Case& c : cases) {
    std::ofstream(path) << c.text;
    std::vector<StrokeSample> v;
    std::string error;
    EXPECT_FALSE(read_stroke_file(path, v, error)) << c.text;
    EXPECT_NE(error.find(path + c.expect), std::string::npos) << error;
  }
  std::vector<StrokeSample> v;
  std::string error;
  EXPECT_FALSE(read_stroke_file("/nonexistent/x.jsonl", v, error));
  EXPECT_NE(error.find("/nonexistent/x.jsonl: not found"), std::string::npos) << error;
  EXPECT_FALSE(write_stroke_file("/nonexistent/dir/x.jsonl", {}, error));
}

TEST(StrokeRing, KeepsOrderAcrossThreadsAndCountsDrops) {
  StrokeRing ring(64);
  EXPECT_EQ(ring.capacity(), 64u);
  constexpr int kCount = 20000;
  std::thread producer([&] {
    for (int i = 0; i < kCount; ++i) {
      StrokeSample s;
      s.time = i;
      while (!ring.push(s)) std::this_thread::yield();
    }
  });
  int next = 0;
  StrokeSample batch[16];
  while (next < kCount) {
    const std::size_t n = ring.pop_many(batch);
    for (std::size_t k = 0; k < n; ++k) ASSERT_EQ(batch[k].time, next++);
    if (n == 0) std::this_thread::yield();
  }
  producer.join();
  StrokeRing small(4);
  for (int i = 0; i < 6; ++i) small.push(StrokeSample{});
  EXPECT_EQ(small.size(), 4u);
  EXPECT_EQ(small.dropped(), 2u);
}

TEST(ReplayStrokeSource, ReleasesSamplesWhenDueAndLoops) {
  std::vector<StrokeSample> rec(3);
  rec[0].time = 10.0;
  rec[1].time = 10.5;
  rec[2].time = 11.0;
  ReplayStrokeSource once(rec, "replay");
  StrokeSample out[8];
  EXPECT_EQ(once.poll(0.0, out), 1u);  // times count from the first sample
  EXPECT_EQ(out[0].time, 0.0);
  EXPECT_EQ(once.poll(0.4, out), 0u);
  EXPECT_EQ(once.poll(1.0, out), 2u);
  EXPECT_TRUE(once.finished());
  ReplayStrokeSource looped(rec, "attract", true, 2.0);
  EXPECT_EQ(looped.poll(1.0, out), 3u);
  EXPECT_EQ(looped.poll(2.9, out), 0u);  // the gap
  EXPECT_EQ(looped.poll(3.0, out), 1u);  // second pass starts at 1.0 + 2.0
  EXPECT_EQ(out[0].time, 3.0);
  EXPECT_FALSE(looped.finished());
}

}  // namespace
}  // namespace ardcell
