// The spectral steps around the device FFT's transforms (fft.cl; host side:
// kernels/cl/opencl_fft.h):
//   seed 003, Eqn 28's linear part, x <- (I - delta K)^{-1} x, each Fourier mode times
//     1 / ((1 - delta symbol(k)) nx ny) (kernels/periodic_stencil_solve.h), and
//   the ETDRK4 step of kernels/periodic_etdrk4.h (Cox & Matthews' ETD4RK with Kassam &
//     Trefethen's coefficients): the reaction N(u) of the stages in cells, and the stages'
//     combinations per mode.
// The transforms take packed fields: `batch` fields of nx x ny cells, field f's cell (x, y) at
// packed[(f ny + y) nx + x]; their half spectra (real-to-complex) at spectrum[(f ny + my) w + mx],
// w = nx / 2 + 1: the transpose of the CPU tables' [mx][my], which the host transposes on upload.
// Sorted after reaction.cl in the one program: rd_rates is its.

// A field's interior into field `at` of a packed batch, and back: the transforms run on packed
// batches (one launch per pass over every field of a batch), not at a field's origin (a
// sub-buffer there would break the device's base-address alignment). One work-item per cell.
__kernel void spectral_pack(__global const float* f, int stride, int origin, int nx, int ny,
                            __global float* packed, int at) {
  const int x = get_global_id(0), y = get_global_id(1);
  if (x >= nx || y >= ny) return;
  packed[(at * ny + y) * nx + x] = f[global_index(stride, origin, x, y)];
}

__kernel void spectral_unpack(__global const float* packed, int at, int nx, int ny,
                              __global float* f, int stride, int origin) {
  const int x = get_global_id(0), y = get_global_id(1);
  if (x >= nx || y >= ny) return;
  f[global_index(stride, origin, x, y)] = packed[(at * ny + y) * nx + x];
}

// Seed 003, Eqn 28: each mode of the spectrum times its multiplier (complex, in float as the
// CPU's std::complex<float> product: (ac - bd, ad + bc)).
__kernel void spectral_multiply(__global float2* spectrum, __global const float2* multiplier,
                                int modes) {
  const int i = get_global_id(0);
  if (i >= modes) return;
  const float2 s = spectrum[i], m = multiplier[i];
  spectrum[i] = (float2)(s.x * m.x - s.y * m.y, s.x * m.y + s.y * m.x);
}

// N(u) = (R_A, R_B) (kernels/reaction.cpp reaction_rates, in real, rounded to float) of `cells`
// packed cells: chemical A's at u[i], B's at u[cells + i]; n likewise. react 0: N = 0.
__kernel void spectral_reaction(__global const float* u, __global float* n, int cells, int model,
                                float p0, float p1, float p2, float p3, float p4, int react) {
  const int i = get_global_id(0);
  if (i >= cells) return;
  real ra = 0, rb = 0;
  if (react) rd_rates(model, p0, p1, p2, p3, p4, u[i], u[cells + i], &ra, &rb);
  n[i] = (float)ra;
  n[cells + i] = (float)rb;
}

// The ETDRK4 coefficient table t (0..5: E, E2, Q, f1, f2, f3) of chemical c at mode m.
inline float etd_coefficient(__global const float* coef, int modes, int c, int t, int m) {
  return coef[(c * 6 + t) * modes + m];
}

// One stage's combination per mode (kernels/periodic_etdrk4.cpp's column pass, in its float
// order), both chemicals: mode m of chemical c at index c modes + m of every spectrum. v = u^,
// n_u = N_u^, n_ab = N_a^ (then N_a^ + N_b^), n_stage = the N^ of the stage's field; out = the
// next stage's field times scale = 1 / (nx ny) (the backward transform does not scale).
//   stage 0 (A): n_u = n_stage, out = E2 v + Q n_u
//   stage 1 (B): n_ab = n_stage, out = E2 v + Q n_ab
//   stage 2 (C): a = E2 v + Q n_u, n_ab += n_stage, out = E2 a + Q (2 n_stage - n_u)
//   stage 3:     out = E v + f1 n_u + 2 f2 n_ab + f3 n_stage
__kernel void etdrk4_combine(__global const float2* v, __global float2* n_u, __global float2* n_ab,
                             __global const float2* n_stage, __global float2* out,
                             __global const float* coef, int modes, int stage, float scale) {
  const int i = get_global_id(0);
  if (i >= 2 * modes) return;
  const int c = i / modes, m = i - c * modes;
  const float e2 = etd_coefficient(coef, modes, c, 1, m);
  const float q = etd_coefficient(coef, modes, c, 2, m);
  const float2 vi = v[i], ns = n_stage[i];
  float2 r;
  switch (stage) {
    case 0:
      n_u[i] = ns;
      r = e2 * vi + q * ns;
      break;
    case 1:
      n_ab[i] = ns;
      r = e2 * vi + q * ns;
      break;
    case 2: {
      const float2 nu = n_u[i];
      const float2 a = e2 * vi + q * nu;
      n_ab[i] = n_ab[i] + ns;
      r = e2 * a + q * (2.0f * ns - nu);
      break;
    }
    default: {
      const float e = etd_coefficient(coef, modes, c, 0, m);
      const float f1 = etd_coefficient(coef, modes, c, 3, m);
      const float f2 = etd_coefficient(coef, modes, c, 4, m);
      const float f3 = etd_coefficient(coef, modes, c, 5, m);
      r = e * vi + f1 * n_u[i] + (2.0f * f2) * n_ab[i] + f3 * ns;
      break;
    }
  }
  out[i] = r * scale;
}
