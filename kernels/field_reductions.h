#pragma once
// Reductions over the interior of a field, one partial per row, for the frame's mass
// bookkeeping (host/engine/fluid_step.cpp: interior_sum, interior_range, restore_mass) and the
// solvers' null space (kernels/stencil_sweeps.h NullSpace):
//   row_sums          partials[j] = sum_x f(x, j)                              (double)
//   row_ranges        sum[j] as row_sums, lo[j] / hi[j] = min / max_x f(x, j)  (float values)
//   row_mass_weights  partials[j] = sum_x double(f - lo) double(hi - f)
//   row_masked_sums   partials[j] = sum_x of f(x, j) over cells with mask(x, j) != 0
// and one map, restore_mass_rows: f = min(max(f + float(k double(f - lo) double(hi - f)), lo),
// hi) (the missing mass put back where the weights above are large).
//
// Each kernel works on the band of rows [y0, y1) and x in [0, nx), and writes partial j at
// partials[j] (absolute row index, as RowExecutor::sum_rows hands out): callers add the rows in
// row order and get the same bits on any number of workers. Each row is summed left to right
// in double (row_masked_sums into four running sums, cell i to sum i % 4, then
// (s0 + s1) + (s2 + s3)). The OpenCL twins (kernels/cl/reductions.cl) write the same partials
// into a device buffer.
#include <cstdint>

#include "runtime/field.h"

namespace ardcell {

void row_sums(View<const float> f, int nx, int y0, int y1, double* partials);
void row_ranges(View<const float> f, int nx, int y0, int y1, double* sum, double* lo, double* hi);
void row_mass_weights(View<const float> f, int nx, int y0, int y1, float lo, float hi,
                      double* partials);
void row_masked_sums(View<const float> f, View<const uint8_t> mask, int nx, int y0, int y1,
                     double* partials);

void restore_mass_rows(View<float> f, int nx, int y0, int y1, double k, float lo, float hi);

}  // namespace ardcell
