#include "kernels/field_reductions.h"

#include <algorithm>

namespace ardcell {

// The loops below are copies of host/engine/fluid_step.cpp's (and NullSpace::null_sum's),
// operation for operation: keep them so.

void row_sums(View<const float> f, int nx, int y0, int y1, double* partials) {
  for (int j = y0; j < y1; ++j) {
    const float* r = f.row(j);
    double row_total = 0.0;
    for (int i = 0; i < nx; ++i) row_total += r[i];
    partials[j] = row_total;
  }
}

void row_ranges(View<const float> f, int nx, int y0, int y1, double* sum, double* lo, double* hi) {
  for (int j = y0; j < y1; ++j) {
    const float* row = f.row(j);
    double row_total = 0.0;
    float row_lo = row[0], row_hi = row[0];
    for (int i = 0; i < nx; ++i) {
      row_total += row[i];
      row_lo = std::min(row_lo, row[i]);
      row_hi = std::max(row_hi, row[i]);
    }
    sum[j] = row_total;
    lo[j] = row_lo;
    hi[j] = row_hi;
  }
}

void row_mass_weights(View<const float> f, int nx, int y0, int y1, float lo, float hi,
                      double* partials) {
  for (int j = y0; j < y1; ++j) {
    const float* row = f.row(j);
    double row_total = 0.0;
    for (int i = 0; i < nx; ++i) row_total += double(row[i] - lo) * double(hi - row[i]);
    partials[j] = row_total;
  }
}

void row_masked_sums(View<const float> f, View<const uint8_t> mask, int nx, int y0, int y1,
                     double* partials) {
  for (int j = y0; j < y1; ++j) {
    const float* r = f.row(j);
    const uint8_t* z = mask.row(j);
    // Four running sums, cell i to sum i % 4, as norm2_squared: one running sum was a chain of
    // dependent additions; a masked-out cell adds 0.
    double sum[4] = {0.0, 0.0, 0.0, 0.0};
    for (int i = 0; i < nx; ++i) sum[i % 4] += z[i] ? double(r[i]) : 0.0;
    partials[j] = (sum[0] + sum[1]) + (sum[2] + sum[3]);
  }
}

void restore_mass_rows(View<float> f, int nx, int y0, int y1, double k, float lo, float hi) {
  for (int j = y0; j < y1; ++j) {
    float* row = f.row(j);
    for (int i = 0; i < nx; ++i) {
      const float q = row[i] + float(k * double(row[i] - lo) * double(hi - row[i]));
      row[i] = std::min(std::max(q, lo), hi);
    }
  }
}

}  // namespace ardcell
