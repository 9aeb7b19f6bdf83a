// Twin of kernels/generalized_rd.h: seed 003's Eqn 27 with reaction on a periodic grid,
//   A' = A + s_A K A + dt R_A(A, B),  B' = B + s_B K B + dt R_B(A, B)
// K the 25-point stencil (weights w[25], row-major from (dx, dy) = (-2, -2)); indices wrap, so it
// reads no halo. Each cell sums its nonzero taps in that order in float, and Gray-Scott (model 0)
// and Turing (1) react in float as the C++ kernel does, each result clamped to box = (a_lo, a_hi,
// b_lo, b_hi); the other models through
// rd_rates (reaction.cl, embedded before this file: sources go in name order). Model ids and
// p0..p4 as reaction.cl's. Gray-Scott's parameter map: F + f_step (x + 1/2), k + k_step (y + 1/2)
// (both 0: uniform). One work-item per cell.
inline int wrap_index(int i, int n) { return i < 0 ? i + n : (i >= n ? i - n : i); }

inline float stencil25(__global const float* f, __constant const float* w, int stride,
                       int origin, int x, int y, int nx, int ny) {
  float acc = 0.0f;
  for (int dy = -2; dy <= 2; ++dy) {
    const int row = origin + wrap_index(y + dy, ny) * stride;
    for (int dx = -2; dx <= 2; ++dx) {
      const float weight = w[(dy + 2) * 5 + dx + 2];
      if (weight != 0.0f) acc += weight * f[row + wrap_index(x + dx, nx)];
    }
  }
  return acc;
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
  if (model == 0 && (f_step != 0.0f || k_step != 0.0f)) {
    const float f = p0 + f_step * ((float)x + 0.5f);
    const float k = p1 + k_step * ((float)y + 0.5f);
    const float abb = A * B * B;
    ra = f * (1.0f - A) - abb;
    rb = abb - (f + k) * B;
  } else if (model == 0) {
    const float abb = A * B * B;
    ra = p0 * (1.0f - A) - abb;
    rb = abb - (p0 + p1) * B;
  } else if (model == 1) {
    const float ab = A * B;
    ra = p0 * (ab - A - p1);
    rb = p0 * (p2 - ab);
  } else {
    real rra, rrb;
    rd_rates(model, p0, p1, p2, p3, p4, (real)A, (real)B, &rra, &rrb);
    ra = (float)rra;
    rb = (float)rrb;
  }
  const float da = sa != 0.0f ? sa * stencil25(a, w, stride, origin, x, y, size.x, size.y) : 0.0f;
  const float db = sb != 0.0f ? sb * stencil25(b, w, stride, origin, x, y, size.x, size.y) : 0.0f;
  a_out[g] = min(max(A + da + dt * ra, box.s0), box.s1);
  b_out[g] = min(max(B + db + dt * rb, box.s2), box.s3);
}
