#include "drivers/bench_program.h"

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "host/io/atomic_file.h"

namespace ardcell {

namespace fs = std::filesystem;

fs::path bench_binary_beside_ardcell(const char* name) {
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  return ec ? fs::path(name) : self.parent_path() / name;
}

int run_bench_program(const std::string& binary, const std::string& filter, double min_time,
                      int repetitions, const std::string& json_path,
                      const std::vector<std::pair<std::string, std::string>>& env,
                      const std::vector<std::string>& launcher) {
  std::vector<std::string> args = launcher;
  for (std::string a :
       {binary, "--benchmark_filter=" + filter, "--benchmark_min_time=" + std::to_string(min_time),
        "--benchmark_repetitions=" + std::to_string(repetitions), "--benchmark_out=" + json_path,
        std::string("--benchmark_out_format=json")})
    args.push_back(std::move(a));
  const pid_t pid = fork();
  if (pid < 0) return -1;
  if (pid == 0) {
    for (const auto& [name, value] : env) setenv(name.c_str(), value.c_str(), 1);
    dup2(STDERR_FILENO, STDOUT_FILENO);
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    execvp(argv[0], argv.data());
    std::fprintf(stderr, "ardcell bench: cannot run %s\n", argv[0]);
    _exit(127);
  }
  int status = 0;
  if (waitpid(pid, &status, 0) < 0) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

Status read_bench_rows(const std::string& json_path, std::vector<BenchRow>& rows,
                       std::string* skipped) {
  try {
    std::ifstream in(json_path);
    const nlohmann::json j = nlohmann::json::parse(in);
    for (const auto& b : j.at("benchmarks")) {
      std::string name = b.at("name").get<std::string>();
      if (b.value("error_occurred", false)) {
        if (skipped && skipped->empty())
          *skipped = name + ": " + b.value("error_message", std::string("error"));
        continue;
      }
      BenchRow row;
      if (b.value("run_type", std::string()) == "aggregate")
        row.aggregate = b.value("aggregate_name", std::string());
      if (!row.aggregate.empty() && name.ends_with("_" + row.aggregate))
        name.resize(name.size() - row.aggregate.size() - 1);
      for (const char* suffix : {"/min_time", "/real_time"})
        if (const auto cut = name.find(suffix); cut != std::string::npos) name.resize(cut);
      row.name = std::move(name);
      for (const auto& [key, value] : b.items())
        if (value.is_number()) row.counters[key] = value.get<double>();
      rows.push_back(std::move(row));
    }
  } catch (const std::exception& e) {
    return Status::error("cannot read " + json_path + ": " + e.what());
  }
  return Status::ok();
}

std::vector<std::string> split_commas(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream in(s);
  std::string item;
  while (std::getline(in, item, ','))
    if (!item.empty()) out.push_back(item);
  return out;
}

Status write_text_atomically(const fs::path& path, const std::string& text) {
  AtomicFile f;
  Status st = f.open(path);
  if (!st) return st;
  if (!f.write(text.data(), text.size())) return Status::error("cannot write " + path.string());
  return f.commit();
}

}  // namespace ardcell
