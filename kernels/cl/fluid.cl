// Twins of the fluid tile kernels (Stam 1999): kernels/stam_sweeps.h (Jacobi sweep, red-black
// half sweep; reads x with halo 1), kernels/project.h (pressure right-hand side and gradient
// subtraction; halo 1), kernels/advect.h (semi-Lagrangian back-trace, Eqn 20; a gather from
// global memory, as the frame plan's gather buffers; the MAC face velocities and the advection
// they carry, kernels/project.h face_velocities and advect.h advect_scalar_mac),
// kernels/sources.h (halo 0), runtime/boundary.h's fill_boundary (edges, then corners) and
// fill_obstacle (halo 1), and the boundary right-hand side of the fluid solves
// (kernels/stencil_operator.h add_boundary_values). Arithmetic in the C++ order.

// ---- Boundary fills (runtime/boundary.h). rules: 0 copy, 1 fixed, 2 mirror, 3 periodic,
// 4 parabolic; .s0 left (x = -1), .s1 right (x = nx), .s2 bottom (y = -1), .s3 top (y = ny).
inline float parabolic_profile(int k, int n) {
  const float s = ((float)k + 0.5f) / (float)n;
  return 6.0f * s * (1.0f - s);
}

inline float ghost_value(int rule, float value, float inner, float wrapped) {
  switch (rule) {
    case 0: return inner;
    case 1: return value;
    case 2: return 2.0f * value - inner;
    default: return wrapped;
  }
}

// The same with the cell's place k of n along the side (rule 4).
inline float ghost_value_along(int rule, float value, float inner, float wrapped, int k, int n) {
  if (rule == 4) return 2.0f * (value * parabolic_profile(k, n)) - inner;
  return ghost_value(rule, value, inner, wrapped);
}

// The whole fill in one launch of ONE work-group: edges, a barrier, then corners (one launch per
// fill instead of two: a frame has hundreds of fills).
__kernel void fill_boundary(__global float* f, int stride, int origin, int nx, int ny, int4 rules,
                            float4 values) {
  const int lid = get_local_id(0), ls = get_local_size(0);
  __global float* c = f + origin;
  for (int i = lid; i < max(nx, ny); i += ls) {
    if (i < ny) {
      __global float* r = c + i * stride;
      r[-1] = ghost_value_along(rules.s0, values.s0, r[0], r[nx - 1], i, ny);
      r[nx] = ghost_value_along(rules.s1, values.s1, r[nx - 1], r[0], i, ny);
    }
    if (i < nx) {
      c[-stride + i] = ghost_value_along(rules.s2, values.s2, c[i], c[(ny - 1) * stride + i], i, nx);
      c[ny * stride + i] =
          ghost_value_along(rules.s3, values.s3, c[(ny - 1) * stride + i], c[i], i, nx);
    }
  }
  barrier(CLK_GLOBAL_MEM_FENCE);
  if (lid != 0) return;
#define CELL(x, y) c[(y) * stride + (x)]
  if (rules.s0 == 3 && rules.s1 == 3 && rules.s2 == 3 && rules.s3 == 3) {
    CELL(-1, -1) = CELL(nx - 1, -1);
    CELL(-1, ny) = CELL(nx - 1, ny);
    CELL(nx, -1) = CELL(0, -1);
    CELL(nx, ny) = CELL(0, ny);
  } else {
    CELL(-1, -1) = 0.5f * (CELL(0, -1) + CELL(-1, 0));
    CELL(nx, -1) = 0.5f * (CELL(nx - 1, -1) + CELL(nx, 0));
    CELL(-1, ny) = 0.5f * (CELL(0, ny) + CELL(-1, ny - 1));
    CELL(nx, ny) = 0.5f * (CELL(nx - 1, ny) + CELL(nx, ny - 1));
  }
#undef CELL
}

// Twin of kernels/stencil_operator.h add_boundary_values (fluid_step's boundary right-hand
// side): b += amounts.sN on the boundary cells of side N (left, right, bottom, top), amounts
// computed on the host as float(factor * scale * value), 0 for a side that adds nothing, times
// parabolic_profile along a side whose `parabolic` flag is set. Each
// cell adds its sides in the C++ order (left, right, bottom, top), so corners, and the cells
// of a one-cell-wide domain, round as the C++. Halo 0. One work-group walks the boundary cells:
// column x = 0, column x = nx - 1 (when nx > 1), then rows y = 0 and y = ny - 1 without their
// end cells.
inline float side_amount(float amount, int parabolic, int k, int n) {
  return parabolic ? amount * parabolic_profile(k, n) : amount;
}

inline void add_side_values(__global float* c, int stride, int nx, int ny, float4 amounts,
                            int4 parabolic, int i, int j) {
  float r = c[j * stride + i];
  if (i == 0 && amounts.s0 != 0.0f) r += side_amount(amounts.s0, parabolic.s0, j, ny);
  if (i == nx - 1 && amounts.s1 != 0.0f) r += side_amount(amounts.s1, parabolic.s1, j, ny);
  if (j == 0 && amounts.s2 != 0.0f) r += side_amount(amounts.s2, parabolic.s2, i, nx);
  if (j == ny - 1 && amounts.s3 != 0.0f) r += side_amount(amounts.s3, parabolic.s3, i, nx);
  c[j * stride + i] = r;
}

__kernel void add_boundary_values(__global float* b, int stride, int origin, int nx, int ny,
                                  float4 amounts, int4 parabolic) {
  const int lid = get_local_id(0), ls = get_local_size(0);
  __global float* c = b + origin;
  const int columns = nx > 1 ? 2 : 1;
  const int rows = ny > 1 ? 2 : 1;
  const int inner = max(nx - 2, 0);
  const int n = columns * ny + rows * inner;
  for (int k = lid; k < n; k += ls) {
    if (k < columns * ny) {
      add_side_values(c, stride, nx, ny, amounts, parabolic, k < ny ? 0 : nx - 1, k % ny);
    } else {
      const int m = k - columns * ny;
      add_side_values(c, stride, nx, ny, amounts, parabolic, 1 + m % inner,
                      m < inner ? 0 : ny - 1);
    }
  }
}

// ---- Obstacles (runtime/boundary.h fill_obstacle): every solid cell of reg (solid != 0: the
// mask as floats, 1 solid, 0 fluid, with the field's layout) set from its fluid 4-neighbours,
// rule 0 their mean (kCopy), 1 minus it (kNoSlip), 2 zero (kZero); no fluid neighbour gives 0.
// Reads f and solid over reg grown by 1. Only solid cells are written and only fluid ones read,
// so the work-items are independent. One work-item per cell.
__kernel void fill_obstacle(__global float* f, __global const float* solid, int stride,
                            int origin, int4 reg, int rule) {
  const int x = reg.s0 + get_global_id(0), y = reg.s1 + get_global_id(1);
  if (x >= reg.s2 || y >= reg.s3) return;
  const int g = global_index(stride, origin, x, y);
  if (solid[g] == 0.0f) return;
  if (rule == 2) {
    f[g] = 0.0f;
    return;
  }
  float sum = 0.0f;
  int count = 0;
  if (solid[g - 1] == 0.0f) sum += f[g - 1], ++count;
  if (solid[g + 1] == 0.0f) sum += f[g + 1], ++count;
  if (solid[g - stride] == 0.0f) sum += f[g - stride], ++count;
  if (solid[g + stride] == 0.0f) sum += f[g + stride], ++count;
  const float mean = count ? sum / (float)count : 0.0f;
  f[g] = rule == 1 ? -mean : mean;
}

// ---- Tiled stencil kernels: SPE-style walk (common.cl). lim is the fields' interior + halo box.

// Stam's Jacobi sweep: out = (x0 + a (x(-1,0) + x(+1,0) + x(0,-1) + x(0,+1))) * inv_c.
// lbuf: 2 slots x 2 fields x (tw + 2) (th + 2) floats.
__kernel void stam_jacobi(__global const float* x0, __global const float* x_in,
                          __global float* x_out, int stride, int origin, int4 reg, int tw, int th,
                          int4 lim4, float a, float inv_c, __local float* lbuf) {
  const box_t region = make_box(reg.s0, reg.s1, reg.s2, reg.s3);
  const box_t lim = make_box(lim4.s0, lim4.s1, lim4.s2, lim4.s3);
  const int nt = tile_count(region, tw, th);
  const int G = get_num_groups(0), lid = get_local_id(0), ls = get_local_size(0);
  const int ff = (tw + 2) * (th + 2), sf = 2 * ff;
  int t = get_group_id(0);
  event_t cur = spe_get(t, nt, region, tw, th, 1, lim, lbuf, sf, ff, 0, 2, x_in, x0, x0, stride,
                        origin);
  for (int i = 0; t < nt; t += G, ++i) {
    const int s = i & 1;
    event_t next = spe_get(t + G, nt, region, tw, th, 1, lim, lbuf, sf, ff, s ^ 1, 2, x_in, x0,
                           x0, stride, origin);
    wait_group_events(1, &cur);
    const box_t c = tile_core(t, region, tw, th);
    const box_t rd = box_grow_clip(c, 1, lim);
    __local const float* X = lbuf + s * sf;
    __local const float* B = X + ff;
    const int p = box_w(rd);
    FOR_CELLS(c, x, y) {
      const int l = local_index(rd, x, y);
      x_out[global_index(stride, origin, x, y)] =
          (B[l] + a * (X[l - 1] + X[l + 1] + X[l - p] + X[l + p])) * inv_c;
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    cur = next;
  }
}

// Half a red-black Gauss-Seidel sweep in place: cells with (x + y) % 2 == color. The cells read
// are of the other colour, which this half never writes, so tiles are independent.
__kernel void stam_rbgs_half(__global const float* x0, __global float* x, int stride, int origin,
                             int4 reg, int tw, int th, int4 lim4, int color, float a,
                             float inv_c, __local float* lbuf) {
  const box_t region = make_box(reg.s0, reg.s1, reg.s2, reg.s3);
  const box_t lim = make_box(lim4.s0, lim4.s1, lim4.s2, lim4.s3);
  const int nt = tile_count(region, tw, th);
  const int G = get_num_groups(0), lid = get_local_id(0), ls = get_local_size(0);
  const int ff = (tw + 2) * (th + 2), sf = 2 * ff;
  int t = get_group_id(0);
  event_t cur =
      spe_get(t, nt, region, tw, th, 1, lim, lbuf, sf, ff, 0, 2, x, x0, x0, stride, origin);
  for (int i = 0; t < nt; t += G, ++i) {
    const int s = i & 1;
    event_t next = spe_get(t + G, nt, region, tw, th, 1, lim, lbuf, sf, ff, s ^ 1, 2, x, x0, x0,
                           stride, origin);
    wait_group_events(1, &cur);
    const box_t c = tile_core(t, region, tw, th);
    const box_t rd = box_grow_clip(c, 1, lim);
    __local const float* X = lbuf + s * sf;
    __local const float* B = X + ff;
    const int p = box_w(rd);
    FOR_CELLS(c, xx, y) {
      if (((xx + y) & 1) != (color & 1)) continue;
      const int l = local_index(rd, xx, y);
      x[global_index(stride, origin, xx, y)] =
          (B[l] + a * (X[l - 1] + X[l + 1] + X[l - p] + X[l + p])) * inv_c;
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    cur = next;
  }
}

// rhs = k (u(x+1) - u(x-1) + v(y+1) - v(y-1)), k = -h/2 (kernels/project.h).
__kernel void pressure_rhs(__global const float* u, __global const float* v, __global float* rhs,
                           int stride, int origin, int4 reg, int tw, int th, int4 lim4, float k,
                           __local float* lbuf) {
  const box_t region = make_box(reg.s0, reg.s1, reg.s2, reg.s3);
  const box_t lim = make_box(lim4.s0, lim4.s1, lim4.s2, lim4.s3);
  const int nt = tile_count(region, tw, th);
  const int G = get_num_groups(0), lid = get_local_id(0), ls = get_local_size(0);
  const int ff = (tw + 2) * (th + 2), sf = 2 * ff;
  int t = get_group_id(0);
  event_t cur =
      spe_get(t, nt, region, tw, th, 1, lim, lbuf, sf, ff, 0, 2, u, v, v, stride, origin);
  for (int i = 0; t < nt; t += G, ++i) {
    const int s = i & 1;
    event_t next = spe_get(t + G, nt, region, tw, th, 1, lim, lbuf, sf, ff, s ^ 1, 2, u, v, v,
                           stride, origin);
    wait_group_events(1, &cur);
    const box_t c = tile_core(t, region, tw, th);
    const box_t rd = box_grow_clip(c, 1, lim);
    __local const float* U = lbuf + s * sf;
    __local const float* V = U + ff;
    const int p = box_w(rd);
    FOR_CELLS(c, x, y) {
      const int l = local_index(rd, x, y);
      rhs[global_index(stride, origin, x, y)] = k * (U[l + 1] - U[l - 1] + V[l + p] - V[l - p]);
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    cur = next;
  }
}

// u -= k (p(x+1) - p(x-1)), v -= k (p(y+1) - p(y-1)), k = 0.5 / h.
__kernel void subtract_gradient(__global const float* pr, __global float* u, __global float* v,
                                int stride, int origin, int4 reg, int tw, int th, int4 lim4,
                                float k, __local float* lbuf) {
  const box_t region = make_box(reg.s0, reg.s1, reg.s2, reg.s3);
  const box_t lim = make_box(lim4.s0, lim4.s1, lim4.s2, lim4.s3);
  const int nt = tile_count(region, tw, th);
  const int G = get_num_groups(0), lid = get_local_id(0), ls = get_local_size(0);
  const int ff = (tw + 2) * (th + 2), sf = ff;
  int t = get_group_id(0);
  event_t cur =
      spe_get(t, nt, region, tw, th, 1, lim, lbuf, sf, ff, 0, 1, pr, pr, pr, stride, origin);
  for (int i = 0; t < nt; t += G, ++i) {
    const int s = i & 1;
    event_t next = spe_get(t + G, nt, region, tw, th, 1, lim, lbuf, sf, ff, s ^ 1, 1, pr, pr, pr,
                           stride, origin);
    wait_group_events(1, &cur);
    const box_t c = tile_core(t, region, tw, th);
    const box_t rd = box_grow_clip(c, 1, lim);
    __local const float* P = lbuf + s * sf;
    const int p = box_w(rd);
    FOR_CELLS(c, x, y) {
      const int l = local_index(rd, x, y);
      const int g = global_index(stride, origin, x, y);
      u[g] -= k * (P[l + 1] - P[l - 1]);
      v[g] -= k * (P[l + p] - P[l - p]);
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    cur = next;
  }
}

// Twin of kernels/project.h face_velocities (top_faces = true): the MAC face velocities of
// the projection from the velocity before subtract_gradient and the solved pressure,
//   uf(i, j) = (u(i-1, j) + u(i, j)) / 2 - (p(i, j) - p(i-1, j)) / h,  i in [x0, x1], j in [y0, y1)
//   vf(i, j) = (v(i, j-1) + v(i, j)) / 2 - (p(i, j) - p(i, j-1)) / h,  i in [x0, x1), j in [y0, y1]
// u, v, p share one layout (read over reg grown by 1, ghosts filled); uf and vf have their own
// (fields of nx + 1 by ny and nx by ny + 1). One work-item per point (i, j) of
// [x0, x1] x [y0, y1], writing the faces that exist there. inv_h = 1 / h in float, as the C++.
// Twin of kernels/project.h pressure_rhs_cut: u, v, rhs share one layout; the open fractions
// ox ((nx + 1) x ny) and oy (nx x (ny + 1)) have their own. One work-item per cell of reg; the
// C++ order of the sum, k = -h/2 in float.
__kernel void pressure_rhs_cut(__global const float* u, __global const float* v,
                               __global float* rhs, int stride, int origin,
                               __global const float* ox, int xs, int xo,
                               __global const float* oy, int ys, int yo, int4 reg, float k) {
  const int x = reg.s0 + get_global_id(0), y = reg.s1 + get_global_id(1);
  if (x >= reg.s2 || y >= reg.s3) return;
  const int g = global_index(stride, origin, x, y);
  const int fx = xo + y * xs + x, fb = yo + y * ys + x, fa = yo + (y + 1) * ys + x;
  const float sum = ox[fx + 1] * (u[g] + u[g + 1]) - ox[fx] * (u[g - 1] + u[g]) +
                    oy[fa] * (v[g] + v[g + stride]) - oy[fb] * (v[g - stride] + v[g]);
  rhs[g] = k * sum;
}

__kernel void face_velocities(__global const float* u, __global const float* v,
                              __global const float* pr, int stride, int origin,
                              __global float* uf, int us, int uo, __global float* vf, int vs,
                              int vo, int4 reg, float inv_h) {
  const int x = reg.s0 + get_global_id(0), y = reg.s1 + get_global_id(1);
  if (x > reg.s2 || y > reg.s3) return;
  const int g = global_index(stride, origin, x, y);
  if (y < reg.s3) uf[uo + y * us + x] = 0.5f * (u[g - 1] + u[g]) - (pr[g] - pr[g - 1]) * inv_h;
  if (x < reg.s2)
    vf[vo + y * vs + x] = 0.5f * (v[g - stride] + v[g]) - (pr[g] - pr[g - stride]) * inv_h;
}

// ---- Semi-Lagrangian advection (kernels/advect.cpp): q0 is read where the back-trace lands.
// view: the box of q0 that may be read (the whole field: interior + halo).
typedef struct {
  float lo, hi;
  int view_min, view_max;
  int wrap;
  float period;
} axis_t;

inline axis_t axis_limits(int view_min, int view_max, int n, int periodic) {
  axis_t a;
  a.view_min = view_min;
  a.view_max = view_max;
  a.wrap = periodic && view_min <= -1 && view_max >= n + 1;
  a.period = (float)n;
  const float domain_lo = periodic ? -1e30f : -0.5f;
  const float domain_hi = periodic ? 1e30f : (float)n - 0.5f;
  a.lo = max(domain_lo, (float)view_min);
  a.hi = min(domain_hi, (float)(view_max - 1));
  return a;
}

inline void locate(axis_t a, float p, int* i0, float* s1) {
  if (a.wrap) {
    p = p - a.period * floor(p / a.period);
    if (!(p < a.period)) p = 0.0f;
  }
  p = min(max(p, a.lo), a.hi);
  int i = (int)floor(p);
  i = min(max(i, a.view_min), a.view_max - 2);
  *i0 = i;
  *s1 = p - (float)i;
}

// Nested lerps a + s (b - a), as the C++ kernel, so a constant field is reproduced exactly.
inline float bilinear(__global const float* q, int stride, int origin, int i0, int j0, float s1,
                      float t1) {
  __global const float* r0 = q + origin + j0 * stride;
  __global const float* r1 = r0 + stride;
  const float low = r0[i0] + s1 * (r0[i0 + 1] - r0[i0]);
  const float high = r1[i0] + s1 * (r1[i0 + 1] - r1[i0]);
  return low + t1 * (high - low);
}

// The back-traced point of cell (x, y) by the midpoint rule (RK2), as kernels/advect.cpp: the
// velocity at x - k/2 u(x) is interpolated from (u, v) with the same clamps as the sample.
inline void back_trace(__global const float* u, __global const float* v, int stride, int origin,
                       axis_t ax, axis_t ay, float k, int x, int y, float ux, float vy, int* i0,
                       int* j0, float* s1, float* t1) {
  int mi, mj;
  float ms, mt;
  locate(ax, (float)x - 0.5f * k * ux, &mi, &ms);
  locate(ay, (float)y - 0.5f * k * vy, &mj, &mt);
  const float um = bilinear(u, stride, origin, mi, mj, ms, mt);
  const float vm = bilinear(v, stride, origin, mi, mj, ms, mt);
  locate(ax, (float)x - k * um, i0, s1);
  locate(ay, (float)y - k * vm, j0, t1);
}

// The departure point of cell (x, y) (flat index g) under (u, v), traced back inside `view`:
// the cell (i0, j0) and weights (s1, t1) every advection kernel interpolates with.
inline void departure(__global const float* u, __global const float* v, int stride, int origin,
                      int4 view, int2 domain, int periodic, float k, int x, int y, int g,
                      int* i0, int* j0, float* s1, float* t1) {
  const axis_t ax = axis_limits(view.s0, view.s2, domain.s0, periodic);
  const axis_t ay = axis_limits(view.s1, view.s3, domain.s1, periodic);
  back_trace(u, v, stride, origin, ax, ay, k, x, y, u[g], v[g], i0, j0, s1, t1);
}

// q = q0 carried by (u, v) over reg (2D range: work-item (i, j) -> cell reg.min + (i, j)).
__kernel void advect_scalar(__global const float* q0, __global const float* u,
                            __global const float* v, __global float* q, int stride, int origin,
                            int4 reg, int4 view, int2 domain, int periodic, float k) {
  const int x = reg.s0 + get_global_id(0), y = reg.s1 + get_global_id(1);
  if (x >= reg.s2 || y >= reg.s3) return;
  const int g = global_index(stride, origin, x, y);
  int i0, j0;
  float s1, t1;
  departure(u, v, stride, origin, view, domain, periodic, k, x, y, g, &i0, &j0, &s1, &t1);
  q[g] = bilinear(q0, stride, origin, i0, j0, s1, t1);
}

// Three scalars along one back-trace (the dye and the chemicals A, B of the Table 1 frame):
// each output is what advect_scalar gives for it, the departure point computed once. view: the
// sources' box (the three share one layout).
__kernel void advect_scalar3(__global const float* q0a, __global const float* q0b,
                             __global const float* q0c, __global const float* u,
                             __global const float* v, __global float* qa, __global float* qb,
                             __global float* qc, int stride, int origin, int4 reg, int4 view,
                             int2 domain, int periodic, float k) {
  const int x = reg.s0 + get_global_id(0), y = reg.s1 + get_global_id(1);
  if (x >= reg.s2 || y >= reg.s3) return;
  const int g = global_index(stride, origin, x, y);
  int i0, j0;
  float s1, t1;
  departure(u, v, stride, origin, view, domain, periodic, k, x, y, g, &i0, &j0, &s1, &t1);
  qa[g] = bilinear(q0a, stride, origin, i0, j0, s1, t1);
  qb[g] = bilinear(q0b, stride, origin, i0, j0, s1, t1);
  qc[g] = bilinear(q0c, stride, origin, i0, j0, s1, t1);
}

// Self-advection: (u, v) = (u0, v0) at x - k (u0, v0)(x). view: u0's box (= v0's).
__kernel void advect_velocity(__global const float* u0, __global const float* v0,
                              __global float* u, __global float* v, int stride, int origin,
                              int4 reg, int4 view, int2 domain, int periodic, float k) {
  const int x = reg.s0 + get_global_id(0), y = reg.s1 + get_global_id(1);
  if (x >= reg.s2 || y >= reg.s3) return;
  const int g = global_index(stride, origin, x, y);
  int i0, j0;
  float s1, t1;
  departure(u0, v0, stride, origin, view, domain, periodic, k, x, y, g, &i0, &j0, &s1, &t1);
  u[g] = bilinear(u0, stride, origin, i0, j0, s1, t1);
  v[g] = bilinear(v0, stride, origin, i0, j0, s1, t1);
}

// ---- Advection by the MAC face velocities (kernels/advect.h advect_scalar_mac): the departure
// point by the midpoint rule, with the velocity at the midpoint interpolated bilinearly from the
// faces (uf(i, j) sits at x = i - 0.5, vf(i, j) at y = j - 0.5). Limits of a face component's
// axis (FaceSampler in kernels/advect.cpp): its faces run over [0, faces - 1], clamped to the
// view; periodic wraps with the cell grid's period over a whole field.
inline axis_t face_axis(int view_min, int view_max, int faces, int periodic, int period) {
  axis_t a = axis_limits(view_min, view_max, faces - 1, periodic);
  if (!periodic) {
    a.lo = max(0.0f, (float)view_min);
    a.hi = min((float)(faces - 1), (float)(view_max - 1));
  } else {
    a.wrap = a.wrap && view_min <= -1 && view_max >= period + 1;
    a.period = (float)period;
  }
  return a;
}

// The departure point of cell (x, y) under the face velocities: the midpoint rule, the
// midpoint's velocity sampled bilinearly from the faces (advect.cpp mac_departure).
inline void mac_departure(__global const float* uf, int us, int uo, __global const float* vf,
                          int vs, int vo, int4 view, int4 uview, int4 vview, int2 domain,
                          int periodic, float k, int x, int y, int* i0, int* j0, float* s1,
                          float* t1) {
  const int nx = domain.s0, ny = domain.s1;
  const axis_t uax = face_axis(uview.s0, uview.s2, nx + 1, periodic, nx);
  const axis_t uay = face_axis(uview.s1, uview.s3, ny, periodic, ny);
  const axis_t vax = face_axis(vview.s0, vview.s2, nx, periodic, nx);
  const axis_t vay = face_axis(vview.s1, vview.s3, ny + 1, periodic, ny);
  const axis_t ax = axis_limits(view.s0, view.s2, nx, periodic);
  const axis_t ay = axis_limits(view.s1, view.s3, ny, periodic);
  __global const float* ul = uf + uo + y * us;
  const float ux = 0.5f * (ul[x] + ul[x + 1]);
  const float vy = 0.5f * (vf[vo + y * vs + x] + vf[vo + (y + 1) * vs + x]);
  const float mx = (float)x - 0.5f * k * ux, my = (float)y - 0.5f * k * vy;
  int fi, fj;
  float fs, ft;
  locate(uax, mx + 0.5f, &fi, &fs);
  locate(uay, my + 0.0f, &fj, &ft);
  const float um = bilinear(uf, us, uo, fi, fj, fs, ft);
  locate(vax, mx + 0.0f, &fi, &fs);
  locate(vay, my + 0.5f, &fj, &ft);
  const float vm = bilinear(vf, vs, vo, fi, fj, fs, ft);
  locate(ax, (float)x - k * um, i0, s1);
  locate(ay, (float)y - k * vm, j0, t1);
}

// q = q0 carried by (uf, vf) over reg. q0 and q share one layout (q0 read over its whole
// allocation: view); uf, vf have their own (uview, vview: their whole allocations). Reads uf,
// vf and q0 over reg grown by ceil(k |u|max) + 1. One work-item per cell.
__kernel void advect_scalar_mac(__global const float* q0, __global float* q, int stride,
                                int origin, __global const float* uf, int us, int uo,
                                __global const float* vf, int vs, int vo, int4 reg, int4 view,
                                int4 uview, int4 vview, int2 domain, int periodic, float k) {
  const int x = reg.s0 + get_global_id(0), y = reg.s1 + get_global_id(1);
  if (x >= reg.s2 || y >= reg.s3) return;
  int i0, j0;
  float s1, t1;
  mac_departure(uf, us, uo, vf, vs, vo, view, uview, vview, domain, periodic, k, x, y, &i0, &j0,
                &s1, &t1);
  q[global_index(stride, origin, x, y)] = bilinear(q0, stride, origin, i0, j0, s1, t1);
}

// ---- MacCormack's limited correction (kernels/advect.h maccormack_correct): after the forward
// step q_hat and the backward one q_back, q = q_hat + (q0 - q_back) / 2 clamped to the four cells
// of q0 around the forward step's departure point. q may be q_hat (each cell reads its own).
inline float maccormack_value(__global const float* q0, int stride, int origin, int i0, int j0,
                              float q_hat, float q0_here, float q_back) {
  __global const float* r0 = q0 + origin + j0 * stride;
  __global const float* r1 = r0 + stride;
  const float lo = min(min(r0[i0], r0[i0 + 1]), min(r1[i0], r1[i0 + 1]));
  const float hi = max(max(r0[i0], r0[i0 + 1]), max(r1[i0], r1[i0 + 1]));
  const float q = q_hat + 0.5f * (q0_here - q_back);
  return min(q > lo ? q : lo, hi);
}

// Cell-centred velocity (u, v) of the forward step (advect_scalar's departure point); q0, u, v,
// q_hat, q_back and q share one layout.
__kernel void maccormack_correct(__global const float* q0, __global const float* q_hat,
                                 __global const float* q_back, __global const float* u,
                                 __global const float* v, __global float* q, int stride,
                                 int origin, int4 reg, int4 view, int2 domain, int periodic,
                                 float k) {
  const int x = reg.s0 + get_global_id(0), y = reg.s1 + get_global_id(1);
  if (x >= reg.s2 || y >= reg.s3) return;
  const int g = global_index(stride, origin, x, y);
  int i0, j0;
  float s1, t1;
  departure(u, v, stride, origin, view, domain, periodic, k, x, y, g, &i0, &j0, &s1, &t1);
  q[g] = maccormack_value(q0, stride, origin, i0, j0, q_hat[g], q0[g], q_back[g]);
}

// By the MAC face velocities (advect_scalar_mac's departure point and layouts).
__kernel void maccormack_correct_mac(__global const float* q0, __global const float* q_hat,
                                     __global const float* q_back, __global float* q, int stride,
                                     int origin, __global const float* uf, int us, int uo,
                                     __global const float* vf, int vs, int vo, int4 reg,
                                     int4 view, int4 uview, int4 vview, int2 domain, int periodic,
                                     float k) {
  const int x = reg.s0 + get_global_id(0), y = reg.s1 + get_global_id(1);
  if (x >= reg.s2 || y >= reg.s3) return;
  int i0, j0;
  float s1, t1;
  mac_departure(uf, us, uo, vf, vs, vo, view, uview, vview, domain, periodic, k, x, y, &i0, &j0,
                &s1, &t1);
  const int g = global_index(stride, origin, x, y);
  q[g] = maccormack_value(q0, stride, origin, i0, j0, q_hat[g], q0[g], q_back[g]);
}

// ---- Sources (kernels/sources.h), halo 0.
__kernel void add_scaled(__global const float* s, __global float* x, int stride, int origin,
                         int4 reg, float scale) {
  const int i = reg.s0 + get_global_id(0), y = reg.s1 + get_global_id(1);
  if (i >= reg.s2 || y >= reg.s3) return;
  const int g = global_index(stride, origin, i, y);
  x[g] += scale * s[g];
}

// reg is already clipped to the splat's 3-radius reach (as the C++ kernel does).
__kernel void add_splat(__global float* f, int stride, int origin, int4 reg, float cx, float cy,
                        float inv_r2, float amount) {
  const int x = reg.s0 + get_global_id(0), y = reg.s1 + get_global_id(1);
  if (x >= reg.s2 || y >= reg.s3) return;
  const float dy2 = ((float)y - cy) * ((float)y - cy);
  const float dx = (float)x - cx;
  f[global_index(stride, origin, x, y)] += amount * exp(-(dx * dx + dy2) * inv_r2);
}

// Twin of kernels/sources.h set_inflow_stripes: the k-th boundary cell of `side` (0 left,
// 1 right, 2 bottom, 3 top) set to 1 in the odd ones of 2 * stripes equal bands, else 0
// (integer arithmetic, as the C++). Halo 0; one work-item per cell of the side.
__kernel void set_inflow_stripes(__global float* dye, int stride, int origin, int nx, int ny,
                                 int stripes, int side) {
  const int k = get_global_id(0);
  const int column = side < 2;
  const int n = column ? ny : nx;
  if (k >= n) return;
  const int bands = 2 * stripes;
  const float value = (k * bands / n) % 2 ? 1.0f : 0.0f;
  const int at = side == 0 ? 0 : side == 1 ? nx - 1 : side == 2 ? 0 : ny - 1;
  dye[column ? global_index(stride, origin, at, k) : global_index(stride, origin, k, at)] = value;
}

// ---- Ghost-zone temporal blocking (the blocked schedule): k Jacobi sweeps per residency.
// A tile's core grown by k (clipped to the field, halo 1) is fetched once with its right-hand
// side; sweep s computes the core grown by k-1-s (clipped to the interior) and refills the
// domain's ghost cells that lie in the tile (fill_boundary restricted to the tile, as the C++
// tile-local fill), so after k sweeps the core - and the ghost cells beside it at the domain
// edge - equal k global sweeps with their fills, bit for bit. Periodic edges are not handled
// here (the host runs those sweep by sweep). lbuf: 2 slots x (X, R) + one scratch Y, each
// (tw + 2k) (th + 2k) floats. x_out must not alias x_in.
inline void local_fill(__local float* Y, box_t L, int nx, int ny, int4 rules, float4 values,
                       int lid, int ls) {
  const int p = box_w(L);
  const int y0 = max(0, L.y0), y1 = min(ny, L.y1), x0 = max(0, L.x0), x1 = min(nx, L.x1);
  for (int y = y0 + lid; y < y1; y += ls) {
    if (L.x0 == -1 && L.x1 > 0) {
      const int l = local_index(L, -1, y);
      Y[l] = ghost_value_along(rules.s0, values.s0, Y[l + 1], 0.0f, y, ny);
    }
    if (L.x1 == nx + 1 && L.x0 < nx) {
      const int l = local_index(L, nx, y);
      Y[l] = ghost_value_along(rules.s1, values.s1, Y[l - 1], 0.0f, y, ny);
    }
  }
  for (int x = x0 + lid; x < x1; x += ls) {
    if (L.y0 == -1 && L.y1 > 0) {
      const int l = local_index(L, x, -1);
      Y[l] = ghost_value_along(rules.s2, values.s2, Y[l + p], 0.0f, x, nx);
    }
    if (L.y1 == ny + 1 && L.y0 < ny) {
      const int l = local_index(L, x, ny);
      Y[l] = ghost_value_along(rules.s3, values.s3, Y[l - p], 0.0f, x, nx);
    }
  }
  barrier(CLK_LOCAL_MEM_FENCE);
  if (lid == 0) {
    const int has_l = L.x0 == -1 && L.x1 > 0, has_r = L.x1 == nx + 1 && L.x0 < nx;
    const int has_b = L.y0 == -1 && L.y1 > 0, has_t = L.y1 == ny + 1 && L.y0 < ny;
    if (has_l && has_b)
      Y[local_index(L, -1, -1)] = 0.5f * (Y[local_index(L, 0, -1)] + Y[local_index(L, -1, 0)]);
    if (has_r && has_b)
      Y[local_index(L, nx, -1)] =
          0.5f * (Y[local_index(L, nx - 1, -1)] + Y[local_index(L, nx, 0)]);
    if (has_l && has_t)
      Y[local_index(L, -1, ny)] =
          0.5f * (Y[local_index(L, 0, ny)] + Y[local_index(L, -1, ny - 1)]);
    if (has_r && has_t)
      Y[local_index(L, nx, ny)] =
          0.5f * (Y[local_index(L, nx - 1, ny)] + Y[local_index(L, nx, ny - 1)]);
  }
  barrier(CLK_LOCAL_MEM_FENCE);
}

__kernel void stam_jacobi_blocked(__global const float* rhs, __global const float* x_in,
                                  __global float* x_out, int stride, int origin, int nx, int ny,
                                  int tw, int th, int k, float a, float inv_c, int4 rules,
                                  float4 values, __local float* lbuf) {
  const box_t interior = make_box(0, 0, nx, ny);
  const box_t lim = make_box(-1, -1, nx + 1, ny + 1);
  const int nt = tile_count(interior, tw, th);
  const int G = get_num_groups(0), lid = get_local_id(0), ls = get_local_size(0);
  const int ff = (tw + 2 * k) * (th + 2 * k), sf = 2 * ff;
  __local float* scratch = lbuf + 2 * sf;
  int t = get_group_id(0);
  event_t cur = spe_get(t, nt, interior, tw, th, k, lim, lbuf, sf, ff, 0, 2, x_in, rhs, rhs,
                        stride, origin);
  for (int i = 0; t < nt; t += G, ++i) {
    const int s = i & 1;
    event_t next = spe_get(t + G, nt, interior, tw, th, k, lim, lbuf, sf, ff, s ^ 1, 2, x_in,
                           rhs, rhs, stride, origin);
    wait_group_events(1, &cur);
    const box_t c = tile_core(t, interior, tw, th);
    const box_t L = box_grow_clip(c, k, lim);
    const int p = box_w(L);
    __local float* X = lbuf + s * sf;
    __local const float* R = X + ff;
    __local float* Y = scratch;
    for (int sweep = 0; sweep < k; ++sweep) {
      const box_t reg = box_grow_clip(c, k - 1 - sweep, interior);
      FOR_CELLS(reg, x, y) {
        const int l = local_index(L, x, y);
        Y[l] = (R[l] + a * (X[l - 1] + X[l + 1] + X[l - p] + X[l + p])) * inv_c;
      }
      barrier(CLK_LOCAL_MEM_FENCE);
      local_fill(Y, L, nx, ny, rules, values, lid, ls);
      __local float* tmp = X;
      X = Y;
      Y = tmp;
    }
    // Put: the core, grown by 1 on the sides at the domain edge (its ghost cells).
    const box_t wb = make_box(c.x0 == 0 ? -1 : c.x0, c.y0 == 0 ? -1 : c.y0,
                              c.x1 == nx ? nx + 1 : c.x1, c.y1 == ny ? ny + 1 : c.y1);
    FOR_CELLS(wb, x, y) {
      x_out[global_index(stride, origin, x, y)] = X[local_index(L, x, y)];
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    cur = next;
  }
}
