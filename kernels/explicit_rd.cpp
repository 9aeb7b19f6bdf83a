#include "kernels/explicit_rd.h"

namespace ardcell {
namespace {

template <class Laplacian>
void explicit_rd_tile(View<const float> a, View<const float> b, View<float> a_out,
                      View<float> b_out, Box2 region, const ExplicitRdParams& p,
                      const Laplacian& lap) {
  ARDCELL_DCHECK(a.box().contains(region.grown(1)) && b.box().contains(region.grown(1)),
                 "explicit RD reads halo 1");
  for (int y = region.min.y; y < region.max.y; ++y) {
    float* ao = a_out.row(y);
    float* bo = b_out.row(y);
    for (int x = region.min.x; x < region.max.x; ++x) {
      const double A = a(x, y), B = b(x, y);
      double ra, rb;
      reaction_rates(p.reaction, A, B, ra, rb);
      ao[x] = float(A + p.dt * ra + p.diffusion_a * lap(a, x, y));
      bo[x] = float(B + p.dt * rb + p.diffusion_b * lap(b, x, y));
    }
  }
}

double laplacian5(const View<const float>& f, int x, int y) {
  return double(f(x - 1, y)) + f(x + 1, y) + f(x, y - 1) + f(x, y + 1) - 4.0 * f(x, y);
}

double laplacian9(const View<const float>& f, int x, int y) {
  const double corners =
      double(f(x - 1, y - 1)) + f(x + 1, y - 1) + f(x - 1, y + 1) + f(x + 1, y + 1);
  const double edges = double(f(x - 1, y)) + f(x + 1, y) + f(x, y - 1) + f(x, y + 1);
  return 0.05 * corners + 0.2 * edges - double(f(x, y));
}

}  // namespace

void explicit_rd5_tile(View<const float> a, View<const float> b, View<float> a_out,
                       View<float> b_out, Box2 region, const ExplicitRdParams& p) {
  explicit_rd_tile(a, b, a_out, b_out, region, p, laplacian5);
}

void explicit_rd9_tile(View<const float> a, View<const float> b, View<float> a_out,
                       View<float> b_out, Box2 region, const ExplicitRdParams& p) {
  explicit_rd_tile(a, b, a_out, b_out, region, p, laplacian9);
}

namespace {

struct Gs9Row {
  float F, fk, dt, ca, cb, ma, mb;
};

// One output row. Separate function so that the restrict-qualified parameters tell the
// compiler the rows do not alias (both loops then vectorise).
inline void gray_scott9_row(const float* __restrict a0, const float* __restrict a1,
                            const float* __restrict a2, const float* __restrict b0,
                            const float* __restrict b1, const float* __restrict b2,
                            float* __restrict va, float* __restrict vb, float* __restrict ao,
                            float* __restrict bo, int n, const Gs9Row& c) {
  for (int i = 0; i < n + 2; ++i) {
    va[i] = a0[i] + 4.0f * a1[i] + a2[i];
    vb[i] = b0[i] + 4.0f * b1[i] + b2[i];
  }
  const float F = c.F, fk = c.fk, dt = c.dt, ca = c.ca, cb = c.cb, ma = c.ma, mb = c.mb;
  for (int i = 0; i < n; ++i) {
    const float A = a1[i + 1], B = b1[i + 1];
    const float sa = va[i] + 4.0f * va[i + 1] + va[i + 2];
    const float sb = vb[i] + 4.0f * vb[i + 1] + vb[i + 2];
    const float abb = A * B * B;
    ao[i] = A + ca * sa - ma * A + dt * (F * (1.0f - A) - abb);
    bo[i] = B + cb * sb - mb * B + dt * (abb - fk * B);
  }
}

}  // namespace

void gray_scott9_explicit_row(const float* const a_rows[3], const float* const b_rows[3],
                              float* a_out, float* b_out, int n, const GrayScott9Params& p,
                              float* scratch) {
  const Gs9Row c{p.F,
                 p.F + p.k,
                 p.dt,
                 0.05f * p.diffusion_a,
                 0.05f * p.diffusion_b,
                 1.8f * p.diffusion_a,
                 1.8f * p.diffusion_b};
  gray_scott9_row(a_rows[0], a_rows[1], a_rows[2], b_rows[0], b_rows[1], b_rows[2], scratch,
                  scratch + (n + 2), a_out, b_out, n, c);
}

void gray_scott9_explicit_tile(View<const float> a, View<const float> b, View<float> a_out,
                               View<float> b_out, Box2 region, const GrayScott9Params& p,
                               float* scratch) {
  ARDCELL_DCHECK(a.box().contains(region.grown(1)) && b.box().contains(region.grown(1)),
                 "explicit RD reads halo 1");
  const int x0 = region.min.x, n = region.width();
  const Gs9Row c{p.F,
                 p.F + p.k,
                 p.dt,
                 0.05f * p.diffusion_a,
                 0.05f * p.diffusion_b,
                 1.8f * p.diffusion_a,
                 1.8f * p.diffusion_b};
  // Column sums (1 4 1) over rows y-1, y, y+1, for columns x0-1 .. x0+n.
  float* va = scratch;
  float* vb = scratch + (n + 2);
  for (int y = region.min.y; y < region.max.y; ++y) {
    gray_scott9_row(a.row(y - 1) + x0 - 1, a.row(y) + x0 - 1, a.row(y + 1) + x0 - 1,
                    b.row(y - 1) + x0 - 1, b.row(y) + x0 - 1, b.row(y + 1) + x0 - 1, va, vb,
                    a_out.row(y) + x0, b_out.row(y) + x0, n, c);
  }
}

}  // namespace ardcell
