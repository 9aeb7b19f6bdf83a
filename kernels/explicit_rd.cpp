#include "kernels/explicit_rd.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>

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

GrayScott9Coeffs gray_scott9_coeffs(const GrayScott9Params& p) {
  return {0.05f * p.diffusion_a,
          0.05f * p.diffusion_b,
          1.0f - 1.8f * p.diffusion_a - p.dt * p.F,
          1.0f - 1.8f * p.diffusion_b - p.dt * (p.F + p.k),
          p.dt * p.F,
          p.dt};
}

namespace {

// One output row. Separate function so that the restrict-qualified parameters tell the
// compiler the rows do not alias (both loops then vectorise; std::fma is one instruction on a
// machine with FMA).
inline void gray_scott9_row(const float* __restrict a0, const float* __restrict a1,
                            const float* __restrict a2, const float* __restrict b0,
                            const float* __restrict b1, const float* __restrict b2,
                            float* __restrict va, float* __restrict vb, float* __restrict ao,
                            float* __restrict bo, int n, const GrayScott9Coeffs& c) {
  for (int i = 0; i < n + 2; ++i) {
    va[i] = std::fma(4.0f, a1[i], a0[i] + a2[i]);
    vb[i] = std::fma(4.0f, b1[i], b0[i] + b2[i]);
  }
  for (int i = 0; i < n; ++i) {
    const float A = a1[i + 1], B = b1[i + 1];
    const float sa = std::fma(4.0f, va[i + 1], va[i] + va[i + 2]);
    const float sb = std::fma(4.0f, vb[i + 1], vb[i] + vb[i + 2]);
    const float bb = c.dt * (B * B);
    ao[i] = std::fma(-A, bb, std::fma(c.ca, sa, std::fma(c.pa, A, c.q)));
    bo[i] = std::fma(A, bb, std::fma(c.cb, sb, c.pb * B));
  }
}

}  // namespace

void gray_scott9_explicit_tile(View<const float> a, View<const float> b, View<float> a_out,
                               View<float> b_out, Box2 region, const GrayScott9Params& p,
                               float* scratch) {
  ARDCELL_DCHECK(a.box().contains(region.grown(1)) && b.box().contains(region.grown(1)),
                 "explicit RD reads halo 1");
  const int x0 = region.min.x, n = region.width();
  const GrayScott9Coeffs c = gray_scott9_coeffs(p);
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

namespace ardcell {
namespace {

uint32_t bits_of(float v) { return std::bit_cast<uint32_t>(v); }
Box2 grown_if_any(const Box2& b) { return b.empty() ? b : b.grown(1); }

}  // namespace

bool QuiescentBox::skips(const GrayScott9Params& p) {
  if (found_ && std::memcmp(&p, &params_, sizeof p) == 0) return skips_;
  params_ = p;
  found_ = true;
  skips_ = false;
  restart();
  // The update of one cell in a uniform 3x3 neighbourhood, iterated from (1, 0): seed 001's
  // parameters reach their fixed point in 2 steps; a state still moving after 64 is not one.
  constexpr int kMaxIterations = 64;
  const Box2 around{{-1, -1}, {2, 2}}, centre{{0, 0}, {1, 1}};
  float a[9], b[9], a_out[9], b_out[9], scratch[2 * 3];
  float A = 1.0f, B = 0.0f;
  for (int i = 0; i < kMaxIterations; ++i) {
    std::fill(a, a + 9, A);
    std::fill(b, b + 9, B);
    gray_scott9_explicit_tile(View<const float>(a, 3, around), View<const float>(b, 3, around),
                              View<float>(a_out, 3, around), View<float>(b_out, 3, around), centre,
                              p, scratch);
    const float a1 = a_out[4], b1 = b_out[4];
    if (!std::isfinite(a1) || !std::isfinite(b1)) return false;
    if (bits_of(a1) == bits_of(A) && bits_of(b1) == bits_of(B)) {
      fixed_a_ = bits_of(A);
      fixed_b_ = bits_of(B);
      skips_ = true;
      return true;
    }
    A = a1;
    B = b1;
  }
  return false;
}

float QuiescentBox::fixed_a() const { return std::bit_cast<float>(fixed_a_); }
float QuiescentBox::fixed_b() const { return std::bit_cast<float>(fixed_b_); }

Box2 QuiescentBox::differing(View<const float> a, View<const float> b, Box2 rows) const {
  Box2 box{};
  const auto differs = [&](const float* ra, const float* rb, int x) {
    return bits_of(ra[x]) != fixed_a_ || bits_of(rb[x]) != fixed_b_;
  };
  for (int y = rows.min.y; y < rows.max.y; ++y) {
    const float* ra = a.row(y);
    const float* rb = b.row(y);
    int lo = rows.min.x;
    while (lo < rows.max.x && !differs(ra, rb, lo)) ++lo;
    if (lo == rows.max.x) continue;
    int hi = rows.max.x - 1;
    while (!differs(ra, rb, hi)) --hi;
    box = box.united({{lo, y}, {hi + 1, y + 1}});
  }
  return box;
}

Box2 QuiescentBox::region(View<const float> a, View<const float> b, Box2 cells) const {
  if (!known_) return cells;
  // The ring's four sides: what the boundary fill or the halo exchange brought in.
  const Box2 around = cells.grown(1);
  const Box2 ring =
      differing(a, b, {around.min, {around.max.x, cells.min.y}})
          .united(differing(a, b, {{around.min.x, cells.max.y}, around.max}))
          .united(differing(a, b, {{around.min.x, cells.min.y}, {cells.min.x, cells.max.y}}))
          .united(differing(a, b, {{cells.max.x, cells.min.y}, {around.max.x, cells.max.y}}));
  return grown_if_any(state_).united(other_).united(grown_if_any(ring)).intersected(cells);
}

namespace {

constexpr Int2 kAllRows{-(1 << 30), 1 << 30};
bool no_rows(Int2 r) { return r.y <= r.x; }
// The smallest interval holding both (an empty one adds nothing).
Int2 rows_united(Int2 a, Int2 b) {
  if (no_rows(b)) return a;
  if (no_rows(a)) return b;
  return {std::min(a.x, b.x), std::max(a.y, b.y)};
}

}  // namespace

void QuiescentBox::restart() {
  known_ = false;  // (a pending halo_exchanged() stays: the state's halo is still the exchange's)
  for (int side = 0; side < 2; ++side)
    for (int d = 0; d <= kMaxGrow + 1; ++d) side_state_[side][d] = side_other_[side][d] = kAllRows;
}

void QuiescentBox::begin_sides(View<const float> a, View<const float> b, Box2 inner, int grow) {
  ARDCELL_CHECK(grow >= 0 && grow <= kMaxGrow, "QuiescentBox: at most kMaxGrow halo columns");
  if (!exchanged_) return;  // a later step of the same exchange
  exchanged_ = false;
  for (int side = 0; side < 2; ++side)
    for (int d = 1; d <= grow + 1; ++d) {
      const int x = side == 0 ? inner.min.x - d : inner.max.x - 1 + d;
      const Box2 box = differing(a, b, {{x, inner.min.y}, {x + 1, inner.max.y}});
      side_state_[side][d] = box.empty() ? Int2{} : Int2{box.min.y, box.max.y};
    }
}

Int2 QuiescentBox::column_rows(int side, int d, Box2 inner) const {
  if (d > 0) return side_state_[side][d];
  // The interior's column next to the halo: the rows of the state's box, if it reaches it.
  if (!known_) return kAllRows;
  const bool reaches = side == 0 ? state_.min.x <= inner.min.x : state_.max.x >= inner.max.x;
  return !state_.empty() && reaches ? Int2{state_.min.y, state_.max.y} : Int2{};
}

Int2 QuiescentBox::side_rows(View<const float> a, View<const float> b, int side, Box2 inner,
                             int grow) const {
  // A cell of column d reads columns d - 1 .. d + 1 a row either side; the other pair's rows
  // that differ are overwritten; the first and last rows also read the state's halo rows above
  // and below (stepped whole, not tracked: the cells they read there are scanned).
  Int2 rows{};
  const int x0 = side == 0 ? inner.min.x - grow - 1 : inner.max.x - 1;
  const int x1 = side == 0 ? inner.min.x + 1 : inner.max.x + grow + 1;
  if (!differing(a, b, {{x0, inner.min.y - 1}, {x1, inner.min.y}}).empty())
    rows = {inner.min.y, inner.min.y + 1};
  if (!differing(a, b, {{x0, inner.max.y}, {x1, inner.max.y + 1}}).empty())
    rows = rows_united(rows, {inner.max.y - 1, inner.max.y});
  for (int d = 1; d <= grow; ++d) {
    Int2 read = rows_united(rows_united(column_rows(side, d - 1, inner), side_state_[side][d]),
                            side_state_[side][d + 1]);
    if (!no_rows(read)) read = {read.x - 1, read.y + 1};
    rows = rows_united(rows_united(rows, read), side_other_[side][d]);
  }
  return {std::max(rows.x, inner.min.y), std::min(rows.y, inner.max.y)};
}

void QuiescentBox::stepped(Box2 written, Box2 input, int grow) {
  // The pairs change roles: the columns the step wrote hold its output, the others what the
  // other pair held there.
  for (int side = 0; side < 2; ++side)
    for (int d = 1; d <= kMaxGrow + 1; ++d) {
      const Int2 now = d <= grow ? side_written_[side] : side_other_[side][d];
      side_other_[side][d] = side_state_[side][d];
      side_state_[side][d] = now;
    }
  other_ = known_ ? state_ : input;
  state_ = written;
  known_ = true;
}

}  // namespace ardcell
