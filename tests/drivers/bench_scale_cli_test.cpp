// `ardcell bench scale` through the real binary: bench/scale_bench under Open MPI's mpirun for
// 1 and 2 ranks, strong and weak, at a small size: the table and scale.md / scale.csv hold one
// row per run with a positive rate; one rank sends no halo, two do; the 1-rank rows are the
// efficiency's reference (1.000); the same for seed 001 (--scene seed001: a scene of stages whose
// blocks exchange before every step) and cavity-gray-scott (a fluid on the gathered grid). Bad
// --ranks and an unknown scene exit 2 with one line.
#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

#include "tests/drivers/binary_run_fixture.h"

namespace ardcell {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> csv_cells(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream in(line);
  for (std::string c; std::getline(in, c, ',');) cells.push_back(c);
  return cells;
}

class BenchScaleTest : public BinaryRunTest {
 protected:
  BinaryRunResult run_bench(const std::string& args) {
    return run_command(mpi_env() + "exec '" ARDCELL_BINARY "' bench scale " + args);
  }
  // scale.md and scale.csv in `dir`: four rows (strong and weak, 1 and 2 ranks) with a positive
  // rate; one rank sends no halo and is the efficiency's reference, two do.
  void expect_scale_rows(const BinaryRunResult& r, const fs::path& dir) {
    EXPECT_NE(r.out.find("| strong | 2 | "), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("| weak | 2 | "), std::string::npos) << r.out;
    const std::string csv = slurp(dir / "scale.csv");
    ASSERT_TRUE(fs::exists(dir / "scale.md"));
    std::stringstream lines(csv);
    std::string header, line;
    std::getline(lines, header);
    EXPECT_EQ(header,
              "scaling,ranks,workers_per_rank,grid_x,grid_y,fps,cells_per_s,efficiency,"
              "halo_bytes_per_frame,mpi_ms_per_frame");
    int rows = 0;
    while (std::getline(lines, line)) {
      const std::vector<std::string> c = csv_cells(line);
      ASSERT_EQ(c.size(), 10u) << line;
      ++rows;
      const int ranks = std::stoi(c[1]);
      EXPECT_GT(std::stod(c[5]), 0.0) << line;
      if (ranks == 1) {
        EXPECT_EQ(std::stod(c[8]), 0.0) << line;  // nothing to send
        EXPECT_EQ(std::stod(c[7]), 1.0) << line;  // the reference
      } else {
        EXPECT_GT(std::stod(c[8]), 0.0) << line;
      }
      // Weak scaling: 64 x 64 cells per rank, blocks of whole rows.
      if (c[0] == "weak") {
        EXPECT_EQ(std::stoi(c[3]), 64) << line;
        EXPECT_EQ(std::stoi(c[4]), ranks * 64) << line;
      }
    }
    EXPECT_EQ(rows, 4);
  }
};

TEST_F(BenchScaleTest, OneAndTwoRanksStrongAndWeak) {
  const BinaryRunResult r = run_bench("--size 96 --weak 64 --frames 2 --ranks 2 --out res");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.out.find("table1-ard (blocked schedule) over Open MPI ranks"), 0u) << r.out;
  expect_scale_rows(r, work() / "res");
}

TEST_F(BenchScaleTest, Seed001AsBlocks) {
  const BinaryRunResult r =
      run_bench("--scene seed001 --size 96 --weak 64 --frames 2 --ranks 2 --out seed");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.out.find("seed001 over Open MPI ranks"), 0u) << r.out;
  expect_scale_rows(r, work() / "seed");
}

TEST_F(BenchScaleTest, BadRanksExitTwo) {
  const BinaryRunResult r = run_bench("--ranks 0,x --out res");
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.err,
            "ardcell bench scale: --ranks '0,x': expected rank counts 1..256, comma-separated\n");
}

// A scene with a fluid runs as blocks too (its fluid on the gathered grid).
TEST_F(BenchScaleTest, AFluidSceneAsBlocks) {
  const BinaryRunResult r =
      run_bench("--scene cavity-gray-scott --size 96 --weak 64 --frames 2 --ranks 2 --out fluid");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.out.find("cavity-gray-scott over Open MPI ranks"), 0u) << r.out;
  expect_scale_rows(r, work() / "fluid");
}

// On its real-time settings an implicit RD scene's blocks sweep their own cells: a frame sends
// the sweeps' one-cell halos, a small part of what the gathered solves of the preset as it ships
// send (the whole grid to every rank, 2 fields a solve).
TEST_F(BenchScaleTest, RealtimeSolversSendHalosNotTheGrid) {
  const auto strong_halo_bytes = [&](const std::string& flags, const std::string& out) {
    const BinaryRunResult r = run_bench(
        "--scene space-cookie-5 --size 96 --weak 64 --frames 2 --ranks 2 --out " + out + flags);
    EXPECT_EQ(r.code, 0) << r.err;
    expect_scale_rows(r, work() / out);
    std::stringstream lines(slurp(work() / out / "scale.csv"));
    std::string line;
    while (std::getline(lines, line)) {
      const std::vector<std::string> c = csv_cells(line);
      if (c.size() == 10 && c[0] == "strong" && c[1] == "2") return std::stod(c[8]);
    }
    ADD_FAILURE() << "no strong 2-rank row in " << out;
    return 0.0;
  };
  const double sweeps = strong_halo_bytes(" --realtime-solvers", "realtime");
  const double gathers = strong_halo_bytes("", "shipped");
  EXPECT_GT(sweeps, 0.0);
  EXPECT_LT(sweeps * 4, gathers) << sweeps << " bytes a frame against " << gathers;
  EXPECT_NE(slurp(work() / "realtime" / "scale.md").find("on its real-time settings"),
            std::string::npos);
}

TEST_F(BenchScaleTest, AnUnknownSceneExitsTwo) {
  const BinaryRunResult r = run_bench("--scene cavityy --out res");
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.err,
            "ardcell bench scale: --scene cavityy: not a built-in scene (expected one such as "
            "table1-ard, seed001 or cavity-gray-scott)\n");
}

}  // namespace
}  // namespace ardcell
