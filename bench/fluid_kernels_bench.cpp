// Fluid kernels at 128^2 .. 1024^2: advection, one Stam Jacobi sweep, one red-black sweep, and
// one pressure projection with each solver. Counters: cells/s and bytes/s (the bytes each
// kernel must at least move: every input and output float read or written once).
#include <benchmark/benchmark.h>

#include <memory>
#include <random>
#include <string>

#include "host/engine/fluid_step.h"
#include "kernels/advect.h"
#include "kernels/stam_sweeps.h"
#include "kernels/stencil_sweeps.h"
#include "runtime/boundary.h"
#include "runtime/thread/thread_backend.h"

namespace ardcell {
namespace {

FieldF noise(Int2 n, unsigned seed, float amplitude) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> dist(-amplitude, amplitude);
  FieldF f(n, 1);
  for (int j = -1; j <= n.y; ++j)
    for (int i = -1; i <= n.x; ++i) f(i, j) = dist(rng);
  return f;
}

void set_counters(benchmark::State& state, Int2 n, double floats_per_cell) {
  const double cells = double(n.x) * n.y * double(state.iterations());
  state.counters["cells/s"] = benchmark::Counter(cells, benchmark::Counter::kIsRate);
  state.counters["bytes/s"] =
      benchmark::Counter(cells * floats_per_cell * sizeof(float), benchmark::Counter::kIsRate);
}

void BM_AdvectScalar(benchmark::State& state) {
  const Int2 n{int(state.range(0)), int(state.range(0))};
  const FieldF q0 = noise(n, 1, 1.0f), u = noise(n, 2, 1.0f), v = noise(n, 3, 1.0f);
  FieldF q(n, 1);
  const AdvectParams p{2.0f, n, false};
  for (auto _ : state) {
    advect_scalar(q0.view(), u.view(), v.view(), q.view(), q.interior(), p);
    benchmark::DoNotOptimize(q.raw());
  }
  set_counters(state, n, 4);  // q0, u, v in, q out
}

void BM_AdvectVelocity(benchmark::State& state) {
  const Int2 n{int(state.range(0)), int(state.range(0))};
  const FieldF u0 = noise(n, 2, 1.0f), v0 = noise(n, 3, 1.0f);
  FieldF u(n, 1), v(n, 1);
  const AdvectParams p{2.0f, n, false};
  for (auto _ : state) {
    advect_velocity(u0.view(), v0.view(), u.view(), v.view(), u.interior(), p);
    benchmark::DoNotOptimize(u.raw());
  }
  set_counters(state, n, 4);
}

void BM_StamJacobiSweep(benchmark::State& state) {
  const Int2 n{int(state.range(0)), int(state.range(0))};
  const FieldF x0 = noise(n, 4, 1.0f);
  FieldF a = noise(n, 5, 1.0f), b(n, 1);
  const StamSweepParams p{1.0f, 0.25f};
  for (auto _ : state) {
    stam_jacobi_sweep(x0.view(), a.view(), b.view(), b.interior(), p);
    set_bnd(b.view(), n, 0);
    std::swap(a, b);
    benchmark::DoNotOptimize(a.raw());
  }
  set_counters(state, n, 3);  // x0, x_in in, x_out out
}

// 20 Jacobi sweeps of the engine's implicit-diffusion operator (kernels/stencil_sweeps.h), sweep
// by sweep (one pass over the grid each) or temporally blocked (one pass), on the serial
// executor or on the threads back end's workers (all cores). Args: N, blocked, threaded.
void BM_JacobiSweeps20(benchmark::State& state) {
  const Int2 n{int(state.range(0)), int(state.range(0))};
  const bool blocked = state.range(1) != 0, threaded = state.range(2) != 0;
  const StencilOperator op = assemble_stencil_operator(
      n, 1.0, 0.75, nullptr, BoundaryKind::kNeumann, BoundaryKind::kNeumann);
  stencil::UniformRows uniform(n.y);
  uniform.analyse(op);
  const FieldF b = noise(n, 6, 1.0f);
  FieldF x = noise(n, 7, 1.0f), y(n, 1);
  std::unique_ptr<ThreadBackend> backend;
  std::unique_ptr<RowExecutor> owned;
  RowExecutor* ex = &RowExecutor::serial();
  if (threaded) {
    backend = std::make_unique<ThreadBackend>(ThreadBackendOptions{});
    owned = std::make_unique<RowExecutor>(*backend);
    ex = owned.get();
  }
  stencil::JacobiBlocking blocking(n, ex->workers());
  for (auto _ : state) {
    if (blocked) {
      blocking.sweeps(op, b, x, y, 20, *ex, &uniform);
      std::swap(x, y);
    } else {
      for (int s = 0; s < 20; ++s) {
        stencil::jacobi_sweep(op, b, x, y, *ex, &uniform);
        std::swap(x, y);
      }
    }
    benchmark::DoNotOptimize(x.raw());
  }
  state.SetLabel(std::string(blocked ? "blocked" : "sweep by sweep") + ", " +
                 std::to_string(ex->workers()) + " workers");
  state.counters["cell_sweeps/s"] = benchmark::Counter(
      double(n.x) * n.y * 20 * double(state.iterations()), benchmark::Counter::kIsRate);
}

void BM_StamRedBlackSweep(benchmark::State& state) {
  const Int2 n{int(state.range(0)), int(state.range(0))};
  const FieldF x0 = noise(n, 4, 1.0f);
  FieldF x = noise(n, 5, 1.0f);
  const StamSweepParams p{1.0f, 0.25f};
  for (auto _ : state) {
    stam_rbgs_half_sweep(x0.view(), x.view(), x.interior(), 0, p);
    set_bnd(x.view(), n, 0);
    stam_rbgs_half_sweep(x0.view(), x.view(), x.interior(), 1, p);
    set_bnd(x.view(), n, 0);
    benchmark::DoNotOptimize(x.raw());
  }
  set_counters(state, n, 3);  // x0 and x read, x written
}

// One projection of a random velocity (fresh each time: no warm start) with each solver:
// Jacobi and red-black GS at 20 sweeps, ICCG and multigrid to a relative residual of 1e-4.
void BM_Projection(benchmark::State& state) {
  const Int2 n{int(state.range(0)), int(state.range(0))};
  const SolverKind kind = SolverKind(state.range(1));
  FluidConfig config;
  config.kind = FluidSceneKind::kInk;
  config.walls = FluidWalls::kFreeSlip;
  const bool fixed = kind == SolverKind::kJacobi || kind == SolverKind::kRedBlackGaussSeidel;
  config.pressure_solver = {kind, fixed ? 20 : 200, fixed ? 0.0 : 1e-4};
  FluidStep fluid(config, n, 1.0 / n.x, 0.01);
  SimState s;
  s.dt = 0.01;
  fluid.reset(s);
  const FieldF u0 = noise(n, 6, 1.0f), v0 = noise(n, 7, 1.0f);
  int iterations = 0;
  for (auto _ : state) {
    state.PauseTiming();
    s.u = u0;
    s.v = v0;
    s.p.fill(0.0f);
    state.ResumeTiming();
    iterations = fluid.project(s).iterations;
    benchmark::DoNotOptimize(s.u.raw());
  }
  state.SetLabel(std::string(solver_kind_name(kind)) + ", " + std::to_string(iterations) +
                 " iterations");
  // rhs (u, v in, rhs out), the solve (per iteration: p read + written, rhs read), gradient
  // (p read, u, v read + written), face velocities (u, v, p in, 2 out).
  set_counters(state, n, 3 + 3.0 * iterations + 5 + 5);
}

void sizes(benchmark::internal::Benchmark* b) {
  for (int n : {128, 256, 512, 1024}) b->Arg(n);
}

void projection_args(benchmark::internal::Benchmark* b) {
  for (int n : {128, 256, 512, 1024})
    for (SolverKind k : {SolverKind::kJacobi, SolverKind::kRedBlackGaussSeidel, SolverKind::kIccg,
                         SolverKind::kMultigrid})
      b->Args({n, int(k)});
}

BENCHMARK(BM_AdvectScalar)->Apply(sizes)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_AdvectVelocity)->Apply(sizes)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_StamJacobiSweep)->Apply(sizes)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_StamRedBlackSweep)->Apply(sizes)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_JacobiSweeps20)
    ->ArgsProduct({{256, 512, 1024, 2048, 4096}, {0, 1}, {0, 1}})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Projection)->Apply(projection_args)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace ardcell

BENCHMARK_MAIN();
