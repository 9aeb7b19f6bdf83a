#include "kernels/aniso_diffusion.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <thread>
#include <vector>

#include "kernels/anisotropy.h"
#include "runtime/block_layout.h"
#include "tests/support/in_flight_channel.h"

namespace ardcell {
namespace {

constexpr Int2 kSize{24, 20};

FieldF random_field(uint32_t seed, float lo = 0.0f, float hi = 1.0f) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> d(lo, hi);
  FieldF f(kSize, 1);
  for (int y = -1; y <= kSize.y; ++y)
    for (int x = -1; x <= kSize.x; ++x) f(x, y) = d(rng);
  return f;
}

FieldF lobe_conductivity(const FieldF& a) {
  AnisotropyParams p;
  p.kind = AnisotropyKind::kCosineLobes;
  p.lobes = 3;
  p.lobe_speed[0] = 2.0f;
  p.lobe_speed[1] = 0.5f;
  p.lobe_speed[2] = 1.0f;
  FieldF k(kSize, 1);
  conductivity_tile(a.view(), {}, k.view(), a.interior(), p);
  return k;
}

double dot(const FieldF& a, const FieldF& b) {
  double s = 0;
  for (int y = 0; y < kSize.y; ++y)
    for (int x = 0; x < kSize.x; ++x) s += double(a(x, y)) * b(x, y);
  return s;
}

double total(const FieldF& a) {
  double s = 0;
  for (int y = 0; y < kSize.y; ++y)
    for (int x = 0; x < kSize.x; ++x) s += a(x, y);
  return s;
}

SolverSettings iccg() { return {SolverKind::kIccg, 500, 1e-7}; }

class EveryBoundary : public ::testing::TestWithParam<BoundaryKind> {};

TEST_P(EveryBoundary, AnisotropicOperatorIsSymmetric) {
  const FieldF a = random_field(1);
  const FieldF k = lobe_conductivity(a);
  const StencilOperator op = assemble_stencil_operator(kSize, 1.0, 3.7, &k, GetParam(), GetParam());
  const FieldF x = random_field(2, -1, 1), y = random_field(3, -1, 1);
  FieldF ax(kSize, 1), ay(kSize, 1);
  apply_stencil_operator(op, x, ax);
  apply_stencil_operator(op, y, ay);
  const double xay = dot(x, ay), yax = dot(y, ax);
  EXPECT_NEAR(xay, yax, 1e-5 * (std::abs(xay) + 1.0));
}

TEST_P(EveryBoundary, ImplicitStepKeepsTheMaximumPrinciple) {
  FieldF a = random_field(4, 0.2f, 0.9f);
  const FieldF k = lobe_conductivity(a);
  ImplicitDiffusion d(kSize, GetParam(), iccg());
  d.step(a, &k, {50.0, 0.5f, false});
  for (int y = 0; y < kSize.y; ++y)
    for (int x = 0; x < kSize.x; ++x) {
      EXPECT_GE(a(x, y), 0.2f - 1e-4f);
      EXPECT_LE(a(x, y), 0.9f + 1e-4f);
    }
}

INSTANTIATE_TEST_SUITE_P(Diffusion, EveryBoundary,
                         ::testing::Values(BoundaryKind::kPeriodic, BoundaryKind::kNeumann,
                                           BoundaryKind::kDirichlet));

TEST(AnisoDiffusion, PeriodicAndNeumannConserveMass) {
  for (BoundaryKind b : {BoundaryKind::kPeriodic, BoundaryKind::kNeumann}) {
    for (bool cn : {false, true}) {
      FieldF a = random_field(5);
      const FieldF k = lobe_conductivity(a);
      const double before = total(a);
      ImplicitDiffusion d(kSize, b, iccg());
      const SolveReport r = d.step(a, &k, {1000.0, 0.0f, cn});
      EXPECT_LT(r.relative_residual, 1e-3);  // float32 operator, condition ~ 4 s
      EXPECT_NEAR(total(a), before, 1e-5 * before) << "cn=" << cn;
    }
  }
}

// Eqn 13 on a periodic grid: a Fourier mode is an eigenvector; one implicit step scales it by
// 1 / (1 + s lambda), Crank-Nicolson by (1 - s lambda / 2) / (1 + s lambda / 2), with
// lambda = 4 sin^2(pi m / n) the 5-point Laplacian's eigenvalue.
TEST(AnisoDiffusion, IsotropicStepMatchesTheFourierClosedForm) {
  const int m = 3;
  const double lambda = 4.0 * std::pow(std::sin(std::numbers::pi * m / kSize.x), 2);
  for (SolverKind kind : {SolverKind::kIccg, SolverKind::kMultigrid,
                          SolverKind::kRedBlackGaussSeidel, SolverKind::kJacobi}) {
    for (bool cn : {false, true}) {
      const double s = 0.8;
      FieldF a(kSize, 1);
      for (int y = 0; y < kSize.y; ++y)
        for (int x = 0; x < kSize.x; ++x)
          a(x, y) = float(std::cos(2 * std::numbers::pi * m * x / kSize.x));
      const int iters =
          kind == SolverKind::kJacobi || kind == SolverKind::kRedBlackGaussSeidel ? 400 : 100;
      ImplicitDiffusion d(kSize, BoundaryKind::kPeriodic, {kind, iters, 1e-7});
      d.step(a, nullptr, {s, 0.0f, cn});
      const double factor =
          cn ? (1 - s * lambda / 2) / (1 + s * lambda / 2) : 1.0 / (1.0 + s * lambda);
      for (int y = 0; y < kSize.y; ++y)
        for (int x = 0; x < kSize.x; ++x)
          ASSERT_NEAR(a(x, y), factor * std::cos(2 * std::numbers::pi * m * x / kSize.x), 2e-5)
              << solver_kind_name(kind) << " cn=" << cn;
    }
  }
}

TEST(AnisoDiffusion, DirichletRelaxesToTheBoundaryValue) {
  FieldF a(kSize, 1);
  ImplicitDiffusion d(kSize, BoundaryKind::kDirichlet, iccg());
  for (int i = 0; i < 5; ++i) d.step(a, nullptr, {1e5, 0.75f, false});
  for (int y = 0; y < kSize.y; ++y)
    for (int x = 0; x < kSize.x; ++x) EXPECT_NEAR(a(x, y), 0.75f, 1e-3);
  // The boundary value is a fixed point, anisotropic too.
  FieldF c(kSize, 1);
  c.fill(0.3f);
  const FieldF k = lobe_conductivity(random_field(9));
  d.step(c, &k, {10.0, 0.3f, true});
  for (int y = 0; y < kSize.y; ++y)
    for (int x = 0; x < kSize.x; ++x) EXPECT_NEAR(c(x, y), 0.3f, 1e-5);
}

TEST(AnisoDiffusion, SolidCellsKeepTheirValueAndBlockFlux) {
  Field<uint8_t> solid(kSize, 1);
  for (int y = 0; y < kSize.y; ++y) solid(10, y) = 1;  // a wall splitting the domain
  FieldF a(kSize, 1);
  for (int y = 0; y < kSize.y; ++y)
    for (int x = 0; x < 10; ++x) a(x, y) = 1.0f;
  a(10, 3) = 0.25f;
  ImplicitDiffusion d(kSize, BoundaryKind::kNeumann, iccg());
  d.set_solid(&solid);
  d.step(a, nullptr, {100.0, 0.0f, false});
  EXPECT_EQ(a(10, 3), 0.25f);
  for (int y = 0; y < kSize.y; ++y) {
    EXPECT_NEAR(a(3, y), 1.0f, 1e-4);
    EXPECT_NEAR(a(15, y), 0.0f, 1e-4);
  }
}

// A block's step (ImplicitDiffusion over the block, Jacobi or red-black Gauss-Seidel sweeps
// exchanging the iterate's halo between them) gives each of its cells the whole grid's bits:
// anisotropic k averaged across the blocks' edges, every boundary kind (periodic through the
// exchange's wrap), Crank-Nicolson's L A reading the neighbours, the Dirichlet value's flux on
// the domain's edges. The blocks' report is the same on every block: the sweep count exactly,
// the residual to rounding.
TEST(AnisoDiffusion, ABlocksSweepsGiveTheWholeGridsBits) {
  const FieldF a0 = random_field(7);
  const FieldF k = lobe_conductivity(random_field(8));
  for (SolverKind kind : {SolverKind::kJacobi, SolverKind::kRedBlackGaussSeidel})
    for (BoundaryKind boundary :
         {BoundaryKind::kPeriodic, BoundaryKind::kDirichlet, BoundaryKind::kNeumann})
      for (bool cn : {false, true})
        for (Int2 parts : {Int2{2, 1}, Int2{1, 3}, Int2{3, 2}}) {
          const SolverSettings jacobi{kind, 15, 0.0};
          ASSERT_TRUE(ImplicitDiffusion::runs_on_block(jacobi, kSize, boundary));
          const DiffusionStep step{3.0, 0.75f, cn};
          const std::string what = std::string(solver_kind_name(kind)) + " boundary " +
                                   std::to_string(int(boundary)) + (cn ? " cn " : " ") +
                                   std::to_string(parts.x) + "x" + std::to_string(parts.y);
          FieldF whole = a0;
          ImplicitDiffusion one(kSize, boundary, jacobi);
          const SolveReport expected = one.step(whole, &k, step);

          const bool wraps = boundary == BoundaryKind::kPeriodic;
          const BlockLayout layout = BlockLayout::split(kSize, parts, wraps, wraps);
          LocalBlockGroup group(layout, 1);
          std::vector<FieldF> fields, conductivities;
          for (int b = 0; b < layout.count(); ++b) {
            const Box2 cells = layout.block(b);
            fields.push_back(FieldF::over(cells, 1));
            conductivities.push_back(FieldF::over(cells, 1));
            copy_box<float>(a0.view(), fields.back().view(), cells);
            copy_box<float>(k.view(), conductivities.back().view(), cells);
          }
          std::vector<SolveReport> reports(std::size_t(layout.count()));
          std::vector<std::thread> threads;
          for (int b = 0; b < layout.count(); ++b)
            threads.emplace_back([&, b] {
              // Made on its block's thread: the serial executor's reduction scratch is per thread.
              const std::size_t i = std::size_t(b);
              ImplicitDiffusion d(kSize, layout.block(b), boundary, jacobi);
              group.channel(b).exchange(conductivities[i], 1);  // as RdStepper does
              reports[i] = d.step(fields[i], &conductivities[i], step, &group.channel(b));
            });
          for (std::thread& t : threads) t.join();
          for (int b = 0; b < layout.count(); ++b) {
            const std::size_t i = std::size_t(b);
            const Box2 cells = layout.block(b);
            for (int y = cells.min.y; y < cells.max.y; ++y)
              for (int x = cells.min.x; x < cells.max.x; ++x)
                ASSERT_EQ(fields[i](x, y), whole(x, y)) << what << " at " << x << "," << y;
            EXPECT_EQ(reports[i].iterations, expected.iterations) << what;
            EXPECT_EQ(reports[i].relative_residual, reports[0].relative_residual) << what;
            EXPECT_NEAR(reports[i].relative_residual, expected.relative_residual,
                        1e-12 + 1e-9 * expected.relative_residual)
                << what;
          }
          EXPECT_GT(expected.relative_residual, 0.0) << what;  // 15 sweeps do not converge
        }
}

// Red-black Gauss-Seidel across a wrap of an odd number of cells updates a colour next to
// itself in an order a block cannot keep: those grids solve on the gathered grid.
TEST(AnisoDiffusion, RbgsAcrossAnOddWrapIsNotABlocksToSweep) {
  const SolverSettings rbgs{SolverKind::kRedBlackGaussSeidel, 10, 0.0};
  EXPECT_FALSE(ImplicitDiffusion::runs_on_block(rbgs, {25, 20}, BoundaryKind::kPeriodic));
  EXPECT_FALSE(ImplicitDiffusion::runs_on_block(rbgs, {24, 21}, BoundaryKind::kPeriodic));
  EXPECT_TRUE(ImplicitDiffusion::runs_on_block(rbgs, {25, 21}, BoundaryKind::kNeumann));
  EXPECT_TRUE(ImplicitDiffusion::runs_on_block({SolverKind::kJacobi, 10, 0.0}, {25, 21},
                                               BoundaryKind::kPeriodic));
  EXPECT_FALSE(ImplicitDiffusion::runs_on_block({SolverKind::kIccg, 10, 0.0}, {24, 20},
                                                BoundaryKind::kNeumann));
  EXPECT_FALSE(ImplicitDiffusion::runs_on_block({SolverKind::kMultigrid, 10, 0.0}, {24, 20},
                                                BoundaryKind::kNeumann));
}

// The sweeps compute a block's inner cells while the exchange of their input is in flight, and
// the ring along its edges after it: with the halo arriving only at finish()
// (tests/support/in_flight_channel.h), still the whole grid's bits, one exchange a sweep.
TEST(AnisoDiffusion, ABlocksInnerCellsSweepWhileTheExchangeIsInFlight) {
  const SolverSettings jacobi{SolverKind::kJacobi, 12, 0.0};
  const FieldF a0 = random_field(11);
  const FieldF k = lobe_conductivity(random_field(12));
  const DiffusionStep step{2.5, 0.5f, true};
  FieldF whole = a0;
  ImplicitDiffusion one(kSize, BoundaryKind::kPeriodic, jacobi);
  one.step(whole, &k, step);
  const BlockLayout layout = BlockLayout::split(kSize, {2, 2}, true, true);
  LocalBlockGroup group(layout, 1);
  std::vector<FieldF> fields(4);
  std::vector<int> exchanges(4);
  std::vector<std::thread> threads;
  for (int b = 0; b < 4; ++b)
    threads.emplace_back([&, b] {
      const std::size_t i = std::size_t(b);
      InFlightChannel channel(group.channel(b));
      fields[i] = FieldF::over(layout.block(b), 1);
      FieldF kb = FieldF::over(layout.block(b), 1);
      copy_box<float>(a0.view(), fields[i].view(), layout.block(b));
      copy_box<float>(k.view(), kb.view(), layout.block(b));
      group.channel(b).exchange(kb, 1);
      ImplicitDiffusion d(kSize, layout.block(b), BoundaryKind::kPeriodic, jacobi);
      d.step(fields[i], &kb, step, &channel);
      exchanges[i] = channel.begun;
    });
  for (std::thread& t : threads) t.join();
  for (int b = 0; b < 4; ++b) {
    const Box2 cells = layout.block(b);
    for (int y = cells.min.y; y < cells.max.y; ++y)
      for (int x = cells.min.x; x < cells.max.x; ++x)
        ASSERT_EQ(fields[std::size_t(b)](x, y), whole(x, y)) << b << " at " << x << "," << y;
    // Crank-Nicolson's field, the start, and one after each of the 12 sweeps.
    EXPECT_EQ(exchanges[std::size_t(b)], 14);
  }
}

// With a tolerance, every block stops at the same sweep (the norms summed over the blocks).
TEST(AnisoDiffusion, ABlocksToleranceStopsEveryBlockAtOneSweep) {
  const SolverSettings jacobi{SolverKind::kJacobi, 500, 1e-4};
  const FieldF a0 = random_field(9);
  FieldF whole = a0;
  ImplicitDiffusion one(kSize, BoundaryKind::kNeumann, jacobi);
  const SolveReport expected = one.step(whole, nullptr, {2.0, 0.0f, false});
  ASSERT_LT(expected.iterations, 500);
  const BlockLayout layout = BlockLayout::split(kSize, {2, 2}, false, false);
  LocalBlockGroup group(layout, 1);
  std::vector<SolveReport> reports(4);
  std::vector<std::thread> threads;
  for (int b = 0; b < 4; ++b)
    threads.emplace_back([&, b] {
      FieldF f = FieldF::over(layout.block(b), 1);
      copy_box<float>(a0.view(), f.view(), layout.block(b));
      ImplicitDiffusion d(kSize, layout.block(b), BoundaryKind::kNeumann, jacobi);
      reports[std::size_t(b)] = d.step(f, nullptr, {2.0, 0.0f, false}, &group.channel(b));
    });
  for (std::thread& t : threads) t.join();
  for (const SolveReport& r : reports) {
    EXPECT_EQ(r.iterations, reports[0].iterations);
    EXPECT_LE(r.relative_residual, 1e-4);
    EXPECT_NEAR(r.iterations, expected.iterations, 1);
  }
}

}  // namespace
}  // namespace ardcell
