// Twins of the row reductions: kernels/field_reductions.h (row_sums, row_ranges,
// row_mass_weights, row_masked_sums and the map restore_mass_rows: the frame's mass
// bookkeeping, host/engine/fluid_step.cpp) and of kernels/stencil_sweeps.cpp's reductions
// (residual r = b - A x with the per-row sums of r^2, norm2_squared's per-row sums of squares,
// NullSpace's masked sums and mean removal). Halo 0 throughout.
//
// A reduction writes one partial per row j of the band [y0, y1) at out[j] (the absolute row,
// as RowExecutor::sum_rows), in `real` (double where the device has cl_khr_fp64): one
// work-item per row walks it left to right, accumulating in the C++ order and precision, so on
// a device with doubles each partial has the C++ bits. The host reads the partials back and
// adds them in row order (ClRowPartials). Masks are float fields with the field's layout
// (1 = in the mask, 0 = not; a uint8_t mask converted by upload_mask).

// Row j of f (stride, origin) starting at x = 0.
inline __global const float* row_of(__global const float* f, int stride, int origin, int j) {
  return f + origin + j * stride;
}

// partials[j] = sum_x f(x, j).
__kernel void row_sums(__global const float* f, int stride, int origin, int nx, int y0, int y1,
                       __global real* out) {
  const int j = y0 + get_global_id(0);
  if (j >= y1) return;
  __global const float* r = row_of(f, stride, origin, j);
  real total = 0;
  for (int i = 0; i < nx; ++i) total += (real)r[i];
  out[j] = total;
}

// The sum as row_sums, and the row's minimum and maximum (std::min / std::max's comparisons:
// the first of equal values wins, and a NaN never replaces the running value).
__kernel void row_ranges(__global const float* f, int stride, int origin, int nx, int y0, int y1,
                         __global real* sum, __global real* lo, __global real* hi) {
  const int j = y0 + get_global_id(0);
  if (j >= y1) return;
  __global const float* r = row_of(f, stride, origin, j);
  real total = 0;
  float row_lo = r[0], row_hi = r[0];
  for (int i = 0; i < nx; ++i) {
    const float q = r[i];
    total += (real)q;
    row_lo = q < row_lo ? q : row_lo;
    row_hi = row_hi < q ? q : row_hi;
  }
  sum[j] = total;
  lo[j] = (real)row_lo;
  hi[j] = (real)row_hi;
}

// partials[j] = sum_x (f - lo)(hi - f), each difference rounded to float first.
__kernel void row_mass_weights(__global const float* f, int stride, int origin, int nx, int y0,
                               int y1, float lo, float hi, __global real* out) {
  const int j = y0 + get_global_id(0);
  if (j >= y1) return;
  __global const float* r = row_of(f, stride, origin, j);
  real total = 0;
  for (int i = 0; i < nx; ++i) total += (real)(r[i] - lo) * (real)(hi - r[i]);
  out[j] = total;
}

// f = min(max(f + float(k (f - lo)(hi - f)), lo), hi) over rows [y0, y1) (reg), one work-item
// per cell (std::max / std::min's comparisons).
__kernel void restore_mass_rows(__global float* f, int stride, int origin, int4 reg, real k,
                                float lo, float hi) {
  const int x = reg.s0 + get_global_id(0), y = reg.s1 + get_global_id(1);
  if (x >= reg.s2 || y >= reg.s3) return;
  const int g = global_index(stride, origin, x, y);
  const float c = f[g];
  float q = c + (float)(k * (real)(c - lo) * (real)(hi - c));
  q = q < lo ? lo : q;
  q = hi < q ? hi : q;
  f[g] = q;
}

// partials[j] = sum_x f(x, j)^2, the square in double, cell i into running sum i % 4 and
// then (s0 + s1) + (s2 + s3) (norm2_squared's order).
__kernel void row_sums_of_squares(__global const float* f, int stride, int origin, int nx, int y0,
                                  int y1, __global real* out) {
  const int j = y0 + get_global_id(0);
  if (j >= y1) return;
  __global const float* r = row_of(f, stride, origin, j);
  real sum[4] = {0, 0, 0, 0};
  for (int i = 0; i < nx; ++i) sum[i % 4] += (real)r[i] * (real)r[i];
  out[j] = (sum[0] + sum[1]) + (sum[2] + sum[3]);
}

// partials[j] = sum of f(x, j) over the cells with mask != 0 (NullSpace::null_sum), into four
// running sums as row_masked_sums in C++ (a masked-out cell adds 0).
__kernel void row_masked_sums(__global const float* f, __global const float* mask, int stride,
                              int origin, int nx, int y0, int y1, __global real* out) {
  const int j = y0 + get_global_id(0);
  if (j >= y1) return;
  __global const float* r = row_of(f, stride, origin, j);
  __global const float* z = row_of(mask, stride, origin, j);
  real sum[4] = {0, 0, 0, 0};
  for (int i = 0; i < nx; ++i) sum[i % 4] += z[i] != 0.0f ? (real)r[i] : (real)0;
  out[j] = (sum[0] + sum[1]) + (sum[2] + sum[3]);
}

// f -= mean on the cells of reg with mask != 0 (NullSpace::remove_mean's map). One work-item
// per cell.
__kernel void subtract_masked(__global float* f, __global const float* mask, int stride, int origin,
                              int4 reg, float mean) {
  const int x = reg.s0 + get_global_id(0), y = reg.s1 + get_global_id(1);
  if (x >= reg.s2 || y >= reg.s3) return;
  const int g = global_index(stride, origin, x, y);
  if (mask[g] != 0.0f) f[g] -= mean;
}

// r = b - A x over rows [y0, y1) (all nx cells; r written when has_r) and partials[j] = the
// row's sum of r^2 (kernels/stencil_sweeps.cpp residual): each r in double as
// b - d x + (wx x(i-1) + wx x(i+1) + wy x(j-1) + wy x(j+1)), cell i's square to running sum
// i % 4, then (s0 + s1) + (s2 + s3). Operator layout as diffusion.cl's sweeps (edges wrap or
// point at the cell itself, weight 0 there). One work-item per row.
__kernel void stencil_residual(__global const float* diag, int s, int o, __global const float* wx,
                               int xs, int xo, __global const float* wy, int ys, int yo,
                               __global const float* b, __global const float* x, __global float* r,
                               int has_r, int nx, int ny, int px, int py, int y0, int y1,
                               __global real* out) {
  const int j = y0 + get_global_id(0);
  if (j >= y1) return;
  const int jb = j > 0 ? j - 1 : (py ? ny - 1 : j);
  const int ja = j < ny - 1 ? j + 1 : (py ? 0 : j);
  __global const float* xb = x + o + jb * s;
  __global const float* x0 = x + o + j * s;
  __global const float* xa = x + o + ja * s;
  __global const float* d = diag + o + j * s;
  __global const float* bj = b + o + j * s;
  __global const float* wxr = wx + xo + j * xs;
  __global const float* wyb = wy + yo + j * ys;
  __global const float* wya = wy + yo + (j + 1) * ys;
  real sum[4] = {0, 0, 0, 0};
  for (int i = 0; i < nx; ++i) {
    const int il = i > 0 ? i - 1 : (px ? nx - 1 : 0);
    const int ir = i < nx - 1 ? i + 1 : (px ? 0 : nx - 1);
    const real ri = (real)bj[i] - (real)d[i] * (real)x0[i] +
                    ((real)wxr[i] * (real)x0[il] + (real)wxr[i + 1] * (real)x0[ir] +
                     (real)wyb[i] * (real)xb[i] + (real)wya[i] * (real)xa[i]);
    if (has_r) r[o + j * s + i] = (float)ri;
    sum[i % 4] += ri * ri;
  }
  out[j] = (sum[0] + sum[1]) + (sum[2] + sum[3]);
}
