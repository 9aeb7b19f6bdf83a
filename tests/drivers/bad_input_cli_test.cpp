// Hostile input against the real binary (issue 18): files that are not regular files or are
// far too large, values outside the preset keys' ranges, destinations that cannot be written.
// Each case must give exit code 2, one line on stderr, and leave nothing behind; none may
// read the whole of an oversized input (they finish in well under the time that would take),
// and every run has its memory bounded to 2 GiB (limit_memory): a case that allocated what the
// input asks for would fail (std::bad_alloc, or ASan's limits abort it) instead of exit 2.
#include <sys/stat.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <vector>

#include "tests/drivers/binary_run_fixture.h"

namespace ardcell {
namespace {

namespace fs = std::filesystem;

class BadInputCli : public BinaryRunTest {
 protected:
  void SetUp() override {
    BinaryRunTest::SetUp();
    limit_memory(2048);
  }
  // `ardcell <args>` must be refused: exit 2, one line holding `expect`, nothing new in work().
  void expect_refused(const std::string& args, const std::string& expect) {
    std::vector<fs::path> before;
    for (const auto& e : fs::directory_iterator(work())) before.push_back(e.path());
    const auto t0 = std::chrono::steady_clock::now();
    const BinaryRunResult r = run(args);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_EQ(r.code, 2) << args << "\n" << r.err;
    EXPECT_EQ(count_lines(r.err), 1) << args << "\n" << r.err;
    EXPECT_NE(r.err.find(expect), std::string::npos) << args << "\n" << r.err;
    EXPECT_LT(seconds, 20) << args;
    std::vector<fs::path> after;
    for (const auto& e : fs::directory_iterator(work())) after.push_back(e.path());
    EXPECT_EQ(after.size(), before.size()) << args << ": left files behind";
  }
  void write(const std::string& name, const std::string& text) {
    std::ofstream(work() / name, std::ios::binary) << text;
  }
  // A saved state of a 16 x 16 cavity in work()/st.
  void make_state() {
    const BinaryRunResult r = run("run cavity --size 16 --steps 1 --every 0 --save-state st");
    ASSERT_EQ(r.code, 0) << r.err;
  }
};

TEST_F(BadInputCli, FilesThatAreNotRegularFilesAreRefusedWithoutReading) {
  fs::create_directories(work() / "dir.toml");
  ASSERT_EQ(::mkfifo((work() / "fifo.toml").c_str(), 0644), 0);
  expect_refused("run --scene ./dir.toml", "is a folder (expected a preset TOML file)");
  expect_refused("run --scene ./fifo.toml", "is a FIFO (expected a preset TOML file)");
  expect_refused("run --scene /dev/zero", "is a character device");
  expect_refused("run cavity --strokes /dev/zero", "is a character device");
  expect_refused("run cavity --strokes ./fifo.toml", "is a FIFO");
  expect_refused("tablet decode /dev/zero", "is a character device");
  expect_refused("tablet decode ./fifo.toml", "is a FIFO");
  make_state();
  fs::remove(work() / "st" / "meta.json");
  fs::create_symlink("/dev/zero", work() / "st" / "meta.json");
  expect_refused("run --load-state st --steps 1 --every 0", "is a character device");
  fs::remove(work() / "st" / "meta.json");
  ASSERT_EQ(::mkfifo((work() / "st" / "meta.json").c_str(), 0644), 0);
  expect_refused("run --load-state st --steps 1 --every 0", "is a FIFO");
  // A number JSON cannot hold (nlohmann throws out_of_range, not parse_error): was exit 1.
  fs::remove(work() / "st" / "meta.json");
  write("st/meta.json", "{\"format\": \"ardcell-state\", \"version\": 1, \"dt\": 2e308}");
  expect_refused("run --load-state st --steps 1 --every 0",
                 "meta.json: not valid JSON (a number out of range)");
}

// A saved state names its scene: a custom preset's state resumes from the parameters saved with
// it, saying so in one line; one whose scene is not built in and whose parameters are not
// complete is refused (it used to run silently on defaults).
TEST_F(BadInputCli, AStateOfASceneThatIsNotBuiltInIsResumedWithOneLineOrRefused) {
  write("mine.toml", "name = \"mine\"\n[grid]\nsize = [16, 16]\n[fluid]\nlid_speed = -2.0\n");
  BinaryRunResult r = run("run --scene ./mine.toml --steps 1 --every 0 --save-state st");
  ASSERT_EQ(r.code, 0) << r.err;
  r = run("run --load-state st --steps 1 --every 0 --stats");
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.err,
            "ardcell: state st was saved from scene 'mine', which is not built in: resuming from "
            "the parameters saved with it\n");
  EXPECT_NE(r.out.find("scene=mine size=16x16"), std::string::npos) << r.out;

  nlohmann::json meta = nlohmann::json::parse(slurp(work() / "st" / "meta.json"));
  meta["parameters"].erase("fluid.lid_speed");
  write("st/meta.json", meta.dump());
  expect_refused("run --load-state st --steps 1 --every 0",
                 "st/meta.json: scene 'mine' is not built in and \"parameters\" lacks "
                 "fluid.lid_speed (expected a built-in scene, or every preset key");
  meta["scene"] = "../mine.toml";  // a name, never a file to read
  write("st/meta.json", meta.dump());
  expect_refused("run --load-state st --steps 1 --every 0", "scene '../mine.toml' is not built in");
}

TEST_F(BadInputCli, OversizedFilesAreRefusedBeforeTheirPayload) {
  // A preset of 2 MiB (the cap is 1 MiB).
  write("big.toml", "# " + std::string(2 << 20, 'x') + "\n");
  expect_refused("run --scene ./big.toml", "too large (expected a preset TOML file of at most");
  // A sparse 2 GiB .npy whose header says 16 x 16: refused from the header and the size.
  make_state();
  const fs::path u = work() / "st" / "u.npy";
  std::string head;
  {
    std::ifstream in(u, std::ios::binary);
    head.assign(128, '\0');
    in.read(head.data(), 128);
  }
  {
    std::ofstream out(u, std::ios::binary | std::ios::trunc);
    out.write(head.data(), 128);
  }
  fs::resize_file(u, std::uintmax_t(2) << 30);
  expect_refused("run --load-state st --steps 1 --every 0", "u.npy: holds");
}

TEST_F(BadInputCli, FlagsGoThroughThePresetKeyRanges) {
  expect_refused("run cavity --dt 1e308 --steps 1",
                 "--dt 1e+308: expected a number in [1e-09, 100]");
  expect_refused("run cavity --dt nan --steps 1", "--dt nan: expected");
  expect_refused("run cavity --re 1e-300 --steps 1", "(preset key fluid.viscosity)");
  expect_refused("run cavity --size 1 --steps 1", "(preset key grid.size)");
  expect_refused("run cavity --size 9000 --steps 1", "(preset key grid.size)");
  expect_refused("run cavity --sweeps 100000 --steps 1",
                 "(preset key fluid.pressure_solver.iterations)");
  write("s.jsonl", "{\"t\": 0, \"x\": 0.5, \"y\": 0.5}\n");
  expect_refused("run cavity --strokes s.jsonl --paint-radius nan --steps 1",
                 "(preset key input.brush_radius)");
  // Painting flags without a recording would do nothing: said, not ignored.
  expect_refused("run cavity --paint-radius nan --steps 1",
                 "--paint-radius: paints a recording; expected --strokes FILE or --replay FILE");
  expect_refused("run cavity --paint-mode orient --steps 1", "--paint-mode: paints a recording");
  write("far.jsonl", "{\"t\": 0, \"x\": 1e308, \"y\": 0.5}\n");
  expect_refused("run cavity --strokes far.jsonl --steps 1", "far.jsonl:1:");
  expect_refused("live --fps nan", "expected a finite number in [0");
  expect_refused("live --playlist cavity,no-such-preset", "--playlist no-such-preset");
  expect_refused("live --osc 0 --osc-bind 0.0.0.0", "--osc-remote");
}

TEST_F(BadInputCli, DestinationsAreCheckedBeforeTheFirstFrame) {
  write("afile", "x");
  fs::create_directories(work() / "adir");
  expect_refused("run cavity --steps 1 --out ''", "--out: expected a path");
  expect_refused("run cavity --steps 1 --every 0 --save-state ''", "--save-state: expected a path");
  expect_refused("run cavity --steps 1 --video adir --no-png", "adir: is a folder");
  expect_refused("run cavity --steps 1 --every 0 --save-state afile/state", "is not a folder");
  write("adir/keep.txt", "mine");
  expect_refused("run cavity --steps 1 --every 0 --save-state adir",
                 "exists and is not an ardcell saved state");
  expect_refused("run cavity --steps 1 --video afile/v.y4m --no-png", "is not a folder");
  expect_refused("live --record adir", "--record");
  expect_refused("live --screenshot-dir afile", "--screenshot-dir");
  EXPECT_EQ(slurp(work() / "adir" / "keep.txt"), "mine");
}

// Every usage error exits 2 with one line, naming file:line where a file is involved: also the
// values the engine refuses (they used to escape as exit 1 with no file:line), wherever a scene
// is made (run, live, tablet play), and grids too large for the memory.
TEST_F(BadInputCli, EveryUsageErrorIsExitTwoWithOneLine) {
  write("spf.toml", "[rd]\nenabled = true\nsteps_per_frame = 5000\n");
  write("res.toml", "[rd]\nenabled = true\n[rd.table]\nenabled = true\nresolution = 65536\n");
  write("polar.toml", "[rd]\nenabled = true\n[rd.anisotropy]\nkind = \"polar\"\n");
  write("big.toml", "[grid]\nsize = [8192, 8192]\n[rd]\nenabled = true\n");
  write("s.jsonl", "{\"t\": 0, \"x\": 0.5, \"y\": 0.5}\n");
  write("pen.txt", "R: 1 05\nE: soon 1 0a\n");
  const std::pair<const char*, const char*> cases[] = {
      {"run --scene ./spf.toml --steps 1 --every 0",
       "./spf.toml:3: rd.steps_per_frame: expected an integer in [1, 1000], got 5000"},
      {"run --scene ./res.toml --steps 1 --every 0",
       "./res.toml:5: rd.table.resolution: expected an integer in [2, 4096], got 65536"},
      {"run --scene ./polar.toml --steps 1 --every 0",
       "./polar.toml:4: rd.anisotropy.samples: expected an integer in [2, 64] with"},
      {"run cavity-gray-scott --set rd.steps_per_frame=5000 --steps 1 --every 0",
       "--set rd.steps_per_frame: expected an integer in [1, 1000], got 5000"},
      {"run cavity-gray-scott --set rd.anisotropy.kind=polar --steps 1 --every 0",
       "ardcell run: rd.anisotropy.samples: expected an integer in [2, 64] with"},
      {"run cavity-gray-scott --set rd.scheme=explicit9 --set rd.anisotropy.kind=lobes --steps 1 "
       "--every 0",
       "ardcell run: rd.scheme: expected implicit, crank-nicolson-am2 or sbdf2 with "
       "rd.anisotropy.kind lobes"},
      {"run --scene ./big.toml --steps 1 --every 0", "needs about"},
      {"live ./spf.toml --frames 1", "./spf.toml:3: rd.steps_per_frame"},
      {"live ./big.toml --frames 1", "needs about"},
      {"tablet play ./spf.toml --strokes s.jsonl --png o.png", "./spf.toml:3: rd.steps_per_frame"},
      {"tablet play ./big.toml --strokes s.jsonl --png o.png", "needs about"},
      {"tablet play cavity --strokes s.jsonl --png nodir/o.png", "--png nodir/o.png"},
      {"tablet play cavity --strokes s.jsonl --png ''", "--png: expected a path"},
      {"tablet record nodir/pen.txt --seconds 1", "nodir/pen.txt"},
      {"tablet decode pen.txt", "ardcell tablet decode: pen.txt:2: E: bad timestamp"},
  };
  for (const auto& [args, expect] : cases) expect_refused(args, expect);
}

// A preset with several problems gives one line for each, every line in the same form.
TEST_F(BadInputCli, PresetProblemsGiveOneLineEach) {
  write("three.toml", "[fluid]\nviscosity = \"x\"\nlid = 1\n[rd]\nsteps_per_frame = 0\n");
  for (const char* cmd : {"run --scene ./three.toml --steps 1 --every 0", "live ./three.toml"}) {
    const BinaryRunResult r = run(cmd);
    EXPECT_EQ(r.code, 2) << cmd;
    const std::string who = std::string("ardcell ") + (cmd[0] == 'r' ? "run" : "live") + ": ";
    EXPECT_EQ(r.err,
              who + "./three.toml:2: fluid.viscosity: expected a number in [0, 1000], " +
                  "got the string \"x\"\n" + who +
                  "./three.toml:3: fluid.lid: unknown key; expected one of: scene, " +
                  "viscosity, lid_speed, dye_diffusion, conserve_dye, advection, inflow_speed, " +
                  "inflow_side, inflow_profile, wall_low, wall_high, obstacle_x, obstacle_y, " +
                  "obstacle_radius, obstacle_boundary, probes, inflow_dye_stripes, walls, " +
                  "emitters, viscosity_solver, pressure_solver\n" + who +
                  "./three.toml:5: rd.steps_per_frame: expected an integer in [1, 1000], " +
                  "got 0\n")
        << cmd;
  }
}

}  // namespace
}  // namespace ardcell
