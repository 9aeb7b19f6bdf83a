// The real `ardcell` binary (ARDCELL_BINARY): every bad-input path exits 2 with one line on
// stderr and leaves no file behind; --list, --help and info; a tiny run writes PNG frames and
// the summary; a saved state resumes bit-exactly; video output.
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <string>

#include "host/io/npy.h"
#include "host/io/state_io.h"
#include "tests/drivers/binary_run_fixture.h"

namespace ardcell {
namespace {

namespace fs = std::filesystem;

// The line of `text` that starts with `prefix`, without its newline ("" when none).
std::string line_starting(const std::string& text, const std::string& prefix) {
  std::size_t at = text.rfind(prefix, 0) == 0 ? 0 : text.find("\n" + prefix);
  if (at == std::string::npos) return "";
  if (text[at] == '\n') ++at;
  return text.substr(at, text.find('\n', at) - at);
}

using Result = BinaryRunResult;

class CliTest : public BinaryRunTest {
 protected:
  std::set<std::string> tree() const {
    std::set<std::string> out;
    for (const auto& e : fs::recursive_directory_iterator(work()))
      out.insert(fs::relative(e.path(), work()).string());
    return out;
  }
};

TEST_F(CliTest, EveryBadInputExitsTwoWithOneLineAndLeavesNothing) {
  // Fixtures: a file where a folder is expected, a corrupt state, a truncated field.
  std::ofstream(work() / "afile") << "x";
  ASSERT_EQ(run("run --size 16 --steps 2 --every 0 --save-state good").code, 0);
  fs::create_directories(work() / "notjson");
  std::ofstream(work() / "notjson" / "meta.json") << "{\"format\": \"ardcell-st";
  fs::copy(work() / "good", work() / "truncated");
  fs::resize_file(work() / "truncated" / "u.npy", 90);
  const std::set<std::string> before = tree();

  const char* cases[] = {
      "frob",
      "--bogus",
      "run --bogus",
      "run --scene nope",
      "run nope",
      "run --scene cavity ink",
      "run --scene missing/preset.toml",
      "run --size 0",
      "run --size -4",
      "run --size 12x",
      "run --size 16x0",
      "run --size abc",
      "run --size 65536",
      "run --steps -1",
      "run --steps abc",
      "run --dt 0",
      "run --dt -0.5",
      "run --re 0",
      "run --solver foo",
      "run --sweeps 0",
      "run --every -2",
      "run --fps 0",
      "run --show temperature",
      "run --show A",
      "run --colormap jet",
      "run --size 16 --steps 1 --out afile/sub",
      "run --size 16 --steps 1 --out /proc/ardcell-test/frames",
      "run --size 16 --steps 1 --video nodir/clip.mp4",
      "run --load-state missing",
      "run --load-state afile",
      "run --load-state notjson",
      "run --load-state truncated --steps 1",
      "run --load-state good --size 32",
      "run --load-state good --scene ink",
      "info --bogus",
  };
  for (const char* args : cases) {
    const Result r = run(args);
    EXPECT_EQ(r.code, 2) << args << "\n" << r.err;
    EXPECT_TRUE(r.out.empty()) << args << ": " << r.out;
    ASSERT_FALSE(r.err.empty()) << args;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << args << ": " << r.err;
    EXPECT_EQ(r.err.back(), '\n') << args;
    EXPECT_EQ(r.err.rfind("ardcell", 0), 0u) << args << ": " << r.err;
    EXPECT_EQ(tree(), before) << args << " left files behind";
  }
}

TEST_F(CliTest, MessagesNameWhatWasWrongAndWhatWasExpected) {
  Result r = run("run --scene nope");
  EXPECT_NE(r.err.find("unknown scene 'nope'"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("cavity"), std::string::npos) << r.err;
  r = run("run --size 65536");  // beyond the preset key's range, before any memory check
  EXPECT_NE(r.err.find("two integers in [4, 8192] (preset key grid.size)"), std::string::npos)
      << r.err;
  r = run("run --solver foo");
  EXPECT_NE(r.err.find("expected jacobi, rbgs, iccg or mg"), std::string::npos) << r.err;
  r = run("run --load-state missing");
  EXPECT_NE(r.err.find("missing: saved state not found"), std::string::npos) << r.err;
}

TEST_F(CliTest, ListShowsEveryFluidSceneWithADescription) {
  const Result r = run("run --list");
  ASSERT_EQ(r.code, 0) << r.err;
  for (const char* scene : {"cavity", "obstacle", "ink"}) {
    const std::string line = line_starting(r.out, std::string(scene) + " ");
    ASSERT_FALSE(line.empty()) << scene << "\n" << r.out;
    const std::size_t text = line.find_first_not_of(' ', std::strlen(scene));
    EXPECT_NE(text, std::string::npos) << "no description: " << line;
  }
  EXPECT_EQ(tree(), std::set<std::string>{});
}

TEST_F(CliTest, HelpForEachCommand) {
  Result r = run("--help");
  ASSERT_EQ(r.code, 0);
  EXPECT_NE(r.out.find("run"), std::string::npos);
  EXPECT_NE(r.out.find("info"), std::string::npos);
  r = run("run --help");
  ASSERT_EQ(r.code, 0);
  for (const char* flag :
       {"--scene", "--list", "--size", "--steps", "--dt", "--re", "--solver", "--sweeps", "--out",
        "--every", "--save-state", "--load-state", "--colormap", "--show", "--video"})
    EXPECT_NE(r.out.find(flag), std::string::npos) << flag;
  r = run("info --help");
  EXPECT_EQ(r.code, 0);
  EXPECT_NE(r.out.find("info"), std::string::npos);
}

TEST_F(CliTest, InfoReportsVersionBuildOptionsCpuAndCores) {
  const Result r = run("info");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find(std::string("ardcell ") + ARDCELL_VERSION), std::string::npos);
  const std::string options = line_starting(r.out, "options: ");
  EXPECT_TRUE(options.rfind("options: opencl=o", 0) == 0 &&
              options.find(" hidapi=o") != std::string::npos)
      << r.out;
#if defined(ARDCELL_WITH_MPI)
  EXPECT_NE(options.find(" mpi=on"), std::string::npos) << r.out;
#else
  EXPECT_NE(options.find(" mpi=off"), std::string::npos) << r.out;
#endif
  EXPECT_NE(r.out.find("cpu features:"), std::string::npos);
#if defined(ARDCELL_WITH_SDL2)
  // This build found the HUD's font (dev.sh installs fonts-dejavu-core): its path, present.
  const std::string font = line_starting(r.out, "hud font: ");
  EXPECT_NE(font.find("DejaVuSansMono-Bold.ttf"), std::string::npos) << r.out;
  EXPECT_EQ(font.find("missing"), std::string::npos) << r.out;
#endif
  const std::string cores = line_starting(r.out, "cores: ");
  EXPECT_TRUE(cores.size() > 7 && cores[7] >= '1' && cores[7] <= '9' &&
              cores.find(" online") != std::string::npos)
      << r.out;
}

TEST_F(CliTest, TinyRunWritesPngFramesAndTheSummary) {
  const Result r = run("run --size 32 --steps 3 --every 1 --out tmp");
  ASSERT_EQ(r.code, 0) << r.err;
  long long frames = -1, images = -1;
  double ms = -1, cells = -1;
  char out[64] = {};
  ASSERT_EQ(std::sscanf(r.out.c_str(), "frames=%lld ms/frame=%lf cells/s=%lf images=%lld out=%63s",
                        &frames, &ms, &cells, &images, out),
            5)
      << r.out;
  EXPECT_EQ(frames, 3);
  EXPECT_EQ(images, 3);
  EXPECT_GT(ms, 0.0);
  EXPECT_GT(cells, 0.0);
  EXPECT_STREQ(out, "tmp");
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
  EXPECT_EQ(tree(), (std::set<std::string>{"tmp", "tmp/dye_00000001.png", "tmp/dye_00000002.png",
                                           "tmp/dye_00000003.png"}));
  const std::string png = slurp(work() / "tmp" / "dye_00000003.png");
  ASSERT_GT(png.size(), 24u);
  EXPECT_EQ(png.substr(0, 8), "\x89PNG\r\n\x1a\n");
  // IHDR width and height, big-endian.
  EXPECT_EQ(png.substr(16, 8), std::string("\0\0\0\x20\0\0\0\x20", 8));
}

TEST_F(CliTest, DefaultRunNamesItsOutputFolder) {
  const Result r = run("run --size 16 --steps 2");
  ASSERT_EQ(r.code, 0) << r.err;
  const std::size_t at = r.out.find("out=out/cavity-");
  ASSERT_NE(at, std::string::npos) << r.out;
  const std::string folder = r.out.substr(at + 4, r.out.find('\n', at) - at - 4);
  EXPECT_TRUE(fs::is_directory(work() / folder)) << folder;
  EXPECT_TRUE(fs::exists(work() / folder / "dye_00000002.png"));
}

TEST_F(CliTest, SavedStateResumesBitExactly) {
  ASSERT_EQ(run("run --size 24x20 --steps 6 --every 0 --save-state full").code, 0);
  ASSERT_EQ(run("run --size 24x20 --steps 3 --every 0 --save-state half").code, 0);
  const Result r = run("run --load-state half --steps 3 --every 0 --save-state resumed");
  ASSERT_EQ(r.code, 0) << r.err;
  SavedStateMeta a, b;
  ASSERT_TRUE(read_state_meta(work() / "full", a));
  ASSERT_TRUE(read_state_meta(work() / "resumed", b));
  EXPECT_EQ(a.step, 6);
  EXPECT_EQ(b.step, 6);
  EXPECT_EQ(a.time, b.time);
  EXPECT_EQ(a.fields, b.fields);
  EXPECT_EQ(a.parameters, b.parameters);
  for (const std::string& f : a.fields) {
    NpyArray x, y;
    ASSERT_TRUE(read_npy(work() / "full" / (f + ".npy"), x));
    ASSERT_TRUE(read_npy(work() / "resumed" / (f + ".npy"), y));
    ASSERT_EQ(x.data.size(), y.data.size());
    EXPECT_EQ(std::memcmp(x.data.data(), y.data.data(), x.data.size() * sizeof(float)), 0) << f;
  }
  // The state moved: a run of 3 steps differs from one of 6.
  NpyArray h, f6;
  ASSERT_TRUE(read_npy(work() / "half" / "u.npy", h));
  ASSERT_TRUE(read_npy(work() / "full" / "u.npy", f6));
  EXPECT_NE(h.data, f6.data);
}

// --realtime-solvers: every solve fixed Jacobi sweeps (quality.max_sweeps, tolerance 0) and the
// tabulated reaction, as the saved parameters say; --sweeps still refines it.
TEST_F(CliTest, RealtimeSolversAreTheSavedSettings) {
  const Result r =
      run("run cavity-gray-scott --size 24x20 --steps 2 --every 0 --realtime-solvers --sweeps 12 "
          "--save-state rt");
  ASSERT_EQ(r.code, 0) << r.err;
  SavedStateMeta m;
  ASSERT_TRUE(read_state_meta(work() / "rt", m));
  for (const char* solver :
       {"fluid.viscosity_solver", "fluid.pressure_solver", "rd.diffusion_solver"}) {
    EXPECT_EQ(m.parameters.at(std::string(solver) + ".kind"), "jacobi") << solver;
    EXPECT_EQ(m.parameters.at(std::string(solver) + ".tolerance"), 0.0) << solver;
  }
  EXPECT_EQ(m.parameters.at("fluid.pressure_solver.iterations"), 12);  // --sweeps on top
  EXPECT_EQ(m.parameters.at("rd.diffusion_solver.iterations"), 20);    // quality.max_sweeps
  EXPECT_EQ(m.parameters.at("rd.table.enabled"), true);
  // The Table 1 plan reacts by Newton in its passes: its sweeps become quality.max_sweeps and
  // its reaction stays; a table asked for explicitly is refused, naming the key.
  const Result t = run("run table1-ard --size 16 --realtime-solvers --steps 1 --save-state t1");
  ASSERT_EQ(t.code, 0) << t.err;
  SavedStateMeta t1;
  ASSERT_TRUE(read_state_meta(work() / "t1", t1));
  EXPECT_EQ(t1.parameters.at("rd.table.enabled"), false);
  const Result table = run("run table1-ard --size 16 --steps 1 --set rd.table.enabled=true");
  EXPECT_EQ(table.code, 2);
  EXPECT_NE(table.err.find("rd.table"), std::string::npos) << table.err;
}

TEST_F(CliTest, Y4mVideoWithoutPngFrames) {
  const Result r = run("run --size 16 --steps 4 --every 2 --no-png --video clip.y4m");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(tree(), std::set<std::string>{"clip.y4m"});
  const std::string data = slurp(work() / "clip.y4m");
  const std::string header = "YUV4MPEG2 W16 H16 F30:1 Ip A1:1 C420jpeg\n";
  ASSERT_EQ(data.substr(0, header.size()), header);
  EXPECT_EQ(data.size(), header.size() + 2 * (6 + 16 * 16 + 2 * 8 * 8));
}

}  // namespace
}  // namespace ardcell
