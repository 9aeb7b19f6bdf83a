#pragma once
// Seed 001's explicit Gray-Scott (9-point Laplacian, periodic) on every core: the grid is cut
// into bands of rows, one per thread. Each thread advances its band kBlockSteps steps at a
// time by a wavefront (temporal blocking): level l's row y is computed as soon as level l-1's
// rows y-1..y+1 exist, in a ring of 4 rows per level that stays in L1/L2, so the global
// fields are read and written once per block instead of once per step; the band's halo
// (kBlockSteps rows each side) is recomputed redundantly. All threads meet at one barrier per
// block. Rows are float, contiguous and aligned, so the row kernel vectorises. The result is
// bit-identical to stepping one step at a time (the same row kernel on the same inputs).
#include <cstdint>

#include "kernels/explicit_rd.h"
#include "runtime/field.h"

namespace ardcell {

class ParallelGrayScott9 {
 public:
  static constexpr int kBlockSteps = 8;

  // threads <= 0: one per hardware thread.
  ParallelGrayScott9(Int2 size, const GrayScott9Params& params, int threads = 0);

  // The current state (halo 1). Write initial conditions into the interior, then run().
  FieldF& a() { return a_[cur_]; }
  FieldF& b() { return b_[cur_]; }
  int threads() const { return threads_; }

  // Seed 001's start: A = 1, B = 0, a 10x10 square of B = 1 at the centre.
  void seed_square();
  // Advances `steps` explicit steps.
  void run(int64_t steps);

 private:
  Int2 size_;
  GrayScott9Params params_;
  int threads_;
  FieldF a_[2], b_[2];
  int cur_ = 0;
};

// Copies the periodic ghosts (x = -1, nx; y = -1, ny, corners included) of a halo-1 field.
void wrap_periodic(FieldF& f);

}  // namespace ardcell
