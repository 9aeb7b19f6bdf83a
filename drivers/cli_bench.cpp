// `ardcell bench table1` (`bench scenes`: drivers/cli_bench_scenes.cpp): runs the Table 1 benchmark
// programs (bench/table1_bench.cpp for the CPU rows and bench/table1_opencl_bench.cpp for the
// opencl-* rows, built next to the ardcell binary) and reports it beside the paper's Cell figures:
// a Markdown table on stdout, and table1.md, table1.csv and table1.png (drivers/chart.h, when
// built with PLplot) in --out.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "drivers/bench_program.h"
#include "drivers/chart.h"
#include "drivers/cli.h"
#include "host/io/atomic_file.h"
#include "runtime/local_store.h"

namespace ardcell {
namespace {

namespace fs = std::filesystem;

// Seed 000, Table 1: FPS of the fluid alone and with RD on the Cell processor.
struct CellRow {
  int n;
  double fluid, ard;
};
constexpr CellRow kCell[] = {
    {128, 223, 223}, {256, 78.7, 78.5}, {512, 21.4, 21.5}, {1024, 5.5, 5.5}};

const CellRow* cell_row(int n) {
  for (const CellRow& r : kCell)
    if (r.n == n) return &r;
  return nullptr;
}

struct Result {
  double fps = 0, bytes_per_s = 0, fps_unshared = 0;
  bool present = false;
};

constexpr const char* kCpuSchedules[] = {"serial", "stream", "blocked"};
constexpr const char* kOpenClSchedules[] = {"opencl-stream", "opencl-blocked"};

bool is_opencl_schedule(const std::string& s) {
  return s == kOpenClSchedules[0] || s == kOpenClSchedules[1];
}
bool is_cpu_schedule(const std::string& s) {
  return s == kCpuSchedules[0] || s == kCpuSchedules[1] || s == kCpuSchedules[2];
}

struct BenchOptions {
  std::string sizes = "128,256,512,1024,2048";
  std::string schedules = "serial,stream,blocked,opencl-stream,opencl-blocked";
  double min_time = 0.5;
  int serial_max = 1024;
  int store_kib = int(machine_local_store_bytes() / 1024);
  std::string out = "bench-results";
  std::string binary;
  std::string opencl_binary;
  int cl_device = -1;
};

// Runs a Table 1 bench program with output to json_path; its console output goes to stderr.
int run_table1_program(const BenchOptions& o, const std::string& binary, const std::string& filter,
                       const std::string& json_path) {
  std::vector<std::pair<std::string, std::string>> env = {
      {"ARDCELL_BENCH_SIZES", o.sizes},
      {"ARDCELL_BENCH_SERIAL_MAX", std::to_string(o.serial_max)},
      {"ARDCELL_BENCH_STORE_KIB", std::to_string(o.store_kib)}};
  if (o.cl_device >= 0) env.emplace_back("ARDCELL_CL_DEVICE", std::to_string(o.cl_device));
  return run_bench_program(binary, filter, o.min_time, 1, json_path, env);
}

// Reads a Google Benchmark JSON report into results ("<schedule>/<fluid|ard>/<N>") and the
// STREAM triad; rows that reported an error are left out, the first error kept in *skipped.
Status read_bench_json(const std::string& json_path, std::map<std::string, Result>& results,
                       double& triad, std::string* skipped) {
  std::vector<BenchRow> rows;
  if (Status st = read_bench_rows(json_path, rows, skipped); !st) return st;
  for (BenchRow& row : rows) {
    const auto counter = [&](const char* key) {
      const auto it = row.counters.find(key);
      return it == row.counters.end() ? 0.0 : it->second;
    };
    if (row.name.rfind("STREAM/triad", 0) == 0) {
      triad = counter("bytes_per_s");
      continue;
    }
    if (row.name.rfind("Table1/", 0) != 0) continue;
    Result r;
    r.fps = counter("fps");
    r.bytes_per_s = counter("bytes_per_s");
    r.fps_unshared = counter("fps_if_unshared");
    r.present = true;
    results[row.name.substr(7)] = r;
  }
  return Status::ok();
}

}  // namespace

void add_bench_scenes_command(CLI::App& bench, CliContext& ctx);  // drivers/cli_bench_scenes.cpp
#if defined(ARDCELL_WITH_MPI)
void add_bench_scale_command(CLI::App& bench, CliContext& ctx);  // drivers/cli_bench_scale.cpp
#endif

void add_bench_command(CLI::App& app, CliContext& ctx) {
  auto* bench =
      app.add_subcommand("bench", "Benchmarks (Table 1 of the paper; every preset on the engine)");
  bench->require_subcommand(1);
  add_bench_scenes_command(*bench, ctx);
#if defined(ARDCELL_WITH_MPI)
  add_bench_scale_command(*bench, ctx);
#endif
  auto* t1 = bench->add_subcommand(
      "table1", "Fluid and fluid+RD FPS per size and schedule beside the Cell's (seed 000)");
  auto o = std::make_shared<BenchOptions>();
  t1->add_option("--sizes", o->sizes, "Grid sizes N, comma-separated")->capture_default_str();
  t1->add_option("--schedules", o->schedules,
                 "serial,stream,blocked,opencl-stream,opencl-blocked (any subset; the OpenCL "
                 "rows come from table1_opencl_bench)")
      ->capture_default_str();
  t1->add_option("--min-time", o->min_time, "Seconds per benchmark (at least)")
      ->capture_default_str();
  t1->add_option("--serial-max", o->serial_max, "Largest N run on the serial schedule")
      ->capture_default_str();
  t1->add_option("--store-kib", o->store_kib,
                 "Local store per worker of the stream and blocked schedules, KiB (default: one "
                 "L2 of this machine per double-buffer slot; 256 is the Cell's)")
      ->capture_default_str();
  t1->add_option("--out", o->out, "Folder for table1.md, table1.csv, table1.png")
      ->capture_default_str();
  t1->add_option("--bench-binary", o->binary, "The table1_bench program (default: beside ardcell)");
  t1->add_option("--opencl-bench-binary", o->opencl_binary,
                 "The table1_opencl_bench program (default: beside ardcell)");
  auto* cl_device_opt = t1->add_option("--cl-device", o->cl_device,
                                       "OpenCL device of the opencl rows (ardcell devices)");
  t1->callback([o, &ctx, cl_device_opt, t1] {
    const std::string cmd = "bench table1";
    std::vector<int> sizes;
    for (const std::string& s : split_commas(o->sizes)) {
      char* end = nullptr;
      const long n = std::strtol(s.c_str(), &end, 10);
      if (*end != '\0' || n < 8 || n > 8192) {
        ctx.exit_code = cli_usage_error(ctx, cmd, "--sizes: '" + s + "' is not a size in 8..8192");
        return;
      }
      sizes.push_back(int(n));
    }
    std::vector<std::string> schedules = split_commas(o->schedules);
    for (const std::string& s : schedules)
      if (!is_cpu_schedule(s) && !is_opencl_schedule(s)) {
        ctx.exit_code = cli_usage_error(ctx, cmd,
                                        "--schedules: '" + s +
                                            "' is not one of serial, stream, blocked, "
                                            "opencl-stream, opencl-blocked");
        return;
      }
    if (cl_device_opt->count() && o->cl_device < 0) {
      ctx.exit_code = cli_usage_error(ctx, cmd, "--cl-device: expected a device index (0 or more)");
      return;
    }
    // The OpenCL rows: from table1_opencl_bench when it was built; left out with a note when
    // they were not asked for by name.
    const bool opencl_asked = t1->get_option("--schedules")->count() > 0;
    if (o->opencl_binary.empty())
      o->opencl_binary = bench_binary_beside_ardcell("table1_opencl_bench").string();
    const bool want_opencl = std::any_of(schedules.begin(), schedules.end(), is_opencl_schedule);
    if (want_opencl && access(o->opencl_binary.c_str(), X_OK) != 0) {
      if (opencl_asked) {
        ctx.exit_code = cli_usage_error(ctx, cmd,
                                        "OpenCL benchmark program '" + o->opencl_binary +
                                            "' not found or not executable (build the "
                                            "table1_opencl_bench target, or pass "
                                            "--opencl-bench-binary)");
        return;
      }
      std::fprintf(ctx.err,
                   "ardcell bench table1: note: no %s (built without OpenCL?); the opencl rows "
                   "are left out\n",
                   o->opencl_binary.c_str());
      std::erase_if(schedules, is_opencl_schedule);
    }
    const bool want_cpu = std::any_of(schedules.begin(), schedules.end(), is_cpu_schedule);
    if (sizes.empty() || schedules.empty() || !(o->min_time > 0) || o->store_kib < 8) {
      ctx.exit_code = cli_usage_error(
          ctx, cmd, "need at least one size and schedule, --min-time > 0, --store-kib >= 8");
      return;
    }
    if (o->binary.empty()) o->binary = bench_binary_beside_ardcell("table1_bench").string();
    if (access(o->binary.c_str(), X_OK) != 0) {
      ctx.exit_code = cli_usage_error(ctx, cmd,
                                      "benchmark program '" + o->binary +
                                          "' not found or not executable (build the "
                                          "table1_bench target, or pass --bench-binary)");
      return;
    }
    std::error_code ec;
    fs::create_directories(o->out, ec);
    if (ec) {
      ctx.exit_code =
          cli_usage_error(ctx, cmd, "--out: cannot create '" + o->out + "': " + ec.message());
      return;
    }
    // The CPU program measures the STREAM triad too (the bandwidth every row is compared with).
    std::map<std::string, Result> results;  // "<schedule>/<fluid|ard>/<N>"
    double triad = 0;
    const auto run_program = [&](const std::string& binary, const std::string& filter,
                                 const std::string& json_path) {
      const int rc = run_table1_program(*o, binary, filter, json_path);
      if (rc != 0) {
        std::fprintf(ctx.err, "ardcell bench table1: %s exited with status %d\n", binary.c_str(),
                     rc);
        return false;
      }
      std::string skipped;
      if (Status st = read_bench_json(json_path, results, triad, &skipped); !st) {
        std::fprintf(ctx.err, "ardcell bench table1: %s\n", st.message().c_str());
        return false;
      }
      if (!skipped.empty())
        std::fprintf(ctx.err, "ardcell bench table1: rows left out (%s)\n", skipped.c_str());
      std::error_code rm;
      fs::remove(json_path, rm);
      return true;
    };
    std::string cpu_filter = "STREAM/triad", cl_filter;
    for (const std::string& s : schedules)
      (is_opencl_schedule(s) ? cl_filter : cpu_filter) += "|Table1/" + s + "/";
    if (!cl_filter.empty()) cl_filter = cl_filter.substr(1);
    if (!want_cpu) cpu_filter = "STREAM/triad";
    if (!run_program(o->binary, cpu_filter, (fs::path(o->out) / ".table1_bench.json").string()) ||
        (!cl_filter.empty() &&
         !run_program(o->opencl_binary, cl_filter,
                      (fs::path(o->out) / ".table1_opencl_bench.json").string()))) {
      ctx.exit_code = kExitFailure;
      return;
    }
    // The table.
    std::ostringstream md, csv;
    char line[512];
    md << "STREAM triad (measured in the same run): " << triad / 1e9 << " GB/s; local store "
       << o->store_kib << " KiB per worker (stream, blocked)\n\n";
    md << "| N | schedule | FPS fluid | FPS fluid+RD | RD overhead | x Cell (fluid+RD) | "
          "eff. GB/s (fluid+RD) | share of triad | Cell FPS fluid / fluid+RD | "
          "fluid+RD FPS if cores unshared |\n";
    md << "|---|---|---|---|---|---|---|---|---|---|\n";
    csv << "n,schedule,fps_fluid,fps_ard,rd_overhead,cell_multiple_ard,eff_bytes_per_s_ard,"
           "triad_share_ard,cell_fps_fluid,cell_fps_ard,fps_ard_unshared\n";
    for (int n : sizes)
      for (const std::string& s : schedules) {
        const Result& f = results[s + "/fluid/" + std::to_string(n)];
        const Result& a = results[s + "/ard/" + std::to_string(n)];
        if (!f.present && !a.present) continue;
        const CellRow* c = cell_row(n);
        const double overhead = (f.present && a.present && a.fps > 0) ? f.fps / a.fps - 1 : NAN;
        const double multiple = (c && a.present) ? a.fps / c->ard : NAN;
        const double share = (a.present && triad > 0) ? a.bytes_per_s / triad : NAN;
        char multiple_text[32] = "-";  // no Cell figure for this size (2048)
        if (std::isfinite(multiple))
          std::snprintf(multiple_text, sizeof multiple_text, "%.2f", multiple);
        std::snprintf(
            line, sizeof line,
            "| %d | %s | %.1f | %.1f | %+.1f%% | %s | %.2f | %.0f%% | %s | %s |\n", n, s.c_str(),
            f.fps, a.fps, 100 * overhead, multiple_text, a.bytes_per_s / 1e9, 100 * share,
            c ? (std::to_string(c->fluid).substr(0, 5) + " / " +
                 std::to_string(c->ard).substr(0, 5))
                    .c_str()
              : "-",
            // Only the threads back end measures it (its counter fps_if_unshared).
            a.fps_unshared > 0 ? std::to_string(a.fps_unshared).substr(0, 7).c_str() : "-");
        md << line;
        std::snprintf(line, sizeof line, "%d,%s,%.4f,%.4f,%.5f,%.4f,%.6g,%.4f,%s,%s,%.4f\n", n,
                      s.c_str(), f.fps, a.fps, overhead, multiple, a.bytes_per_s, share,
                      c ? std::to_string(c->fluid).c_str() : "",
                      c ? std::to_string(c->ard).c_str() : "", a.fps_unshared);
        csv << line;
      }
    std::fputs(md.str().c_str(), ctx.out);
    const fs::path dir(o->out);
    Status st = write_text_atomically(dir / "table1.md", md.str());
    if (st) st = write_text_atomically(dir / "table1.csv", csv.str());
    if (!st) {
      std::fprintf(ctx.err, "ardcell bench table1: %s\n", st.message().c_str());
      ctx.exit_code = kExitFailure;
      return;
    }
    // The chart: fluid and fluid+RD FPS per size and schedule, the Cell's figures marked.
    BarChart chart;
    chart.title = "Table 1: frames per second, fluid alone and with Gray-Scott RD";
    chart.x_label = "grid N (N x N cells)";
    chart.y_label = "frames per second (log)";
    chart.reference_label = "Cell (paper)";
    for (int n : sizes) chart.groups.push_back(std::to_string(n));
    for (const char* kind : {"fluid", "ard"}) {
      BarPanel panel;
      panel.title = std::string(kind) == "fluid" ? "fluid" : "fluid + RD";
      for (const std::string& s : schedules) {
        BarSeries series{s, {}};
        for (int n : sizes) {
          const Result& r = results[s + "/" + kind + "/" + std::to_string(n)];
          series.values.push_back(r.present ? r.fps : NAN);
        }
        panel.series.push_back(std::move(series));
      }
      for (int n : sizes) {
        const CellRow* c = cell_row(n);
        panel.reference.push_back(c ? (std::string(kind) == "fluid" ? c->fluid : c->ard) : NAN);
      }
      chart.panels.push_back(std::move(panel));
    }
    std::string written = (dir / "table1.md").string() + ", " + (dir / "table1.csv").string();
    if (charts_available()) {
      st = write_bar_chart(dir / "table1.png", chart);
      if (!st) {
        std::fprintf(ctx.err, "ardcell bench table1: %s\n", st.message().c_str());
        ctx.exit_code = kExitFailure;
        return;
      }
      written += ", " + (dir / "table1.png").string();
    } else {
      std::fprintf(ctx.err, "ardcell bench table1: note: built without PLplot, no table1.png\n");
    }
    std::fprintf(ctx.err, "ardcell bench table1: wrote %s\n", written.c_str());
    ctx.exit_code = kExitOk;
  });
}

}  // namespace ardcell
