// The radix passes of batched 1D complex FFTs (mixed-radix Stockham autosort), of which the
// device's 2D real transforms are made (host side, and how the passes chain into a 2D
// real-to-complex or complex-to-real transform: kernels/cl/opencl_fft.h, ClFft2d): the periodic
// solve and ETDRK4 steps on the device (spectral.cl). Ours rather than a library's so that a
// transform is nothing but kernel launches: no host allocation per frame.
//
// A transform of length n = R_0 R_1 ... R_{s-1} (each radix 1, 2, 3, 4, 5, 7, 8 or 16) is s
// passes; pass p has radix R = R_p and span = R_0 ... R_{p-1}: it joins R sub-transforms of
// length span into transforms of length span R. Work-item j in [0, n / R) of a transform reads
// elements j + r n / R (r < R), multiplies element r by the twiddle
// w_n^(r (j mod span) n / (span R)), takes their R-point DFT and writes output q to element
// (j / span) span R + (j mod span) + q span (Stockham: the output is in natural order after the
// last pass, no bit reversal). The roots w_n^k = exp(-2 pi i k / n), k < n, come from a table
// computed on the host in double and rounded to float once (the R-point DFT's roots are its
// entries k = m n / R; radices 8 and 16 are two levels of 2- and 4-point DFTs); the inverse
// transform uses their conjugates and does not scale.
//
// One launch runs the pass of every transform of a batch, one work-item per (field, transform,
// j), in a 3D range: dimension 2 the field, 0 and 1 the transform `within` (< per_field) and j,
// in that order with transforms_fastest (columns: neighbouring work-items take neighbouring
// columns, coalesced on a GPU), else j first (rows); both may be padded to whole work-groups.
// Transform `within` of field f starts at element f field_distance + within distance of its
// buffer and steps by `stride`. (The range is 3D so that no work-item decodes (field,
// transform, j) from one index by divisions: on PoCL, decoding a 1D range's index took about a
// third of a transform's time.)
//
// What a pass reads (in_kind) and writes (out_kind), so that the first and last passes of a 2D
// real transform also convert between real fields and complex rows. An even-length real row x
// transforms as the complex row z_j = x_2j + i x_(2j+1) of half its length m (its buffer read
// as float2): its DFT Z gives the row's, X_k = (Z_k + conj Z_(m-k)) / 2 + w_2m^k (Z_k -
// conj Z_(m-k)) / 2i for k <= m (Z_m = Z_0): the split, done as the first column pass loads.
// Backward, the merge 2 Z_k = (X_k + conj X_(m-k)) + i w_2m^-k (X_k - conj X_(m-k)), k < m,
// done as the first row pass loads, inverts it (times 2: the unscaled inverse of length m then
// gives 2m = nx times the row). An odd-length row transforms as a complex row (kinds 1, 2).
//   in_kind  0: complex elements; 1: real elements (the imaginary part 0);
//            2: the half spectrum of a real row of odd length n, elements k <= n / 2 stored,
//               k > n / 2 taken as conj(element n - k) (Hermitian symmetry);
//            3: the split (a column pass: element e of column mx is X_mx of row e, from the Z
//               rows of length m = half_n, row e at field_base + e stride);
//            4: the merge (a row pass: element k of the row is 2 Z_k, from the row's half
//               spectrum X_0 .. X_m, m = half_n, at its base + k stride);
//   out_kind 0: complex elements, only those below out_keep (the half spectrum's n / 2 + 1);
//            1: the real part of each element.
// As FFTW's complex-to-real transforms do, the imaginary parts of a real row's X_0 (and X_m) are
// taken as 0: kind 4 drops them, and kind 2's real part on output drops what they add.
// Products and sums round one by one: common.cl's FP_CONTRACT OFF holds for the whole program.

inline float2 fft_cmul(float2 a, float2 b) {
  return (float2)(a.x * b.x - a.y * b.y, a.x * b.y + a.y * b.x);
}

inline float2 fft_conj(float2 a) { return (float2)(a.x, -a.y); }

// i a, and -i a (exact).
inline float2 fft_times_i(float2 a) { return (float2)(-a.y, a.x); }
inline float2 fft_times_minus_i(float2 a) { return (float2)(a.y, -a.x); }

// w_n^k from the table (its conjugate for the inverse transform).
inline float2 fft_root(__global const float2* roots, int k, int inverse) {
  const float2 w = roots[k];
  return inverse ? fft_conj(w) : w;
}

// Element e of transform `within` of the field at field_base (see in_kind above); split_roots:
// w_(2 half_n)^k, k < 2 half_n.
inline float2 fft_load(__global const float* in, int kind, int field_base, int within, int stride,
                       int distance, int e, int n, int half_n, __global const float2* split_roots) {
  const int base = field_base + within * distance;
  if (kind == 1) return (float2)(in[base + e * stride], 0.0f);
  __global const float2* c = (__global const float2*)in;
  if (kind == 2 && e > n / 2) return fft_conj(c[base + (n - e) * stride]);
  if (kind == 3) {
    const int row = field_base + e * stride, mx = within;
    // Z_(mx mod m) and Z_((m - mx) mod m), mx <= m.
    const float2 z = c[row + (mx == half_n ? 0 : mx)];
    const float2 mirror = fft_conj(c[row + (mx == 0 ? 0 : half_n - mx)]);
    const float2 even = (z + mirror) * 0.5f, odd = fft_times_minus_i(z - mirror) * 0.5f;
    return even + fft_cmul(split_roots[mx], odd);
  }
  if (kind == 4) {
    float2 x = c[base + e * stride], mirror = fft_conj(c[base + (half_n - e) * stride]);
    if (e == 0) x.y = mirror.y = 0.0f;
    const float2 odd = fft_cmul(x - mirror, fft_conj(split_roots[e]));
    return (x + mirror) + fft_times_i(odd);
  }
  return c[base + e * stride];
}

// The 4-point DFT of x in place, by two 2-point ones; w_4 = -i (forward) or i (inverse) is exact.
inline void fft_dft4(float2* x, int inverse) {
  const float2 s02 = x[0] + x[2], d02 = x[0] - x[2];
  const float2 s13 = x[1] + x[3], d13 = x[1] - x[3];
  const float2 d13w = inverse ? fft_times_i(d13) : fft_times_minus_i(d13);
  x[0] = s02 + s13;
  x[1] = d02 + d13w;
  x[2] = s02 - s13;
  x[3] = d02 - d13w;
}

inline void fft_store(__global float* out, int kind, int base, int stride, int e, int keep,
                      float2 v) {
  if (kind == 1) {
    out[base + e * stride] = v.x;
  } else if (e < keep) {
    ((__global float2*)out)[base + e * stride] = v;
  }
}

inline void fft_pass(const int radix, __global const float* in, __global float* out,
                     __global const float2* roots, __global const float2* split_roots, int n,
                     int half_n, int span, int twiddle_stride, int inverse, int per_field,
                     int transforms_fastest, int in_kind, int in_stride, int in_distance,
                     int in_field_distance, int out_kind, int out_stride, int out_distance,
                     int out_field_distance, int out_keep) {
  const int per_transform = n / radix;  // work-items per transform
  const int a = get_global_id(0), b = get_global_id(1), field = get_global_id(2);
  const int within = transforms_fastest ? a : b, j = transforms_fastest ? b : a;
  if (within >= per_field || j >= per_transform) return;
  const int in_field_base = field * in_field_distance;
  const int out_base = field * out_field_distance + within * out_distance;
  const int span_block = j / span, k = j - span_block * span;
  const int twiddle_step = k * twiddle_stride;  // r's twiddle is w_n^(r k n / (span R))

  float2 v[16];
  for (int r = 0; r < radix; ++r) {
    const float2 x = fft_load(in, in_kind, in_field_base, within, in_stride, in_distance,
                              j + r * per_transform, n, half_n, split_roots);
    v[r] = r == 0 ? x : fft_cmul(x, fft_root(roots, r * twiddle_step, inverse));
  }

  float2 y[16];
  if (radix == 2) {
    y[0] = v[0] + v[1];
    y[1] = v[0] - v[1];
  } else if (radix == 4) {
    for (int q = 0; q < 4; ++q) y[q] = v[q];
    fft_dft4(y, inverse);
  } else if (radix == 8 || radix == 16) {
    // R = 4 B (B = 2 or 4), r = B r2 + r1, q = q1 + 4 q2: the 4-point DFTs over r2 of the B
    // sequences x_(B r2 + r1), their outputs q1 times w_R^(r1 q1), then the B-point DFTs over
    // r1 give y_(q1 + 4 q2).
    const int b = radix / 4;
    float2 t[16];
    for (int r1 = 0; r1 < b; ++r1) {
      float2 quarter[4];
      for (int r2 = 0; r2 < 4; ++r2) quarter[r2] = v[b * r2 + r1];
      fft_dft4(quarter, inverse);
      for (int q1 = 0; q1 < 4; ++q1)
        t[4 * r1 + q1] =
            r1 * q1 == 0 ? quarter[q1]
                         : fft_cmul(quarter[q1], fft_root(roots, r1 * q1 * per_transform, inverse));
    }
    for (int q1 = 0; q1 < 4; ++q1) {
      float2 across[4];
      for (int r1 = 0; r1 < b; ++r1) across[r1] = t[4 * r1 + q1];
      if (b == 4) {
        fft_dft4(across, inverse);
      } else {
        const float2 sum = across[0] + across[1], difference = across[0] - across[1];
        across[0] = sum;
        across[1] = difference;
      }
      for (int q2 = 0; q2 < b; ++q2) y[q1 + 4 * q2] = across[q2];
    }
  } else {
    // Radix 1, 3, 5, 7: the direct R-point DFT, y_q = sum_r v_r w_R^(r q), w_R^m = w_n^(m n / R).
    for (int q = 0; q < radix; ++q) {
      float2 sum = v[0];
      for (int r = 1; r < radix; ++r)
        sum += q == 0 ? v[r]
                      : fft_cmul(v[r], fft_root(roots, ((r * q) % radix) * per_transform, inverse));
      y[q] = sum;
    }
  }

  const int first = span_block * span * radix + k;
  for (int q = 0; q < radix; ++q)
    fft_store(out, out_kind, out_base, out_stride, first + q * span, out_keep, y[q]);
}

// Two kernels per radix, so that in each the radix is a constant: the loops over r and q unroll
// and v, y can live in registers (with the radix an argument, a transform took about 1.7x as
// long on PoCL). fft_pass_radixR reads and writes any kind; fft_complex_pass_radixR complex
// elements only (the passes inside a phase, and most first and last ones), without the kinds'
// branches (about 15% less time a transform on PoCL).
#define FFT_PASS_KERNELS(R)                                                                       \
  __kernel void fft_pass_radix##R(                                                                \
      __global const float* in, __global float* out, __global const float2* roots,                \
      __global const float2* split_roots, int n, int half_n, int span, int twiddle_stride,        \
      int inverse, int per_field, int transforms_fastest, int in_kind, int in_stride,             \
      int in_distance, int in_field_distance, int out_kind, int out_stride, int out_distance,     \
      int out_field_distance, int out_keep) {                                                     \
    fft_pass(R, in, out, roots, split_roots, n, half_n, span, twiddle_stride, inverse, per_field, \
             transforms_fastest, in_kind, in_stride, in_distance, in_field_distance, out_kind,    \
             out_stride, out_distance, out_field_distance, out_keep);                             \
  }                                                                                               \
  __kernel void fft_complex_pass_radix##R(                                                        \
      __global const float* in, __global float* out, __global const float2* roots,                \
      __global const float2* split_roots, int n, int half_n, int span, int twiddle_stride,        \
      int inverse, int per_field, int transforms_fastest, int in_kind, int in_stride,             \
      int in_distance, int in_field_distance, int out_kind, int out_stride, int out_distance,     \
      int out_field_distance, int out_keep) {                                                     \
    fft_pass(R, in, out, roots, split_roots, n, half_n, span, twiddle_stride, inverse, per_field, \
             transforms_fastest, 0, in_stride, in_distance, in_field_distance, 0, out_stride,     \
             out_distance, out_field_distance, out_keep);                                         \
  }
FFT_PASS_KERNELS(1)
FFT_PASS_KERNELS(2)
FFT_PASS_KERNELS(3)
FFT_PASS_KERNELS(4)
FFT_PASS_KERNELS(5)
FFT_PASS_KERNELS(7)
FFT_PASS_KERNELS(8)
FFT_PASS_KERNELS(16)
