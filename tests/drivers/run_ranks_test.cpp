// `mpirun -np N ardcell run table1-ard --ranks WxH` through the real binary and Open MPI's
// mpirun (ARDCELL_MPIEXEC): each rank runs one block of the grid, its frame plan exchanging
// halos with the other ranks, and rank 0 writes.
//   - 2, 3 and 4 ranks (2x1, 1x2, 3x1, 2x2; uneven blocks of 127 x 93) save the bytes one
//     process saves, on the blocked schedule, and some of them on serial and stream;
//   - PNG frames gathered on rank 0 are the bytes one process writes;
//   - strokes (deposit, push; orient and obstacle on space-cookie-5) paint 4 ranks' blocks as
//     they paint one grid;
//   - a state saved by 4 ranks resumes in one process, and one process's in 2 ranks, bit for bit;
//   - a rank killed mid-run ends the job (no hang), mpirun naming the rank;
//   - seed 001 (a scene of stages, explicit 9-point Gray-Scott on a periodic grid: its halos
//     exchanged by the stage's ops) saves the bytes one process saves on 2, 3 and 4 ranks, and
//     so do space-cookie-5, turing-spots (implicit RD) and mcgraw-gray-scott-map (seed 003),
//     whose solves and wrapping stencils run on the grid gathered from every rank;
//   - scenes with a fluid (cavity-gray-scott, obstacle-ard-fhn, ink), whose fluid and advection
//     run on the gathered grid: fields, dye frames, push and deposit strokes and a resumed state
//     are one process's;
//   - a layout that does not match the processes, a malformed one, a scene that cannot run as
//     blocks and blocks narrower than their halo exit 2 with one line.
#include <gtest/gtest.h>

#include <chrono>
#include <initializer_list>
#include <string>
#include <tuple>
#include <vector>

#include "tests/drivers/binary_run_fixture.h"

namespace ardcell {
namespace {

namespace fs = std::filesystem;

class RunRanksTest : public BinaryRunTest {
 protected:
  // `ardcell <args>` as `ranks` processes of one mpirun (leak-checked when `checks_leaks`).
  BinaryRunResult run_ranks(int ranks, const std::string& args, bool checks_leaks = false) {
    return run_command(mpi_env(checks_leaks) + "exec '" ARDCELL_MPIEXEC "' --oversubscribe -np " +
                       std::to_string(ranks) + " '" ARDCELL_BINARY "' " + args);
  }
  void expect_same_state(const char* a, const char* b,
                         std::initializer_list<const char*> fields = {
                             "u.npy", "v.npy", "dye.npy", "A.npy", "B.npy", "meta.json"}) {
    for (const char* field : fields) {
      const std::string x = slurp(work() / a / field);
      ASSERT_FALSE(x.empty()) << a << "/" << field;
      EXPECT_EQ(x, slurp(work() / b / field)) << a << " vs " << b << ": " << field;
    }
  }
};

constexpr const char* kScene = "run table1-ard --size 127x93 --quiet --every 0 ";

TEST_F(RunRanksTest, RanksSaveTheFieldsOfOneProcess) {
  for (const char* schedule : {"serial", "stream", "blocked"}) {
    const std::string one = std::string("one-") + schedule;
    ASSERT_EQ(
        run(std::string(kScene) + "--steps 6 --schedule " + schedule + " --backend " +
            (std::string(schedule) == "serial" ? "serial" : "threads") + " --save-state " + one)
            .code,
        0);
    struct Layout {
      int ranks;
      const char* parts;
    };
    // Every layout on the default schedule; the others on an uneven split of each axis.
    const std::vector<Layout> layouts =
        std::string(schedule) == "blocked"
            ? std::vector<Layout>{{2, "2x1"}, {2, "1x2"}, {3, "3x1"}, {4, "2x2"}}
        : std::string(schedule) == "stream" ? std::vector<Layout>{{2, "1x2"}, {4, "2x2"}}
                                            : std::vector<Layout>{{3, "3x1"}};
    for (const Layout l : layouts) {
      const std::string dir = std::string(l.parts) + "-" + schedule;
      const BinaryRunResult r =
          run_ranks(l.ranks, std::string(kScene) + "--steps 6 --schedule " + schedule +
                                 (std::string(schedule) == "serial" ? " --backend serial" : "") +
                                 " --ranks " + l.parts + " --save-state " + dir);
      ASSERT_EQ(r.code, 0) << l.parts << " " << schedule << ": " << r.err;
      // Rank 0 alone reports.
      EXPECT_EQ(r.out.find("frames=6 "), 0u) << r.out;
      EXPECT_EQ(r.out.find("frames=6 ", 1), std::string::npos) << r.out;
      expect_same_state(one.c_str(), dir.c_str());
    }
  }
}

// A scene of stages: seed 001's steps exchange a halo of one cell across the periodic grid's
// blocks before each of a frame's 10 steps.
TEST_F(RunRanksTest, Seed001RanksSaveTheFieldsOfOneProcess) {
  const std::string seed001 = "run seed001 --size 127x93 --quiet --every 0 --steps 8 ";
  ASSERT_EQ(run(seed001 + "--backend threads --save-state one").code, 0);
  struct Layout {
    int ranks;
    const char* parts;
  };
  for (const Layout l : {Layout{2, "2x1"}, Layout{3, "1x3"}, Layout{4, "2x2"}}) {
    const std::string dir = std::string("seed001-") + l.parts;
    const BinaryRunResult r =
        run_ranks(l.ranks, seed001 + "--ranks " + l.parts + " --save-state " + dir);
    ASSERT_EQ(r.code, 0) << l.parts << ": " << r.err;
    EXPECT_EQ(r.out.find("frames=8 "), 0u) << r.out;
    expect_same_state("one", dir.c_str(), {"A.npy", "B.npy", "theta0.npy", "meta.json"});
  }
}

// Seed 000's implicit scheme: reactions per cell, the conductivity from A's gradient across the
// blocks' edges, and each diffusion solve (ICCG) on the grid gathered from every rank; seed
// 003's generalized stencil and FFT solve on the gathered grid too.
TEST_F(RunRanksTest, GatheringRdRanksSaveTheFieldsOfOneProcess) {
  struct Case {
    const char* scene;
    int ranks;
    const char* parts;
  };
  for (const Case c : {Case{"space-cookie-5", 2, "2x1"}, Case{"space-cookie-5", 4, "2x2"},
                       Case{"turing-spots", 3, "1x3"}, Case{"mcgraw-gray-scott-map", 2, "1x2"}}) {
    const std::string scene =
        std::string("run ") + c.scene + " --size 127x93 --quiet --every 0 --steps 5 ";
    const std::string one = std::string(c.scene) + "-one",
                      dir = std::string(c.scene) + "-" + c.parts;
    if (!fs::exists(work() / one)) {
      ASSERT_EQ(run(scene + "--save-state " + one).code, 0);
    }
    const BinaryRunResult r =
        run_ranks(c.ranks, scene + "--ranks " + c.parts + " --save-state " + dir);
    ASSERT_EQ(r.code, 0) << c.scene << " " << c.parts << ": " << r.err;
    EXPECT_EQ(r.out.find("frames=5 "), 0u) << r.out;
    expect_same_state(one.c_str(), dir.c_str(), {"A.npy", "B.npy", "theta0.npy", "meta.json"});
  }
}

// On the real-time settings, the implicit schemes' Jacobi sweeps run on each rank's block and
// exchange the iterate between sweeps over MPI (the residual report summed over the ranks):
// the files are one process's.
TEST_F(RunRanksTest, SweepingRdRanksSaveTheFieldsOfOneProcess) {
  for (const auto& [scene_name, ranks, parts] :
       {std::tuple{"space-cookie-5", 2, "2x1"}, std::tuple{"space-cookie-5", 3, "1x3"},
        std::tuple{"turing-spots", 4, "2x2"}}) {
    const std::string scene = std::string("run ") + scene_name +
                              " --size 127x93 --quiet --every 0 --steps 5 --realtime-solvers ";
    const std::string one = std::string(scene_name) + "-realtime-one",
                      dir = std::string(scene_name) + "-realtime-" + parts;
    if (!fs::exists(work() / one)) {
      ASSERT_EQ(run(scene + "--save-state " + one).code, 0);
    }
    const BinaryRunResult r = run_ranks(ranks, scene + "--ranks " + parts + " --save-state " + dir);
    ASSERT_EQ(r.code, 0) << scene_name << " " << parts << ": " << r.err;
    EXPECT_EQ(r.out.find("frames=5 "), 0u) << r.out;
    expect_same_state(one.c_str(), dir.c_str(), {"A.npy", "B.npy", "theta0.npy", "meta.json"});
  }
}

// Scenes with a fluid: every rank gathers the fluid and runs it on the whole grid
// (host/engine/fluid_step.h), the RD's advection too; the reactions run on the blocks. The
// fields, the frames (dye, with an obstacle) and strokes that push and deposit are one process's,
// and a state saved by 2 ranks resumes in one process.
TEST_F(RunRanksTest, FluidRanksSaveTheFieldsOfOneProcess) {
  const auto same_fluid = [this](const std::string& a, const std::string& b) {
    expect_same_state(a.c_str(), b.c_str(), {"u.npy", "v.npy", "p.npy", "dye.npy", "meta.json"});
  };
  struct Case {
    const char* scene;
    int ranks;
    const char* parts;
  };
  for (const Case c : {Case{"cavity-gray-scott", 2, "2x1"}, Case{"obstacle-ard-fhn", 4, "2x2"},
                       Case{"ink", 3, "1x3"}}) {
    const std::string scene = std::string("run ") + c.scene +
                              " --size 96x64 --quiet --every 4 --steps 4 --show dye --out ";
    const std::string one = std::string(c.scene) + "-one",
                      dir = std::string(c.scene) + "-" + c.parts;
    ASSERT_EQ(run(scene + one + " --save-state " + one + "/state").code, 0);
    const BinaryRunResult r =
        run_ranks(c.ranks, scene + dir + " --ranks " + c.parts + " --save-state " + dir + "/state");
    ASSERT_EQ(r.code, 0) << c.scene << " " << c.parts << ": " << r.err;
    EXPECT_EQ(r.out.find("frames=4 "), 0u) << r.out;
    same_fluid(one + "/state", dir + "/state");
    if (std::string(c.scene) != "ink")
      expect_same_state((one + "/state").c_str(), (dir + "/state").c_str(), {"A.npy", "B.npy"});
    const std::string png = slurp(work() / one / "dye_00000004.png");
    ASSERT_FALSE(png.empty()) << c.scene;
    EXPECT_EQ(png, slurp(work() / dir / "dye_00000004.png")) << c.scene;
  }
  const std::string strokes = std::string(" --strokes '") + ARDCELL_SOURCE_DIR +
                              "/presets/strokes/fig3_spiral.jsonl' --paint-radius 3 ";
  const std::string cavity = "run cavity-gray-scott --size 96x64 --quiet --every 0 --steps 6";
  for (const char* mode : {"push", "deposit"}) {
    const std::string one = std::string("cavity-one-") + mode,
                      four = std::string("cavity-four-") + mode;
    ASSERT_EQ(run(cavity + strokes + "--paint-mode " + mode + " --save-state " + one).code, 0);
    const BinaryRunResult r = run_ranks(
        4, cavity + strokes + "--paint-mode " + mode + " --ranks 2x2 --save-state " + four);
    ASSERT_EQ(r.code, 0) << mode << ": " << r.err;
    same_fluid(one, four);
    expect_same_state(one.c_str(), four.c_str(), {"A.npy", "B.npy"});
  }
  ASSERT_EQ(run(cavity + " --save-state cavity-plain").code, 0);
  EXPECT_NE(slurp(work() / "cavity-plain" / "u.npy"), slurp(work() / "cavity-one-push" / "u.npy"))
      << "the push left no trace";
  EXPECT_NE(slurp(work() / "cavity-plain" / "B.npy"),
            slurp(work() / "cavity-one-deposit" / "B.npy"))
      << "the deposit left no trace";
  // 2 ranks for 3 frames, then one process for 3: six frames of one process.
  const std::string three = "run cavity-gray-scott --size 96x64 --quiet --every 0 --steps 3";
  ASSERT_EQ(run_ranks(2, three + " --ranks 1x2 --save-state cavity-three").code, 0);
  ASSERT_EQ(
      run("run --load-state cavity-three --steps 3 --every 0 --quiet --save-state cavity-six").code,
      0);
  same_fluid("cavity-plain", "cavity-six");
  expect_same_state("cavity-plain", "cavity-six", {"A.npy", "B.npy"});
}

// Every rank reads the strokes and paints its block: the painting of one process.
TEST_F(RunRanksTest, StrokesPaintEveryBlockAsOneGrid) {
  const std::string strokes = std::string(" --strokes '") + ARDCELL_SOURCE_DIR +
                              "/presets/strokes/fig3_spiral.jsonl' --paint-radius 3 --steps 30 ";
  // Orientation: a table1 state has no theta0 until the first stroke makes one on every rank.
  for (const char* mode : {"deposit", "push", "orient"}) {
    const std::string one = std::string("one-") + mode, two = std::string("two-") + mode;
    ASSERT_EQ(
        run(std::string(kScene) + strokes + "--paint-mode " + mode + " --save-state " + one).code,
        0);
    const BinaryRunResult r = run_ranks(4, std::string(kScene) + strokes + "--paint-mode " + mode +
                                               " --ranks 2x2 --save-state " + two);
    ASSERT_EQ(r.code, 0) << mode << ": " << r.err;
    expect_same_state(one.c_str(), two.c_str());
    if (std::string(mode) == "orient") expect_same_state(one.c_str(), two.c_str(), {"theta0.npy"});
  }
  ASSERT_EQ(run(std::string(kScene) + "--steps 30 --save-state plain").code, 0);
  EXPECT_NE(slurp(work() / "plain" / "B.npy"), slurp(work() / "one-deposit" / "B.npy"))
      << "the strokes left no trace";
  // Orientation strokes and obstacles: every rank records them over the whole grid, and the
  // blocks' theta0 and diffusion solves are one process's.
  // The frames written show the obstacle as one process draws it (rank 0 holds the mask).
  const std::string cookie =
      "run space-cookie-5 --size 127x93 --quiet --every 30 --show A" + strokes;
  for (const char* mode : {"orient", "obstacle"}) {
    const std::string one = std::string("cookie-one-") + mode,
                      four = std::string("cookie-four-") + mode;
    ASSERT_EQ(
        run(cookie + "--paint-mode " + mode + " --save-state " + one + " --out " + one + "-frames")
            .code,
        0);
    const BinaryRunResult r =
        run_ranks(4, cookie + "--paint-mode " + mode + " --ranks 2x2 --save-state " + four +
                         " --out " + four + "-frames");
    ASSERT_EQ(r.code, 0) << mode << ": " << r.err;
    expect_same_state(one.c_str(), four.c_str(), {"A.npy", "B.npy", "theta0.npy", "meta.json"});
    const std::string png = slurp(work() / (one + "-frames") / "A_00000030.png");
    ASSERT_FALSE(png.empty()) << mode;
    EXPECT_EQ(png, slurp(work() / (four + "-frames") / "A_00000030.png")) << mode;
  }
  ASSERT_EQ(run(cookie + "--save-state cookie-plain --out cookie-plain-frames").code, 0);
  EXPECT_NE(slurp(work() / "cookie-plain" / "theta0.npy"),
            slurp(work() / "cookie-one-orient" / "theta0.npy"))
      << "the orientation strokes left no trace";
  EXPECT_NE(slurp(work() / "cookie-plain" / "A.npy"),
            slurp(work() / "cookie-one-obstacle" / "A.npy"))
      << "the obstacle strokes left no trace";
}

TEST_F(RunRanksTest, FramesAreGatheredOnRankZero) {
  ASSERT_EQ(run("run table1-ard --size 127x93 --quiet --steps 4 --every 2 --show B --out one").code,
            0);
  // The job of this suite that is checked for leaks (mpi_env).
  const BinaryRunResult r = run_ranks(
      2, "run table1-ard --size 127x93 --quiet --steps 4 --every 2 --show B --out two --ranks 1x2",
      /*checks_leaks=*/true);
  ASSERT_EQ(r.code, 0) << r.err;
  for (const char* png : {"B_00000002.png", "B_00000004.png"}) {
    ASSERT_TRUE(fs::exists(work() / "one" / png)) << png;
    EXPECT_EQ(slurp(work() / "one" / png), slurp(work() / "two" / png)) << png;
  }
}

TEST_F(RunRanksTest, SavedStatesMoveBetweenRanksAndOneProcess) {
  ASSERT_EQ(run(std::string(kScene) + "--steps 6 --save-state six").code, 0);
  // 4 ranks, then one process.
  ASSERT_EQ(
      run_ranks(4, std::string(kScene) + "--steps 3 --ranks 2x2 --save-state three-ranks").code, 0);
  ASSERT_EQ(
      run("run --load-state three-ranks --steps 3 --every 0 --quiet --save-state resumed-1").code,
      0);
  expect_same_state("six", "resumed-1");
  // One process, then 2 ranks.
  ASSERT_EQ(run(std::string(kScene) + "--steps 3 --save-state three-one").code, 0);
  const BinaryRunResult r =
      run_ranks(2,
                "run --load-state three-one --steps 3 --every 0 --quiet --ranks 2x1 --save-state "
                "resumed-2");
  ASSERT_EQ(r.code, 0) << r.err;
  expect_same_state("six", "resumed-2");
}

// Rank 1 is killed mid-run (SIGKILL: no chance to say goodbye); the job must end, not hang with
// rank 0 waiting for a halo that never comes, and mpirun names the rank.
TEST_F(RunRanksTest, ARankThatDiesEndsTheJob) {
  const auto start = std::chrono::steady_clock::now();
  const BinaryRunResult r = run_command(
      mpi_env() +
      "exec '" ARDCELL_MPIEXEC
      "' --oversubscribe -np 2 sh -c 'if [ \"$OMPI_COMM_WORLD_RANK\" = 1 ]; then (sleep 2; kill "
      "-9 $$) & fi; exec \"" ARDCELL_BINARY
      "\" run table1-ard --size 128 --ranks 2x1 --steps 100000000 --every 0 --quiet'");
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_NE(r.code, 0) << r.err;
  EXPECT_LT(seconds, 60.0);
  EXPECT_NE(r.err.find("rank 1"), std::string::npos) << r.err;
  EXPECT_EQ(r.out.find("frames="), std::string::npos) << r.out;
}

TEST_F(RunRanksTest, BadLayoutsExitTwoWithOneLine) {
  const auto first_line = [](const std::string& err) { return err.substr(0, err.find('\n')); };
  BinaryRunResult r = run_ranks(2, std::string(kScene) + "--steps 1 --ranks 2x2");
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_EQ(first_line(r.err),
            "ardcell run: --ranks 2x2 needs 4 processes (mpirun -np 4); this run has 2");
  r = run(std::string(kScene) + "--steps 1 --ranks two");
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.err,
            "ardcell run: --ranks 'two': expected WxH, the ranks along x by along y (e.g. 2x1)\n");
  // Without mpirun: a singleton MPI job of one process.
  r = run_command(mpi_env() + "exec '" ARDCELL_BINARY
                              "' run seed001 --set rd.enabled=false --steps 1 --quiet --ranks 1x1");
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(first_line(r.err),
            "ardcell run: --ranks: scene 'seed001' runs on one process's whole grid: rd.enabled: a "
            "scene without a fluid or RD has nothing to run as blocks (expected no --ranks)");
  r = run_ranks(2, "run table1 --size 40 --steps 1 --quiet --ranks 2x1");
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_EQ(first_line(r.err),
            "ardcell run: --ranks 2x1: a block of 20x40 cells is narrower than its halo of 23 "
            "(expected fewer ranks or a larger --size)");
}

}  // namespace
}  // namespace ardcell
