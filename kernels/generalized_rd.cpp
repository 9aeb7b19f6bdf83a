#include "kernels/generalized_rd.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "kernels/tensor_field_operator.h"

namespace ardcell {
namespace {

// Cells per chunk: a chunk's sums stay in registers while the taps stream past them.
constexpr int kChunk = 64;

// A wrapped row: cells x = -2 .. nx + 1 at [0, nx + 4), padded so that every chunk may read a
// whole kChunk + 4 cells (the padding's sums are computed and never stored).
std::size_t ring_row_floats(int nx) {
  const std::size_t chunks = (std::size_t(nx) + kChunk - 1) / kChunk;
  return chunks * kChunk + 16;
}

int wrap(int i, int n) { return ((i % n) + n) % n; }

// Copies interior row wrap(y) of f, with two wrapped cells on each side, into dst.
void load_wrapped_row(View<const float> f, Int2 size, int y, float* dst) {
  const float* row = f.row(wrap(y, size.y));
  std::memcpy(dst + 2, row, sizeof(float) * std::size_t(size.x));
  for (int i : {0, 1, size.x + 2, size.x + 3}) dst[i] = row[wrap(i - 2, size.x)];
}

// The reaction of a model in float, vectorisable (Gray-Scott, Turing), or through
// reaction_rates in double (the others).
// Each is called with the cell's (x, y), which only the parameter map uses.
struct GrayScottRates {
  float F, fk;
  void operator()(int, int, float A, float B, float& ra, float& rb) const {
    const float abb = A * B * B;
    ra = F * (1.0f - A) - abb;
    rb = abb - fk * B;
  }
};
struct GrayScottMapRates {
  float F, k, f_step, k_step;
  void operator()(int x, int y, float A, float B, float& ra, float& rb) const {
    const float f = F + f_step * (float(x) + 0.5f);
    const float kk = k + k_step * (float(y) + 0.5f);
    const float abb = A * B * B;
    ra = f * (1.0f - A) - abb;
    rb = abb - (f + kk) * B;
  }
};
struct TuringRates {
  float s, beta, supply;
  void operator()(int, int, float A, float B, float& ra, float& rb) const {
    const float ab = A * B;
    ra = s * (ab - A - beta);
    rb = s * (supply - ab);
  }
};
struct AnyRates {
  const ReactionParams* p;
  void operator()(int, int, float A, float B, float& ra, float& rb) const {
    double da, db;
    reaction_rates(*p, A, B, da, db);
    ra = float(da);
    rb = float(db);
  }
};

// Sixteen cells in one register (GCC's vector extension: AVX-512, or two AVX halves).
typedef float Vec16 __attribute__((vector_size(64)));
inline Vec16 load16(const float* p) {
  Vec16 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

// One chunk's sums K f over cells [x0, x0 + kChunk): tap_rows[t] points at the wrapped row of tap
// t, shifted by its dx. The chunk's sums stay in registers (kChunk / 16 vectors of sixteen cells)
// while every group is added in turn (its balanced tree, GeneralizedTaps; the same order for every
// cell wherever it sits): one branch on the group's size per chunk, not per vector.
inline void chunk_sums(const GeneralizedTaps& k, const float* const tap_rows[25], int x0,
                       float* __restrict acc) {
  constexpr int kVecs = kChunk / 16;
  Vec16 sum[kVecs] = {};
  for (int g = 0; g < k.group_count; ++g) {
    const GeneralizedTaps::Group& group = k.groups[g];
    const float* const* r = tap_rows + group.first;
    const float w = group.weight;
    const auto at = [&](int t, int v) { return load16(r[t] + x0 + 16 * v); };
    switch (group.count) {
      case 1:
        for (int v = 0; v < kVecs; ++v) sum[v] += w * at(0, v);
        break;
      case 2:
        for (int v = 0; v < kVecs; ++v) sum[v] += w * (at(0, v) + at(1, v));
        break;
      case 4:
        for (int v = 0; v < kVecs; ++v)
          sum[v] += w * ((at(0, v) + at(1, v)) + (at(2, v) + at(3, v)));
        break;
      default:
        for (int v = 0; v < kVecs; ++v)
          sum[v] += w * (((at(0, v) + at(1, v)) + (at(2, v) + at(3, v))) +
                         ((at(4, v) + at(5, v)) + (at(6, v) + at(7, v))));
    }
  }
  std::memcpy(acc, sum, sizeof sum);
}

// One output row y (unwrapped: it picks the ring slots; y_cell, wrapped, is the row the
// reaction sees): cells [0, nx) of ao, bo from the centre values ac, bc and the ring of rows
// y - 2 .. y + 2 (slot(row) = wrap(row, 5), each a wrapped row of ring_row_floats).
template <class Rates>
inline void row_with(const GeneralizedTaps& k, const float* ring_a, const float* ring_b,
                     std::size_t w, int y, int y_cell, const float* ac, const float* bc, float* ao,
                     float* bo, int nx, const GeneralizedRdParams& p, const Rates& rates) {
  const bool diffuse_a = p.scale_a != 0.0f, diffuse_b = p.scale_b != 0.0f;
  const float sa = p.scale_a, sb = p.scale_b, dt = p.dt;
  const float a_lo = p.a_lo, a_hi = p.a_hi, b_lo = p.b_lo, b_hi = p.b_hi;
  const float* taps_a[25];
  const float* taps_b[25];
  for (int t = 0; t < k.count; ++t) {
    const std::size_t row = w * std::size_t(wrap(y + k.taps[t].dy, 5)) + 2;
    taps_a[t] = ring_a + row + k.taps[t].dx;
    taps_b[t] = ring_b + row + k.taps[t].dx;
  }
  alignas(64) float acc_a[kChunk];
  alignas(64) float acc_b[kChunk];
  for (int x0 = 0; x0 < nx; x0 += kChunk) {
    if (diffuse_a) chunk_sums(k, taps_a, x0, acc_a);
    if (diffuse_b) chunk_sums(k, taps_b, x0, acc_b);
    const int n = std::min(kChunk, nx - x0);
    for (int i = 0; i < n; ++i) {
      const float A = ac[x0 + i], B = bc[x0 + i];
      float ra, rb;
      rates(x0 + i, y_cell, A, B, ra, rb);
      const float da = diffuse_a ? sa * acc_a[i] : 0.0f;
      const float db = diffuse_b ? sb * acc_b[i] : 0.0f;
      ao[x0 + i] = std::min(std::max(A + da + dt * ra, a_lo), a_hi);
      bo[x0 + i] = std::min(std::max(B + db + dt * rb, b_lo), b_hi);
    }
  }
}

// `steps` steps in one walk down the rows: step s (1-based) computes its rows two rows behind
// step s - 1, from step s - 1's ring of 5 wrapped rows (step 1 from the input's), and keeps them
// in its own ring; the last step writes rows [y0, y1) of the outputs. Step s computes rows
// [y0 - 2 (steps - s), y1 + 2 (steps - s)), the rows the next steps read (they wrap at the
// domain's edges). Each row is row_with of the same operands as in `steps` rows_with calls, so
// the same bits; the intermediate rows never leave the cache.
template <class Rates>
void rows_fused_with(const GeneralizedTaps& k, View<const float> a, View<const float> b,
                     View<float> a_out, View<float> b_out, Int2 size, int y0, int y1,
                     const GeneralizedRdParams& p, int steps, const Rates& rates, float* scratch) {
  const int nx = size.x;
  const std::size_t w = ring_row_floats(nx);
  // Ring s (0: the input, s: step s's rows) of field f (0: A, 1: B).
  const auto ring = [&](int s, int f) { return scratch + (2 * std::size_t(s) + f) * 5 * w; };
  const auto slot = [](int y) { return std::size_t(wrap(y, 5)); };
  const int reach = 2 * steps;  // input rows read around an output row
  for (int y = y0 - reach; y <= y0 - reach + 4; ++y) {
    load_wrapped_row(a, size, y, ring(0, 0) + w * slot(y));
    load_wrapped_row(b, size, y, ring(0, 1) + w * slot(y));
  }
  const int last = y1 + 2 * (steps - 1);  // step 1's rows end here
  for (int t = y0 - 2 * (steps - 1); t < last; ++t) {
    for (int st = 1; st <= steps; ++st) {
      const int y = t - 2 * (st - 1);        // step st's row this turn
      if (y < y0 - 2 * (steps - st)) break;  // before its first: so are the later steps'
      const float* in_a = ring(st - 1, 0);
      const float* in_b = ring(st - 1, 1);
      const float* ca = in_a + w * slot(y) + 2;
      const float* cb = in_b + w * slot(y) + 2;
      if (st == steps) {
        row_with(k, in_a, in_b, w, y, y, ca, cb, a_out.row(y), b_out.row(y), nx, p, rates);
        continue;
      }
      float* ma = ring(st, 0) + w * slot(y);
      float* mb = ring(st, 1) + w * slot(y);
      row_with(k, in_a, in_b, w, y, wrap(y, size.y), ca, cb, ma + 2, mb + 2, nx, p, rates);
      for (float* m : {ma, mb})
        for (int i : {0, 1, nx + 2, nx + 3}) m[i] = m[2 + wrap(i - 2, nx)];
    }
    // The input row two below step 1's next row enters its ring.
    if (t + 1 < last) {
      load_wrapped_row(a, size, t + 3, ring(0, 0) + w * slot(t + 3));
      load_wrapped_row(b, size, t + 3, ring(0, 1) + w * slot(t + 3));
    }
  }
}

// One step (generalized_rd_rows): the walk of one step, or, with neither chemical diffusing
// (the reaction and the clamp alone read no neighbour), each row from the fields themselves.
template <class Rates>
void rows_with(const GeneralizedTaps& k, View<const float> a, View<const float> b,
               View<float> a_out, View<float> b_out, Int2 size, int y0, int y1,
               const GeneralizedRdParams& p, const Rates& rates, float* scratch) {
  if (p.scale_a != 0.0f || p.scale_b != 0.0f) {
    rows_fused_with(k, a, b, a_out, b_out, size, y0, y1, p, 1, rates, scratch);
    return;
  }
  const std::size_t w = ring_row_floats(size.x);
  for (int y = y0; y < y1; ++y)
    row_with(k, scratch, scratch + 5 * w, w, y, y, a.row(y), b.row(y), a_out.row(y), b_out.row(y),
             size.x, p, rates);
}

}  // namespace

GeneralizedTaps::GeneralizedTaps(const Stencil5x5& k) {
  struct Offset {
    int dx, dy;
    bool operator==(const Offset&) const = default;
  };
  const auto exact = [&](Offset o) { return k.at(o.dx, o.dy); };
  const auto weight = [&](Offset o) { return float(exact(o)); };
  const auto reflect = [](Offset o) { return Offset{-o.dx, -o.dy}; };
  const auto turn = [](Offset o) { return Offset{-o.dy, o.dx}; };
  const auto transpose = [](Offset o) { return Offset{o.dy, o.dx}; };
  // The stencil's symmetries: its double weights agree to 1e-12 of the largest (the assembly
  // sums mirrored filters in different orders, so mirrored weights may differ in the last bits
  // and, rarely, round to different floats); a group then takes its first tap's float weight.
  // Weights below 1e-12 of the largest are the assembly's rounding of a zero: no tap.
  double largest = 0;
  for (int dy = -2; dy <= 2; ++dy)
    for (int dx = -2; dx <= 2; ++dx) largest = std::max(largest, std::abs(exact({dx, dy})));
  const auto keeps = [&](auto map) {
    for (int dy = -2; dy <= 2; ++dy)
      for (int dx = -2; dx <= 2; ++dx)
        if (std::abs(exact({dx, dy}) - exact(map(Offset{dx, dy}))) > 1e-12 * largest) return false;
    return true;
  };
  const bool reflection = keeps(reflect), quarter = keeps(turn), transposed = keeps(transpose);
  bool used[5][5] = {};
  for (int dy = -2; dy <= 2; ++dy)
    for (int dx = -2; dx <= 2; ++dx) {
      const float w = weight({dx, dy});
      if (std::abs(exact({dx, dy})) <= 1e-12 * largest || used[dy + 2][dx + 2]) continue;
      Offset members[8] = {{dx, dy}};
      int n = 1;
      // Doubles the group with the map's images unless the map sends it onto itself.
      const auto grow = [&](auto map) {
        const Offset image = map(members[0]);
        for (int i = 0; i < n; ++i)
          if (members[i] == image) return;
        for (int i = 0; i < n; ++i) members[n + i] = map(members[i]);
        n *= 2;
      };
      if (reflection) grow(reflect);
      if (quarter)
        grow(turn);
      else if (transposed)
        grow(transpose);
      if (quarter && transposed) grow(transpose);
      groups[group_count++] = {count, n, w};
      for (int i = 0; i < n; ++i) {
        used[members[i].dy + 2][members[i].dx + 2] = true;
        taps[count++] = {members[i].dx, members[i].dy, w};
      }
    }
}

std::size_t generalized_rd_scratch_floats(int nx) {
  return 10 * std::size_t(kGeneralizedFusedSteps) * ring_row_floats(nx);
}

namespace {

// Calls run(rates) with the reaction of p (the uniform or mapped Gray-Scott, Turing, or any).
template <class Run>
void with_rates(const GeneralizedRdParams& p, const Run& run) {
  const ReactionParams& r = p.reaction;
  switch (r.model) {
    case ReactionModel::kGrayScott:
      if (p.f_step != 0.0f || p.k_step != 0.0f) {
        run(GrayScottMapRates{r.F, r.k, p.f_step, p.k_step});
        return;
      }
      run(GrayScottRates{r.F, r.F + r.k});
      return;
    case ReactionModel::kTuring:
      run(TuringRates{r.turing_s, r.turing_beta, r.turing_supply});
      return;
    default:
      run(AnyRates{&r});
      return;
  }
}

}  // namespace

void generalized_rd_rows(const GeneralizedTaps& k, View<const float> a, View<const float> b,
                         View<float> a_out, View<float> b_out, Int2 size, int y0, int y1,
                         const GeneralizedRdParams& p, float* scratch) {
  ARDCELL_DCHECK(size.x >= 2 && size.y >= 2, "generalized RD needs at least 2 x 2 cells");
  if (y0 >= y1) return;
  with_rates(p, [&](const auto& rates) {
    rows_with(k, a, b, a_out, b_out, size, y0, y1, p, rates, scratch);
  });
}

void generalized_rd_fused_rows(const GeneralizedTaps& k, View<const float> a, View<const float> b,
                               View<float> a_out, View<float> b_out, Int2 size, int y0, int y1,
                               const GeneralizedRdParams& p, int steps, float* scratch) {
  ARDCELL_DCHECK(size.x >= 2 && size.y >= 2, "generalized RD needs at least 2 x 2 cells");
  ARDCELL_CHECK(steps >= 1 && steps <= kGeneralizedFusedSteps,
                "generalized_rd_fused_rows: 1 to kGeneralizedFusedSteps steps");
  ARDCELL_CHECK(p.scale_a != 0.0f || p.scale_b != 0.0f,
                "generalized_rd_fused_rows: fused steps need a diffusion (else separate calls)");
  if (y0 >= y1) return;
  with_rates(p, [&](const auto& rates) {
    rows_fused_with(k, a, b, a_out, b_out, size, y0, y1, p, steps, rates, scratch);
  });
}

Rank2FaceField rank2_faces(const FieldF& xx, const FieldF& xy, const FieldF& yy) {
  const Int2 n = xx.size();
  Rank2FaceField f{FieldF(n, 0), FieldF(n, 0), FieldF(n, 0), FieldF(n, 0)};
  for (int y = 0; y < n.y; ++y)
    for (int x = 0; x < n.x; ++x) {
      const int xp = wrap(x + 1, n.x), yp = wrap(y + 1, n.y);
      f.x_xx(x, y) = 0.5f * (xx(x, y) + xx(xp, y));
      f.x_xy(x, y) = 0.5f * (xy(x, y) + xy(xp, y));
      f.y_xy(x, y) = 0.5f * (xy(x, y) + xy(x, yp));
      f.y_yy(x, y) = 0.5f * (yy(x, y) + yy(x, yp));
    }
  return f;
}

Rank2FaceField rank2_tensor_field(Int2 size, TensorFieldKind kind, double d_along,
                                  double d_across) {
  FieldF xx(size, 0), xy(size, 0), yy(size, 0);
  constexpr double kHalfPi = 1.57079632679489661923;
  for (int y = 0; y < size.y; ++y)
    for (int x = 0; x < size.x; ++x) {
      const double rx = x + 0.5 - 0.5 * size.x, ry = y + 0.5 - 0.5 * size.y;
      double phi = 0.0;
      if (kind != TensorFieldKind::kUniform) phi = std::atan2(ry, rx);
      if (kind == TensorFieldKind::kVortex) phi += kHalfPi;
      const double c = std::cos(phi), s = std::sin(phi);
      double dxx = d_along * c * c + d_across * s * s;
      double dxy = (d_along - d_across) * c * s;
      double dyy = d_along * s * s + d_across * c * c;
      if (kind != TensorFieldKind::kUniform && rx == 0.0 && ry == 0.0)
        dxx = dyy = 0.5 * (d_along + d_across), dxy = 0.0;
      xx(x, y) = float(dxx), xy(x, y) = float(dxy), yy(x, y) = float(dyy);
    }
  return rank2_faces(xx, xy, yy);
}

void tensor_field_rd_rows(const Rank2FaceField& d, View<const float> a, View<const float> b,
                          View<float> a_out, View<float> b_out, Int2 size, int y0, int y1,
                          const GeneralizedRdParams& p) {
  ARDCELL_DCHECK(size.x >= 2 && size.y >= 2, "tensor-field RD needs at least 2 x 2 cells");
  ARDCELL_CHECK(d.size() == size, "tensor-field RD: the face field is not the grid's size");
  if (y0 >= y1) return;
  const TensorFieldOperator<View<const float>> la{d, a}, lb{d, b};
  const float sa = p.scale_a, sb = p.scale_b, dt = p.dt;
  with_rates(p, [&](const auto& rates) {
    for (int y = y0; y < y1; ++y) {
      const float* ac = a.row(y);
      const float* bc = b.row(y);
      float* ao = a_out.row(y);
      float* bo = b_out.row(y);
      const int ym = wrap(y - 1, size.y), yp = wrap(y + 1, size.y);
      const auto cell = [&](int x, int xm, int xp) {
        const float A = ac[x], B = bc[x];
        float ra, rb;
        rates(x, y, A, B, ra, rb);
        const float da = sa != 0.0f ? sa * la(x, xm, xp, y, ym, yp) : 0.0f;
        const float db = sb != 0.0f ? sb * lb(x, xm, xp, y, ym, yp) : 0.0f;
        ao[x] = std::min(std::max(A + da + dt * ra, p.a_lo), p.a_hi);
        bo[x] = std::min(std::max(B + db + dt * rb, p.b_lo), p.b_hi);
      };
      // The edge columns wrap; the others read their neighbours directly (a loop the compiler
      // can vectorise: the same operations per cell, so the same bits).
      cell(0, size.x - 1, 1);
      for (int x = 1; x + 1 < size.x; ++x) cell(x, x - 1, x + 1);
      if (size.x > 1) cell(size.x - 1, size.x - 2, 0);
    }
  });
}

}  // namespace ardcell
