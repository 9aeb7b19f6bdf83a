// Twin of kernels/reaction.h: the implicit (backward Euler) reaction of seed 000, Eqn 6, per
// cell by safeguarded Newton (Eqns 9-12, Appendix A). Reads halo 0. The arithmetic follows
// kernels/reaction.cpp line by line, in double where the device has cl_khr_fp64.
//
// Model ids and parameters (p0..p4) as kernels/reaction.h's ReactionModel / ReactionParams:
//   0 gray-scott       F, k
//   1 turing           s, beta, supply
//   2 meinhardt        s, alpha, p1, p2, p3
//   3 fitzhugh-nagumo  epsilon, a0, a1, M (the invariant box half-width)
//   4 barkley          epsilon, a, b
//   5 barkley-turbulent as 4

#define RD_MAX_ITERATIONS 200
#if ARDCELL_REAL_IS_DOUBLE
#define RD_BRACKET_EPS 1e-15
#define RD_MIN_TOL 0.0
#else
#define RD_BRACKET_EPS 1e-7f
#define RD_MIN_TOL 1e-6f
#endif

typedef struct {
  int model;
  real dt, A, B;
  real c0, c1, c2, c3, c4;  // per-model constants, see rd_setup
  int turbulent;
} rd_cell_t;

inline void rd_eval(const rd_cell_t* s, real x, real* g, real* dg) {
  switch (s->model) {
    case 0: {  // gray-scott in B^: c0 = c, c1 = lin, c2 = d0
      const real D = s->c2 + s->dt * x * x;
      *g = x * s->c1 - s->B - s->dt * s->c0 * x * x / D;
      *dg = s->c1 - s->dt * s->c0 * (real)2.0 * x * s->c2 / (D * D);
      return;
    }
    case 1: {  // turing in A^: c0 = q, c1 = beta, c2 = C
      const real q = s->c0;
      const real den = (real)1.0 + q * x;
      *g = x * ((real)1.0 + q) - s->A + q * s->c1 - q * s->c2 * x / den;
      *dg = (real)1.0 + q - q * s->c2 / (den * den);
      return;
    }
    case 2: {  // meinhardt in A^: c0 = q, c1 = m, c2 = p1, c3 = p3, c4 = P
      const real q = s->c0, m = s->c1, P = s->c4;
      const real den = s->B + q * m * x * x;
      const real T = den > 0 ? m * x * x * P / den : (real)0.0;
      const real dT = den > 0 ? (real)2.0 * m * P * s->B * x / (den * den) : (real)0.0;
      *g = x - s->A - q * (s->c2 * x + T + s->c3);
      *dg = (real)1.0 - q * s->c2 - q * dT;
      return;
    }
    case 3: {  // fitzhugh-nagumo in A^: c0 = r, c1 = a0, c2 = P
      const real bx = (s->B + s->c0 * (x - s->c1)) / s->c2;
      *g = x - s->A - s->dt * (x - x * x * x - bx);
      *dg = (real)1.0 - s->dt * ((real)1.0 - (real)3.0 * x * x - s->c0 / s->c2);
      return;
    }
    default: {  // barkley in A^: c0 = 1/eps, c1 = a, c2 = b, c3 = w
      const real bx =
          (s->B + s->dt * (s->turbulent ? x * x * x : x)) / ((real)1.0 + s->dt);
      const real u = (bx + s->c2) / s->c1;
      const real du = (s->turbulent ? (real)3.0 * x * x * s->c3 : s->c3) / s->c1;
      const real h = x * ((real)1.0 - x) * (x - u);
      const real dh = ((real)1.0 - (real)2.0 * x) * (x - u) + x * ((real)1.0 - x) * ((real)1.0 - du);
      *g = x - s->A - s->dt * s->c0 * h;
      *dg = (real)1.0 - s->dt * s->c0 * dh;
      return;
    }
  }
}

// Numerical Recipes' rtsafe, as safeguarded_newton in kernels/reaction.cpp. Returns the root.
inline real rd_newton(const rd_cell_t* s, real lo, real hi, real x0, real tol) {
  real g = 0, dg = 0;
  rd_eval(s, lo, &g, &dg);
  if (fabs(g) <= tol) return lo;
  const int increasing = g < 0;
  rd_eval(s, hi, &g, &dg);
  if (fabs(g) <= tol) return hi;
  const real sign = increasing ? (real)1.0 : (real)-1.0;
  real x = clamp(x0, lo, hi);
  if (!(x == x)) x = (real)0.5 * (lo + hi);
  real dx_old = hi - lo, dx = dx_old;
  rd_eval(s, x, &g, &dg);
  for (int it = 0; it < RD_MAX_ITERATIONS && fabs(g) > tol; ++it) {
    const real gs = sign * g, dgs = sign * dg;
    if (gs < 0)
      lo = x;
    else
      hi = x;
    const real newton = dgs != 0 ? x - gs / dgs : (real)INFINITY;
    if (!(newton > lo && newton < hi) || fabs((real)2.0 * gs) > fabs(dx_old * dgs)) {
      dx_old = dx;
      dx = (real)0.5 * (hi - lo);
      x = lo + dx;
    } else {
      dx_old = dx;
      dx = x - newton;
      x = newton;
    }
    if (hi - lo <= RD_BRACKET_EPS * ((real)1.0 + fabs(x))) {
      rd_eval(s, x, &g, &dg);
      break;
    }
    rd_eval(s, x, &g, &dg);
  }
  return x;
}

// One cell: (A, B) -> (A^, B^), from inputs in real (rd_implicit_cell's floats, or the
// trapezoidal rule's forward half step).
// Inputs are first clamped into the model's invariant box (a_lo..b_hi, infinite where open),
// where each bracket provably holds a root, as implicit_reaction_cell does.
inline void rd_implicit_real(int model, float p0, float p1, float p2, float p3, float p4,
                             float4 box, real dt_in, real af, real bf, float* a_out, float* b_out) {
  rd_cell_t s;
  s.model = model;
  s.dt = dt_in;
  s.A = clamp(af, (real)box.s0, (real)box.s1);
  s.B = clamp(bf, (real)box.s2, (real)box.s3);
  s.turbulent = model == 5;
  const real tol = max((real)1e-9, (real)RD_MIN_TOL);
  const real dt = s.dt, A = s.A, B = s.B;
  switch (model) {
    case 0: {
      const real F = (real)p0, k = (real)p1;
      s.c0 = s.A + F * dt;
      s.c1 = (real)1.0 + (F + k) * dt;
      s.c2 = (real)1.0 + F * dt;
      const real hi = max((real)0.0, (s.B + s.c0) / s.c1);
      const real b_hat = rd_newton(&s, (real)0.0, hi, s.B, tol);
      *a_out = (float)(s.c0 / (s.c2 + dt * b_hat * b_hat));
      *b_out = (float)b_hat;
      return;
    }
    case 1: {
      const real q = (real)p0 * dt, beta = (real)p1;
      const real C = B + (real)p2 * q;
      s.c0 = q;
      s.c1 = beta;
      s.c2 = C;
      real g0, dg0;
      rd_eval(&s, (real)0.0, &g0, &dg0);
      real hi;
      if (g0 <= 0) {
        hi = max((real)0.0, (A - q * beta + C) / ((real)1.0 + q));
      } else {
        const real r2 = q > 0 ? q * C / ((real)1.0 + q) : (real)0.0;
        const real x_star = (sqrt(r2) - (real)1.0) / q;
        real gs = 1, dgs;
        if (r2 > (real)1.0) rd_eval(&s, x_star, &gs, &dgs);
        if (r2 <= (real)1.0 || gs > 0) {
          *a_out = 0.0f;
          *b_out = (float)(C / (real)1.0);
          return;
        }
        hi = x_star;
      }
      const real x = rd_newton(&s, (real)0.0, hi, A, tol);
      *a_out = (float)x;
      *b_out = (float)(C / ((real)1.0 + q * x));
      return;
    }
    case 2: {
      const real q = (real)p0 * dt, m = (real)0.01 * (real)p1;
      const real pp1 = (real)p2, pp2 = (real)p3, pp3 = (real)p4;
      const real P = (real)1.0 - q * pp2;
      s.c0 = q;
      s.c1 = m;
      s.c2 = pp1;
      s.c3 = pp3;
      s.c4 = P;
      const real hi = max((real)0.0, (A + q * pp3 + P) / ((real)1.0 - q * pp1));
      const real x = rd_newton(&s, (real)0.0, hi, A, tol);
      *a_out = (float)x;
      *b_out = (float)((B + q * m * x * x) / P);
      return;
    }
    case 3: {
      const real r = (real)p0 * dt, a0 = (real)p1, a1 = (real)p2, M = (real)p3;
      const real P = (real)1.0 + r * a1;
      s.c0 = r;
      s.c1 = a0;
      s.c2 = P;
      const real x = rd_newton(&s, min(-M, A), max(M, A), A, tol);
      *a_out = (float)x;
      *b_out = (float)((B + r * (x - a0)) / P);
      return;
    }
    default: {
      s.c0 = (real)1.0 / (real)p0;
      s.c1 = (real)p1;
      s.c2 = (real)p2;
      s.c3 = dt / ((real)1.0 + dt);
      const real x = rd_newton(&s, min((real)0.0, A), max((real)1.0, A), A, tol);
      *a_out = (float)x;
      *b_out = (float)((B + dt * (s.turbulent ? x * x * x : x)) / ((real)1.0 + dt));
      return;
    }
  }
}

inline void rd_implicit_cell(int model, float p0, float p1, float p2, float p3, float p4,
                             float4 box, float dtf, float af, float bf, float* a_out,
                             float* b_out) {
  rd_implicit_real(model, p0, p1, p2, p3, p4, box, (real)dtf, (real)af, (real)bf, a_out, b_out);
}

// Eqn 6 over `region` in tiles: A, B in, A^, B^ out (outputs may alias the inputs). lbuf holds
// 4 tw*th floats: (A, B) for each of the two slots.
__kernel void reaction_implicit(__global const float* a, __global const float* b,
                                __global float* a_out, __global float* b_out, int stride,
                                int origin, int rx0, int ry0, int rx1, int ry1, int tw, int th,
                                int model, float p0, float p1, float p2, float p3, float p4,
                                float4 box, float dt, __local float* lbuf) {
  const box_t region = make_box(rx0, ry0, rx1, ry1);
  const int nt = tile_count(region, tw, th);
  const int groups = get_num_groups(0), lid = get_local_id(0), lsize = get_local_size(0);
  const int slot_floats = 2 * tw * th;
  int t = get_group_id(0);
  event_t ev0 = 0, ev1 = 0;
  if (t < nt) {
    const box_t c = tile_core(t, region, tw, th);
    ev0 = fetch_box(lbuf, a, stride, origin, c, ev0);
    ev0 = fetch_box(lbuf + tw * th, b, stride, origin, c, ev0);
  }
  for (int i = 0; t < nt; t += groups, ++i) {
    const int slot = i & 1;
    const int next = t + groups;
    if (next < nt) {  // uniform over the work-group: every work-item issues the same copies
      const box_t c = tile_core(next, region, tw, th);
      __local float* s = lbuf + (slot ^ 1) * slot_floats;
      if (slot == 0) {
        ev1 = fetch_box(s, a, stride, origin, c, 0);
        ev1 = fetch_box(s + tw * th, b, stride, origin, c, ev1);
      } else {
        ev0 = fetch_box(s, a, stride, origin, c, 0);
        ev0 = fetch_box(s + tw * th, b, stride, origin, c, ev0);
      }
    }
    if (slot == 0)
      wait_group_events(1, &ev0);
    else
      wait_group_events(1, &ev1);
    const box_t c = tile_core(t, region, tw, th);
    __local const float* la = lbuf + slot * slot_floats;
    __local const float* lb = la + tw * th;
    const int ls = lsize;
    FOR_CELLS(c, x, y) {
      const int j = local_index(c, x, y);
      float ao, bo;
      rd_implicit_cell(model, p0, p1, p2, p3, p4, box, dt, la[j], lb[j], &ao, &bo);
      const int gi = global_index(stride, origin, x, y);
      a_out[gi] = ao;
      b_out[gi] = bo;
    }
    barrier(CLK_LOCAL_MEM_FENCE);  // the slot is refilled by the next iteration's prefetch
  }
}

// Twin of kernels/reaction_table.h: the implicit reaction read from a precomputed table,
// bilinearly (reaction_table_lookup, float arithmetic in its order). table: n * n pairs
// (A^, B^), row-major in B; range: (a_lo, a_hi, b_lo, b_hi). Halo 0, one work-item per cell;
// outputs may alias the inputs. The table is a buffer uploaded once per (model, dt) and its
// range and size are arguments: a new table is a buffer write, never a rebuild.
__kernel void reaction_table(__global const float* a, __global const float* b,
                             __global float* a_out, __global float* b_out, int stride, int origin,
                             int4 reg, __global const float* table, int n, float4 range) {
  const int x = reg.s0 + get_global_id(0), y = reg.s1 + get_global_id(1);
  if (x >= reg.s2 || y >= reg.s3) return;
  const int g = global_index(stride, origin, x, y);
  const float top = (float)(n - 1);
  const float sx = top / (range.s1 - range.s0), sy = top / (range.s3 - range.s2);
  float fx = (a[g] - range.s0) * sx, fy = (b[g] - range.s2) * sy;
  fx = fx < 0 ? 0 : (fx > top ? top : fx);
  fy = fy < 0 ? 0 : (fy > top ? top : fy);
  int i = (int)fx, j = (int)fy;
  if (i > n - 2) i = n - 2;
  if (j > n - 2) j = n - 2;
  const float u = fx - (float)i, v = fy - (float)j;
  __global const float* p00 = table + (j * n + i) * 2;
  __global const float* p01 = p00 + n * 2;
  const float w00 = (1 - u) * (1 - v), w10 = u * (1 - v), w01 = (1 - u) * v, w11 = u * v;
  const float a_hat = w00 * p00[0] + w10 * p00[2] + w01 * p01[0] + w11 * p01[2];
  const float b_hat = w00 * p00[1] + w10 * p00[3] + w01 * p01[1] + w11 * p01[3];
  a_out[g] = a_hat;
  b_out[g] = b_hat;
}

// ---- Forward Euler reaction-diffusion (kernels/explicit_rd.h), the explicit schemes.

// Twin of kernels/reaction.cpp reaction_rates: R_A, R_B at (A, B), in real, in the C++ order.
// Model ids and p0..p4 as reaction_implicit's.
inline void rd_rates(int model, float p0, float p1, float p2, float p3, float p4, real A, real B,
                     real* ra, real* rb) {
  switch (model) {
    case 0:  // gray-scott: F, k
      *ra = -A * B * B + (real)p0 * ((real)1.0 - A);
      *rb = A * B * B - ((real)p0 + (real)p1) * B;
      return;
    case 1:  // turing: s, beta
      *ra = (real)p0 * (A * B - A - (real)p1);
      *rb = (real)p0 * ((real)p2 - A * B);
      return;
    case 2: {  // meinhardt: s, alpha, p1, p2, p3
      const real m = (real)0.01 * (real)p1 * A * A;
      *ra = (real)p0 * (A * (real)p2 + (B != 0 ? m / B : (real)0.0) + (real)p4);
      *rb = (real)p0 * (B * (real)p3 + m);
      return;
    }
    case 3:  // fitzhugh-nagumo: epsilon, a0, a1
      *ra = A - A * A * A - B;
      *rb = (real)p0 * (A - (real)p2 * B - (real)p1);
      return;
    default:  // barkley (4) and turbulent barkley (5): epsilon, a, b
      *ra = A * ((real)1.0 - A) * (A - (B + (real)p2) / (real)p1) / (real)p0;
      *rb = (model == 4 ? A : A * A * A) - B;
      return;
  }
}

// The 5-point Laplacian (Eqn 5) and seed 001's 9-point one (corners 0.05, edges 0.2, centre
// -1) of f at global index g, in real as kernels/explicit_rd.cpp's laplacian5 / laplacian9.
inline real rd_laplacian5(__global const float* f, int stride, int g) {
  return (real)f[g - 1] + (real)f[g + 1] + (real)f[g - stride] + (real)f[g + stride] -
         (real)4.0 * (real)f[g];
}

inline real rd_laplacian9(__global const float* f, int stride, int g) {
  const real corners = (real)f[g - stride - 1] + (real)f[g - stride + 1] +
                       (real)f[g + stride - 1] + (real)f[g + stride + 1];
  const real edges =
      (real)f[g - 1] + (real)f[g + 1] + (real)f[g - stride] + (real)f[g + stride];
  return (real)0.05 * corners + (real)0.2 * edges - (real)f[g];
}

// Twin of explicit_rd5_tile (nine = 0) and explicit_rd9_tile (nine = 1):
//   A' = A + dt R_A(A, B) + da L(A),  B' = B + dt R_B(A, B) + db L(B)
// (da, db: D dt / h^2). Reads a and b over reg grown by 1; outputs must not alias inputs. One
// work-item per cell.
__kernel void explicit_rd(__global const float* a, __global const float* b, __global float* a_out,
                          __global float* b_out, int stride, int origin, int4 reg, int model,
                          float p0, float p1, float p2, float p3, float p4, float dt, float da,
                          float db, int nine) {
  const int x = reg.s0 + get_global_id(0), y = reg.s1 + get_global_id(1);
  if (x >= reg.s2 || y >= reg.s3) return;
  const int g = global_index(stride, origin, x, y);
  const real A = a[g], B = b[g];
  real ra, rb;
  rd_rates(model, p0, p1, p2, p3, p4, A, B, &ra, &rb);
  const real la = nine ? rd_laplacian9(a, stride, g) : rd_laplacian5(a, stride, g);
  const real lb = nine ? rd_laplacian9(b, stride, g) : rd_laplacian5(b, stride, g);
  a_out[g] = (float)(A + (real)dt * ra + (real)da * la);
  b_out[g] = (float)(B + (real)dt * rb + (real)db * lb);
}

// Twin of gray_scott9_explicit_tile (seed 001's Gray-Scott step, 9-point Laplacian as the
// separable (1 4 1) x (1 4 1) sum S: L9 = 0.05 S - 1.8 A), in float, each multiply-add fused as
// the C++ writes it (kernels/explicit_rd.h): column sums v(c) = fma(4, f(c, y), f(c, y-1) +
// f(c, y+1)), S = fma(4, v(x), v(x-1) + v(x+1)), then
//   A' = fma(-A, dt B^2, fma(ca, S_A, fma(pa, A, q))),  B' = fma(A, dt B^2, fma(cb, S_B, pb B))
// with the folded constants of GrayScott9Coeffs (computed on the host). Reads halo 1; outputs
// must not alias inputs. One work-item per cell.
inline float gs9_column(__global const float* f, int stride, int g) {
  return fma(4.0f, f[g], f[g - stride] + f[g + stride]);
}

__kernel void gray_scott9_explicit(__global const float* a, __global const float* b,
                                   __global float* a_out, __global float* b_out, int stride,
                                   int origin, int4 reg, float ca, float cb, float pa, float pb,
                                   float q, float dt) {
  const int x = reg.s0 + get_global_id(0), y = reg.s1 + get_global_id(1);
  if (x >= reg.s2 || y >= reg.s3) return;
  const int g = global_index(stride, origin, x, y);
  const float A = a[g], B = b[g];
  const float sa = fma(4.0f, gs9_column(a, stride, g),
                       gs9_column(a, stride, g - 1) + gs9_column(a, stride, g + 1));
  const float sb = fma(4.0f, gs9_column(b, stride, g),
                       gs9_column(b, stride, g - 1) + gs9_column(b, stride, g + 1));
  const float bb = dt * (B * B);
  a_out[g] = fma(-A, bb, fma(ca, sa, fma(pa, A, q)));
  b_out[g] = fma(A, bb, fma(cb, sb, pb * B));
}

// ---- The second-order schemes' per-cell kernels (docs/numerics.md, "Reaction-diffusion in
// time"). Halo 0, one work-item per cell, in real in the C++ order.

// Twin of reaction_trapezoidal_tile (kernels/reaction.h): the trapezoidal rule over dt as Eqn 6
// over dt / 2 from the forward half step (A, B) + dt / 2 R(A, B). Model ids, p0..p4 and box as
// reaction_implicit's. Outputs may alias the inputs.
__kernel void reaction_trapezoidal(__global const float* a, __global const float* b,
                                   __global float* a_out, __global float* b_out, int stride,
                                   int origin, int4 reg, int model, float p0, float p1, float p2,
                                   float p3, float p4, float4 box, float dt) {
  const int x = reg.s0 + get_global_id(0), y = reg.s1 + get_global_id(1);
  if (x >= reg.s2 || y >= reg.s3) return;
  const int g = global_index(stride, origin, x, y);
  const real A = a[g], B = b[g];
  real ra, rb;
  rd_rates(model, p0, p1, p2, p3, p4, A, B, &ra, &rb);
  const real half_dt = (real)0.5 * (real)dt;
  float ao, bo;
  rd_implicit_real(model, p0, p1, p2, p3, p4, box, half_dt, A + half_dt * ra, B + half_dt * rb, &ao,
                   &bo);
  a_out[g] = ao;
  b_out[g] = bo;
}

// Twin of sbdf_rhs_tile (kernels/imex_rd.h): a, b <- SBDF1 (order 1) or SBDF2 (order 2)
// right-hand side; a_prev, b_prev <- a, b. react 0: no reaction terms.
__kernel void sbdf_rhs(__global float* a, __global float* b, __global float* a_prev,
                       __global float* b_prev, int stride, int origin, int4 reg, int model,
                       float p0, float p1, float p2, float p3, float p4, float dtf, int order,
                       int react) {
  const int x = reg.s0 + get_global_id(0), y = reg.s1 + get_global_id(1);
  if (x >= reg.s2 || y >= reg.s3) return;
  const int g = global_index(stride, origin, x, y);
  const real dt = (real)dtf;
  const real A = a[g], B = b[g];
  real ra = 0, rb = 0;
  if (react) rd_rates(model, p0, p1, p2, p3, p4, A, B, &ra, &rb);
  real rhs_a, rhs_b;
  if (order == 2) {
    const real A1 = a_prev[g], B1 = b_prev[g];
    real ra1 = 0, rb1 = 0;
    if (react) rd_rates(model, p0, p1, p2, p3, p4, A1, B1, &ra1, &rb1);
    rhs_a = ((real)4.0 * A - A1) / (real)3.0 + (real)2.0 / (real)3.0 * dt * ((real)2.0 * ra - ra1);
    rhs_b = ((real)4.0 * B - B1) / (real)3.0 + (real)2.0 / (real)3.0 * dt * ((real)2.0 * rb - rb1);
  } else {
    rhs_a = A + dt * ra;
    rhs_b = B + dt * rb;
  }
  a_prev[g] = a[g];
  b_prev[g] = b[g];
  a[g] = (float)rhs_a;
  b[g] = (float)rhs_b;
}
