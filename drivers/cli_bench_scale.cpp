// `ardcell bench scale`: one grid of a scene that runs as blocks (--scene: table1-ard, the
// default, or seed001) over several processes (Open MPI), against one process on the same
// cores: bench/scale_bench.cpp under mpirun, one process group per row.
//   strong - the fixed grid --size (default 2048^2), 1 rank and R ranks (R x 1 blocks), the
//            machine's cores shared out (workers per rank = cores / R);
//   weak   - --weak^2 cells per rank ((R --weak) x --weak), the same cores.
// On one machine the cores stay the same, so "efficiency" is a row's throughput (cells per
// second) over the 1-rank row of its kind: what running as processes and MPI messages costs
// against threads. Prints a Markdown table and writes scale.md and scale.csv into --out.
#include <sched.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "drivers/bench_program.h"
#include "drivers/cli.h"
#include "host/engine/engine.h"
#include "host/scenes/scene_registry.h"
#include "runtime/box.h"

#ifndef ARDCELL_MPIEXEC
#define ARDCELL_MPIEXEC "mpirun"
#endif

namespace ardcell {
namespace {

namespace fs = std::filesystem;

struct ScaleOptions {
  std::string scene = "table1-ard";
  int size = 2048;
  int weak = 1024;
  std::string ranks = "1,2";
  int frames = 20;
  std::string out = "bench-results";
  std::string binary;
  std::string mpirun = ARDCELL_MPIEXEC;
  bool realtime_solvers = false;
};

struct ScaleRow {
  std::string kind;  // strong | weak
  int ranks = 1, workers = 1;
  Int2 grid{};
  double fps = 0, cells_per_s = 0, halo_bytes = 0, mpi_ms = 0, efficiency = 0;
};

int run_scale(const ScaleOptions& o, CliContext& ctx) {
  const auto usage = [&](const std::string& m) { return cli_usage_error(ctx, "bench scale", m); };
  std::vector<int> ranks;
  for (const std::string& item : split_commas(o.ranks)) {
    char* end = nullptr;
    const long r = std::strtol(item.c_str(), &end, 10);
    if (*end != '\0' || r < 1 || r > 256)
      return usage("--ranks '" + o.ranks + "': expected rank counts 1..256, comma-separated");
    ranks.push_back(int(r));
  }
  if (std::find(ranks.begin(), ranks.end(), 1) == ranks.end()) ranks.insert(ranks.begin(), 1);
  if (o.size < 64 || o.weak < 64 || o.frames < 1)
    return usage("--size and --weak: expected 64 or more cells; --frames: 1 or more");
  if (const SceneEntry* entry = builtin_scenes().find(o.scene); !entry)
    return usage("--scene " + o.scene +
                 ": not a built-in scene (expected one such as table1-ard, seed001 or "
                 "cavity-gray-scott)");
  else if (std::string why = block_support(entry->make()).problem; !why.empty())
    return usage("--scene " + o.scene + ": runs on one process's whole grid: " + why);
  const std::string binary =
      o.binary.empty() ? bench_binary_beside_ardcell("scale_bench").string() : o.binary;
  if (!fs::exists(binary))
    return usage("no " + binary + " (build the scale_bench target, or pass --bench-binary)");
  std::error_code ec;
  fs::create_directories(o.out, ec);
  if (ec) return usage("--out " + o.out + ": " + ec.message());
  // The CPUs this process may use (a cpuset or taskset counts; hardware threads count as CPUs,
  // as mpirun's --use-hwthread-cpus below counts them).
  cpu_set_t usable;
  CPU_ZERO(&usable);
  const int cores = ::sched_getaffinity(0, sizeof usable, &usable) == 0
                        ? std::max(1, CPU_COUNT(&usable))
                        : int(std::max(1u, std::thread::hardware_concurrency()));

  std::vector<ScaleRow> rows;
  for (const char* kind : {"strong", "weak"})
    for (int r : ranks) {
      ScaleRow row;
      row.kind = kind;
      row.ranks = r;
      row.workers = std::max(1, cores / r);
      // Blocks of whole rows (1xR): a row-major grid's halo rows are contiguous, and seed
      // 001's blocks run its temporally blocked kernel only on whole rows.
      row.grid = row.kind == "strong" ? Int2{o.size, o.size} : Int2{o.weak, o.weak * r};
      const std::string grid = std::to_string(row.grid.x) + "x" + std::to_string(row.grid.y);
      const std::string json = (fs::path(o.out) / ".scale_bench.json").string();
      std::vector<std::pair<std::string, std::string>> env = {
          {"ARDCELL_BENCH_SCENE", o.scene},
          {"ARDCELL_BENCH_GRID", grid},
          {"ARDCELL_BENCH_RANKS", "1x" + std::to_string(r)},
          {"ARDCELL_BENCH_WORKERS", std::to_string(row.workers)},
          {"ARDCELL_BENCH_FRAMES", std::to_string(o.frames)}};
      if (o.realtime_solvers) env.emplace_back("ARDCELL_BENCH_REALTIME", "1");
      // Each rank bound to CPUs of its own, as many as its workers (Open MPI's default binds
      // each of up to 2 ranks to ONE core, whatever its workers); --use-hwthread-cpus makes
      // mpirun count CPUs as `cores` does (else physical cores, and PE=W fails on a machine with
      // hyperthreads). When the ranks outnumber the CPUs, no binding.
      std::vector<std::string> launcher = {o.mpirun, "--oversubscribe"};
      if (r * row.workers <= cores)
        launcher.insert(launcher.end(),
                        {"--use-hwthread-cpus", "--map-by",
                         "slot:PE=" + std::to_string(row.workers), "--bind-to", "hwthread"});
      else
        launcher.insert(launcher.end(), {"--bind-to", "none"});
      launcher.insert(launcher.end(), {"-np", std::to_string(r)});
      const int rc = run_bench_program(binary, "Scale/", 0.0, 1, json, env, launcher);
      std::vector<BenchRow> report;
      std::string skipped;
      if (rc != 0 || !read_bench_rows(json, report, &skipped) || report.empty()) {
        std::fprintf(
            ctx.err, "ardcell bench scale: %s x %d ranks on %s exited with status %d%s%s\n",
            binary.c_str(), r, grid.c_str(), rc, skipped.empty() ? "" : ": ", skipped.c_str());
        return kExitFailure;
      }
      const auto counter = [&](const char* key) {
        const auto it = report[0].counters.find(key);
        return it == report[0].counters.end() ? 0.0 : it->second;
      };
      row.fps = counter("fps");
      row.cells_per_s = counter("cells_per_s");
      row.halo_bytes = counter("halo_bytes_per_frame");
      row.mpi_ms = counter("mpi_ms_per_frame");
      rows.push_back(row);
      fs::remove(json, ec);
    }
  for (ScaleRow& row : rows)
    for (const ScaleRow& one : rows)
      if (one.kind == row.kind && one.ranks == 1 && one.cells_per_s > 0)
        row.efficiency = row.cells_per_s / one.cells_per_s;

  std::ostringstream md, csv;
  md << o.scene << (o.scene == "table1-ard" ? " (blocked schedule)" : "")
     << (o.realtime_solvers ? " on its real-time settings (--realtime-solvers)" : "")
     << " over Open MPI ranks on " << cores
     << " cores; efficiency = cells/s over the 1-rank row of the same kind\n\n"
     << "| scaling | ranks | workers/rank | grid | fps | cells/s | efficiency | halo KiB/frame "
        "| MPI ms/frame (rank 0) |\n"
     << "|---|---|---|---|---|---|---|---|---|\n";
  csv << "scaling,ranks,workers_per_rank,grid_x,grid_y,fps,cells_per_s,efficiency,"
         "halo_bytes_per_frame,mpi_ms_per_frame\n";
  char line[320];
  for (const ScaleRow& r : rows) {
    std::snprintf(line, sizeof line,
                  "| %s | %d | %d | %dx%d | %.2f | %.3g | %.3f | %.1f | %.3f |\n", r.kind.c_str(),
                  r.ranks, r.workers, r.grid.x, r.grid.y, r.fps, r.cells_per_s, r.efficiency,
                  r.halo_bytes / 1024.0, r.mpi_ms);
    md << line;
    std::snprintf(line, sizeof line, "%s,%d,%d,%d,%d,%.6g,%.6g,%.6g,%.6g,%.6g\n", r.kind.c_str(),
                  r.ranks, r.workers, r.grid.x, r.grid.y, r.fps, r.cells_per_s, r.efficiency,
                  r.halo_bytes, r.mpi_ms);
    csv << line;
  }
  const fs::path dir(o.out);
  Status st = write_text_atomically(dir / "scale.md", md.str());
  if (st) st = write_text_atomically(dir / "scale.csv", csv.str());
  if (!st) {
    std::fprintf(ctx.err, "ardcell bench scale: %s\n", st.message().c_str());
    return kExitFailure;
  }
  std::fputs(md.str().c_str(), ctx.out);
  std::fprintf(ctx.out, "\nwritten: %s, %s\n", (dir / "scale.md").c_str(),
               (dir / "scale.csv").c_str());
  return kExitOk;
}

}  // namespace

void add_bench_scale_command(CLI::App& bench, CliContext& ctx) {
  auto* scale = bench.add_subcommand(
      "scale", "One scene's grid over MPI ranks against one process: strong and weak scaling");
  auto o = std::make_shared<ScaleOptions>();
  scale
      ->add_option("--scene", o->scene,
                   "A built-in scene (table1-ard, seed001, space-cookie-5, cavity-gray-scott, ...)")
      ->capture_default_str();
  scale->add_option("--size", o->size, "Strong scaling: the grid side N (N x N)")
      ->capture_default_str();
  scale->add_option("--weak", o->weak, "Weak scaling: the grid side per rank")
      ->capture_default_str();
  scale->add_option("--ranks", o->ranks, "Rank counts, comma-separated (1 always runs)")
      ->capture_default_str();
  scale->add_option("--frames", o->frames, "Frames timed per row")->capture_default_str();
  scale->add_option("--out", o->out, "Folder for scale.md and scale.csv")->capture_default_str();
  scale->add_option("--bench-binary", o->binary,
                    "The scale_bench program (default: beside ardcell)");
  scale->add_option("--mpirun", o->mpirun, "Open MPI's launcher")->capture_default_str();
  scale->add_flag("--realtime-solvers", o->realtime_solvers,
                  "The scene's real-time settings (fixed Jacobi sweeps, the reaction's table), as "
                  "ardcell run/live --realtime-solvers: a block's diffusion sweeps its own cells");
  scale->callback([o, &ctx] { ctx.exit_code = run_scale(*o, ctx); });
}

}  // namespace ardcell
