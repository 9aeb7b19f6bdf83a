// Seed 004's Table 3: one reaction-diffusion step on a Catmull-Clark surface (ardcell surface's
// Gray-Scott on the threads back end, every core: forward Euler reaction, implicit diffusion of a
// and b by Jacobi sweeps to a relative residual of 1e-6, the pattern's scale a mean patch side /
// 20), beside the paper's GPU (GTX 470) and 8-core CPU (i7) milliseconds, on procedural control
// meshes with the paper's patch counts:
//   Surface/rd/<mesh>/<N>   torus-128 (16 x 8 quads; the paper's toroidal), box-166 (1 x 5 x 13
//   cells; the paper's fertility has 166), box-238 (4 x 5 x 11; dog), torus-1127 (49 x 23; rocker
//   arm), torus-1292 (38 x 34; bunny), N = 8, 16, 32, 64 cells a patch side (the paper has no 64
//   for the two largest). One iteration = one step of a growing pattern (after 50 steps).
//   Surface/mg/<mesh>/<N>   the same with the diffusion solved by multigrid V-cycles
//   (`ardcell surface --solver mg`, host/surface/surface_multigrid.h).
//   SurfaceWorkers/genus2/<N>   the double torus (50 patches) on one worker against every core.
//   Surface/fluid/<mesh>/<N>   seed 004's Table 1: one full step of stable fluids
//   (`ardcell surface --fluid walk`: dye sources, dye and velocity advection, the walkers' force,
//   the projection by multigrid to a relative residual of 1e-6; no viscosity) after 20 steps, on
//   the meshes of Table 1 (torus-1127 and torus-1292 at N = 8, 16 and 32, as in the paper),
//   beside the paper's GPU and CPU ms per full step; counters forces_ms, projection_ms,
//   sources_ms, dye_advection_ms and advection_ms are the sub-steps of Table 2 (its fertility,
//   166 patches, N = 32: box-166/32).
//   Surface/fluid/elephant/2   the same step on libcgal-demo's elephant (`ardcell surface --shape
//   elephant --fluid walk --patch-cells 2`: 16674 patches, too many for the dense bottom solve,
//   so the multigrid's bottom grid goes through aggregate levels, host/surface/
//   coarse_aggregation.h); not in the paper (skipped when the mesh is not packaged).
//   SurfaceRender/torus/16   the live window's 3D view (host/surface/surface_render.h): the torus
//   of `ardcell live --shape torus` (32 patches of 16 x 16 cells) drawn at 800 x 600, a frame on
//   the calling thread and a frame in bands of rows on every core in turn: serial_ms, threads_ms,
//   speedup, same_image (1 when the two images are equal).
// Counters: ms_per_step, sweeps (Jacobi or smoothing sweeps on the finest grid a step, both
// solves), cycles (mg: V-cycles a step, both solves), paper_cpu_ms, paper_gpu_ms, x_paper_cpu (the
// paper's CPU time over ours, wall clock: > 1 is faster).
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#if ARDCELL_WITH_OPENSUBDIV
#include "host/surface/limit_surface.h"
#include "host/surface/patch_metric.h"
#include "host/surface/procedural_mesh.h"
#include "host/surface/surface_fluid.h"
#include "host/surface/surface_gray_scott.h"
#include "host/surface/surface_multigrid.h"
#include "host/surface/surface_render.h"
#include "host/surface/surface_scene.h"
#include "runtime/row_executor.h"
#include "runtime/thread/thread_backend.h"
#endif

namespace ardcell {
namespace {

#if ARDCELL_WITH_OPENSUBDIV

struct TableRow {
  const char* mesh;
  int patches;
  double gpu_ms[4], cpu_ms[4];  // N = 8, 16, 32, 64 (0: not in the paper)
};
// Seed 004, Table 3 (gpu/cpu ms per iteration).
constexpr TableRow kTable3[] = {
    {"torus-128", 128, {2, 6, 16, 60}, {16, 27, 89, 312}},
    {"box-166", 166, {3, 7, 22, 75}, {15, 36, 110, 500}},
    {"box-238", 238, {4, 10, 30, 107}, {24, 51, 155, 531}},
    {"torus-1127", 1127, {33, 55, 144, 0}, {89, 250, 786, 0}},
    {"torus-1292", 1292, {29, 56, 160, 0}, {102, 295, 911, 0}},
};

PolyMesh mesh_for(const std::string& name) {
  if (name == "torus-128") return torus_mesh(16, 8, 2.0, 0.8);
  if (name == "box-166") return box_mesh(1, 5, 13);
  if (name == "box-238") return box_mesh(4, 5, 11);
  if (name == "torus-1127") return torus_mesh(49, 23, 2.0, 0.8);
  return torus_mesh(38, 34, 2.0, 0.8);
}

// One surface simulation as `ardcell surface` runs it: the patches on the threads back end
// (workers 0: one per core), the pattern's scale a mean patch side / 20, 50 steps grown.
struct SurfaceRun {
  LimitSurface surface;
  std::unique_ptr<SurfaceLaplacian> op;
  std::unique_ptr<ThreadBackend> backend;
  std::unique_ptr<RowExecutor> executor;
  std::unique_ptr<SurfaceMultigrid> multigrid;  // --solver mg
  std::unique_ptr<SurfaceGrayScott> rd;
};

std::unique_ptr<SurfaceRun> surface_run(PolyMesh mesh, int n, int workers, std::string* error,
                                        bool multigrid = false) {
  auto r = std::make_unique<SurfaceRun>();
  if (Status s = LimitSurface::build(std::move(mesh), {}, r->surface); !s) {
    *error = s.message();
    return nullptr;
  }
  r->op =
      std::make_unique<SurfaceLaplacian>(r->surface.topology(), sample_limit_metric(r->surface, n));
  ThreadBackendOptions threads;
  threads.workers = workers;
  threads.pin = false;
  r->backend = std::make_unique<ThreadBackend>(threads);
  r->executor = std::make_unique<RowExecutor>(*r->backend);
  r->op->set_executor(*r->executor);
  const double side = std::sqrt(r->op->area() / r->op->patches());
  if (multigrid) r->multigrid = std::make_unique<SurfaceMultigrid>(r->surface, *r->op);
  r->rd = std::make_unique<SurfaceGrayScott>(*r->op, gray_scott_for_length(side / 20),
                                             r->multigrid.get());
  r->rd->seed_spots(cell_positions(r->surface, r->op->grid()), 1, 3 * r->op->patches(), 0.2 * side);
  for (int i = 0; i < 50; ++i) r->rd->step();
  return r;
}

void BM_SurfaceRd(benchmark::State& state, const TableRow& row, int column, bool multigrid) {
  std::string error;
  const std::unique_ptr<SurfaceRun> r =
      surface_run(mesh_for(row.mesh), 8 << column, 0, &error, multigrid);
  if (!r) {
    state.SkipWithError(error.c_str());
    return;
  }
  long long sweeps = 0, cycles = 0;
  const auto start = std::chrono::steady_clock::now();
  for (auto _ : state) {
    const DiffusionReport report = r->rd->step();
    sweeps += report.sweeps;
    cycles += report.cycles;
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double steps = double(state.iterations());
  state.counters["sweeps"] = double(sweeps) / steps;
  if (multigrid) state.counters["cycles"] = double(cycles) / steps;
  state.counters["patches"] = r->op->patches();
  state.counters["workers"] = r->backend->workers();
  state.counters["paper_cpu_ms"] = row.cpu_ms[column];
  state.counters["paper_gpu_ms"] = row.gpu_ms[column];
  state.counters["ms_per_step"] = 1e3 * seconds / steps;
  state.counters["x_paper_cpu"] = row.cpu_ms[column] * 1e-3 * steps / seconds;
}

// SurfaceWorkers/genus2/<N>: the double torus on one worker and on every core, a step of each in
// turn (so a slow spell of the machine hits both): serial_ms, threads_ms, speedup, and
// same_bits (1 when the two runs' fields are equal after the timed steps).
void BM_SurfaceWorkers(benchmark::State& state, int n) {
  std::string error;
  const std::unique_ptr<SurfaceRun> one = surface_run(genus2_mesh(1.0), n, 1, &error);
  const std::unique_ptr<SurfaceRun> all = surface_run(genus2_mesh(1.0), n, 0, &error);
  if (!one || !all) {
    state.SkipWithError(error.c_str());
    return;
  }
  using Clock = std::chrono::steady_clock;
  double seconds[2] = {0, 0};
  for (auto _ : state) {
    for (int k = 0; k < 2; ++k) {
      const auto t0 = Clock::now();
      (k == 0 ? one : all)->rd->step();
      seconds[k] += std::chrono::duration<double>(Clock::now() - t0).count();
    }
  }
  const double steps = double(state.iterations());
  state.counters["serial_ms"] = 1e3 * seconds[0] / steps;
  state.counters["threads_ms"] = 1e3 * seconds[1] / steps;
  state.counters["speedup"] = seconds[0] / seconds[1];
  state.counters["workers"] = all->backend->workers();
  state.counters["same_bits"] = one->rd->a() == all->rd->a() && one->rd->b() == all->rd->b();
}

void BM_SurfaceRender(benchmark::State& state) {
  LimitSurface surface;
  if (Status s = LimitSurface::build(torus_mesh(8, 4, 2.0, 0.8), {}, surface); !s) {
    state.SkipWithError(s.message().c_str());
    return;
  }
  const PatchGrid grid(surface.topology(), 16, CornerGhosts::kDiagonalExtrapolate);
  PatchField field = grid.make_field();
  for (std::size_t k = 0; k < field.size(); ++k) field[k] = 0.5 + 0.5 * std::sin(0.05 * double(k));
  ThreadBackendOptions threads;
  threads.pin = false;
  ThreadBackend backend(threads);
  RowExecutor executor(backend);
  SurfaceRenderer serial(surface, grid), banded(surface, grid);
  banded.set_executor(executor);
  SurfaceView view;  // 800 x 600, as the live window
  view.fit = SurfaceFit::kSphere;
  ImageRgb8 images[2];
  using Clock = std::chrono::steady_clock;
  double seconds[2] = {0, 0};
  for (auto _ : state) {
    view.azimuth_deg += 1;  // a turning view, as a drag turns it
    for (int k = 0; k < 2; ++k) {
      const auto t0 = Clock::now();
      (k == 0 ? serial : banded).render(field, SurfaceColours{}, view, images[k]);
      seconds[k] += std::chrono::duration<double>(Clock::now() - t0).count();
    }
  }
  const double frames = double(state.iterations());
  state.counters["serial_ms"] = 1e3 * seconds[0] / frames;
  state.counters["threads_ms"] = 1e3 * seconds[1] / frames;
  state.counters["speedup"] = seconds[0] / seconds[1];
  state.counters["workers"] = backend.workers();
  state.counters["same_image"] = images[0].rgb == images[1].rgb;
}

// Seed 004, Table 1 (gpu/cpu ms per full fluid step), the rows our meshes stand in for.
constexpr TableRow kTable1[] = {
    {"torus-128", 128, {16, 17, 34, 78}, {41, 131, 474, 1764}},
    {"box-166", 166, {16, 21, 42, 98}, {52, 172, 609, 2216}},
    {"box-238", 238, {17, 28, 58, 141}, {73, 246, 904, 3352}},
    {"torus-1127", 1127, {65, 107, 235, 0}, {368, 1394, 4638, 0}},
    {"torus-1292", 1292, {73, 122, 270, 0}, {430, 1536, 5367, 0}},
};

struct FluidRun {
  LimitSurface surface;
  std::unique_ptr<SurfaceLaplacian> op;
  std::unique_ptr<ThreadBackend> backend;
  std::unique_ptr<RowExecutor> executor;
  std::unique_ptr<SurfaceMultigrid> multigrid;
  std::unique_ptr<SurfaceFluid> fluid;
};

// column: of the paper's Table 1 (N = 8 << column), or -1 for a mesh it does not have at N = n.
void BM_SurfaceFluid(benchmark::State& state, const TableRow& row, int column, int n) {
  FluidRun r;
  PolyMesh mesh;
  if (column >= 0) {
    mesh = mesh_for(row.mesh);
  } else {
    std::string label;
    if (Status s = surface_control_mesh(row.mesh, "", mesh, label); !s) {
      state.SkipWithError(s.message().c_str());
      return;
    }
  }
  if (Status s = LimitSurface::build(std::move(mesh), {}, r.surface); !s) {
    state.SkipWithError(s.message().c_str());
    return;
  }
  {
    const PatchMetric metric = sample_limit_metric(r.surface, n);
    r.op = std::make_unique<SurfaceLaplacian>(r.surface.topology(), metric);
    ThreadBackendOptions threads;
    threads.pin = false;
    r.backend = std::make_unique<ThreadBackend>(threads);
    r.executor = std::make_unique<RowExecutor>(*r.backend);
    r.op->set_executor(*r.executor);
    r.multigrid = std::make_unique<SurfaceMultigrid>(r.surface, *r.op);
    SurfaceFluidParams params;  // `ardcell surface --fluid walk`'s
    params.force = FluidForce::kWalk;
    r.fluid = std::make_unique<SurfaceFluid>(r.surface, metric, *r.op, *r.multigrid, params);
  }
  for (int i = 0; i < 20; ++i) r.fluid->step();
  const FluidTimings before = r.fluid->timings();
  long long cycles = 0;
  const auto start = std::chrono::steady_clock::now();
  for (auto _ : state) cycles += r.fluid->step().cycles;
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double steps = double(state.iterations());
  const FluidTimings& after = r.fluid->timings();
  const auto ms = [&](double FluidTimings::*field) {
    return 1e3 * (after.*field - before.*field) / steps;
  };
  state.counters["ms_per_step"] = 1e3 * seconds / steps;
  state.counters["cycles"] = double(cycles) / steps;
  state.counters["forces_ms"] = ms(&FluidTimings::forces);
  state.counters["projection_ms"] = ms(&FluidTimings::projection);
  state.counters["sources_ms"] = ms(&FluidTimings::sources);
  state.counters["dye_advection_ms"] = ms(&FluidTimings::dye_advection);
  state.counters["advection_ms"] = ms(&FluidTimings::velocity_advection);
  state.counters["patches"] = r.op->patches();
  state.counters["workers"] = r.backend->workers();
  if (column < 0) return;
  state.counters["paper_cpu_ms"] = row.cpu_ms[column];
  state.counters["paper_gpu_ms"] = row.gpu_ms[column];
  state.counters["x_paper_cpu"] = row.cpu_ms[column] * 1e-3 * steps / seconds;
}

#endif

}  // namespace
}  // namespace ardcell

int main(int argc, char** argv) {
#if ARDCELL_WITH_OPENSUBDIV
  using namespace ardcell;
  for (const bool multigrid : {false, true})
    for (const TableRow& row : kTable3)
      for (int column = 0; column < 4; ++column) {
        if (row.cpu_ms[column] == 0) continue;
        benchmark::RegisterBenchmark((std::string(multigrid ? "Surface/mg/" : "Surface/rd/") +
                                      row.mesh + "/" + std::to_string(8 << column))
                                         .c_str(),
                                     [&row, column, multigrid](benchmark::State& s) {
                                       BM_SurfaceRd(s, row, column, multigrid);
                                     })
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime();
      }
  for (const TableRow& row : kTable1)
    for (int column = 0; column < 4; ++column) {
      if (row.cpu_ms[column] == 0) continue;
      benchmark::RegisterBenchmark(
          (std::string("Surface/fluid/") + row.mesh + "/" + std::to_string(8 << column)).c_str(),
          [&row, column](benchmark::State& s) { BM_SurfaceFluid(s, row, column, 8 << column); })
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
    }
  static constexpr TableRow kElephant{"elephant", 16674, {0, 0, 0, 0}, {0, 0, 0, 0}};
  benchmark::RegisterBenchmark("Surface/fluid/elephant/2",
                               [](benchmark::State& s) { BM_SurfaceFluid(s, kElephant, -1, 2); })
      ->Unit(benchmark::kMillisecond)
      ->UseRealTime();
  benchmark::RegisterBenchmark("SurfaceRender/torus/16", BM_SurfaceRender)
      ->Unit(benchmark::kMillisecond)
      ->UseRealTime();
  for (int n : {16, 32})
    benchmark::RegisterBenchmark(("SurfaceWorkers/genus2/" + std::to_string(n)).c_str(),
                                 [n](benchmark::State& s) { BM_SurfaceWorkers(s, n); })
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
#else
  std::fprintf(stderr, "surface_bench: built without OpenSubdiv: no surfaces to time\n");
#endif
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
}
