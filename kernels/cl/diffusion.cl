// Twins of the implicit (anisotropic) diffusion of seed 000: kernels/anisotropy.h (Eqn 15
// Witkin-Kass, Eqn 16 j cosine lobes, sampled polar functions; the per-cell conductivity
// k = a(theta + theta0), theta the gradient angle of A: reads halo 1 of A),
// kernels/stencil_operator.h (Eqn 17/19: face coefficients k_f = scale (k_c + k_nb) / 2 and the
// diagonal, periodic / Neumann / Dirichlet edges folded in; halo 0 of k) and
// kernels/stencil_sweeps.h (Jacobi sweep, red-black Gauss-Seidel half sweep, y = A x; halo 0:
// the edges wrap or carry weight 0), and the right-hand side of kernels/aniso_diffusion.cpp's
// ImplicitDiffusion::step (Crank-Nicolson, Dirichlet boundary value). Arithmetic in the C++
// order and precision (double where the C++ uses double and the device has it).
//
// Operator layout: diag, b and x share one layout (stride s, origin o); wx (nx + 1 by ny) and wy
// (nx by ny + 1) each have their own. Boundary kinds as BoundaryKind: 0 periodic, 1 Neumann,
// 2 Dirichlet.

// ---- Anisotropy (kernels/anisotropy.cpp). The parameters travel BY VALUE as one kernel
// argument (ClAnisotropyArgs on the host, the same layout): a slider move sets an argument.
typedef struct {
  int kind;  // 0 isotropic, 1 witkin-kass, 2 lobes, 3 polar
  float isotropic_value, a1, a2;
  int lobes;
  float lobe_speed[16];
  int samples;
  float sample[64];
  float theta0;
  float gradient_epsilon;
} aniso_t;

#define ARD_PI ((real)3.14159265358979323846)
#define ARD_TWO_PI ((real)2.0 * ARD_PI)

inline real wrap_angle(real phi) {
  real w = fmod(phi, ARD_TWO_PI);
  if (w < 0) w += ARD_TWO_PI;
  if (w >= ARD_TWO_PI) w = 0;
  return w;
}

inline real anisotropy_value(const aniso_t* p, real phi) {
  switch (p->kind) {
    case 0:
      return (real)p->isotropic_value;
    case 1: {
      const real w = wrap_angle(phi), pi = ARD_PI;
      const real alpha = ((real)p->a1 + (real)p->a2) / (real)4.0;
      const int a1_slice = w <= pi / 4 || w >= 7 * pi / 4 || (w >= 3 * pi / 4 && w <= 5 * pi / 4);
      const real an = a1_slice ? (real)p->a1 : (real)p->a2;
      return alpha + (an - alpha) / (real)2.0 * ((real)1.0 + cos((real)4.0 * w));
    }
    case 2: {
      const int j = clamp(p->lobes, 1, 16);
      const real w = wrap_angle(phi + ARD_PI / (real)j);
      int n = (int)floor(w * (real)j / ARD_TWO_PI);
      n = clamp(n, 0, j - 1);
      return (real)p->lobe_speed[n] / (real)2.0 * ((real)1.0 + cos((real)j * phi));
    }
    default: {
      const int count = clamp(p->samples, 1, 64);
      const real s = wrap_angle(phi) * (real)count / ARD_TWO_PI;
      const int i0 = min((int)floor(s), count - 1);
      const int i1 = (i0 + 1) % count;
      const real t = s - (real)i0;
      return ((real)1.0 - t) * (real)p->sample[i0] + t * (real)p->sample[i1];
    }
  }
}

// k(x, y) = a(theta(x, y) + theta0) over reg; theta0 per cell when has_theta0 (same layout as
// a), else p.theta0. One work-item per cell.
__kernel void conductivity(__global const float* a, __global const float* theta0, int has_theta0,
                           __global float* k, int stride, int origin, int4 reg, aniso_t p) {
  const int x = reg.s0 + get_global_id(0), y = reg.s1 + get_global_id(1);
  if (x >= reg.s2 || y >= reg.s3) return;
  const int g = global_index(stride, origin, x, y);
  if (p.kind == 0) {
    k[g] = p.isotropic_value;
    return;
  }
  const real gx = (real)0.5 * ((real)a[g + 1] - (real)a[g - 1]);
  const real gy = (real)0.5 * ((real)a[g + stride] - (real)a[g - stride]);
  const real eps = (real)p.gradient_epsilon;
  const real theta = (fabs(gx) <= eps && fabs(gy) <= eps) ? (real)0.0 : atan2(gy, gx);
  const real t0 = has_theta0 ? (real)theta0[g] : (real)p.theta0;
  k[g] = (float)anisotropy_value(&p, theta + t0);
}

// ---- Operator assembly (kernels/stencil_operator.cpp's fill_coefficients).
inline real k_at(__global const float* k, int has_k, int ks, int ko, int x, int y) {
  return has_k ? (real)k[ko + y * ks + x] : (real)1.0;
}

// wx(i, j): the face between cells (i - 1, j) and (i, j), 0 <= i <= nx.
inline float face_x(__global const float* k, int has_k, int ks, int ko, int nx, int bx,
                    real scale, int i, int j) {
  if (i > 0 && i < nx)
    return (float)(scale * (real)0.5 *
                   (k_at(k, has_k, ks, ko, i - 1, j) + k_at(k, has_k, ks, ko, i, j)));
  if (bx == 0)
    return (float)(scale * (real)0.5 *
                   (k_at(k, has_k, ks, ko, nx - 1, j) + k_at(k, has_k, ks, ko, 0, j)));
  return 0.0f;
}

// wy(i, j): the face between cells (i, j - 1) and (i, j), 0 <= j <= ny.
inline float face_y(__global const float* k, int has_k, int ks, int ko, int ny, int by,
                    real scale, int i, int j) {
  if (j > 0 && j < ny)
    return (float)(scale * (real)0.5 *
                   (k_at(k, has_k, ks, ko, i, j - 1) + k_at(k, has_k, ks, ko, i, j)));
  if (by == 0)
    return (float)(scale * (real)0.5 *
                   (k_at(k, has_k, ks, ko, i, ny - 1) + k_at(k, has_k, ks, ko, i, 0)));
  return 0.0f;
}

// Whether cell (i, j) is inside the grid and solid (a mask from upload_mask, stride s, origin o).
inline int solid_at(__global const float* m, int has_m, int s, int o, int nx, int ny, int i,
                    int j) {
  return has_m && i >= 0 && i < nx && j >= 0 && j < ny && m[o + j * s + i] != 0.0f;
}

// A fluid cell's diagonal less the face it shares with a solid neighbour: isolate_solid_cells's
// update with wall factor 0, in its precision.
inline float cut_face(float d, float face) {
  return d + ((float)((real)0.0 * (real)face) - face);
}

// identity * I - scale div(k grad .): one work-item per point (i, j) of [0, nx] x [0, ny]
// writes wx(i, j), wy(i, j) and diag(i, j) where they exist (diag recomputes its four faces:
// the same expressions, so the same floats). With a solid mask (has_m; the layout of k and
// diag), then isolate_solid_cells(op, solid, 0): faces of a solid cell 0, a solid cell's row
// the identity, and a fluid cell's diagonal less the faces it shares with solid neighbours, in
// the order the C++ visits those neighbours (row by row: below, left, right, above).
__kernel void stencil_assemble(__global const float* k, int has_k, int ks, int ko,
                               __global const float* m, int has_m, __global float* diag, int ds,
                               int dorg, __global float* wx, int xs, int xo, __global float* wy,
                               int ys, int yo, int nx, int ny, int bx, int by, float identity_f,
                               float scale_f) {
  const int i = get_global_id(0), j = get_global_id(1);
  if (i > nx || j > ny) return;
  const real scale = (real)scale_f;
#define SOLID(x, y) solid_at(m, has_m, ds, dorg, nx, ny, (x), (y))
  if (j < ny)
    wx[xo + j * xs + i] =
        SOLID(i - 1, j) || SOLID(i, j) ? 0.0f : face_x(k, has_k, ks, ko, nx, bx, scale, i, j);
  if (i < nx)
    wy[yo + j * ys + i] =
        SOLID(i, j - 1) || SOLID(i, j) ? 0.0f : face_y(k, has_k, ks, ko, ny, by, scale, i, j);
  if (i >= nx || j >= ny) return;
  if (SOLID(i, j)) {
    diag[dorg + j * ds + i] = 1.0f;
    return;
  }
  const float left = face_x(k, has_k, ks, ko, nx, bx, scale, i, j);
  const float right = face_x(k, has_k, ks, ko, nx, bx, scale, i + 1, j);
  const float below = face_y(k, has_k, ks, ko, ny, by, scale, i, j);
  const float above = face_y(k, has_k, ks, ko, ny, by, scale, i, j + 1);
  real sum = (real)identity_f + (real)left + (real)right + (real)below + (real)above;
  // Dirichlet: the ghost is fixed, so the boundary face keeps its weight on the diagonal.
  const real kc = k_at(k, has_k, ks, ko, i, j);
  if (bx == 2) {
    if (i == 0) sum += scale * kc;
    if (i == nx - 1) sum += scale * kc;
  }
  if (by == 2) {
    if (j == 0) sum += scale * kc;
    if (j == ny - 1) sum += scale * kc;
  }
  float d = (float)sum;
  if (SOLID(i, j - 1)) d = cut_face(d, below);
  if (SOLID(i - 1, j)) d = cut_face(d, left);
  if (SOLID(i + 1, j)) d = cut_face(d, right);
  if (SOLID(i, j + 1)) d = cut_face(d, above);
#undef SOLID
  diag[dorg + j * ds + i] = d;
}

// ---- Sweeps (kernels/stencil_sweeps.cpp). Neighbour indices: periodic edges wrap, others
// point at the cell itself (weight 0 there). The C++ sums an edge cell's (i = 0, nx - 1)
// neighbours first and adds them to b, an inner cell's terms left to right: kept here.
typedef struct {
  float d, b, x, n1, n2, n3, n4;  // n: the weighted neighbours wx x(i-1), wx x(i+1), wy..., wy...
  int edge;
} op_row_t;

inline op_row_t op_terms(__global const float* diag, int s, int o, __global const float* wx,
                         int xs, int xo, __global const float* wy, int ys, int yo,
                         __global const float* b, __global const float* x, int nx, int ny, int px,
                         int py, int i, int j) {
  const int il = i > 0 ? i - 1 : (px ? nx - 1 : 0);
  const int ir = i < nx - 1 ? i + 1 : (px ? 0 : nx - 1);
  const int jb = j > 0 ? j - 1 : (py ? ny - 1 : j);
  const int ja = j < ny - 1 ? j + 1 : (py ? 0 : j);
  op_row_t t;
  const int c = o + j * s;
  t.d = diag[c + i];
  t.b = b ? b[c + i] : 0.0f;
  t.x = x[c + i];
  t.n1 = wx[xo + j * xs + i] * x[c + il];
  t.n2 = wx[xo + j * xs + i + 1] * x[c + ir];
  t.n3 = wy[yo + j * ys + i] * x[o + jb * s + i];
  t.n4 = wy[yo + (j + 1) * ys + i] * x[o + ja * s + i];
  t.edge = i == 0 || i == nx - 1;
  return t;
}

inline float op_relax(op_row_t t) {
  return t.edge ? (t.b + (t.n1 + t.n2 + t.n3 + t.n4)) / t.d
                : (t.b + t.n1 + t.n2 + t.n3 + t.n4) / t.d;
}

// x_out = D^-1 (b + (D - A) x_in) over the interior; one work-item per cell.
__kernel void stencil_jacobi(__global const float* diag, int s, int o, __global const float* wx,
                             int xs, int xo, __global const float* wy, int ys, int yo,
                             __global const float* b, __global const float* x_in,
                             __global float* x_out, int nx, int ny, int px, int py) {
  const int i = get_global_id(0), j = get_global_id(1);
  if (i >= nx || j >= ny) return;
  const op_row_t t =
      op_terms(diag, s, o, wx, xs, xo, wy, ys, yo, b, x_in, nx, ny, px, py, i, j);
  x_out[o + j * s + i] = op_relax(t);
}

// Half a red-black Gauss-Seidel sweep in place: cells with (i + j) % 2 == color. The C++ visits
// them row by row, left to right; on a periodic axis of odd length the last column (row) has
// the colour of the first and reads its NEW value. So the cells run in phases: 0 every cell but
// those, 1 the last column and last row (corner excepted), 2 the corner; late_x / late_y say
// which axis is periodic and odd. A phase's cells read no cell of their own phase.
__kernel void stencil_rbgs_half(__global const float* diag, int s, int o,
                                __global const float* wx, int xs, int xo,
                                __global const float* wy, int ys, int yo,
                                __global const float* b, __global float* x, int nx, int ny,
                                int px, int py, int color, int late_x, int late_y, int phase) {
  const int i = get_global_id(0), j = get_global_id(1);
  if (i >= nx || j >= ny || ((i + j) & 1) != (color & 1)) return;
  const int cell_phase = (late_x && i == nx - 1) + (late_y && j == ny - 1);
  if (cell_phase != phase) return;
  const op_row_t t = op_terms(diag, s, o, wx, xs, xo, wy, ys, yo, b, x, nx, ny, px, py, i, j);
  x[o + j * s + i] = op_relax(t);
}

// y = A x over the interior.
__kernel void stencil_apply(__global const float* diag, int s, int o, __global const float* wx,
                            int xs, int xo, __global const float* wy, int ys, int yo,
                            __global const float* x, __global float* y, int nx, int ny, int px,
                            int py) {
  const int i = get_global_id(0), j = get_global_id(1);
  if (i >= nx || j >= ny) return;
  const op_row_t t = op_terms(diag, s, o, wx, xs, xo, wy, ys, yo, 0, x, nx, ny, px, py, i, j);
  y[o + j * s + i] = t.d * t.x - (t.n1 + t.n2 + t.n3 + t.n4);
}

// ImplicitDiffusion::step's right-hand side: rhs = field, or 2 field - A field (crank: ax holds
// A field); then on Dirichlet edges with a non-zero value, each boundary side a cell lies on
// adds float(g k) (g = value * D dt / h^2, a double where the device has them; k = 1 without
// conductivity), as the C++ adds it once per side, unless the cell is solid (has_m: a mask
// from upload_mask).
__kernel void diffusion_rhs(__global const float* field, __global const float* ax,
                            __global float* rhs, __global const float* k, int has_k,
                            __global const float* m, int has_m, int s, int o, int nx, int ny,
                            int crank, int dirichlet, real g) {
  const int i = get_global_id(0), j = get_global_id(1);
  if (i >= nx || j >= ny) return;
  const int c = o + j * s + i;
  float r = crank ? 2.0f * field[c] - ax[c] : field[c];
  if (dirichlet && !solid_at(m, has_m, s, o, nx, ny, i, j)) {
    const int sides = (i == 0) + (i == nx - 1) + (j == 0) + (j == ny - 1);
    if (sides > 0) {
      const float add = (float)(g * (has_k ? (real)k[c] : (real)1.0));
      for (int n = 0; n < sides; ++n) r += add;
    }
  }
  rhs[c] = r;
}
