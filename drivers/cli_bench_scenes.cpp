// `ardcell bench scenes`: every preset through the engine users run, serial against threads and
// (with an OpenCL device) opencl in one run (bench/scenes_bench.cpp, SceneSpeedup/<preset>/<N>:
// the back ends' runs of frames alternate, so a slow spell of the machine hits each). Prints a
// Markdown table and writes scenes.md, scenes.csv and scenes.png (drivers/chart.h, when built with
// PLplot) in --out.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "drivers/bench_program.h"
#include "drivers/chart.h"
#include "drivers/cli.h"
#include "host/scenes/preset.h"

namespace ardcell {
namespace {

namespace fs = std::filesystem;

struct ScenesOptions {
  std::string sizes = "256,512,1024";
  std::string presets;  // empty: every embedded preset
  double min_time = 0.3;
  int repetitions = 1;  // > 1: the medians, and the range of threads / serial
  std::string out = "bench-results";
  std::string binary;
  int cl_device = -1;  // -1: the first device; -2: none (--cl-device none)
  bool realtime_solvers = false;
};

int run_scenes(const ScenesOptions& o, CliContext& ctx) {
  const std::string cmd = "bench scenes";
  for (const std::string& s : split_commas(o.sizes)) {
    char* end = nullptr;
    const long n = std::strtol(s.c_str(), &end, 10);
    if (*end != '\0' || n < 16 || n > 8192)
      return cli_usage_error(ctx, cmd, "--sizes: '" + s + "' is not a size in 16..8192");
  }
  std::vector<std::string> presets = o.presets.empty() ? preset_names() : split_commas(o.presets);
  for (const std::string& name : presets) {
    Preset p;
    if (Status st = load_preset(name, p); !st)
      return cli_usage_error(ctx, cmd, "--presets: " + st.message());
  }
  if (split_commas(o.sizes).empty() || presets.empty() || !(o.min_time > 0))
    return cli_usage_error(ctx, cmd, "need at least one size and preset, and --min-time > 0");
  if (o.repetitions < 1 || o.repetitions > 100)
    return cli_usage_error(ctx, cmd,
                           "--repetitions: " + std::to_string(o.repetitions) +
                               " is not a number of repetitions in 1..100");
  const std::string binary =
      o.binary.empty() ? bench_binary_beside_ardcell("scenes_bench").string() : o.binary;
  if (access(binary.c_str(), X_OK) != 0)
    return cli_usage_error(ctx, cmd,
                           "benchmark program '" + binary +
                               "' not found or not executable (build the scenes_bench target, "
                               "or pass --bench-binary)");
  std::error_code ec;
  fs::create_directories(o.out, ec);
  if (ec) return cli_usage_error(ctx, cmd, "--out: cannot create '" + o.out + "': " + ec.message());

  std::string joined;
  for (const std::string& name : presets) joined += (joined.empty() ? "" : ",") + name;
  const std::string json = (fs::path(o.out) / ".scenes_bench.json").string();
  std::vector<std::pair<std::string, std::string>> env = {{"ARDCELL_BENCH_SIZES", o.sizes},
                                                          {"ARDCELL_BENCH_PRESETS", joined}};
  if (o.cl_device != -1)
    env.emplace_back("ARDCELL_CL_DEVICE", o.cl_device >= 0 ? std::to_string(o.cl_device) : "none");
  if (o.realtime_solvers) env.emplace_back("ARDCELL_BENCH_REALTIME", "1");
  const int rc = run_bench_program(binary, "SceneSpeedup/", o.min_time, o.repetitions, json, env);
  if (rc != 0) {
    std::fprintf(ctx.err, "ardcell bench scenes: %s exited with status %d\n", binary.c_str(), rc);
    return kExitFailure;
  }
  std::vector<BenchRow> report;
  std::string skipped;
  if (Status st = read_bench_rows(json, report, &skipped); !st) {
    std::fprintf(ctx.err, "ardcell bench scenes: %s\n", st.message().c_str());
    return kExitFailure;
  }
  fs::remove(json, ec);
  if (!skipped.empty())
    std::fprintf(ctx.err, "ardcell bench scenes: rows left out (%s)\n", skipped.c_str());
  // One row per preset and size: the only run, or the median of the repetitions; the range of
  // threads / serial over the repetitions beside it.
  const bool repeated = o.repetitions > 1;
  std::vector<BenchRow> rows;
  std::map<std::string, std::pair<double, double>> speedup_range;
  for (const BenchRow& row : report) {
    if (row.aggregate == (repeated ? "median" : "")) rows.push_back(row);
    if (!row.aggregate.empty()) continue;
    const auto it = row.counters.find("speedup");
    if (it == row.counters.end()) continue;
    auto [range, fresh] = speedup_range.try_emplace(row.name, it->second, it->second);
    if (!fresh)
      range->second = {std::min(range->second.first, it->second),
                       std::max(range->second.second, it->second)};
  }

  std::ostringstream md, csv;
  bool with_opencl = false;
  for (const BenchRow& row : rows) with_opencl = with_opencl || row.counters.count("opencl_ms");
  if (o.realtime_solvers) md << "Every preset on its real-time settings (--realtime-solvers).\n\n";
  if (repeated)
    md << "Medians of " << o.repetitions
       << " repetitions; range: threads / serial in the fastest and slowest.\n\n";
  md << "| preset | N | serial FPS | threads FPS | threads / serial |"
     << (repeated ? " range |" : "") << " workers |"
     << (with_opencl ? " opencl FPS | opencl / serial |" : "") << "\n|---|---|---|---|---|"
     << (repeated ? "---|" : "") << "---|" << (with_opencl ? "---|---|" : "") << "\n";
  csv << "preset,n,serial_fps,threads_fps,speedup" << (repeated ? ",speedup_min,speedup_max" : "")
      << ",workers" << (with_opencl ? ",opencl_fps,opencl_speedup\n" : "\n");
  char line[256];
  struct ChartRow {
    std::string preset, n;
    double fps[3];  // serial, threads, opencl
  };
  std::vector<ChartRow> chart_rows;
  for (const BenchRow& row : rows) {
    // SceneSpeedup/<preset>/<N>
    const auto first = row.name.find('/'), last = row.name.rfind('/');
    if (first == std::string::npos || last == first) continue;
    const std::string preset = row.name.substr(first + 1, last - first - 1);
    const std::string n = row.name.substr(last + 1);
    const auto counter = [&](const char* key) {
      const auto it = row.counters.find(key);
      return it == row.counters.end() ? 0.0 : it->second;
    };
    const double serial_fps = 1e3 / counter("serial_ms"), threads_fps = 1e3 / counter("threads_ms");
    const double opencl_fps_chart = counter("opencl_ms") > 0 ? 1e3 / counter("opencl_ms") : NAN;
    chart_rows.push_back({preset, n, {serial_fps, threads_fps, opencl_fps_chart}});
    std::snprintf(line, sizeof line, "| %s | %s | %.1f | %.1f | %.2fx |", preset.c_str(), n.c_str(),
                  serial_fps, threads_fps, counter("speedup"));
    md << line;
    std::snprintf(line, sizeof line, "%s,%s,%.4f,%.4f,%.4f", preset.c_str(), n.c_str(), serial_fps,
                  threads_fps, counter("speedup"));
    csv << line;
    if (repeated) {
      const auto it = speedup_range.find(row.name);
      const auto [lo, hi] =
          it == speedup_range.end() ? std::pair<double, double>{NAN, NAN} : it->second;
      std::snprintf(line, sizeof line, " %.2f-%.2fx |", lo, hi);
      md << line;
      std::snprintf(line, sizeof line, ",%.4f,%.4f", lo, hi);
      csv << line;
    }
    std::snprintf(line, sizeof line, " %.0f |", counter("workers"));
    md << line;
    std::snprintf(line, sizeof line, ",%.0f", counter("workers"));
    csv << line;
    if (with_opencl) {
      const double opencl_fps = counter("opencl_ms") > 0 ? 1e3 / counter("opencl_ms") : 0.0;
      std::snprintf(line, sizeof line, " %.1f | %.2fx |", opencl_fps, counter("opencl_speedup"));
      md << line;
      std::snprintf(line, sizeof line, ",%.4f,%.4f", opencl_fps, counter("opencl_speedup"));
      csv << line;
    }
    md << '\n';
    csv << '\n';
  }
  const fs::path dir(o.out);
  Status st = write_text_atomically(dir / "scenes.md", md.str());
  if (st) st = write_text_atomically(dir / "scenes.csv", csv.str());
  if (!st) {
    std::fprintf(ctx.err, "ardcell bench scenes: %s\n", st.message().c_str());
    return kExitFailure;
  }
  std::fputs(md.str().c_str(), ctx.out);
  std::string written = (dir / "scenes.md").string() + ", " + (dir / "scenes.csv").string();
  if (charts_available()) {
    // One panel per size, one group per preset, a bar per back end.
    BarChart chart;
    chart.title = "Every preset on the engine: frames per second per back end";
    chart.x_label = "";  // the presets label the bars, the panels say N
    chart.y_label = "frames per second (log)";
    chart.vertical_group_labels = true;
    std::vector<std::string> sizes;
    for (const ChartRow& r : chart_rows) {
      if (std::find(chart.groups.begin(), chart.groups.end(), r.preset) == chart.groups.end())
        chart.groups.push_back(r.preset);
      if (std::find(sizes.begin(), sizes.end(), r.n) == sizes.end()) sizes.push_back(r.n);
    }
    const char* names[3] = {"serial", "threads", "opencl"};
    for (const std::string& n : sizes) {
      BarPanel panel;
      panel.title = "N = " + n;
      for (int k = 0; k < (with_opencl ? 3 : 2); ++k) {
        BarSeries series{names[k], std::vector<double>(chart.groups.size(), NAN)};
        for (const ChartRow& r : chart_rows)
          if (r.n == n)
            series
                .values[std::size_t(std::find(chart.groups.begin(), chart.groups.end(), r.preset) -
                                    chart.groups.begin())] = r.fps[k];
        panel.series.push_back(std::move(series));
      }
      chart.panels.push_back(std::move(panel));
    }
    if (Status cs = write_bar_chart(dir / "scenes.png", chart, 1400, 680); !cs) {
      std::fprintf(ctx.err, "ardcell bench scenes: %s\n", cs.message().c_str());
      return kExitFailure;
    }
    written += ", " + (dir / "scenes.png").string();
  } else {
    std::fprintf(ctx.err, "ardcell bench scenes: note: built without PLplot, no scenes.png\n");
  }
  std::fprintf(ctx.err, "ardcell bench scenes: wrote %s\n", written.c_str());
  return kExitOk;
}

}  // namespace

void add_bench_scenes_command(CLI::App& bench, CliContext& ctx) {
  auto* scenes = bench.add_subcommand(
      "scenes", "Every preset on the engine: serial, threads and OpenCL FPS per size, in one run");
  auto o = std::make_shared<ScenesOptions>();
  scenes->add_option("--sizes", o->sizes, "Grid widths N, comma-separated")->capture_default_str();
  scenes->add_option("--presets", o->presets, "Presets, comma-separated (default: every one)");
  scenes->add_option("--min-time", o->min_time, "Seconds per benchmark (at least)")
      ->capture_default_str();
  scenes
      ->add_option("--repetitions", o->repetitions,
                   "Runs of each benchmark: above 1, the table shows their medians and the range "
                   "of threads / serial (a VM's ratio moves between runs)")
      ->capture_default_str();
  scenes->add_option("--out", o->out, "Folder for scenes.md, scenes.csv and scenes.png")
      ->capture_default_str();
  scenes
      ->add_option_function<std::string>(
          "--cl-device",
          [o](const std::string& v) {
            if (v == "none") {
              o->cl_device = -2;
              return;
            }
            char* end = nullptr;
            const long n = std::strtol(v.c_str(), &end, 10);
            if (v.empty() || *end != '\0' || n < 0 || n > 1000)
              throw CLI::ValidationError("--cl-device",
                                         "'" + v + "': expected a device index or none");
            o->cl_device = int(n);
          },
          "OpenCL device for the opencl column (see ardcell devices), or none")
      ->type_name("N|none");
  scenes->add_flag("--realtime-solvers", o->realtime_solvers,
                   "Every preset on its real-time settings (fixed Jacobi sweeps, tabulated "
                   "reaction), as ardcell run/live --realtime-solvers");
  scenes->add_option("--bench-binary", o->binary,
                     "The scenes_bench program (default: beside ardcell)");
  scenes->callback([o, &ctx] { ctx.exit_code = run_scenes(*o, ctx); });
}

}  // namespace ardcell
