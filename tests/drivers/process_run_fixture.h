#pragma once
// A test fixture that starts the real `ardcell` binary (ARDCELL_BINARY) as a child process in a
// fresh folder, for tests that act on it while it runs (signals, OSC, its memory): start,
// wait for a line of its output, wait for its exit, read its files. BinaryRunTest
// (binary_run_fixture.h) is for runs that only need the exit code and output.
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

#include "tests/drivers/binary_run_fixture.h"

namespace ardcell {

class ProcessRunTest : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = fresh_test_dir("ardcell_process"); }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  // Starts `ardcell args...` in dir_ (stdout, stderr to files); `ignore_sigint` as a shell's `&`;
  // `env`: NAME=VALUE entries added to its environment.
  pid_t start(const std::vector<std::string>& args, bool ignore_sigint = false,
              const std::vector<std::string>& env = {}) {
    const pid_t pid = ::fork();
    if (pid == 0) {
      if (::chdir(dir_.c_str()) != 0) _exit(127);
      const int out = ::open("stdout", O_WRONLY | O_CREAT | O_TRUNC, 0644);
      const int err = ::open("stderr", O_WRONLY | O_CREAT | O_TRUNC, 0644);
      ::dup2(out, 1);
      ::dup2(err, 2);
      std::signal(SIGINT, ignore_sigint ? SIG_IGN : SIG_DFL);
      for (const std::string& e : env) ::putenv(const_cast<char*>(e.c_str()));
      std::vector<char*> argv{const_cast<char*>(ARDCELL_BINARY)};
      for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
      argv.push_back(nullptr);
      ::execv(ARDCELL_BINARY, argv.data());
      _exit(127);
    }
    return pid;
  }
  // Waits for `pid` (at most `seconds`, then kills it and returns -1): its exit code, or 128 +
  // the signal that killed it.
  static int wait_for(pid_t pid, double seconds = 120) {
    for (int i = 0; i < int(seconds * 100); ++i) {
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
    for (const auto& e : std::filesystem::recursive_directory_iterator(dir_))
      if (e.path().filename().string().find(".tmp") != std::string::npos)
        out.push_back(e.path().string());
    return out;
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
  // Its resident memory (/proc/PID/status VmRSS) in KiB; -1 when it cannot be read.
  static long rss_kib(pid_t pid) {
    std::ifstream in("/proc/" + std::to_string(pid) + "/status");
    std::string line;
    while (std::getline(in, line))
      if (line.rfind("VmRSS:", 0) == 0) return std::stol(line.substr(6));
    return -1;
  }
  const std::filesystem::path& dir() const { return dir_; }

 private:
  std::filesystem::path dir_;
};

}  // namespace ardcell
