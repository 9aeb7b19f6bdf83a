#include "kernels/gray_scott9.h"

#include "tests/support/alloc_counter.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <vector>

#include "runtime/row_executor.h"
#include "runtime/thread/thread_backend.h"

namespace ardcell {
namespace {

// An executor with `workers` workers: the calling thread's serial one for 1, else a threads back
// end of its own (unpinned: tests share the machine).
struct Executor {
  std::unique_ptr<ThreadBackend> backend;
  std::unique_ptr<RowExecutor> own;
  RowExecutor* ex = &RowExecutor::serial();
  explicit Executor(int workers) {
    if (workers <= 1) return;
    ThreadBackendOptions o;
    o.workers = workers;
    o.pin = false;
    backend = std::make_unique<ThreadBackend>(o);
    own = std::make_unique<RowExecutor>(*backend);
    ex = own.get();
  }
};

// Seed 001's fields and a blocked stepper over them.
struct Sim {
  FieldF a, b;
  GrayScott9Blocked gs;
  Sim(Int2 size, RowExecutor& ex, int bands, int block_steps = GrayScott9Blocked::kBlockSteps,
      GrayScott9Blocked::Rows rows = GrayScott9Blocked::Rows::kPeriodic)
      : a(GrayScott9Blocked::make_field(size)),
        b(GrayScott9Blocked::make_field(size)),
        gs(size, ex, bands, block_steps, rows) {}
  void run(int64_t steps) { gs.run(a, b, steps, GrayScott9Params{}); }
  // Seed 001's start: A = 1, B = 0, a 10x10 square of B = 1 at the centre.
  void seed_square() {
    a.fill(1.0f);
    b.fill(0.0f);
    const Int2 n = a.size();
    for (int y = 0; y < 10; ++y)
      for (int x = 0; x < 10; ++x) {
        const int px = n.x / 2 + x - 5, py = n.y / 2 + y - 5;
        if (px >= 0 && px < n.x && py >= 0 && py < n.y) b(px, py) = 1.0f;
      }
  }
};

// Deterministic values in [0, 1) so that every cell, ghosts and wrap included, matters.
void fill_noise(Sim& s, uint32_t seed) {
  uint32_t x = seed;
  auto next = [&x] {
    x = x * 1664525u + 1013904223u;
    return float(x >> 8) / float(1u << 24);
  };
  for (int y = 0; y < s.a.ny(); ++y)
    for (int i = 0; i < s.a.nx(); ++i) {
      s.a(i, y) = next();
      s.b(i, y) = 0.5f * next();
    }
}

void expect_same_bits(const Sim& want, const Sim& got, Int2 shift = {0, 0}) {
  const int nx = want.a.nx(), ny = want.a.ny();
  for (int y = 0; y < ny; ++y)
    for (int x = 0; x < nx; ++x) {
      const int gx = (x + shift.x) % nx, gy = (y + shift.y) % ny;
      ASSERT_EQ(want.a(x, y), got.a(gx, gy)) << "A at " << x << "," << y;
      ASSERT_EQ(want.b(x, y), got.b(gx, gy)) << "B at " << x << "," << y;
    }
}

// Reference: one band, one step per pass (plain sweeps of the same row kernel), on the calling
// thread. Widths 40 (not a whole number of SIMD vectors) and 48; heights split unevenly; bands
// run on 1, 2 and 3 workers (more bands than workers: the back end hands them out).
TEST(GrayScott9Blocked, EveryScheduleGivesTheBitsOfStepByStepSweeps) {
  for (const Int2 size : {Int2{40, 30}, Int2{48, 37}}) {
    const int steps = 23;
    Sim ref(size, RowExecutor::serial(), 1, 1);
    fill_noise(ref, 7);
    ref.run(steps);
    struct Schedule {
      int workers, bands, block_steps;
    };
    for (const Schedule sc :
         {Schedule{1, 1, 2}, Schedule{1, 3, 5}, Schedule{2, 2, 2}, Schedule{2, 2, 5},
          Schedule{3, 3, 8}, Schedule{2, 2, 1}, Schedule{2, 7, 3}, Schedule{3, 4, 3}}) {
      Executor ex(sc.workers);
      Sim s(size, *ex.ex, sc.bands, sc.block_steps);
      fill_noise(s, 7);
      s.run(steps);  // 23: blocks of unequal lengths for every block_steps above
      SCOPED_TRACE(testing::Message()
                   << size.x << "x" << size.y << " workers " << sc.workers << " bands " << sc.bands
                   << " block_steps " << sc.block_steps);
      expect_same_bits(ref, s);
    }
  }
}

TEST(GrayScott9Blocked, RunInPiecesEqualsOneRun) {
  Executor ex(2);
  Sim whole({40, 30}, *ex.ex, 2), pieces({40, 30}, *ex.ex, 2);
  fill_noise(whole, 3);
  fill_noise(pieces, 3);
  whole.run(20);
  for (int i : {1, 1, 3, 7, 8}) pieces.run(i);
  expect_same_bits(whole, pieces);
}

// Resumed runs take the differing vectors the last run recorded instead of scanning the rows:
// the bits of fresh runs, and the cells computed stay few. A resumed run after the fields were
// written behind its back is the caller's error; one after a run that could not record (blocks
// of one step, no fixed point) or on other fields scans anyway.
TEST(GrayScott9Blocked, ResumedRunsGiveTheBitsOfFreshOnes) {
  Executor ex(2);
  for (const int bands : {1, 3}) {
    SCOPED_TRACE(testing::Message() << bands << " bands");
    Sim fresh({200, 160}, *ex.ex, bands), resumed({200, 160}, *ex.ex, bands);
    fresh.seed_square();
    resumed.seed_square();
    for (const int piece : {10, 10, 1, 7, 10, 10, 4}) {
      fresh.gs.run(fresh.a, fresh.b, piece, GrayScott9Params{});
      resumed.gs.run(resumed.a, resumed.b, piece, GrayScott9Params{}, true);
      expect_same_bits(fresh, resumed);
      EXPECT_EQ(fresh.gs.last_run_cell_updates(), resumed.gs.last_run_cell_updates());
    }
    EXPECT_LT(double(resumed.gs.last_run_cell_updates()), 0.7 * 200 * 160 * 4);  // 4 steps
    // Other fields (a copy): scanned, so the same bits again.
    Sim other({200, 160}, *ex.ex, bands);
    other.a = resumed.a;
    other.b = resumed.b;
    resumed.a = other.a;  // new storage: the recorded vectors do not apply
    resumed.b = other.b;
    for (Sim* s : {&fresh, &resumed}) s->gs.run(s->a, s->b, 10, GrayScott9Params{}, s == &resumed);
    expect_same_bits(fresh, resumed);
  }
}

// A periodic grid cut into blocks of whole rows, each stepped with its rows from the halo: the
// neighbours' rows (wrapping between the last block and the first) copied in before every run
// of block_steps() steps, as a rank's halo exchange does. Uneven blocks, several bands, a
// seed-001 square (skipping quiescent cells) and noise (none skipped): the whole grid's bits.
TEST(GrayScott9Blocked, RowBlocksFromTheHaloGiveTheWholeGridsBits) {
  const Int2 size{48, 61};
  const int steps = 37;
  struct Schedule {
    int workers, bands, block_steps;
  };
  for (const int blocks : {1, 2, 3})
    for (const Schedule sc : {Schedule{1, 1, 5}, Schedule{2, 2, 5}, Schedule{2, 3, 3},
                              Schedule{1, 2, 4}, Schedule{1, 1, 1}})
      for (const bool noise : {false, true}) {
        SCOPED_TRACE(testing::Message()
                     << blocks << " blocks, workers " << sc.workers << " bands " << sc.bands
                     << " block_steps " << sc.block_steps << (noise ? " noise" : " square"));
        Sim whole(size, RowExecutor::serial(), 1, 1);
        if (noise)
          fill_noise(whole, 11);
        else
          whole.seed_square();
        Executor ex(sc.workers);
        std::vector<int> y0(std::size_t(blocks) + 1);
        std::vector<std::unique_ptr<Sim>> parts;
        int k = sc.block_steps;
        for (int i = 0; i <= blocks; ++i) y0[std::size_t(i)] = size.y * i / blocks;
        for (int i = 0; i < blocks; ++i) {
          const int rows = y0[std::size_t(i) + 1] - y0[std::size_t(i)];
          parts.push_back(std::make_unique<Sim>(Int2{size.x, rows}, *ex.ex, sc.bands,
                                                sc.block_steps,
                                                GrayScott9Blocked::Rows::kFromHalo));
          // The block's fields over its own cells of the grid (global coordinates).
          Sim& part = *parts.back();
          const Box2 cells{{0, y0[std::size_t(i)]}, {size.x, y0[std::size_t(i) + 1]}};
          part.a = FieldF::over(cells, GrayScott9Blocked::kHalo);
          part.b = FieldF::over(cells, GrayScott9Blocked::kHalo);
          for (int y = cells.min.y; y < cells.max.y; ++y)
            for (int x = 0; x < size.x; ++x) {
              part.a(x, y) = whole.a(x, y);
              part.b(x, y) = whole.b(x, y);
            }
          k = std::min(k, part.gs.block_steps());
        }
        whole.run(steps);
        // Global row g (wrapped) as its block holds it now.
        auto owner_row = [&](int g, int chem) -> const float* {
          g = (g % size.y + size.y) % size.y;
          int i = 0;
          while (g >= y0[std::size_t(i) + 1]) ++i;
          const Sim& part = *parts[std::size_t(i)];
          return (chem == 0 ? part.a : part.b).row(g);
        };
        std::vector<float> rows_in(std::size_t(blocks) * 2 * std::size_t(k) * 2 *
                                   std::size_t(size.x));
        for (int done = 0; done < steps;) {
          const int run = std::min(k, steps - done);
          // Every block's halo rows first (from the others' current rows), then every run.
          std::size_t at = 0;
          for (int i = 0; i < blocks; ++i)
            for (int r = 0; r < k; ++r)
              for (const int g : {y0[std::size_t(i)] - k + r, y0[std::size_t(i) + 1] + r})
                for (int chem = 0; chem < 2; ++chem, at += std::size_t(size.x))
                  std::copy_n(owner_row(g, chem), size.x, rows_in.begin() + std::ptrdiff_t(at));
          at = 0;
          for (int i = 0; i < blocks; ++i) {
            Sim& part = *parts[std::size_t(i)];
            for (int r = 0; r < k; ++r)
              for (const int y : {y0[std::size_t(i)] - k + r, y0[std::size_t(i) + 1] + r})
                for (int chem = 0; chem < 2; ++chem, at += std::size_t(size.x))
                  std::copy_n(rows_in.begin() + std::ptrdiff_t(at), size.x,
                              (chem == 0 ? part.a : part.b).row(y));
          }
          for (auto& part : parts) part->run(run);
          done += run;
        }
        for (int i = 0; i < blocks; ++i)
          for (int y = y0[std::size_t(i)]; y < y0[std::size_t(i) + 1]; ++y)
            for (int x = 0; x < size.x; ++x) {
              const Sim& part = *parts[std::size_t(i)];
              ASSERT_EQ(whole.a(x, y), part.a(x, y)) << x << "," << y;
              ASSERT_EQ(whole.b(x, y), part.b(x, y)) << x << "," << y;
            }
      }
}

// Periodic wrap: shifting the initial state shifts the result, bit for bit (the ghosts carry
// exactly the wrapped values, in x inside the SIMD lanes and in y across bands and blocks).
TEST(GrayScott9Blocked, PeriodicShiftCommutesWithStepping) {
  const int nx = 40, ny = 30;
  Executor ex(2);
  Sim base({nx, ny}, *ex.ex, 2), shifted({nx, ny}, *ex.ex, 2);
  fill_noise(base, 11);
  const Int2 shift{7, 11};
  for (int y = 0; y < ny; ++y)
    for (int x = 0; x < nx; ++x) {
      shifted.a((x + shift.x) % nx, (y + shift.y) % ny) = base.a(x, y);
      shifted.b((x + shift.x) % nx, (y + shift.y) % ny) = base.b(x, y);
    }
  base.run(17);
  shifted.run(17);
  expect_same_bits(base, shifted, shift);
}

// The periodic ghosts of the result (rows -1 and ny, columns -1 and nx, corners) hold the cells
// they wrap, whatever they held before (a painted field's ghosts are stale).
TEST(GrayScott9Blocked, WritesThePeriodicGhosts) {
  Executor ex(2);
  Sim s({37, 29}, *ex.ex, 2);
  fill_noise(s, 5);
  s.a(-1, 4) = s.b(37, 10) = -7.0f;  // stale ghosts: the kernel must not read them
  Sim ref({37, 29}, RowExecutor::serial(), 1, 1);
  fill_noise(ref, 5);
  s.run(9);
  ref.run(9);
  expect_same_bits(ref, s);
  for (const FieldF* f : {&s.a, &s.b})
    for (int y = -1; y <= 29; ++y)
      for (int x = -1; x <= 37; ++x)
        ASSERT_EQ((*f)(x, y), (*f)((x + 37) % 37, (y + 29) % 29)) << x << "," << y;
}

// Quiescent cells are skipped only where that changes no bit: seed 001's start on grids whose
// width is and is not a whole number of SIMD vectors, with the square in the middle and across
// the periodic corner (the pattern then crosses both wraps), for several schedules, against the
// same schedules with skipping off.
TEST(GrayScott9Blocked, SkippingQuiescentCellsChangesNoBit) {
  struct Case {
    Int2 size;
    Int2 square_at;  // lower-left cell of the 10x10 square of B = 1
  };
  struct Schedule {
    int workers, bands, block_steps;
  };
  for (const Case c :
       {Case{{256, 200}, {123, 95}}, Case{{250, 190}, {120, 90}}, Case{{250, 190}, {245, 186}}}) {
    for (const Schedule sc : {Schedule{1, 1, 4}, Schedule{2, 2, 2}, Schedule{2, 2, 5},
                              Schedule{3, 3, 8}, Schedule{2, 8, 4}}) {
      SCOPED_TRACE(testing::Message()
                   << c.size.x << "x" << c.size.y << " square at " << c.square_at.x << ","
                   << c.square_at.y << " workers " << sc.workers << " bands " << sc.bands
                   << " block_steps " << sc.block_steps);
      Executor ex(sc.workers);
      Sim dense(c.size, *ex.ex, sc.bands, sc.block_steps);
      Sim skipping(c.size, *ex.ex, sc.bands, sc.block_steps);
      dense.gs.set_skip_quiescent(false);
      for (Sim* s : {&dense, &skipping}) {
        s->a.fill(1.0f);
        s->b.fill(0.0f);
        for (int y = 0; y < 10; ++y)
          for (int x = 0; x < 10; ++x)
            s->b((c.square_at.x + x) % c.size.x, (c.square_at.y + y) % c.size.y) = 1.0f;
      }
      // In pieces, so that later runs start from a settled background.
      for (const int piece : {100, 1, 99}) {
        dense.run(piece);
        skipping.run(piece);
        expect_same_bits(dense, skipping);
      }
      const double computed =
          double(skipping.gs.last_run_cell_updates()) / double(dense.gs.last_run_cell_updates());
      // After 200 steps the pattern spans most of these grids (the last piece computes 86-91%
      // of the cells on 2026-11-21); across the corner it spans both wraps, so nothing is
      // skipped there.
      EXPECT_GT(skipping.gs.last_run_cell_updates(), 0);
      if (c.square_at.x < c.size.x / 2) {
        EXPECT_LT(computed, 0.95);
      }
    }
  }
}

// A state with no uniform region (noise) is computed in full, and a state at the fixed point
// everywhere is not computed at all and stays there.
TEST(GrayScott9Blocked, SkippingFollowsTheFixedPoint) {
  Executor ex(2);
  Sim noisy({48, 37}, *ex.ex, 2, 4);
  fill_noise(noisy, 9);
  noisy.run(20);
  EXPECT_GE(noisy.gs.last_run_cell_updates(), int64_t(48) * 37 * 20);

  Sim uniform({48, 37}, *ex.ex, 2, 4);
  uniform.a.fill(1.0f);
  uniform.b.fill(0.0f);
  uniform.run(300);  // settles on the fixed point, bit for bit, everywhere
  const float fixed_a = uniform.a(0, 0);
  EXPECT_NEAR(fixed_a, 1.0f, 1e-5f);  // rounding drifts seed 001's A = 1 by an ulp or two
  uniform.run(100);
  EXPECT_EQ(uniform.gs.last_run_cell_updates(), 0);
  for (int y = 0; y < 37; ++y)
    for (int x = 0; x < 48; ++x) {
      ASSERT_EQ(uniform.a(x, y), fixed_a);
      ASSERT_EQ(uniform.b(x, y), 0.0f);
    }
}

// Moving band boundaries during a run changes no bit: a probe moves every boundary by -6 .. 6
// rows after every block (as far as the bands' minimum height allows), dense and skipping,
// against one band stepping one step at a time. The partition is checked to have moved.
TEST(GrayScott9Blocked, MovingBandBoundariesChangesNoBit) {
  struct Case {
    Int2 size;
    int workers, bands, block_steps;
    bool seed_square;  // else noise (no quiescent cells)
  };
  for (const Case c : {Case{{40, 60}, 2, 2, 3, false}, Case{{48, 97}, 3, 3, 4, false},
                       Case{{33, 80}, 4, 4, 2, false}, Case{{128, 120}, 2, 2, 4, true},
                       Case{{100, 90}, 3, 3, 5, true}, Case{{100, 90}, 1, 4, 5, true},
                       Case{{64, 100}, 2, 6, 3, true}}) {
    SCOPED_TRACE(testing::Message() << c.size.x << "x" << c.size.y << " workers " << c.workers
                                    << " bands " << c.bands << " block_steps " << c.block_steps);
    Executor ex(c.workers);
    Sim ref(c.size, RowExecutor::serial(), 1, 1);
    Sim moved(c.size, *ex.ex, c.bands, c.block_steps);
    for (Sim* s : {&ref, &moved}) {
      if (c.seed_square)
        s->seed_square();
      else
        fill_noise(*s, 13);
    }
    moved.gs.set_balance_probe(12345);
    const std::vector<int> before = moved.gs.band_starts();
    std::vector<std::vector<int>> seen;
    for (const int piece : {37, 1, 60}) {
      ref.run(piece);
      moved.run(piece);
      expect_same_bits(ref, moved);
      seen.push_back(moved.gs.band_starts());
    }
    EXPECT_TRUE(seen[0] != before || seen[1] != before || seen[2] != before);
    for (const std::vector<int>& starts : seen) {
      ASSERT_EQ(int(starts.size()), c.bands);
      EXPECT_EQ(starts[0], 0);
      for (int t = 1; t < c.bands; ++t)
        EXPECT_GE(starts[std::size_t(t)] - starts[std::size_t(t - 1)], 2 * c.block_steps);
      EXPECT_GE(c.size.y - starts.back(), 2 * c.block_steps);
    }
  }
}

// The balancing rule: rows go from the slower band to the faster one, about half of what would
// equalise them (a row taken to cost the same throughout a band), none within 5%.
TEST(GrayScott9Blocked, BalancedBoundaryShiftGivesRowsToTheFasterBand) {
  EXPECT_EQ(balanced_boundary_shift(1.0, 1.0, 200, 200, 50), 0);
  EXPECT_EQ(balanced_boundary_shift(1.04, 1.0, 200, 200, 50), 0);  // noise
  EXPECT_EQ(balanced_boundary_shift(0.0, 0.0, 200, 200, 50), 0);
  // b's core runs at 0.58 of a's speed: 200 rows each take 1.0 and 1.724. Equal times need a
  // to take 400 * 1 / 1.58 = 253 rows, i.e. 53 from b; half of it per decision.
  const int shift = balanced_boundary_shift(1.0, 1.0 / 0.58, 200, 200, 50);
  EXPECT_EQ(shift, -27);
  EXPECT_EQ(balanced_boundary_shift(1.0 / 0.58, 1.0, 200, 200, 50), 27);
  EXPECT_EQ(balanced_boundary_shift(1.0 / 0.58, 1.0, 200, 200, 10), 10);  // capped
  EXPECT_EQ(balanced_boundary_shift(1.1, 1.0, 4, 4, 10), 1);  // at least a row when over 5%
}

int threads_of_this_process() {
  int n = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator("/proc/self/task")) ++n;
  return n;
}

// The kernel runs on the executor's workers and starts no thread of its own; a run, as a frame
// loop calls it, allocates nothing.
TEST(GrayScott9Blocked, StartsNoThreadAndRunAllocatesNothing) {
  Executor ex(3);
  const int threads = threads_of_this_process();
  Sim sim({64, 48}, *ex.ex, 3, 4);
  sim.seed_square();
  sim.run(5);
  EXPECT_EQ(threads_of_this_process(), threads);
  const long before = g_allocations.load();
  for (int frame = 0; frame < 20; ++frame) sim.run(7);
  EXPECT_EQ(g_allocations.load() - before, 0);
  EXPECT_EQ(sim.gs.bands(), 3);
}

// adopt() gives a field of another halo the kernel's, keeping its cells; one that has it is left
// alone (no allocation).
TEST(GrayScott9Blocked, AdoptKeepsTheCells) {
  FieldF f({21, 13}, 1);
  for (int y = -1; y <= 13; ++y)
    for (int x = -1; x <= 21; ++x) f(x, y) = float(x * 100 + y);
  GrayScott9Blocked::adopt(f);
  ASSERT_TRUE(GrayScott9Blocked::fits(f));
  for (int y = -1; y <= 13; ++y)
    for (int x = -1; x <= 21; ++x) ASSERT_EQ(f(x, y), float(x * 100 + y));
  const float* storage = f.raw();
  const long before = g_allocations.load();
  GrayScott9Blocked::adopt(f);
  EXPECT_EQ(g_allocations.load() - before, 0);
  EXPECT_EQ(f.raw(), storage);
}

// Seed 001's update in double precision, written plainly (3x3 weights, periodic indices).
void reference_steps(int nx, int ny, std::vector<double>& A, std::vector<double>& B, int steps) {
  const double coef[3][3] = {{0.05, 0.2, 0.05}, {0.2, -1.0, 0.2}, {0.05, 0.2, 0.05}};
  std::vector<double> A2(A.size()), B2(B.size());
  for (int s = 0; s < steps; ++s) {
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x) {
        double la = 0, lb = 0;
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int i = ((y + dy + ny) % ny) * nx + (x + dx + nx) % nx;
            la += coef[dy + 1][dx + 1] * A[i];
            lb += coef[dy + 1][dx + 1] * B[i];
          }
        const double a = A[y * nx + x], b = B[y * nx + x];
        A2[y * nx + x] = a + 1.0 * la - a * b * b + 0.055 * (1.0 - a);
        B2[y * nx + x] = b + 0.5 * lb + a * b * b - (0.062 + 0.055) * b;
      }
    std::swap(A, A2);
    std::swap(B, B2);
  }
}

// Max |ours - reference| over both chemicals.
double max_difference(const Sim& sim, const std::vector<double>& A, const std::vector<double>& B) {
  const int nx = sim.a.nx(), ny = sim.a.ny();
  double worst = 0;
  for (int y = 0; y < ny; ++y)
    for (int x = 0; x < nx; ++x) {
      worst = std::max(worst, std::abs(double(sim.a(x, y)) - A[y * nx + x]));
      worst = std::max(worst, std::abs(double(sim.b(x, y)) - B[y * nx + x]));
    }
  return worst;
}

// Against the double-precision reference from seed 001's start.
TEST(GrayScott9Blocked, MatchesSeed001Reference) {
  const int n = 32, steps = 150;
  Executor ex(2);
  Sim sim({n, n}, *ex.ex, 2);
  sim.seed_square();
  std::vector<double> A(n * n, 1.0), B(n * n, 0.0);
  for (int y = 0; y < 10; ++y)
    for (int x = 0; x < 10; ++x) B[(n / 2 + y - 5) * n + (n / 2 + x - 5)] = 1.0;
  reference_steps(n, n, A, B, steps);
  sim.run(steps);
  EXPECT_LT(max_difference(sim, A, B), 1e-4);   // float32 vs double over 150 steps
  EXPECT_GT(B[(n / 2) * n + n / 2 + 6], 1e-3);  // the pattern has spread (non-trivial)
}

// Degenerate grids (one row, one column, fewer rows than bands and than a block's halo): the
// wrap then folds the stencil onto the same cells, and bands are a row high.
TEST(GrayScott9Blocked, TinyGridsMatchTheReference) {
  Executor ex(4);
  for (const Int2 size : {Int2{1, 1}, Int2{5, 1}, Int2{1, 4}, Int2{3, 2}, Int2{17, 3}}) {
    Sim sim(size, *ex.ex, 4, 8);
    fill_noise(sim, 5);
    std::vector<double> A, B;
    for (int y = 0; y < size.y; ++y)
      for (int x = 0; x < size.x; ++x) {
        A.push_back(sim.a(x, y));
        B.push_back(sim.b(x, y));
      }
    reference_steps(size.x, size.y, A, B, 30);
    sim.run(30);
    EXPECT_LT(max_difference(sim, A, B), 1e-4) << size.x << "x" << size.y;
  }
}

}  // namespace
}  // namespace ardcell
