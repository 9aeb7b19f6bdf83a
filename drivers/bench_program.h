#pragma once
// What the `ardcell bench` subcommands share: finding a benchmark program built beside the
// ardcell binary, running it with a Google Benchmark filter and a JSON report, reading that
// report back, and writing result files atomically.
#include <filesystem>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "host/config/status.h"

namespace ardcell {

// `name` in the folder of the running ardcell binary (or the bare name when that is unknown).
std::filesystem::path bench_binary_beside_ardcell(const char* name);

// Runs `binary` with --benchmark_filter=filter, --benchmark_min_time=min_time,
// --benchmark_repetitions=repetitions and a JSON report to json_path, with `env` set, through
// `launcher` when given (mpirun and its arguments; looked up in PATH); its console output goes to
// stderr. Returns its exit status, or -1 when it could not be run.
int run_bench_program(const std::string& binary, const std::string& filter, double min_time,
                      int repetitions, const std::string& json_path,
                      const std::vector<std::pair<std::string, std::string>>& env,
                      const std::vector<std::string>& launcher = {});

// One benchmark of a report: its name without the /min_time and /real_time suffixes (and the
// aggregate's), and its numeric counters (fps, cells_per_s, ...). With repetitions, each
// repetition is a row and so is each aggregate over them, named by `aggregate` ("mean",
// "median", "stddev", "cv"; empty for a repetition).
struct BenchRow {
  std::string name;
  std::map<std::string, double> counters;
  std::string aggregate;
};

// Reads a Google Benchmark JSON report. Rows that reported an error are left out, the first
// error kept in *skipped.
Status read_bench_rows(const std::string& json_path, std::vector<BenchRow>& rows,
                       std::string* skipped);

// The non-empty items of a comma-separated list.
std::vector<std::string> split_commas(const std::string& s);

// Writes `text` to path through a temporary file renamed into place.
Status write_text_atomically(const std::filesystem::path& path, const std::string& text);

}  // namespace ardcell
