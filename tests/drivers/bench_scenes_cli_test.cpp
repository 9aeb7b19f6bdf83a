// `ardcell bench scenes` through the real binary: a tiny run prints the Markdown table and writes
// scenes.md and scenes.csv with one row per preset and size, each with both back ends' FPS and
// their ratio (with --repetitions, the medians and the ratio's range), and scenes.png when built
// with PLplot; bad sizes, presets, times and repetitions exit 2 with one line and write nothing.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "drivers/chart.h"
#include "tests/drivers/binary_run_fixture.h"

namespace ardcell {
namespace {

namespace fs = std::filesystem;
using BenchScenesCliTest = BinaryRunTest;

bool scenes_bench_built() {
  return fs::exists(fs::path(ARDCELL_BINARY).parent_path() / "scenes_bench");
}

TEST_F(BenchScenesCliTest, TinyRunWritesOneRowPerPresetAndSize) {
  if (!scenes_bench_built()) GTEST_SKIP() << "scenes_bench not built (ARDCELL_BUILD_BENCH=OFF)";
  const bool device = run("devices").out.find("device 0:") != std::string::npos;
  const BinaryRunResult r =
      run("bench scenes --sizes 24,32 --presets turing-spots,cavity --min-time 0.01 --out res");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("| preset | N | serial FPS | threads FPS | threads / serial | workers |"),
            std::string::npos)
      << r.out;
  const std::string csv = slurp(work() / "res" / "scenes.csv");
  EXPECT_EQ(slurp(work() / "res" / "scenes.md"), r.out);
  std::istringstream in(csv);
  std::string line;
  std::getline(in, line);
  // An OpenCL device (PoCL in CI) adds its column.
  EXPECT_EQ(line, std::string("preset,n,serial_fps,threads_fps,speedup,workers") +
                      (device ? ",opencl_fps,opencl_speedup" : ""));
  std::vector<std::string> rows;
  while (std::getline(in, line)) rows.push_back(line.substr(0, line.find(',', line.find(',') + 1)));
  EXPECT_EQ(rows, (std::vector<std::string>{"turing-spots,24", "turing-spots,32", "cavity,24",
                                            "cavity,32"}))
      << csv;
  EXPECT_FALSE(fs::exists(work() / "res" / ".scenes_bench.json")) << "the raw report stays";
  // --cl-device none leaves the device out.
  const BinaryRunResult cpu =
      run("bench scenes --sizes 24 --presets cavity --min-time 0.01 --cl-device none --out res2");
  ASSERT_EQ(cpu.code, 0) << cpu.err;
  std::istringstream in2(slurp(work() / "res2" / "scenes.csv"));
  std::getline(in2, line);
  EXPECT_EQ(line, "preset,n,serial_fps,threads_fps,speedup,workers");
  // --repetitions: the medians, and the range of threads / serial, which holds the median.
  const BinaryRunResult rep = run(
      "bench scenes --sizes 24 --presets cavity --min-time 0.01 --cl-device none --repetitions 3 "
      "--out res3");
  ASSERT_EQ(rep.code, 0) << rep.err;
  EXPECT_NE(rep.out.find("Medians of 3 repetitions"), std::string::npos) << rep.out;
  EXPECT_NE(rep.out.find("| threads / serial | range | workers |"), std::string::npos) << rep.out;
  std::istringstream in3(slurp(work() / "res3" / "scenes.csv"));
  std::getline(in3, line);
  EXPECT_EQ(line, "preset,n,serial_fps,threads_fps,speedup,speedup_min,speedup_max,workers");
  std::getline(in3, line);
  double serial = 0, threads = 0, median = 0, lo = 0, hi = 0, workers = 0;
  ASSERT_EQ(std::sscanf(line.c_str(), "cavity,24,%lf,%lf,%lf,%lf,%lf,%lf", &serial, &threads,
                        &median, &lo, &hi, &workers),
            6)
      << line;
  EXPECT_GT(serial, 0);
  EXPECT_GT(threads, 0);
  EXPECT_LE(lo, median);
  EXPECT_LE(median, hi);
  EXPECT_FALSE(std::getline(in3, line)) << "one row: the median's";
  // The chart (PLplot): present exactly when this build draws charts.
  EXPECT_EQ(fs::exists(work() / "res" / "scenes.png"), charts_available()) << r.err;
}

TEST_F(BenchScenesCliTest, BadInputExitsTwoWithOneLine) {
  for (const char* args :
       {"--sizes 8", "--sizes 64x", "--presets no-such-preset", "--min-time 0", "--repetitions 0",
        "--repetitions 101", "--bench-binary /nonexistent/scenes_bench"}) {
    const BinaryRunResult r = run(std::string("bench scenes --out res ") + args);
    EXPECT_EQ(r.code, 2) << args << ": " << r.err;
    EXPECT_EQ(count_lines(r.err), 1) << args << ": " << r.err;
    EXPECT_FALSE(fs::exists(work() / "res" / "scenes.csv")) << args;
  }
}

}  // namespace
}  // namespace ardcell
