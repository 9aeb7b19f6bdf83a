// seed 003, Eqn 28's linear solve x <- (I - delta K)^{-1} x on a periodic N x N grid by FFT
// (kernels/periodic_stencil_solve.h), on every hardware thread: Table 2's (a) (real symbol,
// 3x3 taps) and (d) (rank 4, 5x5 taps; the stencil does not change the FFT's cost).
#include <benchmark/benchmark.h>

#include <random>

#include "kernels/generalized_diffusion.h"
#include "kernels/periodic_stencil_solve.h"
#include "runtime/thread/thread_backend.h"

namespace {

using namespace ardcell;

void BM_PeriodicSolve(benchmark::State& state, TensorSequence sequence) {
  const int n = int(state.range(0));
  ThreadBackend backend;  // one worker per hardware thread
  RowExecutor executor(backend);
  PeriodicStencilSolve solve(Int2{n, n}, assemble_generalized_stencil(sequence), executor);
  solve.set_delta(0.05);  // well-posed for both (d's backward hyperdiffusion needs < 1/12)
  FieldF x(Int2{n, n}, 2);
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int y = 0; y < n; ++y)
    for (int i = 0; i < n; ++i) x(i, y) = u(rng);
  for (auto _ : state) {
    solve.solve(x);
    benchmark::DoNotOptimize(x.raw());
  }
  state.counters["solves_per_s"] =
      benchmark::Counter(double(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["workers"] = double(executor.workers());
}

BENCHMARK_CAPTURE(BM_PeriodicSolve, a, kTable2A)
    ->Name("PeriodicSolve/a")
    ->Arg(256)
    ->Arg(512)
    ->Arg(1024)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_PeriodicSolve, d, kTable2D)
    ->Name("PeriodicSolve/d")
    ->Arg(256)
    ->Arg(512)
    ->Arg(1024)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
