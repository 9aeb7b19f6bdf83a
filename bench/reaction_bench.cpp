// Reaction per model: forward Euler (explicit rates), implicit Newton (Eqn 6), implicit table
// (cells/s, 256x256 cells per iteration, single thread). And implicit diffusion (Eqn 13 and
// Eqn 19) per solver on 256x256.
#include <benchmark/benchmark.h>

#include <random>

#include "kernels/aniso_diffusion.h"
#include "kernels/anisotropy.h"
#include "kernels/reaction.h"
#include "kernels/reaction_table.h"

namespace {

using namespace ardcell;

constexpr Int2 kSize{256, 256};

void fill_state(const ReactionParams& p, FieldF& a, FieldF& b) {
  const ConcentrationBox r = typical_range(p);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.05, 0.95);
  for (int y = 0; y < kSize.y; ++y)
    for (int x = 0; x < kSize.x; ++x) {
      a(x, y) = float(r.a_lo + (r.a_hi - r.a_lo) * u(rng));
      b(x, y) = float(r.b_lo + (r.b_hi - r.b_lo) * u(rng));
    }
}

enum Method { kExplicit, kNewton, kTable };

void BM_Reaction(benchmark::State& state) {
  ReactionParams p;
  p.model = ReactionModel(state.range(0));
  const Method method = Method(state.range(1));
  const float dt = 1.0f;
  FieldF a(kSize, 1), b(kSize, 1), ao(kSize, 1), bo(kSize, 1);
  fill_state(p, a, b);
  const ReactionTable table =
      method == kTable ? ReactionTable(p, dt, typical_range(p), 256) : ReactionTable();
  for (auto _ : state) {
    switch (method) {
      case kExplicit:
        reaction_explicit_tile(a.view(), b.view(), ao.view(), bo.view(), a.interior(), p, dt);
        break;
      case kNewton:
        reaction_implicit_tile(a.view(), b.view(), ao.view(), bo.view(), a.interior(), p, dt);
        break;
      case kTable:
        reaction_table_tile(a.view(), b.view(), ao.view(), bo.view(), a.interior(), table.view());
        break;
    }
    benchmark::DoNotOptimize(ao.raw());
  }
  state.SetLabel(std::string(reaction_model_name(p.model)) + " " +
                 (method == kExplicit ? "explicit"
                  : method == kNewton ? "newton"
                                      : "table"));
  state.counters["cells_per_s"] = benchmark::Counter(
      double(kSize.x) * kSize.y * double(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_Reaction)
    ->ArgsProduct({{0, 1, 2, 3, 4, 5}, {kExplicit, kNewton, kTable}})
    ->Unit(benchmark::kMicrosecond);

// One implicit diffusion step (s = 1) per solver; range(1) = 1: anisotropic (3 lobes,
// conductivity and operator rebuilt each step, as in the RD frame).
void BM_ImplicitDiffusion(benchmark::State& state) {
  const SolverKind kind = SolverKind(state.range(0));
  const bool aniso = state.range(1) != 0;
  const bool fixed = kind == SolverKind::kJacobi || kind == SolverKind::kRedBlackGaussSeidel;
  const SolverSettings settings{kind, fixed ? 20 : 50, fixed ? 0.0 : 1e-5};
  ImplicitDiffusion diffusion(kSize, BoundaryKind::kDirichlet, settings);
  ReactionParams gs;
  FieldF a(kSize, 1), b(kSize, 1), k(kSize, 1);
  fill_state(gs, a, b);
  AnisotropyParams an;
  an.kind = AnisotropyKind::kCosineLobes;
  an.lobes = 3;
  int iterations = 0;
  for (auto _ : state) {
    const FieldF* cond = nullptr;
    if (aniso) {
      conductivity_tile(a.view(), {}, k.view(), a.interior(), an);
      cond = &k;
    }
    iterations = diffusion.step(a, cond, {1.0, 1.0f, false}).iterations;
  }
  state.SetLabel(std::string(solver_kind_name(kind)) + (aniso ? " anisotropic" : " isotropic"));
  state.counters["iterations"] = iterations;
  state.counters["cells_per_s"] = benchmark::Counter(
      double(kSize.x) * kSize.y * double(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_ImplicitDiffusion)->ArgsProduct({{0, 1, 2, 3}, {0, 1}})->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
