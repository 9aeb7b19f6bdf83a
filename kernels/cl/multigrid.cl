// Twins of kernels/multigrid_solver.cpp's grid transfers (cell-centred 2x2 aggregation; odd
// sizes keep a 1-wide last aggregate) and of its smoothing on small levels:
//   restriction   b_c(I, J) = sum of r(i, j), i in {2I, 2I+1}, j in {2J, 2J+1}, inside the grid
//                 (added in the C++ order: r(2I,2J), r(2I+1,2J), r(2I,2J+1), r(2I+1,2J+1));
//   prolongation  x(i, j) += x_c(i / 2, j / 2);
//   smoothing     `sweeps` red-black Gauss-Seidel sweeps (diffusion.cl's op_terms / op_relax).
// Halo 0: no ghost cell is read. Fine and coarse fields have their own strides and origins.

// One work-item per coarse cell.
__kernel void mg_restrict_sum(__global const float* fine, int fs, int fo, int fnx, int fny,
                              __global float* coarse, int cs, int co, int cnx, int cny) {
  const int I = get_global_id(0), J = get_global_id(1);
  if (I >= cnx || J >= cny) return;
  const int i = 2 * I, j = 2 * J;
  __global const float* f0 = fine + fo + j * fs;
  float s = f0[i];
  if (i + 1 < fnx) s += f0[i + 1];
  if (j + 1 < fny) {
    __global const float* f1 = f0 + fs;
    s += f1[i];
    if (i + 1 < fnx) s += f1[i + 1];
  }
  coarse[co + J * cs + I] = s;
}

// One work-item per fine cell.
__kernel void mg_prolong_add(__global const float* coarse, int cs, int co, __global float* fine,
                             int fs, int fo, int fnx, int fny) {
  const int i = get_global_id(0), j = get_global_id(1);
  if (i >= fnx || j >= fny) return;
  fine[fo + j * fs + i] += coarse[co + (j / 2) * cs + i / 2];
}

// `sweeps` red-black Gauss-Seidel sweeps in ONE work-group, barriers between the colours (and
// the late phases of odd periodic axes, see stencil_rbgs_half): a small level (the coarsest has
// a dozen cells) costs less than a launch per half sweep, so one launch does them all.
// Bit for bit `sweeps` x (stencil_rbgs_half colour 0, then colour 1).
__kernel void mg_rbgs_sweeps_one_group(__global const float* diag, int s, int o,
                                       __global const float* wx, int xs, int xo,
                                       __global const float* wy, int ys, int yo,
                                       __global const float* b, __global float* x, int nx, int ny,
                                       int px, int py, int late_x, int late_y, int sweeps) {
  const int lid = get_local_id(0), ls = get_local_size(0);
  const int cells = nx * ny;
  for (int k = 0; k < sweeps; ++k)
    for (int color = 0; color < 2; ++color)
      for (int phase = 0; phase <= late_x + late_y; ++phase) {
        for (int c = lid; c < cells; c += ls) {
          const int i = c % nx, j = c / nx;
          if (((i + j) & 1) != color) continue;
          if ((late_x && i == nx - 1) + (late_y && j == ny - 1) != phase) continue;
          const op_row_t t =
              op_terms(diag, s, o, wx, xs, xo, wy, ys, yo, b, x, nx, ny, px, py, i, j);
          x[o + j * s + i] = op_relax(t);
        }
        barrier(CLK_GLOBAL_MEM_FENCE);
      }
}
