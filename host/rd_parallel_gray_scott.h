#pragma once
// Seed 001's explicit Gray-Scott (9-point Laplacian, periodic) on every core: the grid is cut
// into bands of rows, one per thread; each thread runs gray_scott9_explicit_tile on its band,
// wraps its own rows' periodic ghosts into the next buffer, and all meet at one barrier per
// step. Fields are float, rows contiguous and aligned, so the tile kernel's loops vectorise.
#include <cstdint>

#include "kernels/explicit_rd.h"
#include "runtime/field.h"

namespace ardcell {

class ParallelGrayScott9 {
 public:
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
