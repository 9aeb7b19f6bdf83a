#pragma once
// Seed 001's explicit Gray-Scott (9-point Laplacian, periodic) on every core. Reads halo 1.
//   A' = A + DA L9(A) + dt (F (1 - A) - A B^2),  B' = B + DB L9(B) + dt (A B^2 - (F + k) B)
//   L9 = 0.05 S - 1.8 c with S the separable (1 4 1) x (1 4 1) sum (seed 001's rewrite).
// Schedule: the grid is cut into bands of rows, one per thread, updated in place. Each thread
// advances its band block_steps steps at a time by a wavefront (temporal blocking): level l
// computes its next two rows as soon as rows y-1..y+2 of level l-1 exist, into a ring of 5
// rows per level, so a band (about 690 KiB for 400^2 on 2 threads) stays in L2 and the rows
// in flight in L1; the band's halo (block_steps rows each side) is recomputed redundantly.
// The block_steps rows at either end of a band are double-buffered by block parity, so the
// neighbours read them while their owner writes the next ones (no copies). All threads meet
// at one barrier per block. The row kernel forms each vertical (1 4 1) sum once per SIMD
// vector (AVX-512 when built for it, else SSE/AVX/NEON through GCC vector extensions) and
// shifts it in registers for the horizontal pass. Every schedule (threads, block_steps) gives
// the same bits as stepping one step at a time; the result differs from the article's
// double-precision loop by float rounding only.
// Quiescent cells are skipped, bit for bit: a uniform state that the float update maps to
// itself exactly (seed 001's background settles on A = 1.00000036, B = 0 after 2 steps)
// stays so wherever its whole 3x3 neighbourhood has it. Each block starts from the bounding
// box of the rows and SIMD vectors that differ from it (recorded as rows are written), grows
// it by one cell per level, and computes only that; everything outside is known to be the
// fixed point. Seed 001's pattern covers 35% of the grid on average over 2000 steps.
// Balancing: the boundaries between bands move while a run goes on. Every kBalanceBlocks
// blocks, the thread that completes the barrier compares the neighbours' busy times (barrier
// waits excluded) and gives rows from the slower band to the faster one, so that a core
// slowed by something else (another process, a host that shares it) or a band with more
// active cells does not hold every block up. Moving a boundary copies the few rows whose
// storage changes (end rows live in the double-buffered edge copies); the bits do not change.
#include <atomic>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <thread>
#include <vector>

#include "kernels/explicit_rd.h"
#include "runtime/field.h"

namespace ardcell {

class ParallelGrayScott9 {
 public:
  // Steps per residency. On Zen 4, 2 to 16 run within noise of each other on one thread;
  // 4 keeps the redundant halo rows (k (k - 1) per band per block) and the barriers (one
  // per block) both small.
  static constexpr int kBlockSteps = 4;

  // threads <= 0: one per hardware thread. block_steps: steps per residency (1 = plain
  // step-by-step sweeps; any value gives the same bits), capped at the smallest band height.
  ParallelGrayScott9(Int2 size, const GrayScott9Params& params, int threads = 0,
                     int block_steps = kBlockSteps);
  // The threads - 1 workers are started here and kept: run() allocates nothing and starts
  // no thread, so that a frame loop may call it.
  ~ParallelGrayScott9();
  ParallelGrayScott9(const ParallelGrayScott9&) = delete;
  ParallelGrayScott9& operator=(const ParallelGrayScott9&) = delete;

  // The current state (halo 1). Write initial conditions into the interior, then run().
  FieldF& a() { return a_; }
  FieldF& b() { return b_; }
  int threads() const { return threads_; }
  int block_steps() const { return block_steps_; }

  // Seed 001's start: A = 1, B = 0, a 10x10 square of B = 1 at the centre.
  void seed_square();
  // Advances `steps` explicit steps.
  void run(int64_t steps);

  // New rates for the next run() (a live parameter change).
  void set_params(const GrayScott9Params& params) { params_ = params; }
  const GrayScott9Params& params() const { return params_; }

  // Skipping of quiescent cells (on by default; the result is the same bits either way).
  // Never applies with block_steps 1.
  void set_skip_quiescent(bool on) { skip_quiescent_ = on; }
  // Cell updates the last run() computed, band halos included: nx * ny * steps (plus the
  // redundant halo rows) without skipping, less with it.
  int64_t last_run_cell_updates() const { return last_run_cell_updates_; }

  // Moving band boundaries by measured busy time (on by default; the bits are the same
  // either way). The partition persists across run() calls.
  void set_balancing(bool on) { balancing_ = on; }
  // The first row of each band (band t owns rows [band_starts()[t], band_starts()[t + 1]),
  // the last band up to ny).
  std::vector<int> band_starts() const;
  // For tests of the row moves: instead of timing, every block moves each boundary by a
  // pseudo-random number of rows drawn from `seed` (0: back to timing).
  void set_balance_probe(uint32_t seed) { probe_state_ = seed; }

  // Blocks per balancing decision: about half a millisecond of seed 001 on two cores.
  static constexpr int kBalanceBlocks = 8;

 private:
  // Rows of floats with x = 0 64-byte aligned: kPad floats before it (the periodic ghost
  // x = -1 is the last), then the row, its ghost x = nx and SIMD padding.
  class RowStore {
   public:
    static constexpr int kPad = 16;
    void resize(int rows, std::ptrdiff_t stride);
    float* row(int y) { return data_.get() + y * stride_ + kPad; }
    const float* row(int y) const { return data_.get() + y * stride_ + kPad; }

   private:
    struct Free {
      void operator()(float* p) const { std::free(p); }
    };
    std::unique_ptr<float[], Free> data_;
    std::ptrdiff_t stride_ = 0;
  };

  // One thread's rows [y0, y1), its wavefront ring, and the storage of its first and last
  // block_steps_ rows, which its neighbours read as halo: two copies by block parity (the
  // previous block's are read while the next ones are written).
  struct Band {
    int y0 = 0, y1 = 0;
    RowStore ring, edges;
    std::vector<int> next;    // per level, the next row to compute
    std::vector<int> lo, hi;  // per level, the rows it computes in this block
    int64_t busy_ns = 0;      // time computing (not waiting) since the last balancing
  };
  // Rows per level in a band's wavefront ring: the next level reads 4 while 2 are written.
  static constexpr int kRingRows = 5;
  // Row y of a band as of block parity `parity` (rows within block_steps_ of the band's ends
  // alternate between two copies, the others are updated in place).
  float* band_row(Band& band, int parity, int y, int chem);
  // Row y of the whole grid: where a band's inner rows live (its end rows' are unused).
  float* grid_row(int y, int chem) { return chem == 0 ? grid_a_.row(y) : grid_b_.row(y); }
  void copy_whole_row(const float* from, float* to) const;  // padding and ghosts included
  // Run by the last thread to reach a block's barrier: every kBalanceBlocks blocks (every
  // block under a probe), moves band boundaries; `parity` is the next block's.
  void balance_bands(int parity);
  // Moves the boundary between bands t and t + 1 to row `to`, keeping the rows of block
  // parity `parity` (the others are rewritten by the next block).
  void move_boundary(int t, int to, int parity);

  Int2 size_;
  GrayScott9Params params_;
  int threads_ = 1;
  int block_steps_ = kBlockSteps;
  FieldF a_, b_;
  int vectors_ = 0;
  std::ptrdiff_t stride_ = 0;
  RowStore grid_a_, grid_b_;
  std::vector<Band> bands_;
  bool skip_quiescent_ = true;
  int64_t last_run_cell_updates_ = 0;
  bool balancing_ = true;
  int min_band_rows_ = 1;
  int blocks_since_balance_ = 0;
  uint32_t probe_state_ = 0;  // xorshift32 state of the test probe; 0: no probe
  // The fixed point (valid while a run skips) as whole rows, read wherever a level's rows
  // are known to hold it, and each row's differing vectors by block parity:
  // row_activity_[parity * ny + y].
  float fixed_a_ = 0, fixed_b_ = 0;
  RowStore fixed_rows_;
  std::vector<Int2> row_activity_;

  // Persistent workers 1 .. threads - 1 (the caller of run() is worker 0). run() posts a job
  // (a function and its context) by bumping job_generation_; each worker runs job(context, t)
  // and counts itself into jobs_done_.
  void worker_loop(int t);
  void (*job_)(void* context, int t) = nullptr;
  void* job_context_ = nullptr;
  std::atomic<uint32_t> job_generation_{0};
  std::atomic<int> jobs_done_{0};
  std::atomic<bool> stopping_{false};
  std::vector<std::jthread> workers_;  // last member: started after everything they read
};

// Rows to move from band a to its neighbour b (negative: from b to a) so that both take
// about the same time, given each one's busy time and rows over the last period: the
// difference over the cost of a row in each, halved against over-reaction to noise, nothing
// within a 5% dead band, at most max_rows.
int balanced_boundary_shift(double busy_a, double busy_b, int rows_a, int rows_b, int max_rows);

// Copies the periodic ghosts (x = -1, nx; y = -1, ny, corners included) of a halo-1 field.
void wrap_periodic(FieldF& f);

}  // namespace ardcell
