// `mpirun -np N ardcell live PRESET --wall WxH` through the real binary, Open MPI's mpirun
// (ARDCELL_MPIEXEC) and SDL windows under the test's X display (Xvfb in CI): each rank shows its
// block of one table1-ard simulation in a window of its own (2 pixels a cell), and the wall's
// screenshot (every screen's frame, gathered on rank 0 and placed as the views lie) is the bytes
// of one process's window at one pixel a cell after the same frames, for 2 and 4 screens (2x1,
// 1x2, 2x2); with a bezel the hidden cells are black and every other pixel is one process's. A
// signal to one screen ends every screen; bad wall settings exit 2 with one line.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

#include "tests/drivers/binary_run_fixture.h"
#include "tests/drivers/png_read_back.h"

namespace ardcell {
namespace {

class LiveWallCliTest : public BinaryRunTest {
 protected:
  void SetUp() override {
    BinaryRunTest::SetUp();
    // table1-ard on 96 x 64 cells: blocks of 48 x 32 hold its halo of 23.
    std::ifstream in(ARDCELL_SOURCE_DIR "/presets/table1-ard.toml");
    std::stringstream text;
    text << in.rdbuf();
    std::string preset = text.str();
    const std::size_t at = preset.find("size = [256, 256]");
    ASSERT_NE(at, std::string::npos);
    preset.replace(at, 17, "size = [96, 64]");
    std::ofstream(work() / "wall.toml") << preset;
  }
  bool has_display() const { return std::getenv("DISPLAY") || std::getenv("WAYLAND_DISPLAY"); }
  // An Open MPI job's environment (mpi_env) with Mesa's softpipe for SDL's GL: llvmpipe's JIT
  // registers its code's unwind tables with a malloc inside libgcc's unwinder lock, and the slow
  // unwinder that a sanitizer build needs for Open MPI (mpi_env) takes that lock again on
  // malloc: the process deadlocks.
  static std::string wall_env() { return mpi_env() + "GALLIUM_DRIVER=softpipe "; }
  // One process's window at one pixel a cell: the frame a wall's screenshot shows.
  BinaryRunResult live(const std::string& args) {
    return run("live wall.toml --fps 0 --no-vsync --scale 1 " + args);
  }
  BinaryRunResult wall(int ranks, const std::string& args) {
    return run_command(wall_env() + "exec '" ARDCELL_MPIEXEC "' --oversubscribe -np " +
                       std::to_string(ranks) +
                       " '" ARDCELL_BINARY "' live wall.toml --fps 0 --no-vsync --scale 2 " + args);
  }
};

TEST_F(LiveWallCliTest, TheWallShowsOneProcesssFrame) {
  if (!has_display()) GTEST_SKIP() << "no X or Wayland display";
  const BinaryRunResult one = live("--frames 30 --screenshot one.png");
  ASSERT_EQ(one.code, 0) << one.err;
  const std::string single = slurp(work() / "one.png");
  ASSERT_FALSE(single.empty());
  struct Layout {
    int ranks;
    const char* parts;
  };
  for (const Layout l : {Layout{2, "2x1"}, Layout{2, "1x2"}, Layout{4, "2x2"}}) {
    const std::string shot = std::string("wall-") + l.parts + ".png";
    const BinaryRunResult r =
        wall(l.ranks, std::string("--wall ") + l.parts + " --frames 30 --screenshot " + shot);
    ASSERT_EQ(r.code, 0) << l.parts << ": " << r.err;
    // Rank 0 alone reports.
    EXPECT_EQ(count_lines(r.err.substr(0, r.err.find("frames 30,"))), 1) << r.err;
    EXPECT_EQ(slurp(work() / shot), single) << l.parts;
  }
}

TEST_F(LiveWallCliTest, BezelCellsAreHiddenAndTheRestIsOneProcesssFrame) {
  if (!has_display()) GTEST_SKIP() << "no X or Wayland display";
  ASSERT_EQ(live("--frames 20 --screenshot one.png").code, 0);
  // 7 pixels at 2 per cell: 4 cells hidden between the screens, 2 on each side of the gap.
  const BinaryRunResult r = wall(2, "--wall 2x1 --bezel 7 --frames 20 --screenshot wall.png");
  ASSERT_EQ(r.code, 0) << r.err;
  const PngInfo one = read_png(work() / "one.png"), w = read_png(work() / "wall.png");
  ASSERT_TRUE(one.ok && w.ok);
  ASSERT_EQ(w.width, 96);
  ASSERT_EQ(w.height, 64);
  ASSERT_EQ(w.width, one.width);
  ASSERT_EQ(w.height, one.height);
  const int gap_lo = 48 - 2, gap_hi = 48 + 2;  // the hidden cells' columns
  int black = 0, same = 0, others = 0;
  for (int y = 0; y < w.height; ++y)
    for (int x = 0; x < w.width; ++x) {
      const uint8_t* p = &w.rows[std::size_t(y)][std::size_t(3 * x)];
      const uint8_t* q = &one.rows[std::size_t(y)][std::size_t(3 * x)];
      if (x >= gap_lo && x < gap_hi)
        black += p[0] == 0 && p[1] == 0 && p[2] == 0;
      else
        (p[0] == q[0] && p[1] == q[1] && p[2] == q[2] ? same : others) += 1;
    }
  EXPECT_EQ(black, (gap_hi - gap_lo) * w.height);
  EXPECT_EQ(others, 0);
  EXPECT_EQ(same, (w.width - (gap_hi - gap_lo)) * w.height);
}

// SIGTERM to one screen: it passes the stop to every screen with its next frame's input, and
// every screen ends cleanly, as after Esc (the job does not hang).
TEST_F(LiveWallCliTest, ASignalToOneScreenEndsTheWall) {
  if (!has_display()) GTEST_SKIP() << "no X or Wayland display";
  const BinaryRunResult r =
      run_command("( " + wall_env() +
                  "'" ARDCELL_MPIEXEC "' --oversubscribe -np 2 '" ARDCELL_BINARY
                  "' live wall.toml --fps 30 --no-vsync --scale 2 --wall 2x1 & job=$!; "
                  // Running: rank 0 has built its engine (the screens' signal handlers are in
                  // place by then) and the first frames have joined both screens.
                  "for i in $(seq 600); do grep -q 'ardcell live: backend' ../stderr && break; "
                  "sleep 0.1; done; sleep 1; "
                  // The newest of this mpirun's own ranks (other tests run walls beside it).
                  "pkill -TERM -n -P $job; "
                  "timeout 60 tail --pid=$job -f /dev/null; echo ended=$? )");
  EXPECT_NE(r.out.find("ended=0"), std::string::npos) << r.out << r.err;
  // Rank 0 printed its report: it left its loop as after Esc.
  EXPECT_NE(r.err.find("deadline misses"), std::string::npos) << r.err;
}

// A screen that cannot start (here screen 1's GPIO file is missing: what differs between hosts)
// says so, naming itself, and every screen leaves instead of waiting for it.
TEST_F(LiveWallCliTest, AScreenThatCannotStartEndsTheWall) {
  if (!has_display()) GTEST_SKIP() << "no X or Wayland display";
  const std::string screen =
      "'" ARDCELL_BINARY "' live wall.toml --fps 0 --no-vsync --scale 1 --wall 2x1 --frames 5 ";
  const BinaryRunResult r =
      run_command(wall_env() + "exec timeout 60 '" ARDCELL_MPIEXEC "' --oversubscribe -np 1 " +
                  screen + ": -np 1 " + screen + "--gpio missing.toml");
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.code, 124) << "the wall hung: " << r.err;
  EXPECT_NE(r.err.find("ardcell live: screen 1: "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("missing.toml"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("ardcell live: another screen of the wall could not start"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(r.err.find("deadline misses"), std::string::npos) << r.err;
}

// Under mpirun every rank checks alike and rank 0 says it in one line, then mpirun says that a
// process exited with an error.
TEST_F(LiveWallCliTest, BadWallSettingsExit2WithOneLine) {
  const auto one_line = [](const BinaryRunResult& r, const std::string& what) {
    EXPECT_EQ(r.code, 2) << what << ": " << r.err;
    const std::string first = r.err.substr(0, r.err.find('\n'));
    EXPECT_EQ(first.find("ardcell live: "), 0u) << r.err;
    EXPECT_NE(first.find(what), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("ardcell live: ", 1), std::string::npos) << r.err;
  };
  one_line(live("--wall 2x1 --pipeline"), "--pipeline does not run on a --wall");
  one_line(live("--wall 2x1 --record a.y4m"), "--record does not run on a --wall");
  one_line(live("--bezel 4"), "--bezel applies to a --wall");
  one_line(run("live wall.toml --wall 2x1 --bezel 4"), "--bezel 4 needs --scale");
  one_line(live("--wall two"), "--wall 'two': expected WxH");
  one_line(wall(2, "--wall 2x2"), "--wall 2x2 needs 4 processes (mpirun -np 4); this run has 2");
  one_line(
      run_command(wall_env() + "exec '" ARDCELL_MPIEXEC "' --oversubscribe -np 2 '" ARDCELL_BINARY
                               "' live cavity --wall 2x1"),
      "--wall applies to the scenes built of tile passes");
  one_line(wall(2, "--wall 2x1 --bezel 200"), "--bezel 200: hides every cell of a 48x64 screen");
}

}  // namespace
}  // namespace ardcell
