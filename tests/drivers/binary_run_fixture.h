#pragma once
// A test fixture that runs the real `ardcell` binary (ARDCELL_BINARY) in a fresh working folder
// per test, capturing its exit code, stdout and stderr. Every CLI test uses it.
// limit_memory(MiB) bounds the memory of the runs that follow: RLIMIT_AS (`ulimit -v`), or in a
// sanitizer build, whose shadow memory reserves terabytes of address space, ASan's own limits
// (resident memory, largest allocation); a run that goes beyond them fails, or ASan aborts it.
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

// An empty folder for the running test: PREFIX_<pid>_<suite>_<test> in the temp directory.
inline std::filesystem::path fresh_test_dir(const std::string& prefix) {
  const ::testing::TestInfo* test = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / (prefix + "_" + std::to_string(::getpid()) + "_" +
                                                test->test_suite_name() + "_" + test->name());
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

class BinaryRunTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fresh_test_dir("ardcell_binary_run");
    std::filesystem::create_directories(dir_ / "work");
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  static std::string slurp(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
  }
  void limit_memory(int mib) {
#if defined(__SANITIZE_ADDRESS__)
    limits_ = "ASAN_OPTIONS=\"${ASAN_OPTIONS:-}:hard_rss_limit_mb=" + std::to_string(mib) +
              ":max_allocation_size_mb=" + std::to_string(mib) + "\" ";
#else
    limits_ = "ulimit -v " + std::to_string(mib * 1024) + " && ";
#endif
  }
  // Runs `ardcell <args>` in work() (args are shell words).
  BinaryRunResult run(const std::string& args) {
    return run_command("exec '" ARDCELL_BINARY "' " + args);
  }
  // Runs `command` (shell words) in work(), its output captured.
  BinaryRunResult run_command(const std::string& command) {
    const std::string cmd = "cd '" + work().string() + "' && " + limits_ + command + " >'" +
                            (dir_ / "stdout").string() + "' 2>'" + (dir_ / "stderr").string() +
                            "' </dev/null";
    const int status = std::system(cmd.c_str());
    BinaryRunResult r;
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    r.out = slurp(dir_ / "stdout");
    r.err = slurp(dir_ / "stderr");
    return r;
  }
  std::filesystem::path work() const { return dir_ / "work"; }
  // The environment an Open MPI job of the tests runs in (shell words, before `exec mpirun`):
  // root allowed (CI runs as root); no single-copy mechanism (containers forbid the ptrace it
  // needs). In sanitizer builds, LeakSanitizer's check at exit costs every rank seconds beside
  // Open MPI (a 2-rank run: 6.6 s with it, 0.9 s without; a 2-screen wall: 20 s and 5 s), so a
  // job runs without it unless it `checks_leaks`, as one job of `run --ranks` and one of `live
  // --wall` do (`bench scale` runs the same rank code as `run --ranks`). Those run
  // with the slow unwinder, since Open MPI unloads its plugins at MPI_Finalize: a leak one left
  // has no module at exit, but the libmpi frames beneath it, which scripts/lsan.supp names, are
  // kept.
  static std::string mpi_env(bool checks_leaks = false) {
    return std::string(
               "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 "
               "OMPI_MCA_btl_vader_single_copy_mechanism=none ASAN_OPTIONS=\"${ASAN_OPTIONS:-}:") +
           (checks_leaks ? "fast_unwind_on_malloc=0" : "detect_leaks=0") + "\" ";
  }

 private:
  std::filesystem::path dir_;
  std::string limits_;  // put before the command: limit_memory()
};

}  // namespace ardcell
