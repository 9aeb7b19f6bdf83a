// SIGINT, SIGTERM and SIGHUP sent to a real `ardcell run` / `ardcell live` end it the way Esc
// does: the state or recording is finished and renamed into place, the summary printed, no
// temporary file left; a second signal while finishing changes nothing; an inherited ignored
// SIGINT (a script's `&`) does not make the process deaf to it.
#include <csignal>
#include <cstring>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "drivers/hid_recorder.h"
#include "tests/drivers/process_run_fixture.h"

namespace ardcell {
namespace {

namespace fs = std::filesystem;

class SignalsCli : public ProcessRunTest {
 protected:
  // A run long enough to be interrupted; its state goes to st. On the threads back end: an
  // OpenCL runtime (PoCL) catches SIGHUP and SIGINT itself while `auto` probes it, which
  // started() would take for the stop handlers.
  std::vector<std::string> long_run(const std::string& size) const {
    return {"run", "cavity",       "--size", size,      "--steps",   "100000000", "--every",
            "0",   "--save-state", "st",     "--quiet", "--backend", "threads"};
  }
};

TEST_F(SignalsCli, EachStopSignalFinishesTheRunAndSavesTheState) {
  for (const int sig : {SIGINT, SIGTERM, SIGHUP}) {
    fs::remove_all(dir() / "st");
    const pid_t pid = start(long_run("64"));
    started(pid);
    ASSERT_EQ(::kill(pid, sig), 0);
    EXPECT_EQ(wait_for(pid), 128 + sig) << strsignal(sig) << "\n" << read("stderr");
    EXPECT_TRUE(fs::exists(dir() / "st" / "meta.json")) << strsignal(sig);
    EXPECT_TRUE(fs::exists(dir() / "st" / "u.npy")) << strsignal(sig);
    EXPECT_NE(read("stdout").find("frames="), std::string::npos) << read("stdout");
    EXPECT_NE(read("stderr").find("interrupted after"), std::string::npos) << read("stderr");
    EXPECT_TRUE(temporaries().empty()) << temporaries().front();
  }
}

TEST_F(SignalsCli, ASecondSignalWhileSavingLeavesTheStateWholeAndNoTemporaries) {
  const pid_t pid = start(long_run("1024"));
  started(pid);
  ASSERT_EQ(::kill(pid, SIGINT), 0);
  for (int i = 0; i < 20; ++i) {  // through the saving (about a second at 1024^2)
    std::this_thread::sleep_for(std::chrono::milliseconds(25));
    ::kill(pid, i % 2 ? SIGTERM : SIGINT);
  }
  EXPECT_EQ(wait_for(pid), 130) << read("stderr");
  EXPECT_TRUE(fs::exists(dir() / "st" / "meta.json")) << read("stderr") << read("stdout");
  EXPECT_TRUE(temporaries().empty()) << temporaries().front();
}

TEST_F(SignalsCli, AnInheritedIgnoredSigintStillStopsRun) {
  const pid_t pid = start(long_run("64"), /*ignore_sigint=*/true);
  started(pid);
  ASSERT_EQ(::kill(pid, SIGINT), 0);
  EXPECT_EQ(wait_for(pid), 130) << read("stderr");
  EXPECT_TRUE(fs::exists(dir() / "st" / "meta.json"));
}

TEST_F(SignalsCli, LiveFinishesTheRecordingOnSigintAndSigterm) {
  if (!std::getenv("DISPLAY") && !std::getenv("WAYLAND_DISPLAY"))
    GTEST_SKIP() << "no X or Wayland display";
  for (const int sig : {SIGINT, SIGTERM}) {
    fs::remove(dir() / "rec.y4m");
    // Started as from a script with `&`: SIGINT arrives ignored.
    const pid_t pid = start({"live", "cavity", "--no-vsync", "--fps", "30", "--record", "rec.y4m",
                             "--backend", "serial"},
                            /*ignore_sigint=*/true);
    started(pid);
    ASSERT_TRUE(wait_for_text("stderr", "recording to")) << read("stderr");
    std::this_thread::sleep_for(std::chrono::milliseconds(1000));
    ASSERT_EQ(::kill(pid, sig), 0);
    EXPECT_EQ(wait_for(pid), 128 + sig) << read("stderr");
    EXPECT_NE(read("stderr").find("recorded rec.y4m"), std::string::npos) << read("stderr");
    EXPECT_NE(read("stderr").find("deadline misses"), std::string::npos) << read("stderr");
    ASSERT_TRUE(fs::exists(dir() / "rec.y4m"));
    EXPECT_EQ(read("rec.y4m").rfind("YUV4MPEG2", 0), 0u);
    EXPECT_GT(fs::file_size(dir() / "rec.y4m"), 1000u);
    EXPECT_TRUE(temporaries().empty()) << temporaries().front();
  }
}

// `tablet record` reads a real tablet (hidraw through hidapi; there is no simulated device to
// record from), so this runs only with one: ARDCELL_TEST_TABLET=/dev/hidrawN. Without it, what
// the recording's end relies on is tested elsewhere: the stop handlers (the run and live tests
// above, the same StopSignals) and the atomic write (hid_recorder_test).
TEST_F(SignalsCli, TabletRecordFinishesTheFileOnEachStopSignal) {
  const char* device = std::getenv("ARDCELL_TEST_TABLET");
  if (!device) GTEST_SKIP() << "no tablet: set ARDCELL_TEST_TABLET=/dev/hidrawN to run it";
  for (const int sig : {SIGINT, SIGTERM, SIGHUP}) {
    fs::remove(dir() / "pen.hid.txt");
    const pid_t pid = start({"tablet", "record", "pen.hid.txt", "--device", device});
    started(pid);
    ASSERT_TRUE(wait_for_text("stderr", "recording ")) << read("stderr");
    ASSERT_EQ(::kill(pid, sig), 0);
    EXPECT_EQ(wait_for(pid), 128 + sig) << strsignal(sig) << "\n" << read("stderr");
    EXPECT_NE(read("stdout").find("wrote pen.hid.txt"), std::string::npos) << read("stdout");
    HidRecording rec;
    std::string error;
    EXPECT_TRUE(read_hid_recording((dir() / "pen.hid.txt").string(), rec, error)) << error;
    EXPECT_FALSE(rec.descriptor.empty());
    EXPECT_TRUE(temporaries().empty()) << temporaries().front();
  }
}

}  // namespace
}  // namespace ardcell
