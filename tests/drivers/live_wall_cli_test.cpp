// `mpirun -np N ardcell live PRESET --wall WxH` through the real binary, Open MPI's mpirun
// (ARDCELL_MPIEXEC) and SDL windows under the test's X display (Xvfb in CI): each rank shows its
// block of one table1-ard simulation in a window of its own (2 pixels a cell), and the wall's
// screenshot (every screen's frame, gathered on rank 0 and placed as the views lie) is the bytes
// of one process's window at one pixel a cell after the same frames, for 2 and 4 screens (2x1,
// 1x2, 2x2); with a bezel the hidden cells are black and every other pixel is one process's. A
// mirrored wall (cavity-gray-scott: every screen steps the whole grid) shows one process's frame
// too (also space-cookie-5, whose blocks would gather the grid), and so does a split wall of a
// scene of stages (seed 001: each screen steps its block), and screens on different back ends
// (PoCL and the CPU) are brought back in step. A signal to one screen ends every screen; bad wall
// settings exit 2 with one line.
#include <gtest/gtest.h>

#include <fstream>
#include <functional>
#include <initializer_list>
#include <sstream>
#include <string>

#include "runtime/block_layout.h"
#include "tests/drivers/binary_run_fixture.h"
#include "tests/drivers/png_read_back.h"

namespace ardcell {
namespace {

class LiveWallCliTest : public BinaryRunTest {
 protected:
  void SetUp() override {
    BinaryRunTest::SetUp();
    // table1-ard on 96 x 64 cells: blocks of 48 x 32 hold its halo of 23.
    write_resized("table1-ard", "size = [256, 256]", "size = [96, 64]", "wall.toml");
    // cavity-gray-scott (fluid and anisotropic RD as stages on whole fields) on 48 x 32 cells.
    write_resized("cavity-gray-scott", "size = [256, 256]", "size = [48, 32]", "mirrored.toml");
    // seed001 (explicit 9-point Gray-Scott as stages, halos of one cell) on 96 x 64 cells.
    write_resized("seed001", "size = [400, 400]", "size = [96, 64]", "seed001.toml");
    // space-cookie-5 (implicit anisotropic RD, whose blocks gather the grid) on 96 x 64 cells.
    write_resized("space-cookie-5", "size = [128, 128]", "size = [96, 64]", "cookie.toml");
  }
  // The built-in preset `name` with its grid line `size` replaced by `resized`, as work()/out.
  void write_resized(const std::string& name, const std::string& size, const std::string& resized,
                     const std::string& out) {
    std::ifstream in(std::string(ARDCELL_SOURCE_DIR "/presets/") + name + ".toml");
    std::stringstream text;
    text << in.rdbuf();
    std::string preset = text.str();
    const std::size_t at = preset.find(size);
    ASSERT_NE(at, std::string::npos) << name;
    preset.replace(at, size.size(), resized);
    std::ofstream(work() / out) << preset;
  }
  bool has_display() const { return std::getenv("DISPLAY") || std::getenv("WAYLAND_DISPLAY"); }
  // An Open MPI job's environment (mpi_env) with Mesa's softpipe for SDL's GL: llvmpipe's JIT
  // registers its code's unwind tables with a malloc inside libgcc's unwinder lock, and the slow
  // unwinder of a leak-checked sanitizer job (mpi_env) takes that lock again on malloc: the
  // process deadlocks.
  static std::string wall_env(bool checks_leaks = false) {
    return mpi_env(checks_leaks) + "GALLIUM_DRIVER=softpipe ";
  }
  // `preset` for `frames` frames in one process's window at one pixel a cell, then on a wall of
  // each of `layouts` (2 pixels a cell): the wall's screenshot is the same bytes; `check` looks
  // at each wall's run.
  void walls_show_one_frame(const std::string& preset, int frames,
                            std::initializer_list<const char*> layouts,
                            const std::function<void(const BinaryRunResult&)>& check,
                            const std::string& flags = "") {
    const std::string common = preset + flags + " --fps 0 --no-vsync --backend threads --frames " +
                               std::to_string(frames) + " --screenshot ";
    const BinaryRunResult one = live_process(common + "one.png --scale 1");
    ASSERT_EQ(one.code, 0) << one.err;
    const std::string single = slurp(work() / "one.png");
    ASSERT_FALSE(single.empty());
    for (const char* parts : layouts) {
      Int2 n{};
      ASSERT_TRUE(parse_block_parts(parts, n));
      const std::string shot = "wall-" + preset + "-" + parts + ".png";
      const BinaryRunResult r =
          run_command(wall_env() + "exec '" ARDCELL_MPIEXEC "' --oversubscribe -np " +
                      std::to_string(n.x * n.y) + " '" ARDCELL_BINARY "' live " + common + shot +
                      " --scale 2 --wall " + parts);
      ASSERT_EQ(r.code, 0) << parts << ": " << r.err;
      check(r);
      EXPECT_EQ(slurp(work() / shot), single) << parts;
    }
  }
  // `ardcell live <args>` in one process, drawn by the screens' renderer (wall_env): softpipe's
  // one thread also spares LeakSanitizer's exit check llvmpipe's pool (its tracer crashed once
  // stopping those threads, signal 11).
  BinaryRunResult live_process(const std::string& args) {
    return run_command("GALLIUM_DRIVER=softpipe exec '" ARDCELL_BINARY "' live " + args);
  }
  // One process's window at one pixel a cell: the frame a wall's screenshot shows.
  BinaryRunResult live(const std::string& args) {
    return live_process("wall.toml --fps 0 --no-vsync --scale 1 " + args);
  }
  BinaryRunResult wall(int ranks, const std::string& args, bool checks_leaks = false) {
    return run_command(wall_env(checks_leaks) + "exec '" ARDCELL_MPIEXEC "' --oversubscribe -np " +
                       std::to_string(ranks) +
                       " '" ARDCELL_BINARY "' live wall.toml --fps 0 --no-vsync --scale 2 " + args);
  }
};

TEST_F(LiveWallCliTest, TheWallShowsOneProcesssFrame) {
  if (!has_display()) GTEST_SKIP() << "no X or Wayland display";
  walls_show_one_frame("wall.toml", 30, {"2x1", "1x2", "2x2"}, [](const BinaryRunResult& r) {
    // Rank 0 alone reports: its back end and how the wall runs, in one line.
    EXPECT_EQ(count_lines(r.err.substr(0, r.err.find("frames 30,"))), 1) << r.err;
    EXPECT_NE(r.err.find("each screen steps its block of the grid (split)"), std::string::npos)
        << r.err;
  });
}

// A scene of stages whose ops exchange a block's halos (seed 001) splits its grid too.
TEST_F(LiveWallCliTest, AScreenOfAStageSceneStepsItsBlock) {
  if (!has_display()) GTEST_SKIP() << "no X or Wayland display";
  walls_show_one_frame("seed001.toml", 20, {"2x1", "2x2"}, [](const BinaryRunResult& r) {
    EXPECT_NE(r.err.find("each screen steps its block of the grid (split)"), std::string::npos)
        << r.err;
  });
  // On the real-time settings, space-cookie-5's implicit diffusion sweeps each screen's block
  // (Jacobi, exchanging between sweeps), so its wall splits too.
  walls_show_one_frame(
      "cookie.toml", 10, {"2x1"},
      [](const BinaryRunResult& r) {
        EXPECT_NE(r.err.find("each screen steps its block of the grid (split)"), std::string::npos)
            << r.err;
      },
      " --realtime-solvers");
}

// A scene of stages runs whole on every screen: the screens compute the same bits (no drift is
// found at the checks of frames 1 and 61), and the wall's screenshot is one process's frame.
TEST_F(LiveWallCliTest, AMirroredWallShowsOneProcesssFrame) {
  if (!has_display()) GTEST_SKIP() << "no X or Wayland display";
  walls_show_one_frame("mirrored.toml", 62, {"2x1", "2x2"}, [](const BinaryRunResult& r) {
    EXPECT_NE(r.err.find("every screen steps the whole grid (mirrored)"), std::string::npos)
        << r.err;
    EXPECT_EQ(r.err.find("drifted"), std::string::npos) << r.err;
  });
  // A scene whose blocks would gather the grid for their solves (space-cookie-5 with its ICCG
  // solves, which `run --ranks` cuts) is mirrored: every screen would compute the whole solve
  // anyway.
  walls_show_one_frame("cookie.toml", 10, {"2x1"}, [](const BinaryRunResult& r) {
    EXPECT_NE(r.err.find("every screen steps the whole grid (mirrored)"), std::string::npos)
        << r.err;
  });
}

#if defined(ARDCELL_WITH_LIBLO)
// A wall with a playlist is mirrored, even when its first preset is a scene of tile passes
// (wall.toml: table1-ard), and switches presets live: an OSC /ardcell/preset/next to screen 0
// (sent from bash's /dev/udp) reaches every screen, they switch in the same frame (the checks
// after it find no drift), and the last frame is the new preset's grid.
TEST_F(LiveWallCliTest, AMirroredWallSwitchesPresetsInStep) {
  if (!has_display()) GTEST_SKIP() << "no X or Wayland display";
  std::string next = slurp(work() / "mirrored.toml");
  next.replace(next.find("size = [48, 32]"), 15, "size = [40, 24]");
  std::ofstream(work() / "next.toml") << next;
  // "/ardcell/preset/next" and the type tags "," as OSC pads them (to 4 bytes, NUL-ended).
  std::ofstream(work() / "switch.sh")
      << "ardcell() { " << wall_env()
      << "'" ARDCELL_MPIEXEC "' --oversubscribe -np 2 '" ARDCELL_BINARY
         "' live wall.toml --playlist wall.toml next.toml --osc 0 --fps 60 --no-vsync "
         "--scale 1 --wall 2x1 --frames 200 --screenshot wall.png; }\n"
         "ardcell 2> err.txt & job=$!\n"
         "for i in $(seq 600); do grep -q 'OSC on udp://127.0.0.1:' err.txt && break; "
         "sleep 0.1; done\n"
         "port=$(sed -n 's|.*OSC on udp://127.0.0.1:\\([0-9]*\\).*|\\1|p' err.txt)\n"
         "printf '/ardcell/preset/next\\0\\0\\0\\0,\\0\\0\\0' > /dev/udp/127.0.0.1/$port\n"
         "wait $job; code=$?; cat err.txt >&2; exit $code\n";
  const BinaryRunResult r = run_command("exec timeout 300 bash switch.sh");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("every screen steps the whole grid (mirrored)"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("live: preset cavity-gray-scott"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("drifted"), std::string::npos) << r.err;
  const PngInfo w = read_png(work() / "wall.png");
  ASSERT_TRUE(w.ok);
  EXPECT_EQ(w.width, 40);
  EXPECT_EQ(w.height, 24);
}
#endif

#if defined(ARDCELL_WITH_OPENCL)
// Screen 0 steps on OpenCL (PoCL), screen 1 on the CPU's threads: their rounding differs, the
// checks find it (after frame 1, then every 60 frames) and both go on from screen 0's state: the
// last frame is then one OpenCL process's. Only screen 0 is given --screenshot: screen 1 still
// takes part in gathering it.
TEST_F(LiveWallCliTest, ScreensOnDifferentBackEndsAreBroughtBackInStep) {
  if (!has_display()) GTEST_SKIP() << "no X or Wayland display";
  const BinaryRunResult devices = run("devices");
  if (devices.out.find("device 0:") == std::string::npos)
    GTEST_SKIP() << "no OpenCL device: " << devices.out;
  // 61 frames: the second check, after the last step, hands screen 1 screen 0's state, so the
  // last frame is one OpenCL process's on both screens.
  const BinaryRunResult one =
      run("live mirrored.toml --fps 0 --no-vsync --scale 1 --backend opencl --frames 61 "
          "--screenshot one.png");
  ASSERT_EQ(one.code, 0) << one.err;
  const std::string screen = "'" ARDCELL_BINARY
                             "' live mirrored.toml --fps 0 --no-vsync --scale 1 --wall 2x1 "
                             "--frames 61 ";
  const BinaryRunResult r = run_command(
      wall_env() + "exec timeout 300 '" ARDCELL_MPIEXEC "' --oversubscribe -np 1 " + screen +
      "--backend opencl --screenshot wall.png : -np 1 " + screen + "--backend threads");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("ardcell live: backend opencl"), std::string::npos) << r.err;
  // Said once; the second drift is counted in the last line.
  EXPECT_NE(r.err.find("wall: screen 1 drifted from screen 0 by frame 1 "), std::string::npos)
      << r.err;
  EXPECT_EQ(r.err.find("by frame 61"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("wall: the screens drifted apart 2 times"), std::string::npos) << r.err;
  EXPECT_EQ(slurp(work() / "wall.png"), slurp(work() / "one.png"));
}
#endif

TEST_F(LiveWallCliTest, BezelCellsAreHiddenAndTheRestIsOneProcesssFrame) {
  if (!has_display()) GTEST_SKIP() << "no X or Wayland display";
  ASSERT_EQ(live("--frames 20 --screenshot one.png").code, 0);
  // 7 pixels at 2 per cell: 4 cells hidden between the screens, 2 on each side of the gap.
  // The wall's job that is checked for leaks (mpi_env).
  const BinaryRunResult r =
      wall(2, "--wall 2x1 --bezel 7 --frames 20 --screenshot wall.png", /*checks_leaks=*/true);
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
  // Screens told different things: the first that differs from screen 0 is named.
  const std::string screen =
      "'" ARDCELL_BINARY "' live mirrored.toml --fps 0 --no-vsync --scale 1 --wall 2x1 ";
  one_line(
      run_command(wall_env() + "exec timeout 120 '" ARDCELL_MPIEXEC "' --oversubscribe -np 1 " +
                  screen + "--frames 5 : -np 1 " + screen + "--frames 6"),
      "--wall: screen 1 runs another preset or other settings than screen 0");
  one_line(wall(2, "--wall 2x1 --bezel 200"), "--bezel 200: hides every cell of a 48x64 screen");
}

}  // namespace
}  // namespace ardcell
