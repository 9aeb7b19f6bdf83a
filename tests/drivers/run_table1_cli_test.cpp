// `ardcell run table1 | table1-ard` through the real binary (ARDCELL_BINARY): the Table 1
// scenes, which the Engine builds as a frame plan, with --schedule, --backend, --cl-device,
// --workers and --stats.
//   - blocked with --stats prints the summary, the frame times and one timing line per pass;
//   - serial, stream and blocked save bitwise-identical dye, A and B (.npy bytes);
//   - --backend opencl (PoCL) agrees with serial within 1e-5 relative in the max norm
//     (max |cl - serial| / max |serial| over the interior, per field);
//   - --cl-device 99 prints the fallback line and still runs (on threads);
//   - a saved state resumes bit for bit; --dt reaches the plan;
//   - bad --schedule / --backend / settings the plan cannot run exit 2 with one line; general
//   scenes refuse --schedule with
//     one line (their --backend opencl: tests/drivers/run_opencl_cli_test.cpp);
//   - general scenes on --backend serial and threads (--workers 2, 3) save the same bytes.
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "host/io/npy.h"
#include "tests/drivers/binary_run_fixture.h"

namespace ardcell {
namespace {

namespace fs = std::filesystem;

using Result = BinaryRunResult;
using RunTable1Test = BinaryRunTest;

constexpr const char* kSmall = "run table1-ard --size 48 --steps 5 --quiet ";

TEST_F(RunTable1Test, BlockedWithStatsPrintsPassTimingsAndFrames) {
  const Result r = run(std::string(kSmall) + "--schedule blocked --backend threads --stats " +
                       "--workers 2 --every 5 --out frames");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("frames=5 "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("backend=threads workers=2 schedule=blocked local_store="),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("frame ms: mean="), std::string::npos) << r.out;
  // The plan's passes: at least the sources pass and a projection, each with a ms figure.
  EXPECT_GE(count_lines(r.out), 5) << r.out;
  EXPECT_NE(r.out.find("ms"), std::string::npos);
  ASSERT_TRUE(fs::is_directory(work() / "frames"));
  EXPECT_TRUE(
      std::any_of(fs::directory_iterator(work() / "frames"), fs::directory_iterator(),
                  [](const fs::directory_entry& e) { return e.path().extension() == ".png"; }))
      << "no PNG frame written";
}

TEST_F(RunTable1Test, SchedulesSaveBitwiseIdenticalFields) {
  for (const char* schedule : {"serial", "stream", "blocked"}) {
    const Result r = run(std::string(kSmall) + "--every 0 --schedule " + schedule +
                         " --backend threads --save-state " + schedule);
    ASSERT_EQ(r.code, 0) << schedule << ": " << r.err;
  }
  for (const char* field : {"dye.npy", "A.npy", "B.npy", "u.npy", "v.npy"}) {
    const std::string serial = slurp(work() / "serial" / field);
    ASSERT_GT(serial.size(), 48u * 48u * 4u) << field;
    EXPECT_EQ(serial, slurp(work() / "stream" / field)) << field << " stream vs serial";
    EXPECT_EQ(serial, slurp(work() / "blocked" / field)) << field << " blocked vs serial";
  }
  // The fields moved: the dye is not all zero after 5 frames of splats.
  NpyArray dye;
  ASSERT_TRUE(read_npy(work() / "serial" / "dye.npy", dye));
  EXPECT_GT(*std::max_element(dye.data.begin(), dye.data.end()), 0.0f);
}

double relative_max_error(const NpyArray& got, const NpyArray& ref) {
  double diff = 0, mag = 0;
  for (std::size_t i = 0; i < ref.data.size(); ++i) {
    diff = std::max(diff, std::abs(double(got.data[i]) - double(ref.data[i])));
    mag = std::max(mag, std::abs(double(ref.data[i])));
  }
  return diff / std::max(mag, 1e-30);
}

TEST_F(RunTable1Test, OpenClAgreesWithSerial) {
#if !defined(ARDCELL_WITH_OPENCL)
  GTEST_SKIP() << "built without OpenCL";
#else
  ASSERT_EQ(run(std::string(kSmall) + "--every 0 --schedule serial --save-state serial").code, 0);
  for (const char* schedule : {"stream", "blocked"}) {
    const std::string dir = std::string("cl-") + schedule;
    const Result r = run(std::string(kSmall) + "--every 0 --backend opencl --stats --schedule " +
                         schedule + " --save-state " + dir);
    ASSERT_EQ(r.code, 0) << r.err;
    ASSERT_EQ(r.err.find("falling back"), std::string::npos) << "no OpenCL device: " << r.err;
    EXPECT_NE(r.out.find("backend=opencl"), std::string::npos) << r.out;
    for (const char* field : {"u.npy", "v.npy", "dye.npy", "A.npy", "B.npy"}) {
      NpyArray got, ref;
      ASSERT_TRUE(read_npy(work() / dir / field, got)) << field;
      ASSERT_TRUE(read_npy(work() / "serial" / field, ref)) << field;
      ASSERT_EQ(got.data.size(), ref.data.size());
      EXPECT_LE(relative_max_error(got, ref), 1e-5) << schedule << " " << field;
    }
  }
#endif
}

TEST_F(RunTable1Test, InvalidClDeviceFallsBackToThreads) {
  const Result r = run(std::string(kSmall) + "--every 0 --backend opencl --cl-device 99 --stats");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("falling back to the threads back end"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("backend=threads"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("frames=5 "), std::string::npos) << r.out;
}

TEST_F(RunTable1Test, BadFlagsExitTwoWithOneLine) {
  const std::vector<std::string> cases = {
      std::string(kSmall) + "--schedule bogus",
      std::string(kSmall) + "--backend bogus",
      std::string(kSmall) + "--backend serial --schedule blocked",
      std::string(kSmall) + "--backend opencl --schedule serial",
      std::string(kSmall) + "--workers 0",
      std::string(kSmall) + "--solver mg",
      std::string(kSmall) + "--set rd.reaction.model=fhn",
      std::string(kSmall) + "--set fluid.viscosity_solver.iterations=7",
      std::string(kSmall) + "--show pressure",
      std::string("run table1 --size 48 --show A"),
      std::string("run cavity --size 16 --steps 1 --schedule blocked"),
      std::string("run cavity --size 16 --steps 1 --backend opencl --schedule stream"),
      std::string("run cavity --size 16 --steps 1 --schedule bogus"),
      std::string("run cavity --size 16 --steps 1 --workers 0"),
      std::string(kSmall) + "--store-kib 100",
      std::string(kSmall) + "--store-kib 16",  // no blocked tile fits 8 KiB a slot
      std::string(kSmall) + "--store-kib big",
      std::string("run cavity --size 16 --steps 1 --store-kib spe"),
      std::string("run cavity --size 16 --steps 1 --backend serial --workers 2")};
  for (const std::string& args : cases) {
    const Result r = run(args);
    EXPECT_EQ(r.code, 2) << args << "\n" << r.err;
    EXPECT_EQ(count_lines(r.err), 1) << args << "\n" << r.err;
    EXPECT_EQ(r.out, "") << args;
    EXPECT_TRUE(fs::is_empty(work())) << args << ": left files behind";
  }
}

// The Table 1 scenes are scenes like any other: a saved state resumes bit for bit (the splats
// turn with the saved frame number), and the scene's dt reaches the plan.
TEST_F(RunTable1Test, SavedStatesResumeAndTheScenesParametersApply) {
  const std::string base = "run table1-ard --size 40x36 --quiet --every 0 --backend threads ";
  ASSERT_EQ(run(base + "--steps 10 --save-state ten").code, 0);
  ASSERT_EQ(run(base + "--steps 5 --save-state five").code, 0);
  const Result resumed = run(base + "--steps 5 --load-state five --save-state resumed");
  ASSERT_EQ(resumed.code, 0) << resumed.err;
  for (const char* field : {"u.npy", "v.npy", "dye.npy", "A.npy", "B.npy"})
    EXPECT_EQ(slurp(work() / "ten" / field), slurp(work() / "resumed" / field)) << field;
  ASSERT_EQ(run(base + "--steps 10 --dt 0.05 --save-state half-dt").code, 0);
  EXPECT_NE(slurp(work() / "ten" / "u.npy"), slurp(work() / "half-dt" / "u.npy"));
  // --sweeps sets every solve's, the RD's too (the plan runs one count).
  const Result sweeps = run(base + "--steps 10 --sweeps 9 --save-state nine");
  ASSERT_EQ(sweeps.code, 0) << sweeps.err;
  EXPECT_NE(slurp(work() / "ten" / "B.npy"), slurp(work() / "nine" / "B.npy"));
}

TEST_F(RunTable1Test, GeneralSceneStatsPrintFrameTimes) {
  const Result r = run("run cavity --size 16 --steps 20 --every 0 --stats --backend threads");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("frame ms: mean="), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("(20 frames)"), std::string::npos) << r.out;
}

TEST_F(RunTable1Test, StoreKibSpeRunsTheCellSizedLocalStore) {
  const Result r = run(std::string(kSmall) + "--schedule stream --backend threads --stats " +
                       "--store-kib spe --every 0");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("local_store=256KiB"), std::string::npos) << r.out;
}

TEST_F(RunTable1Test, GeneralSceneBackendsSaveTheSameBytes) {
  // A scene with fluid, dye mass fix and RD: every kind of stage and reduction.
  const std::string base = "run obstacle-ard-gray-scott --size 96x120 --steps 12 --every 0 ";
  const Result serial = run(base + "--backend serial --stats --save-state serial");
  ASSERT_EQ(serial.code, 0) << serial.err;
  EXPECT_NE(serial.out.find("backend=serial workers=1"), std::string::npos) << serial.out;
  for (const char* workers : {"2", "3"}) {
    const std::string dir = std::string("threads") + workers;
    const Result r =
        run(base + "--backend threads --workers " + workers + " --stats --save-state " + dir);
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find(std::string("backend=threads workers=") + workers), std::string::npos)
        << r.out;
    for (const char* field : {"u.npy", "v.npy", "p.npy", "dye.npy", "A.npy", "B.npy"}) {
      const std::string expected = slurp(work() / "serial" / field);
      ASSERT_GT(expected.size(), 96u * 120u * 4u) << field;
      EXPECT_EQ(slurp(work() / dir / field), expected)
          << field << " with " << workers << " workers";
    }
  }
}

}  // namespace
}  // namespace ardcell
