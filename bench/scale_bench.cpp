// Scaling across processes: frames per second of a scene on ONE grid cut into blocks, one per
// MPI rank, as `mpirun -np R ardcell run SCENE --ranks WxH` runs it (table1-ard: the blocked
// schedule, the plan's halo exchange; seed001: its stages, a halo of kExplicitBlockSteps cells
// exchanged every that many steps; one rank's workers pinned, several ranks' left to mpirun's
// binding; the exchange through MpiHaloChannel). One rank runs the whole grid, as `ardcell run
// SCENE` does. Run under mpirun by `ardcell bench scale` (drivers/cli_bench_scale.cpp), one
// configuration a process group:
//   ARDCELL_BENCH_SCENE    a built-in scene that runs as blocks (default table1-ard);
//   ARDCELL_BENCH_GRID     the whole grid, "WxH" (default 2048x2048);
//   ARDCELL_BENCH_RANKS    the layout, "1x2" (must match mpirun -np; default 1x1);
//   ARDCELL_BENCH_WORKERS  threads back end workers per rank (default 1);
//   ARDCELL_BENCH_FRAMES   frames timed (default 20): a fixed count, the same on every rank,
//                          since ranks that chose their own iteration counts would wait on
//                          each other's exchanges for ever;
//   ARDCELL_BENCH_REALTIME 1: the scene's real-time settings (use_realtime_solvers, as
//                          `--realtime-solvers`).
// Benchmark Scale/<scene>/<ranks>/<grid>/workers:<n>, one iteration a frame. Counters: fps,
// cells_per_s, halo_bytes_per_frame (sent by all ranks), mpi_ms_per_frame (rank 0's time in
// exchanges, waiting for its neighbours included, while its other workers compute the inner
// tiles), ranks, workers. Rank 0 reports; the other
// ranks run silently.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "bench/bench_env.h"
#include "host/engine/engine.h"
#include "host/scenes/preset.h"
#include "host/scenes/scene_registry.h"
#include "runtime/block_layout.h"
#include "runtime/mpi/mpi_world.h"

namespace ardcell {
namespace {

class SilentReporter : public benchmark::BenchmarkReporter {
 public:
  bool ReportContext(const Context&) override { return true; }
  void ReportRuns(const std::vector<Run>&) override {}
};

void run_scale(benchmark::State& state, MpiWorld& world, SceneConfig scene, Int2 ranks,
               int workers) {
  const Int2 grid = scene.size;
  const BlockSupport support = block_support(scene);
  const BlockLayout layout =
      BlockLayout::split(grid, ranks, support.periodic_x, support.periodic_y);
  MpiHaloChannel channel(layout, support.halo, world);
  EngineOptions o;
  o.backend = EngineOptions::Backend::kThreads;
  o.workers = workers;
  // As `ardcell run`: one process pins its workers (unpinned, a woken worker tends to land on
  // the core of the thread that woke it); ranks do not (each would pin to the same cores).
  o.pin_workers = world.size() == 1;
  o.plan.schedule = PlanSchedule::kBlocked;
  // One rank runs the whole grid as `ardcell run` does (seed001: its temporally blocked kernel);
  // several run blocks.
  if (world.size() > 1) {
    o.plan.block = layout.block(world.rank());
    o.plan.halo = &channel;
  }
  Engine engine(scene, o);
  engine.step();  // warm: first touch of every field and store
  channel.reset_stats();
  for (auto _ : state) engine.step();
  const double frames = double(state.iterations());
  state.counters["fps"] = benchmark::Counter(frames, benchmark::Counter::kIsRate);
  state.counters["cells_per_s"] =
      benchmark::Counter(frames * double(grid.x) * grid.y, benchmark::Counter::kIsRate);
  state.counters["halo_bytes_per_frame"] = world.sum(channel.bytes_sent()) / frames;
  state.counters["mpi_ms_per_frame"] = 1e3 * channel.seconds() / frames;
  state.counters["ranks"] = ranks.x * ranks.y;
  state.counters["workers"] = workers;
}

}  // namespace
}  // namespace ardcell

// Sanitizer builds: Open MPI keeps its runtime's allocations past MPI_Finalize (as ardcell's
// main does, scripts/lsan.supp).
extern "C" const char* __lsan_default_options() {
  return "suppressions=" ARDCELL_SOURCE_DIR "/scripts/lsan.supp:print_suppressions=0";
}

int main(int argc, char** argv) {
  using namespace ardcell;
  MpiWorld world;
  Int2 grid{2048, 2048}, ranks{1, 1};
  const std::string grid_text = bench_env_text("ARDCELL_BENCH_GRID", "2048x2048");
  const std::string ranks_text = bench_env_text("ARDCELL_BENCH_RANKS", "1x1");
  if (!parse_block_parts(grid_text, grid) || !parse_block_parts(ranks_text, ranks) ||
      ranks.x * ranks.y != world.size()) {
    if (world.rank() == 0)
      std::fprintf(stderr,
                   "scale_bench: ARDCELL_BENCH_GRID '%s' and ARDCELL_BENCH_RANKS '%s': expected "
                   "WxH each, the ranks' product equal to mpirun -np (%d)\n",
                   grid_text.c_str(), ranks_text.c_str(), world.size());
    return 2;
  }
  const std::string scene_name = bench_env_text("ARDCELL_BENCH_SCENE", "table1-ard");
  const SceneEntry* entry = builtin_scenes().find(scene_name);
  SceneConfig scene;
  if (entry) {
    Preset preset = preset_from_entry(*entry);
    if (bench_env_int("ARDCELL_BENCH_REALTIME", 0) == 1) use_realtime_solvers(preset);
    scene = preset.scene;
    scene.size = grid;
  }
  if (!entry || !block_support(scene).problem.empty()) {
    if (world.rank() == 0)
      std::fprintf(stderr, "scale_bench: ARDCELL_BENCH_SCENE '%s': %s\n", scene_name.c_str(),
                   entry ? block_support(scene).problem.c_str()
                         : "not a built-in scene (expected one that runs as blocks)");
    return 2;
  }
  const int workers = std::max(1, bench_env_int("ARDCELL_BENCH_WORKERS", 1));
  const int frames = std::max(1, bench_env_int("ARDCELL_BENCH_FRAMES", 20));
  const std::string name = "Scale/" + scene_name + "/" + ranks_text + "/" + grid_text +
                           "/workers:" + std::to_string(workers);
  benchmark::RegisterBenchmark(
      name.c_str(), [&](benchmark::State& st) { run_scale(st, world, scene, ranks, workers); })
      ->Iterations(frames)
      ->UseRealTime()
      ->Unit(benchmark::kMillisecond);
  // Only rank 0 reports (and writes --benchmark_out): the others drop the report flags.
  std::vector<char*> args(argv, argv + argc);
  if (world.rank() != 0)
    std::erase_if(args, [](const char* a) { return std::strncmp(a, "--benchmark_out", 15) == 0; });
  int n = int(args.size());
  benchmark::Initialize(&n, args.data());
  if (benchmark::ReportUnrecognizedArguments(n, args.data())) return 1;
  SilentReporter silent;
  if (world.rank() == 0)
    benchmark::RunSpecifiedBenchmarks();
  else
    benchmark::RunSpecifiedBenchmarks(&silent);
  benchmark::Shutdown();
  return 0;
}
