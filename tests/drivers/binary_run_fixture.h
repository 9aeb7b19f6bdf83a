#pragma once
// A test fixture that runs the real `ardcell` binary (ARDCELL_BINARY) in a fresh working folder
// per test, capturing its exit code, stdout and stderr. Every CLI test uses it.
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace ardcell {

struct BinaryRunResult {
  int code = -1;
  std::string out, err;
};

inline int count_lines(const std::string& s) { return int(std::count(s.begin(), s.end(), '\n')); }

class BinaryRunTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("ardcell_binary_run_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->test_suite_name() + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_ / "work");
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  static std::string slurp(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
  }
  // Runs `ardcell <args>` in work() (args are shell words).
  BinaryRunResult run(const std::string& args) {
    const std::string cmd = "cd '" + work().string() + "' && exec '" ARDCELL_BINARY "' " + args +
                            " >'" + (dir_ / "stdout").string() + "' 2>'" +
                            (dir_ / "stderr").string() + "' </dev/null";
    const int status = std::system(cmd.c_str());
    BinaryRunResult r;
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    r.out = slurp(dir_ / "stdout");
    r.err = slurp(dir_ / "stderr");
    return r;
  }
  std::filesystem::path work() const { return dir_ / "work"; }

 private:
  std::filesystem::path dir_;
};

}  // namespace ardcell
