// Twin of kernels/generalized_rd.h: seed 003's Eqn 27 with reaction on a periodic grid,
//   A' = A + s_A K A + dt R_A(A, B),  B' = B + s_B K B + dt R_B(A, B)
// K the 25-point stencil, as groups (w: OpenClKernels::stencil_groups, GeneralizedTaps' order);
// indices wrap, so it reads no halo. Each cell adds weight * (the group's balanced tree of taps)
// over the groups in order in float, and Gray-Scott (model 0) and Turing (1) react in float as the
// C++ kernel does (the same bits), each result clamped to box = (a_lo, a_hi, b_lo, b_hi); the
// other models through rd_rates (reaction.cl, embedded before this file: sources go in name
// order). Model ids and p0..p4 as reaction.cl's. Gray-Scott's parameter map: F + f_step (x + 1/2),
// k + k_step (y + 1/2) (both 0: uniform). One work-item per cell.
inline int wrap_index(int i, int n) { return i < 0 ? i + n : (i >= n ? i - n : i); }

inline float stencil_groups(__global const float* f, __constant const float* w, int stride,
                            int origin, int x, int y, int nx, int ny) {
  float acc = 0.0f;
  const int groups = (int)w[0];
  int at = 1;
  for (int g = 0; g < groups; ++g) {
    const int n = (int)w[at];
    const float weight = w[at + 1];
    at += 2;
    float t[8];
    for (int i = 0; i < n; ++i, at += 2)
      t[i] = f[origin + wrap_index(y + (int)w[at + 1], ny) * stride + wrap_index(x + (int)w[at], nx)];
    float tree;
    if (n == 1)
      tree = t[0];
    else if (n == 2)
      tree = t[0] + t[1];
    else if (n == 4)
      tree = (t[0] + t[1]) + (t[2] + t[3]);
    else
      tree = ((t[0] + t[1]) + (t[2] + t[3])) + ((t[4] + t[5]) + (t[6] + t[7]));
    acc += weight * tree;
  }
  return acc;
}

// The reaction of generalized_rd_rows' rates at cell (x, y): Gray-Scott (model 0, with the
// parameter map when f_step or k_step is not 0), Turing (1) in float, the others through rd_rates.
inline void generalized_rates(int model, float p0, float p1, float p2, float p3, float p4,
                              float f_step, float k_step, int x, int y, float A, float B,
                              float* ra, float* rb) {
  if (model == 0 && (f_step != 0.0f || k_step != 0.0f)) {
    const float f = p0 + f_step * ((float)x + 0.5f);
    const float k = p1 + k_step * ((float)y + 0.5f);
    const float abb = A * B * B;
    *ra = f * (1.0f - A) - abb;
    *rb = abb - (f + k) * B;
  } else if (model == 0) {
    const float abb = A * B * B;
    *ra = p0 * (1.0f - A) - abb;
    *rb = abb - (p0 + p1) * B;
  } else if (model == 1) {
    const float ab = A * B;
    *ra = p0 * (ab - A - p1);
    *rb = p0 * (p2 - ab);
  } else {
    real rra, rrb;
    rd_rates(model, p0, p1, p2, p3, p4, (real)A, (real)B, &rra, &rrb);
    *ra = (float)rra;
    *rb = (float)rrb;
  }
}

__kernel void generalized_rd(__global const float* a, __global const float* b,
                             __global float* a_out, __global float* b_out, int stride, int origin,
                             int2 size, __constant const float* w, int model, float p0, float p1,
                             float p2, float p3, float p4, float dt, float sa, float sb,
                             float4 box, float f_step, float k_step) {
  const int x = get_global_id(0), y = get_global_id(1);
  if (x >= size.x || y >= size.y) return;
  const int g = global_index(stride, origin, x, y);
  const float A = a[g], B = b[g];
  float ra, rb;
  generalized_rates(model, p0, p1, p2, p3, p4, f_step, k_step, x, y, A, B, &ra, &rb);
  const float da = sa != 0.0f ? sa * stencil_groups(a, w, stride, origin, x, y, size.x, size.y) : 0.0f;
  const float db = sb != 0.0f ? sb * stencil_groups(b, w, stride, origin, x, y, size.x, size.y) : 0.0f;
  a_out[g] = min(max(A + da + dt * ra, box.s0), box.s1);
  b_out[g] = min(max(B + db + dt * rb, box.s2), box.s3);
}

// Twin of kernels/generalized_rd.h tensor_field_rd_rows (seed 003, Table 1's last row at rank 2):
// div(D(x) grad u) in flux form on the face field (x_xx, x_xy: the face between x and x + 1;
// y_xy, y_yy: between y and y + 1; halo 0, their own stride fs), indices wrapped, the C++'s
// arithmetic in its order (kernels/tensor_field_operator.h TensorFieldOperator). The reaction and the clamp as generalized_rd's.
inline float u_at(__global const float* u, int stride, int origin, int x, int y) {
  return u[global_index(stride, origin, x, y)];
}

inline float face_flux_x(__global const float* u, int stride, int origin,
                         __global const float* x_xx, __global const float* x_xy, int fs, int x,
                         int xp, int y, int ym, int yp) {
  const float gx = u_at(u, stride, origin, xp, y) - u_at(u, stride, origin, x, y);
  const float gy = 0.25f * ((u_at(u, stride, origin, x, yp) + u_at(u, stride, origin, xp, yp)) -
                            (u_at(u, stride, origin, x, ym) + u_at(u, stride, origin, xp, ym)));
  return x_xx[y * fs + x] * gx + x_xy[y * fs + x] * gy;
}

inline float face_flux_y(__global const float* u, int stride, int origin,
                         __global const float* y_xy, __global const float* y_yy, int fs, int x,
                         int xm, int xp, int y, int yp) {
  const float gy = u_at(u, stride, origin, x, yp) - u_at(u, stride, origin, x, y);
  const float gx = 0.25f * ((u_at(u, stride, origin, xp, y) + u_at(u, stride, origin, xp, yp)) -
                            (u_at(u, stride, origin, xm, y) + u_at(u, stride, origin, xm, yp)));
  return y_yy[y * fs + x] * gy + y_xy[y * fs + x] * gx;
}

inline float tensor_divergence(__global const float* u, int stride, int origin,
                               __global const float* x_xx, __global const float* x_xy,
                               __global const float* y_xy, __global const float* y_yy, int fs,
                               int x, int y, int nx, int ny) {
  const int xm = wrap_index(x - 1, nx), xp = wrap_index(x + 1, nx);
  const int ym = wrap_index(y - 1, ny), yp = wrap_index(y + 1, ny);
  const float fe = face_flux_x(u, stride, origin, x_xx, x_xy, fs, x, xp, y, ym, yp);
  const float fw = face_flux_x(u, stride, origin, x_xx, x_xy, fs, xm, x, y, ym, yp);
  const float gn = face_flux_y(u, stride, origin, y_xy, y_yy, fs, x, xm, xp, y, yp);
  const float gs = face_flux_y(u, stride, origin, y_xy, y_yy, fs, x, xm, xp, ym, y);
  return (fe - fw) + (gn - gs);
}

__kernel void tensor_field_rd(__global const float* a, __global const float* b,
                              __global float* a_out, __global float* b_out, int stride, int origin,
                              int2 size, __global const float* x_xx, __global const float* x_xy,
                              __global const float* y_xy, __global const float* y_yy, int fs,
                              int model, float p0, float p1, float p2, float p3, float p4,
                              float dt, float sa, float sb, float4 box, float f_step,
                              float k_step) {
  const int x = get_global_id(0), y = get_global_id(1);
  if (x >= size.x || y >= size.y) return;
  const int g = global_index(stride, origin, x, y);
  const float A = a[g], B = b[g];
  float ra, rb;
  generalized_rates(model, p0, p1, p2, p3, p4, f_step, k_step, x, y, A, B, &ra, &rb);
  const float da =
      sa != 0.0f
          ? sa * tensor_divergence(a, stride, origin, x_xx, x_xy, y_xy, y_yy, fs, x, y, size.x,
                                   size.y)
          : 0.0f;
  const float db =
      sb != 0.0f
          ? sb * tensor_divergence(b, stride, origin, x_xx, x_xy, y_xy, y_yy, fs, x, y, size.x,
                                   size.y)
          : 0.0f;
  a_out[g] = min(max(A + da + dt * ra, box.s0), box.s1);
  b_out[g] = min(max(B + db + dt * rb, box.s2), box.s3);
}
