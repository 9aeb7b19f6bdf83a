// SIGINT, SIGTERM and SIGHUP sent to a real `ardcell run` / `ardcell live` end it the way Esc
// does: the state or recording is finished and renamed into place, the summary printed, no
// temporary file left; a second signal while finishing changes nothing; an inherited ignored
// SIGINT (a script's `&`) does not make the process deaf to it.
#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

namespace ardcell {
namespace {

namespace fs = std::filesystem;

class SignalsCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("ardcell_signals_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Starts `ardcell args...` in dir_ (stdout, stderr to files); `ignore_sigint` as a shell's `&`.
  pid_t start(const std::vector<std::string>& args, bool ignore_sigint = false) {
    const pid_t pid = ::fork();
    if (pid == 0) {
      if (::chdir(dir_.c_str()) != 0) _exit(127);
      const int out = ::open("stdout", O_WRONLY | O_CREAT | O_TRUNC, 0644);
      const int err = ::open("stderr", O_WRONLY | O_CREAT | O_TRUNC, 0644);
      ::dup2(out, 1);
      ::dup2(err, 2);
      std::signal(SIGINT, ignore_sigint ? SIG_IGN : SIG_DFL);
      std::vector<char*> argv{const_cast<char*>(ARDCELL_BINARY)};
      for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
      argv.push_back(nullptr);
      ::execv(ARDCELL_BINARY, argv.data());
      _exit(127);
    }
    return pid;
  }
  // Waits for `pid` (at most 120 s): its exit code, or 128 + the signal that killed it.
  static int wait_for(pid_t pid) {
    for (int i = 0; i < 12000; ++i) {
      int status = 0;
      if (::waitpid(pid, &status, WNOHANG) == pid)
        return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    ::kill(pid, SIGKILL);
    ::waitpid(pid, nullptr, 0);
    return -1;
  }
  // Waits until `file` holds `text` (the run or loop is under way).
  bool wait_for_text(const std::string& file, const std::string& text, double seconds = 60) {
    for (int i = 0; i < int(seconds * 100); ++i) {
      if (read(file).find(text) != std::string::npos) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return false;
  }
  std::string read(const std::string& name) const {
    std::ifstream in(dir_ / name, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
  }
  // Names in dir_ that look like temporary files (".NAME.tmp-PID-N").
  std::vector<std::string> temporaries() const {
    std::vector<std::string> out;
    for (const auto& e : fs::recursive_directory_iterator(dir_))
      if (e.path().filename().string().find(".tmp") != std::string::npos)
        out.push_back(e.path().string());
    return out;
  }
  // A run long enough to be interrupted; its state goes to st.
  std::vector<std::string> long_run(const std::string& size) const {
    return {"run",     "cavity", "--size",       size, "--steps", "100000000",
            "--every", "0",      "--save-state", "st", "--quiet"};
  }
  // Waits until `pid` catches SIGHUP (/proc/PID/status SigCgt): its stop handlers are in.
  static bool catching_stop_signals(pid_t pid, double seconds = 60) {
    for (int i = 0; i < int(seconds * 100); ++i) {
      std::ifstream in("/proc/" + std::to_string(pid) + "/status");
      std::string line;
      while (std::getline(in, line))
        if (line.rfind("SigCgt:", 0) == 0 &&
            (std::stoull(line.substr(7), nullptr, 16) >> (SIGHUP - 1)) & 1)
          return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return false;
  }
  void started(pid_t pid) {
    ASSERT_TRUE(catching_stop_signals(pid)) << read("stderr");
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
  }
  fs::path dir_;
};

TEST_F(SignalsCli, EachStopSignalFinishesTheRunAndSavesTheState) {
  for (const int sig : {SIGINT, SIGTERM, SIGHUP}) {
    fs::remove_all(dir_ / "st");
    const pid_t pid = start(long_run("64"));
    started(pid);
    ASSERT_EQ(::kill(pid, sig), 0);
    EXPECT_EQ(wait_for(pid), 128 + sig) << strsignal(sig) << "\n" << read("stderr");
    EXPECT_TRUE(fs::exists(dir_ / "st" / "meta.json")) << strsignal(sig);
    EXPECT_TRUE(fs::exists(dir_ / "st" / "u.npy")) << strsignal(sig);
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
  EXPECT_TRUE(fs::exists(dir_ / "st" / "meta.json"));
  EXPECT_TRUE(temporaries().empty()) << temporaries().front();
}

TEST_F(SignalsCli, AnInheritedIgnoredSigintStillStopsRun) {
  const pid_t pid = start(long_run("64"), /*ignore_sigint=*/true);
  started(pid);
  ASSERT_EQ(::kill(pid, SIGINT), 0);
  EXPECT_EQ(wait_for(pid), 130) << read("stderr");
  EXPECT_TRUE(fs::exists(dir_ / "st" / "meta.json"));
}

TEST_F(SignalsCli, LiveFinishesTheRecordingOnSigintAndSigterm) {
  if (!std::getenv("DISPLAY") && !std::getenv("WAYLAND_DISPLAY"))
    GTEST_SKIP() << "no X or Wayland display";
  for (const int sig : {SIGINT, SIGTERM}) {
    fs::remove(dir_ / "rec.y4m");
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
    ASSERT_TRUE(fs::exists(dir_ / "rec.y4m"));
    EXPECT_EQ(read("rec.y4m").rfind("YUV4MPEG2", 0), 0u);
    EXPECT_GT(fs::file_size(dir_ / "rec.y4m"), 1000u);
    EXPECT_TRUE(temporaries().empty()) << temporaries().front();
  }
}

}  // namespace
}  // namespace ardcell
