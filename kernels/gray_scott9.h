#pragma once
// Seed 001's explicit Gray-Scott, 9-point Laplacian, periodic, temporally blocked. Reads halo 1.
//   A' = A + DA L9(A) + dt (F (1 - A) - A B^2),  B' = B + DB L9(B) + dt (A B^2 - (F + k) B)
//   L9 = 0.05 S - 1.8 c with S the separable (1 4 1) x (1 4 1) sum (seed 001's rewrite), DA and
//   DB carrying dt / h^2 (seed 001: dt = h = 1, DA = 1, DB = 0.5, F = 0.055, k = 0.062).
// A pass kernel: run() advances A and B in place by passes of a RowExecutor (the engine's back
// end: RowExecutor::for_tasks, one task per band of rows) and starts no thread of its own.
// Schedule: the rows are cut into bands. Each pass advances every band by a block of up to
// block_steps steps by a wavefront (temporal blocking): level l computes its next two rows as
// soon as rows y-1..y+2 of level l-1 exist, into a ring of 5 rows per level, so a band stays in
// L2 and the rows in flight in L1; the band's halo (the block's steps, rows each side) is
// recomputed redundantly. A band's inner rows are updated in place in the fields; the
// block_steps rows at either end, which the neighbours read as halo, alternate between the
// fields (even blocks) and a copy of the band's own (odd blocks), so that the neighbours read
// the previous block's rows while their owner writes the next ones, with no copy. The end of a
// pass is the only barrier. The row kernel forms each vertical (1 4 1) sum once per SIMD vector
// (AVX-512 when built for it, else SSE/AVX/NEON through GCC vector extensions) and shifts it in
// registers for the horizontal pass. Any banding, block length and worker count gives the same
// bits as stepping one step at a time; the result differs from the article's double-precision
// loop by float rounding only.
// Quiescent cells are skipped, bit for bit: a uniform state that the float update maps to
// itself exactly (seed 001's background settles on A = 1.00000036, B = 0 after 2 steps) stays so
// wherever its whole 3x3 neighbourhood has it. Each block starts from the bounding box of the
// rows and SIMD vectors that differ from it (recorded as rows are written), grows it by one cell
// per level, and computes only that; everything outside is known to be the fixed point. A run
// scans every row for them first, unless it resumes from the last run's record (the caller
// knows nothing else wrote the fields): on a large grid with a small pattern that scan is most
// of a frame.
// Seed 001's pattern covers 35% of the grid on average over 2000 steps.
// Balance: the back end's workers run their own bands first and then take the bands of a worker
// that has not started them (runtime/thread/thread_backend.h), and with balancing on (the
// default) the boundaries between bands move between passes: every kBalanceBlocks blocks the
// calling thread compares the neighbouring bands' busy times and gives rows from the slower
// band to the faster one, so that a core slowed by something else or a band with more active
// cells does not hold every pass up. Moving a boundary copies the few rows whose storage
// changes; the bits do not change.
// Fields: run() steps FieldFs of halo kHalo in place (x = 0 on a 64-byte line, room for whole
// SIMD vectors on either side); make_field() makes one, adopt() converts another.
// Rows: periodic (the whole grid), or - for a block of whole rows of a periodic grid, one rank's
// share of a grid split into rows - given by the halo: the block_steps() rows above and below
// the fields' interior hold the neighbouring blocks' rows (the caller's halo exchange) and a
// run of up to block_steps() steps computes the rows it needs from them, as the bands do from
// each other's; the rows still wrap in x.
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <vector>

#include "kernels/explicit_rd.h"
#include "runtime/field.h"

namespace ardcell {

class RowExecutor;

class GrayScott9Blocked {
 public:
  // Steps per pass (at most). On Zen 4, 2 to 16 run within noise of each other on one thread;
  // 5 makes a frame of 10 steps two passes, and keeps the redundant halo rows (k (k - 1) per
  // band per block) small.
  static constexpr int kBlockSteps = 5;
  // The halo of the fields run() steps: 16 floats, a 64-byte line, on either side of a row.
  static constexpr int kHalo = 16;
  // Blocks per balancing decision: about half a millisecond of seed 001 on two cores.
  static constexpr int kBalanceBlocks = 8;

  enum class Rows : uint8_t { kPeriodic, kFromHalo };

  // bands <= 0: one per worker of `ex`. block_steps: steps per pass at most (1 = plain
  // step-by-step sweeps; any value gives the same bits), capped at the smallest band height.
  // Everything a run needs is allocated here: run() allocates nothing.
  GrayScott9Blocked(Int2 size, RowExecutor& ex, int bands = 0, int block_steps = kBlockSteps,
                    Rows rows = Rows::kPeriodic);
  ~GrayScott9Blocked();
  GrayScott9Blocked(const GrayScott9Blocked&) = delete;
  GrayScott9Blocked& operator=(const GrayScott9Blocked&) = delete;

  // A field run() can step: size cells, halo kHalo, zero-filled.
  static FieldF make_field(Int2 size) { return FieldF(size, kHalo); }
  static bool fits(const FieldF& f) { return f.halo() == kHalo; }
  // Gives f the layout run() needs, keeping its cells (halo 1 included); allocates only when f
  // lacks it.
  static void adopt(FieldF& f);

  // Advances a and b (this grid's size, fits()) by `steps` explicit steps, in place, on the
  // executor's workers; returns when done. Periodic rows: the interior is read and the periodic
  // ghosts are written. Rows from the halo: steps <= block_steps(), and the interior and the
  // block_steps() rows either side are read (their x ghosts written).
  // resume: a and b hold what the last run left in them (apart from the rows from the halo), as
  // when the caller steps on without painting or loading anything: the differing vectors that
  // run recorded are used instead of a scan of every row (the same bits; checked as far as it
  // can be: the same fields, fixed point and skipping, else every row is scanned).
  void run(FieldF& a, FieldF& b, int64_t steps, const GrayScott9Params& params,
           bool resume = false);

  Int2 size() const { return size_; }
  int bands() const { return int(bands_.size()); }
  int block_steps() const { return block_steps_; }

  // Skipping of quiescent cells (on by default; the result is the same bits either way).
  // Never applies to blocks of one step.
  void set_skip_quiescent(bool on) { skip_quiescent_ = on; }
  // Cell updates the last run() computed, band halos included: nx * ny * steps (plus the
  // redundant halo rows) without skipping, less with it.
  int64_t last_run_cell_updates() const { return last_run_cell_updates_; }

  // Moving band boundaries by measured busy time (on by default; the bits are the same either
  // way). The partition persists across run() calls.
  void set_balancing(bool on) { balancing_ = on; }
  // The first row of each band (band t owns rows [band_starts()[t], band_starts()[t + 1]), the
  // last band up to ny).
  std::vector<int> band_starts() const;
  // For tests of the row moves: instead of timing, every block moves each boundary by a
  // pseudo-random number of rows drawn from `seed` (0: back to timing).
  void set_balance_probe(uint32_t seed) { probe_state_ = seed; }

  // The row kernel's constants (seed 001's update with them folded in, gray_scott9.cpp).
  // The update's folded constants (kernels/explicit_rd.h), and what the vectors outside a
  // call's [jlo, jhi) hold when that range is not the whole row.
  struct RowCoeffs : GrayScott9Coeffs {
    float fixed_a = 0, fixed_b = 0;
  };
  using RowsKernel = void (*)(const float* const*, const float* const*, float* const*,
                              float* const*, int, int, int, const RowCoeffs&);

 private:
  // Rows of floats with x = 0 64-byte aligned: kPad floats before it (the periodic ghost
  // x = -1 is the last), then the row, its ghost x = nx and SIMD padding.
  class RowStore {
   public:
    static constexpr int kPad = kHalo;
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

  // A band: rows [y0, y1), its wavefront ring, and the odd-block copy of its first and last
  // block_steps_ rows (which its neighbours read as halo). The ring and the per-level counters
  // are the band's own, so that any worker may run it.
  struct Band {
    int y0 = 0, y1 = 0;
    RowStore ring, edges;
    std::vector<int> next;    // per level, the next row to compute
    std::vector<int> lo, hi;  // per level, the rows it computes in this block
    int64_t busy_ns = 0;      // time computing since the last balancing
    int64_t updates = 0;      // cell updates in this run
  };
  // Rows per level in a band's wavefront ring: the next level reads 4 while 2 are written.
  static constexpr int kRingRows = 5;

  // Row y of a band as of block parity `parity`: the field's row, except for rows within
  // block_steps_ of the band's ends at odd parity (the band's edge copy).
  float* band_row(Band& band, int parity, int y, int chem);
  // Row y of the run's field (y and x from the interior's first cell: a block's may be anywhere).
  float* field_row(int y, int chem) { return fields_[chem]->row(origin_.y + y) + origin_.x; }
  void copy_whole_row(const float* from, float* to) const;  // padding and ghosts included
  // Pass 0 of a run for band t: periodic ghosts of its rows, their differing vectors, and their
  // edge copy when the run starts at odd parity.
  void prepare_band(int t);
  // One block of block_k_ steps for band t (from parity parity_).
  void step_band(int t);
  // Between blocks, on the calling thread: every kBalanceBlocks blocks (every block under a
  // probe) moves band boundaries; `parity` is the next block's.
  void balance_bands(int parity);
  // Moves the boundary between bands t and t + 1 to row `to`, keeping the rows of block parity
  // `parity` (the others are rewritten by the next block).
  void move_boundary(int t, int to, int parity);

  Int2 size_;
  RowExecutor* ex_;
  int block_steps_ = kBlockSteps;
  int vectors_ = 0;
  std::ptrdiff_t stride_ = 0;  // of the rows run() touches, from x = -kHalo
  std::vector<Band> bands_;
  Rows rows_ = Rows::kPeriodic;
  bool skip_quiescent_ = true;
  int64_t last_run_cell_updates_ = 0;
  bool balancing_ = true;
  int min_band_rows_ = 1;
  int blocks_since_balance_ = 0;
  uint32_t probe_state_ = 0;  // xorshift32 state of the test probe; 0: no probe
  // The fixed point (valid while a run skips) as whole rows, read wherever a level's rows are
  // known to hold it, and each row's differing vectors by block parity:
  // row_activity_[parity * ny + y].
  RowStore fixed_rows_;
  std::vector<Int2> row_activity_;
  // Rows from the halo: the differing vectors of rows -block_steps_ .. -1, then ny .. ny +
  // block_steps_ - 1, as of the run's start.
  std::vector<Int2> halo_activity_;
  // What the last run left for a resumed one: its fields, the fixed point its differing
  // vectors are relative to and their parity; valid only when that run skipped to its end.
  bool activity_valid_ = false;
  int activity_parity_ = 0;
  const float* activity_fields_[2] = {nullptr, nullptr};
  float activity_fixed_[2] = {0, 0};
  bool resume_ = false;  // this run uses them (prepare_band scans no row of the fields)

  // The run in progress, read by the bands' tasks.
  FieldF* fields_[2] = {nullptr, nullptr};
  Int2 origin_{};
  RowCoeffs coeffs_;
  RowsKernel kernel_[2] = {nullptr, nullptr};  // one and two output rows per call
  bool skip_ = false;                          // the run skips quiescent cells
  int block_k_ = 1;                            // steps in the block being run
  int parity_ = 0;                             // its parity
};

// Rows to move from band a to its neighbour b (negative: from b to a) so that both take about
// the same time, given each one's busy time and rows over the last period: the difference over
// the cost of a row in each, halved against over-reaction to noise, nothing within a 5% dead
// band, at most max_rows.
int balanced_boundary_shift(double busy_a, double busy_b, int rows_a, int rows_b, int max_rows);

}  // namespace ardcell
