#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

namespace {

struct Result {
  int code;
  std::string output;
};

Result run(const std::string& args) {
  const std::string cmd = std::string(ARDCELL_BINARY) + " " + args + " 2>&1";
  Result r{0, ""};
  std::FILE* p = popen(cmd.c_str(), "r");
  char buf[4096];
  while (p && std::fgets(buf, sizeof buf, p)) r.output += buf;
  const int status = p ? pclose(p) : -1;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

TEST(LiveCli, RendersFramesToAWindowAndWritesTheScreenshot) {
  if (!std::getenv("DISPLAY") && !std::getenv("WAYLAND_DISPLAY"))
    GTEST_SKIP() << "no X or Wayland display";
  const auto dir =
      std::filesystem::temp_directory_path() / ("ardcell_live_cli_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const Result r = run("live cavity --frames 4 --fps 0 --scale 1 --screenshot " +
                       (dir / "shot.png").string() + " --record " + (dir / "rec.y4m").string());
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(std::filesystem::exists(dir / "shot.png")) << r.output;
  EXPECT_GT(std::filesystem::file_size(dir / "rec.y4m"), 0u);
  EXPECT_NE(r.output.find("frames 4, deadline misses "), std::string::npos) << r.output;
  std::filesystem::remove_all(dir);
}

TEST(LiveCli, BadPresetIsOneLineAndExitCodeTwo) {
  const Result r = run("live no-such-preset --frames 1");
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.output.rfind("ardcell live: preset 'no-such-preset': no such file or preset", 0), 0u)
      << r.output;
  EXPECT_EQ(r.output.find('\n'), r.output.size() - 1);
}

TEST(LiveCli, ListsPresetKeys) {
  const Result r = run("live --keys");
  EXPECT_EQ(r.code, 0);
  EXPECT_NE(r.output.find("fluid.viscosity"), std::string::npos);
  EXPECT_NE(r.output.find("quality.min_sweeps"), std::string::npos);
}

}  // namespace
