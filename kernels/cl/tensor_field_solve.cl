// Twin of kernels/tensor_field_solve.cpp (TensorFieldSolve), seed 003, Eqn 28's linear part with
// a per-cell tensor (Table 1's last row at rank 2):
//   x <- (I - s L)^{-1} x,  L u = F(x + 1/2, y) - F(x - 1/2, y) + G(x, y + 1/2) - G(x, y - 1/2)
// (kernels/tensor_field_operator.h), by right-preconditioned BiCGSTAB (kernels/bicgstab.h) with
// the diagonal of I - s L (Jacobi). The host (kernels/cl/opencl_tensor_field_solve.cpp) runs
// bicgstab()'s loop step for step on these kernels and adds each dot product's per-row partials
// in row order, as RowExecutor::sum_rows does. The operator, the preconditioner and the new
// direction run one work-item per cell; the dot products and the half steps (which compute the
// partials of the new r) one work-item per row, each row's sum left to right.
// Reads NO halo: the grid is periodic and the indices wrap; the four face fields are floats of
// the grid's size, halo 0, one stride fs (as tensor_field_rd reads them).
//
// Vectors in double: n = nx * ny, cell (i, j) at j * nx + i, the C++ vectors' layout; the float
// faces converted to double where read (exact). Rounding: every product and sum as the C++
// writes it, in its order, none fused (common.cl: FP_CONTRACT OFF; kernels/tensor_field_solve.cpp
// is compiled with -ffp-contract=off, CMakeLists.txt). On a device with correctly rounded doubles
// (PoCL) every vector then has the C++ bits.
//
// Needs doubles (cl_khr_fp64): without them the file compiles to nothing and the host keeps the
// CPU solve (OpenClKernels::has_fp64).
#if ARDCELL_REAL_IS_DOUBLE

// a * b + c, the product rounded on its own.
inline double tfs_madd(double a, double b, double c) { return a * b + c; }

// F between (x, y) and (xp, y), rows ym, yp around y (TensorFieldOperator::face_x): the C++'s
// xx gx + xy gy.
inline double tfs_face_x(__global const double* u, int nx, __global const float* x_xx,
                         __global const float* x_xy, int fs, int x, int xp, int y, int ym, int yp) {
  const double gx = u[y * nx + xp] - u[y * nx + x];
  const double gy =
      0.25 * ((u[yp * nx + x] + u[yp * nx + xp]) - (u[ym * nx + x] + u[ym * nx + xp]));
  return tfs_madd((double)x_xx[y * fs + x], gx, (double)x_xy[y * fs + x] * gy);
}

// G between (x, y) and (x, yp), columns xm, xp around x (TensorFieldOperator::face_y).
inline double tfs_face_y(__global const double* u, int nx, __global const float* y_xy,
                         __global const float* y_yy, int fs, int x, int xm, int xp, int y, int yp) {
  const double gy = u[yp * nx + x] - u[y * nx + x];
  const double gx =
      0.25 * ((u[y * nx + xp] + u[yp * nx + xp]) - (u[y * nx + xm] + u[yp * nx + xm]));
  return tfs_madd((double)y_yy[y * fs + x], gy, (double)y_xy[y * fs + x] * gx);
}

// Twin of TensorFieldSolve::apply: out = (I - s L) u, or with_b: out = b - (I - s L) u.
// One work-item per cell.
__kernel void tfs_apply(__global const double* u, __global const double* b, int with_b,
                        __global double* out, __global const float* x_xx,
                        __global const float* x_xy, __global const float* y_xy,
                        __global const float* y_yy, int fs, int nx, int ny, double s) {
  const int i = get_global_id(0), j = get_global_id(1);
  if (i >= nx || j >= ny) return;
  const int im = i == 0 ? nx - 1 : i - 1, ip = i == nx - 1 ? 0 : i + 1;
  const int jm = j == 0 ? ny - 1 : j - 1, jp = j == ny - 1 ? 0 : j + 1;
  const double fe = tfs_face_x(u, nx, x_xx, x_xy, fs, i, ip, j, jm, jp);
  const double fw = tfs_face_x(u, nx, x_xx, x_xy, fs, im, i, j, jm, jp);
  const double gn = tfs_face_y(u, nx, y_xy, y_yy, fs, i, im, ip, j, jp);
  const double gs = tfs_face_y(u, nx, y_xy, y_yy, fs, i, im, ip, jm, j);
  const double l = (fe - fw) + (gn - gs);
  const int c = j * nx + i;
  const double a = tfs_madd(-s, l, u[c]);  // u - s L u
  out[c] = with_b ? b[c] - a : a;
}

// The diagonal of -L at (i, j): the four faces' normal terms (TensorFieldOperator::diagonal,
// which the C++ keeps from its constructor: the same sums).
inline double tfs_diagonal(__global const float* x_xx, __global const float* y_yy, int fs, int i,
                           int j, int nx, int ny) {
  const int im = i == 0 ? nx - 1 : i - 1, jm = j == 0 ? ny - 1 : j - 1;
  return ((double)x_xx[j * fs + i] + (double)x_xx[j * fs + im]) +
         ((double)y_yy[j * fs + i] + (double)y_yy[jm * fs + i]);
}

// The solve's preconditioner at (i, j): q / (1 + s diag).
inline double tfs_jacobi(double q, __global const float* x_xx, __global const float* y_yy, int fs,
                         int i, int j, int nx, int ny, double s) {
  return q / tfs_madd(s, tfs_diagonal(x_xx, y_yy, fs, i, j, nx, ny), 1.0);
}

// Twin of the solve's preconditioner: y = q / (1 + s diag). One work-item per cell.
__kernel void tfs_precondition(__global const double* q, __global double* y,
                               __global const float* x_xx, __global const float* y_yy, int fs,
                               int nx, int ny, double s) {
  const int i = get_global_id(0), j = get_global_id(1);
  if (i >= nx || j >= ny) return;
  const int c = j * nx + i;
  y[c] = tfs_jacobi(q[c], x_xx, y_yy, fs, i, j, nx, ny, s);
}

// One row's dot product of a and b, left to right.
inline double tfs_row_dot(__global const double* a, __global const double* b, int row, int nx) {
  double sum = 0.0;
  for (int i = 0; i < nx; ++i) sum += a[row + i] * b[row + i];
  return sum;
}

// Twin of TensorFieldSolve::Space::dot's rows: partials[j] = row j of a . b and, with `two`,
// partials[ny + j] = row j of c . d (two dot products, one read). One work-item per row.
__kernel void tfs_dots(__global const double* a, __global const double* b,
                       __global const double* c, __global const double* d, int two, int nx,
                       int ny, __global double* partials) {
  const int j = get_global_id(0);
  if (j >= ny) return;
  partials[j] = tfs_row_dot(a, b, j * nx, nx);
  if (two) partials[ny + j] = tfs_row_dot(c, d, j * nx, nx);
}

// The first and last copies between x and the double vectors are iccg.cl's load_doubles and
// store_doubles.

// A pass's start: p = v = 0. One work-item per element.
__kernel void tfs_zero(__global double* p, __global double* v, int n) {
  const int m = get_global_id(0);
  if (m >= n) return;
  p[m] = 0.0;
  v[m] = 0.0;
}

// bicgstab's new direction, p = r + beta (p - omega v), and its preconditioning, y = M^-1 p.
// One work-item per cell.
__kernel void tfs_direction(__global double* p, __global const double* r,
                            __global const double* v, __global double* y,
                            __global const float* x_xx, __global const float* y_yy, int fs, int nx,
                            int ny, double beta, double omega, double s) {
  const int i = get_global_id(0), j = get_global_id(1);
  if (i >= nx || j >= ny) return;
  const int c = j * nx + i;
  const double pc = tfs_madd(beta, tfs_madd(-omega, v[c], p[c]), r[c]);
  p[c] = pc;
  y[c] = tfs_jacobi(pc, x_xx, y_yy, fs, i, j, nx, ny, s);
}

// bicgstab's half steps, r -= w av and x += w y (w = alpha with y, v; w = omega with z, t), then
// what the loop reads of the new r: partials[j] = row j of r . r and, with `two`,
// partials[ny + j] = row j of shadow . r (the next step's rho: one read for both); with
// `precondition`, z = M^-1 r (the second half step's direction). Each sum as tfs_row_dot's.
// One work-item per row.
__kernel void tfs_step(__global double* x, __global double* r, __global const double* y,
                       __global const double* av, double w, __global const double* shadow,
                       int two, __global double* z, int precondition, __global const float* x_xx,
                       __global const float* y_yy, int fs, int nx, int ny, double s,
                       __global double* partials) {
  const int j = get_global_id(0);
  if (j >= ny) return;
  double rr = 0.0, sr = 0.0;
  for (int i = 0; i < nx; ++i) {
    const int c = j * nx + i;
    const double rc = tfs_madd(-w, av[c], r[c]);
    r[c] = rc;
    x[c] = tfs_madd(w, y[c], x[c]);
    if (precondition) z[c] = tfs_jacobi(rc, x_xx, y_yy, fs, i, j, nx, ny, s);
    rr += rc * rc;
    if (two) sr += shadow[c] * rc;
  }
  partials[j] = rr;
  if (two) partials[ny + j] = sr;
}

// bicgstab's plain preconditioned step after a breakdown: x += y. One work-item per element.
__kernel void tfs_add(__global double* x, __global const double* y, int n) {
  const int m = get_global_id(0);
  if (m >= n) return;
  x[m] += y[m];
}

#endif  // ARDCELL_REAL_IS_DOUBLE
