// Twins of kernels/iccg_solver.cpp (IccgSolver): conjugate gradients preconditioned by block
// IC(0), blocks of block_rows rows (iccg::kBlockRows) fixed by the grid, the couplings between
// blocks left out of the factor. The host (kernels/cl/opencl_iccg.cpp) runs the C++ solve's
// loop, step for step, on these kernels and adds the per-row partials of every dot product in
// row order.
//
// Vectors in double: n = nx * ny, cell (i, j) at j * nx + i, the C++ vectors' layout. The
// operator stays in its float fields (diag, and the fields b and x: stride s, origin o; wx and wy
// each their own), converted to double where read: the values the C++ copies into its double
// arrays. Products and sums in the C++ order, unfused (common.cl: FP_CONTRACT OFF; the C++ is
// compiled with -ffp-contract=off) but for the triangular solves' recurrences, fused where the
// C++ fuses them (`fused`: iccg::kFusedRecurrences), so on a device with correctly rounded
// doubles and fma (PoCL) every vector has the C++ bits.
//
// The factorisation and the triangular solves are sequential within a block (each pivot and
// each z(i, j) needs its left and lower neighbour's): on a CPU device ONE work-item per block
// walks it in the C++ order, blocks side by side (the C++ runs them as one task per block); on a
// GPU the *_wavefront kernels below walk it by anti-diagonals, with the same bits. The row-parallel
// parts (the matvec, dot products, updates) are one work-item per row or per cell.
//
// Needs doubles (cl_khr_fp64): without them the file compiles to nothing and the host keeps the
// CPU solver (OpenClKernels::has_fp64).
#if ARDCELL_REAL_IS_DOUBLE

// a * b + c, in one rounding when `fused` (the C++ multiply_add).
inline double multiply_add(double a, double b, double c, int fused) {
  return fused ? fma(a, b, c) : a * b + c;
}

// Twin of IccgSolver::prepare's factorisation: pivot(i, j) = diag - wx(i, j)^2 / pivot(i - 1, j)
// - wy(i, j)^2 / pivot(i, j - 1) (the wy term only inside the block), floored as the C++ floors
// it. One work-item per block.
__kernel void iccg_factor(__global const float* diag, int s, int o, __global const float* wx,
                          int xs, int xo, __global const float* wy, int ys, int yo, int nx, int ny,
                          int block_rows, __global double* pivot, __global double* inv_pivot) {
  const int j0 = (int)get_global_id(0) * block_rows;
  if (j0 >= ny) return;
  const int j1 = min(ny, j0 + block_rows);
  for (int j = j0; j < j1; ++j)
    for (int i = 0; i < nx; ++i) {
      const double dg = (double)diag[o + j * s + i];
      double d = dg;
      if (i > 0) {
        const double w = (double)wx[xo + j * xs + i];
        d -= w * w / pivot[j * nx + i - 1];
      }
      if (j > j0) {
        const double w = (double)wy[yo + j * ys + i];
        d -= w * w / pivot[(j - 1) * nx + i];
      }
      const double floor_value = 1e-3 * dg;
      if (!(d > floor_value)) d = dg > 0.0 ? dg : 1.0;
      pivot[j * nx + i] = d;
      inv_pivot[j * nx + i] = 1.0 / d;
    }
}

// The double-vector solvers' first copy (IccgSolver::solve's, TensorFieldSolve::solve's): xd = x
// (float field to double vector). One work-item per cell.
__kernel void load_doubles(__global const float* x, int s, int o, __global double* xd, int nx,
                           int ny) {
  const int i = get_global_id(0), j = get_global_id(1);
  if (i >= nx || j >= ny) return;
  xd[j * nx + i] = (double)x[o + j * s + i];
}

// Their last copy: x = float(xd). One work-item per cell.
__kernel void store_doubles(__global const double* xd, __global float* x, int s, int o, int nx,
                            int ny) {
  const int i = get_global_id(0), j = get_global_id(1);
  if (i >= nx || j >= ny) return;
  x[o + j * s + i] = (float)xd[j * nx + i];
}

// Twin of IccgSolver::multiply (out = A in, wrap couplings included; a non-periodic edge points
// at the cell itself, whose face weight is 0) and of dot(in, out): partials[j] = the row's
// sum of in * out, left to right. One work-item per row.
__kernel void iccg_multiply(__global const float* diag, int s, int o, __global const float* wx,
                            int xs, int xo, __global const float* wy, int ys, int yo,
                            __global const double* in, __global double* out, int nx, int ny,
                            int px, int py, __global double* partials) {
  const int j = get_global_id(0);
  if (j >= ny) return;
  const int jb = j > 0 ? j - 1 : (py ? ny - 1 : j);
  const int ja = j < ny - 1 ? j + 1 : (py ? 0 : j);
  __global const double* x0 = in + j * nx;
  __global const double* xb = in + jb * nx;
  __global const double* xa = in + ja * nx;
  __global const float* d = diag + o + j * s;
  __global const float* wxr = wx + xo + j * xs;
  __global const float* wyb = wy + yo + j * ys;
  __global const float* wya = wy + yo + (j + 1) * ys;
  __global double* y = out + j * nx;
  double dot = 0.0;
  for (int i = 0; i < nx; ++i) {
    const int il = i > 0 ? i - 1 : (px ? nx - 1 : i);
    const int ir = i < nx - 1 ? i + 1 : (px ? 0 : i);
    y[i] = (double)d[i] * x0[i] - ((double)wxr[i] * x0[il] + (double)wxr[i + 1] * x0[ir] +
                                   (double)wyb[i] * xb[i] + (double)wya[i] * xa[i]);
    dot += x0[i] * y[i];
  }
  partials[j] = dot;
}

// Twin of IccgSolver::solve's initial residual: r = b - q (q = A x) and partials[j] = the row's
// sum of b^2, left to right. One work-item per row.
__kernel void iccg_residual(__global const float* b, int s, int o, __global const double* q,
                            __global double* r, int nx, int ny, __global double* partials) {
  const int j = get_global_id(0);
  if (j >= ny) return;
  __global const float* bj = b + o + j * s;
  double row = 0.0;
  for (int i = 0; i < nx; ++i) {
    const double bi = (double)bj[i];
    r[j * nx + i] = bi - q[j * nx + i];
    row += bi * bi;
  }
  partials[j] = row;
}

// The block solve of iccg_precondition: rows [j0, j1). Inlined where `fused` is a constant, so
// that the compiler drops the choice from the loops (choosing in the loops made PoCL's
// preconditioning 1.5 times slower).
__attribute__((always_inline)) inline void iccg_block_solve(
    __global const double* inv_pivot, __global const float* wx, int xs, int xo,
    __global const float* wy, int ys, int yo, __global const double* r, __global double* z, int nx,
    int j0, int j1, const int fused) {
  for (int j = j0; j < j1; ++j) {
    __global const double* rj = r + j * nx;
    __global const double* inv = inv_pivot + j * nx;
    __global const float* wxr = wx + xo + j * xs;
    __global const float* wyb = wy + yo + j * ys;
    __global double* zj = z + j * nx;
    if (j > j0) {
      __global const double* zb = z + (j - 1) * nx;
      for (int i = 0; i < nx; ++i) zj[i] = rj[i] + (double)wyb[i] * zb[i];
    } else {
      for (int i = 0; i < nx; ++i) zj[i] = rj[i];
    }
    zj[0] *= inv[0];
    for (int i = 1; i < nx; ++i)
      zj[i] = multiply_add((double)wxr[i], zj[i - 1], zj[i], fused) * inv[i];
  }
  // t(i) = wy(i, j + 1) z(i, j + 1), 0 on the block's last row, then the recurrence along the
  // row (the C++ keeps t in a row of scratch: the same values).
  for (int j = j1 - 1; j >= j0; --j) {
    __global const double* inv = inv_pivot + j * nx;
    __global const float* wxr = wx + xo + j * xs;
    __global const float* wya = wy + yo + (j + 1) * ys;
    __global double* zj = z + j * nx;
    if (j < j1 - 1) {
      __global const double* za = z + (j + 1) * nx;
      zj[nx - 1] += (double)wya[nx - 1] * za[nx - 1] * inv[nx - 1];
      for (int i = nx - 2; i >= 0; --i)
        zj[i] = multiply_add(multiply_add((double)wxr[i + 1], zj[i + 1], (double)wya[i] * za[i],
                                          fused),
                             inv[i], zj[i], fused);
    } else {
      zj[nx - 1] += 0.0 * inv[nx - 1];
      for (int i = nx - 2; i >= 0; --i)
        zj[i] = multiply_add(multiply_add((double)wxr[i + 1], zj[i + 1], 0.0, fused), inv[i], zj[i],
                             fused);
    }
  }
}

// Twin of IccgSolver::precondition (its null-space projection aside): z = M^-1 r, in each block
// forward then backward substitution, row by row. One work-item per block (see the top).
__kernel void iccg_precondition(__global const double* inv_pivot, __global const float* wx, int xs,
                                int xo, __global const float* wy, int ys, int yo,
                                __global const double* r, __global double* z, int nx, int ny,
                                int block_rows, int fused) {
  const int j0 = (int)get_global_id(0) * block_rows;
  if (j0 >= ny) return;
  const int j1 = min(ny, j0 + block_rows);
  if (fused)
    iccg_block_solve(inv_pivot, wx, xs, xo, wy, ys, yo, r, z, nx, j0, j1, 1);
  else
    iccg_block_solve(inv_pivot, wx, xs, xo, wy, ys, yo, r, z, nx, j0, j1, 0);
}

// --- The same factorisation and solves as wavefronts, for GPUs --------------------------------
// Cell (i, j) of a block needs (i - 1, j) and (i, j - 1) (forward; backward the mirror), so the
// cells with i + (j - j0) = t can go at once: one work-group per block, one work-item per row
// (lane l = row j0 + l), step t doing lane l's cell i = t - l. A lane keeps its own last value in
// a register and takes its upper neighbour's, computed in the step before, from a ring in local
// memory; one barrier a step. Each cell's arithmetic is the sequential kernels' (same operands,
// same order), so the two give the same bits; the wavefront has nx + block_rows - 1 steps of up to
// block_rows cells where the sequential walk has nx * block_rows steps of one. Each step's
// operands are loaded in the step before, so a step waits on the barrier, not on memory.
// Work-group size: block_rows (at most kWavefrontRows).
#define kWavefrontRows 64

__kernel void iccg_factor_wavefront(__global const float* diag, int s, int o,
                                    __global const float* wx, int xs, int xo,
                                    __global const float* wy, int ys, int yo, int nx, int ny,
                                    int block_rows, __global double* pivot,
                                    __global double* inv_pivot) {
  __local double ring[2][kWavefrontRows];
  const int l = get_local_id(0);
  const int j0 = (int)get_group_id(0) * block_rows;
  const int rows = min(block_rows, ny - j0);
  const int j = j0 + l;
  const bool lane = l < rows;
  double left = 0.0;  // pivot(i - 1, j)
  // This step's operands (cell i = t - l), loaded in the step before.
  double dg = 0.0, w_x = 0.0, w_y = 0.0;
  if (lane && l == 0) {
    dg = (double)diag[o + j * s];
    w_y = 0.0;
  }
  for (int t = 0; t < nx + rows - 1; ++t) {
    const int i = t - l;
    if (lane && i >= 0 && i < nx) {
      double d = dg;
      if (i > 0) d -= w_x * w_x / left;
      if (l > 0) d -= w_y * w_y / ring[(t + 1) & 1][l - 1];
      const double floor_value = 1e-3 * dg;
      if (!(d > floor_value)) d = dg > 0.0 ? dg : 1.0;
      pivot[j * nx + i] = d;
      inv_pivot[j * nx + i] = 1.0 / d;
      left = d;
      ring[t & 1][l] = d;
    }
    const int next = i + 1;
    if (lane && next >= 0 && next < nx) {
      dg = (double)diag[o + j * s + next];
      w_x = next > 0 ? (double)wx[xo + j * xs + next] : 0.0;
      w_y = l > 0 ? (double)wy[yo + j * ys + next] : 0.0;
    }
    barrier(CLK_LOCAL_MEM_FENCE);
  }
}

// The block solve of iccg_precondition as two wavefronts: forward (lane l = row j0 + l, cell
// i = t - l) then backward (lane l from the block's last row up: row j1 - 1 - l, cell
// i = nx - 1 - (t - l)).
__attribute__((always_inline)) inline void iccg_wavefront_solve(
    __global const double* inv_pivot, __global const float* wx, int xs, int xo,
    __global const float* wy, int ys, int yo, __global const double* r, __global double* z, int nx,
    int j0, int rows, __local double (*ring)[kWavefrontRows], const int fused) {
  const int l = get_local_id(0);
  const bool lane = l < rows;
  const int steps = nx + rows - 1;
  {
    const int j = j0 + l;
    double left = 0.0;  // z(i - 1, j)
    double rv = 0.0, w_x = 0.0, w_y = 0.0, inv = 0.0;
    if (lane && l == 0) {
      rv = r[j * nx];
      inv = inv_pivot[j * nx];
    }
    for (int t = 0; t < steps; ++t) {
      const int i = t - l;
      if (lane && i >= 0 && i < nx) {
        double v = l > 0 ? rv + w_y * ring[(t + 1) & 1][l - 1] : rv;
        v = i == 0 ? v * inv : multiply_add(w_x, left, v, fused) * inv;
        z[j * nx + i] = v;
        left = v;
        ring[t & 1][l] = v;
      }
      const int next = i + 1;
      if (lane && next >= 0 && next < nx) {
        rv = r[j * nx + next];
        inv = inv_pivot[j * nx + next];
        w_x = next > 0 ? (double)wx[xo + j * xs + next] : 0.0;
        w_y = l > 0 ? (double)wy[yo + j * ys + next] : 0.0;
      }
      barrier(CLK_LOCAL_MEM_FENCE);
    }
  }
  // The backward pass reads rows other work-items wrote forward.
  barrier(CLK_GLOBAL_MEM_FENCE | CLK_LOCAL_MEM_FENCE);
  {
    // Lane l's row; the row below it in the backward order (j + 1) is lane l - 1's.
    const int j = j0 + rows - 1 - l;
    double right = 0.0;  // z(i + 1, j), backward
    double zf = 0.0, w_x = 0.0, w_ya = 0.0, inv = 0.0;
    if (lane && l == 0) {
      zf = z[j * nx + nx - 1];
      inv = inv_pivot[j * nx + nx - 1];
    }
    for (int t = 0; t < steps; ++t) {
      const int i = nx - 1 - (t - l);
      if (lane && i >= 0 && i < nx) {
        double v;
        if (l == 0) {
          v = i == nx - 1 ? zf + 0.0 * inv
                          : multiply_add(multiply_add(w_x, right, 0.0, fused), inv, zf, fused);
        } else {
          const double za = ring[(t + 1) & 1][l - 1];
          v = i == nx - 1 ? zf + w_ya * za * inv
                          : multiply_add(multiply_add(w_x, right, w_ya * za, fused), inv, zf, fused);
        }
        z[j * nx + i] = v;
        right = v;
        ring[t & 1][l] = v;
      }
      const int next = i - 1;
      if (lane && next >= 0 && next < nx) {
        zf = z[j * nx + next];
        inv = inv_pivot[j * nx + next];
        w_x = next + 1 < nx ? (double)wx[xo + j * xs + next + 1] : 0.0;
        w_ya = l > 0 ? (double)wy[yo + (j + 1) * ys + next] : 0.0;
      }
      barrier(CLK_LOCAL_MEM_FENCE);
    }
  }
}

// iccg_precondition as wavefronts: one work-group of block_rows work-items per block.
__kernel void iccg_precondition_wavefront(__global const double* inv_pivot,
                                          __global const float* wx, int xs, int xo,
                                          __global const float* wy, int ys, int yo,
                                          __global const double* r, __global double* z, int nx,
                                          int ny, int block_rows, int fused) {
  __local double ring[2][kWavefrontRows];
  const int j0 = (int)get_group_id(0) * block_rows;
  const int rows = min(block_rows, ny - j0);
  if (fused)
    iccg_wavefront_solve(inv_pivot, wx, xs, xo, wy, ys, yo, r, z, nx, j0, rows, ring, 1);
  else
    iccg_wavefront_solve(inv_pivot, wx, xs, xo, wy, ys, yo, r, z, nx, j0, rows, ring, 0);
}

// Twin of IccgSolver::solve's dot(r, z) and dot(r, r) after a preconditioning (r does not change
// between them): partials[j] = the row's sum of r * z, partials[ny + j] its sum of r * r, each
// left to right. One work-item per row.
__kernel void iccg_dots(__global const double* r, __global const double* z, int nx, int ny,
                        __global double* partials) {
  const int j = get_global_id(0);
  if (j >= ny) return;
  double rz = 0.0, rr = 0.0;
  for (int m = j * nx, end = (j + 1) * nx; m < end; ++m) {
    rz += r[m] * z[m];
    rr += r[m] * r[m];
  }
  partials[j] = rz;
  partials[ny + j] = rr;
}

// Twin of IccgSolver::solve's update: x += alpha p, r -= alpha q. One work-item per cell.
__kernel void iccg_update(__global double* x, __global double* r, __global const double* p,
                          __global const double* q, double alpha, int n) {
  const int m = get_global_id(0);
  if (m >= n) return;
  x[m] += alpha * p[m];
  r[m] -= alpha * q[m];
}

// Twin of IccgSolver::solve's new direction: p = z + beta p. One work-item per cell.
__kernel void iccg_direction(__global double* p, __global const double* z, double beta, int n) {
  const int m = get_global_id(0);
  if (m >= n) return;
  p[m] = z[m] + beta * p[m];
}

// Twin of IccgSolver::project's sum: partials[j] = the row's sum of v over the null-space mask
// (a float field with stride s, origin o: upload_mask), left to right. One work-item per row.
__kernel void iccg_masked_row_sums(__global const double* v, __global const float* mask, int s,
                                   int o, int nx, int ny, __global double* partials) {
  const int j = get_global_id(0);
  if (j >= ny) return;
  __global const float* z = mask + o + j * s;
  double sum = 0.0;
  for (int i = 0; i < nx; ++i)
    if (z[i] != 0.0f) sum += v[j * nx + i];
  partials[j] = sum;
}

// Twin of IccgSolver::project's map: v -= mean over the null-space mask. One work-item per cell.
__kernel void iccg_subtract_masked(__global double* v, __global const float* mask, int s, int o,
                                   int nx, int ny, double mean) {
  const int i = get_global_id(0), j = get_global_id(1);
  if (i >= nx || j >= ny) return;
  if (mask[o + j * s + i] != 0.0f) v[j * nx + i] -= mean;
}

#endif  // ARDCELL_REAL_IS_DOUBLE
