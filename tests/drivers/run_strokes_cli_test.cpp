// `ardcell run --strokes FILE` through the real binary (ARDCELL_BINARY): the recorded Fig. 3
// spiral is painted into the scene before each step, deterministically; a bad stroke file or
// stroke options on the fixed Table 1 workload exit 2 with one line and leave nothing behind.
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace ardcell {
namespace {

namespace fs = std::filesystem;

class RunStrokesTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("ardcell_run_strokes_test_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  static std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
  }
  // Runs the binary in dir_; returns the exit code, stderr in err_.
  int run(const std::string& args) {
    const std::string cmd = "cd '" + dir_.string() + "' && exec '" ARDCELL_BINARY "' " + args +
                            " >/dev/null 2>'" + (dir_ / "stderr").string() + "' </dev/null";
    const int status = std::system(cmd.c_str());
    err_ = slurp(dir_ / "stderr");
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  }

  fs::path dir_;
  std::string err_;
};

const std::string kSpiral = std::string(ARDCELL_SOURCE_DIR) + "/presets/strokes/fig3_spiral.jsonl";
const std::string kSmall = "run fig3-deposit --size 48 --steps 30 --every 0 --quiet ";

TEST_F(RunStrokesTest, StrokesPaintIntoTheSceneDeterministically) {
  ASSERT_EQ(run(kSmall + "--save-state plain"), 0) << err_;
  ASSERT_EQ(run(kSmall + "--strokes '" + kSpiral + "' --paint-radius 3 --save-state painted1"), 0)
      << err_;
  ASSERT_EQ(run(kSmall + "--strokes '" + kSpiral + "' --paint-radius 3 --save-state painted2"), 0)
      << err_;
  const std::string plain = slurp(dir_ / "plain" / "B.npy");
  const std::string painted = slurp(dir_ / "painted1" / "B.npy");
  ASSERT_FALSE(plain.empty());
  ASSERT_EQ(plain.size(), painted.size());
  EXPECT_NE(plain, painted) << "the strokes left no trace in B";
  EXPECT_EQ(painted, slurp(dir_ / "painted2" / "B.npy")) << "stroke playback is not repeatable";
}

TEST_F(RunStrokesTest, BadStrokeFileGivesOneLineAndExitTwo) {
  EXPECT_EQ(run(kSmall + "--strokes missing.jsonl --save-state s"), 2);
  EXPECT_EQ(std::count(err_.begin(), err_.end(), '\n'), 1) << err_;
  EXPECT_NE(err_.find("missing.jsonl"), std::string::npos) << err_;
  EXPECT_FALSE(fs::exists(dir_ / "s"));

  std::ofstream(dir_ / "broken.jsonl") << "{\"t\": 0, \"x\": \n";
  EXPECT_EQ(run(kSmall + "--strokes broken.jsonl"), 2);
  EXPECT_EQ(std::count(err_.begin(), err_.end(), '\n'), 1) << err_;
}

// The Table 1 scene runs as a frame plan on state's own fields: strokes paint into it as into
// any scene.
TEST_F(RunStrokesTest, StrokesPaintIntoTheTable1Scene) {
  const std::string base = "run table1-ard --size 48 --steps 30 --every 0 --quiet ";
  ASSERT_EQ(run(base + "--save-state plain"), 0) << err_;
  ASSERT_EQ(run(base + "--strokes '" + kSpiral + "' --paint-radius 3 --save-state painted"), 0)
      << err_;
  const std::string plain = slurp(dir_ / "plain" / "B.npy");
  ASSERT_FALSE(plain.empty());
  EXPECT_NE(plain, slurp(dir_ / "painted" / "B.npy")) << "the strokes left no trace in B";
}

}  // namespace
}  // namespace ardcell
