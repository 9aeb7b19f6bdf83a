#include "kernels/stencil_sweeps.h"

#include <algorithm>
#include <cmath>
#include <type_traits>

#include "kernels/field_reductions.h"

namespace ardcell::stencil {

namespace {

// Row pointers of the operator and of x for row j, with the edge rows resolved: periodic wraps,
// otherwise the row itself (its boundary face weight is 0, so any finite value will do).
struct RowRefs {
  const float* xb;
  const float* x0;
  const float* xa;
  const float* d;
  const float* wx;
  const float* wyb;
  const float* wya;
};

// The columns a row of a sweep computes, [begin, end) of a grid nx wide, and the operator's
// edge_wraps: where the cells on a periodic domain edge find their neighbour across it.
struct Cols {
  int begin, end, nx;
  bool periodic;
  EdgeWraps wrap;
};
// A sweep's cells: `region` (inside the operator's cells), or all of them when it is empty.
inline Box2 cells_of(const StencilOperator& op, Box2 region) {
  if (region.empty()) return op.diag.interior();
  ARDCELL_CHECK(op.diag.interior().contains(region), "a sweep's region lies in its operator's");
  return region;
}
// The columns of `region` (cells_of).
inline Cols cols_of(const StencilOperator& op, Box2 region = {}) {
  const Box2 cells = cells_of(op, region);
  return {cells.min.x, cells.max.x, op.size.x, op.boundary_x == BoundaryKind::kPeriodic,
          edge_wraps(op)};
}
inline int left_of(int i, const Cols& c) { return i > 0 ? i - 1 : (c.periodic ? c.wrap.left : 0); }
inline int right_of(int i, const Cols& c) {
  return i < c.nx - 1 ? i + 1 : (c.periodic ? c.wrap.right : c.nx - 1);
}

inline RowRefs row_refs(const StencilOperator& op, const FieldF& x, int j, const Cols& c) {
  const int ny = op.size.y;
  const bool py = op.boundary_y == BoundaryKind::kPeriodic;
  return {x.row(j > 0 ? j - 1 : (py ? c.wrap.below : j)),
          x.row(j),
          x.row(j < ny - 1 ? j + 1 : (py ? c.wrap.above : j)),
          op.diag.row(j),
          op.wx.row(j),
          op.wy.row(j),
          op.wy.row(j + 1)};
}

// Sum of the weighted neighbours of cell i with left/right neighbour indices il/ir.
inline float neighbours(const RowRefs& r, int i, int il, int ir) {
  return r.wx[i] * r.x0[il] + r.wx[i + 1] * r.x0[ir] + r.wyb[i] * r.xb[i] + r.wya[i] * r.xa[i];
}

// b - A x at cell i of a row (left and right neighbours il, ir), in double.
inline double residual_cell(const RowRefs& r, const float* bj, int i, int il, int ir) {
  return double(bj[i]) - double(r.d[i]) * r.x0[i] +
         (double(r.wx[i]) * r.x0[il] + double(r.wx[i + 1]) * r.x0[ir] + double(r.wyb[i]) * r.xb[i] +
          double(r.wya[i]) * r.xa[i]);
}

}  // namespace

void UniformRows::analyse(const StencilOperator& op, RowExecutor& ex) {
  const int nx = op.size.x, ny = op.size.y;
  ARDCELL_CHECK(uniform_.size() == std::size_t(ny), "UniformRows: size mismatch");
  ex.for_rows(ny, nx, [&](int y0, int y1) {
    for (int j = y0; j < y1; ++j) {
      const float* d = op.diag.row(j);
      const float* wx = op.wx.row(j);
      const float* wyb = op.wy.row(j);
      const float* wya = op.wy.row(j + 1);
      const float dj = nx > 2 ? d[1] : 0.0f, w = nx > 2 ? wx[1] : 0.0f;
      bool same = nx > 2;
      for (int i = 1; same && i < nx - 1; ++i)
        same = d[i] == dj && wx[i + 1] == w && wyb[i] == w && wya[i] == w;
      uniform_[std::size_t(j)] = same ? 1 : 0;
      diag_[std::size_t(j)] = dj;
      weight_[std::size_t(j)] = w;
    }
  });
}

namespace {

// Row j of a Jacobi sweep, out = D^-1 (b + (D - A) x), from x's rows as r gives them: the one
// expression every sweep (plain or temporally blocked) evaluates, so both give the same bits.
// kWholeRow: c covers the whole row (the loops' bounds are then 1 and nx - 1, as the compiler
// vectorises best).
template <bool kWholeRow>
inline void jacobi_row(const RowRefs& r, const float* bj, float* out, int j, const Cols& c,
                       const UniformRows* uniform) {
  const int nx = c.nx;
  const int mid_begin = kWholeRow ? 1 : std::max(c.begin, 1);
  const int mid_end = kWholeRow ? nx - 1 : std::min(c.end, nx - 1);
  if (uniform && uniform->uniform(j)) {
    const float w = uniform->weight(j), d = uniform->diag(j);
    for (int i = mid_begin; i < mid_end; ++i)
      out[i] = (bj[i] + w * r.x0[i - 1] + w * r.x0[i + 1] + w * r.xb[i] + w * r.xa[i]) / d;
  } else {
    for (int i = mid_begin; i < mid_end; ++i)
      out[i] = (bj[i] + r.wx[i] * r.x0[i - 1] + r.wx[i + 1] * r.x0[i + 1] + r.wyb[i] * r.xb[i] +
                r.wya[i] * r.xa[i]) /
               r.d[i];
  }
  if (c.begin == 0) out[0] = (bj[0] + neighbours(r, 0, left_of(0, c), right_of(0, c))) / r.d[0];
  if (nx > 1 && c.end == nx) {
    const int i = nx - 1;
    out[i] = (bj[i] + neighbours(r, i, left_of(i, c), right_of(i, c))) / r.d[i];
  }
}

// Row j's share of |b - A x|^2 (r = b - A x written to out when not null). The squares go to
// four running sums, cell i to sum i % 4 (then (s0 + s1) + (s2 + s3)): a fixed order, so the
// bits do not depend on the banding, and the middle of the row vectorises; the edge cells take
// the (periodic or weight-0) neighbours separately.
template <bool kWholeRow>
inline double residual_row(const RowRefs& r, const float* bj, float* out, const Cols& c) {
  const int nx = c.nx;
  const auto cell = [&](int i, int il, int ir) { return residual_cell(r, bj, i, il, ir); };
  double sum[4] = {0.0, 0.0, 0.0, 0.0};
  const auto edge = [&](int i) {
    const double ri = cell(i, left_of(i, c), right_of(i, c));
    if (out) out[i] = float(ri);
    sum[i % 4] += ri * ri;
  };
  if (c.begin == 0) edge(0);
  const int mid_end = kWholeRow ? nx - 1 : std::min(c.end, nx - 1);
  int i = kWholeRow ? 1 : std::max(c.begin, 1);
  if (out) {
    for (; i + 4 <= mid_end; i += 4)
      for (int k = 0; k < 4; ++k) {
        const double ri = cell(i + k, i + k - 1, i + k + 1);
        out[i + k] = float(ri);
        sum[(i + k) % 4] += ri * ri;
      }
  } else {
    for (; i + 4 <= mid_end; i += 4)
      for (int k = 0; k < 4; ++k) {
        const double ri = cell(i + k, i + k - 1, i + k + 1);
        sum[(i + k) % 4] += ri * ri;
      }
  }
  for (; i < mid_end; ++i) {
    const double ri = cell(i, i - 1, i + 1);
    if (out) out[i] = float(ri);
    sum[i % 4] += ri * ri;
  }
  if (nx > 1 && c.end == nx) edge(nx - 1);
  return (sum[0] + sum[1]) + (sum[2] + sum[3]);
}

// A row's share of |f|^2: four running sums, cell i to sum i % 4, as residual_row (one running
// sum is a chain of dependent additions).
inline double norm2_row(const float* r, int nx) {
  double sum[4] = {0.0, 0.0, 0.0, 0.0};
  int i = 0;
  for (; i + 4 <= nx; i += 4)
    for (int k = 0; k < 4; ++k) sum[k] += double(r[i + k]) * r[i + k];
  for (; i < nx; ++i) sum[i % 4] += double(r[i]) * r[i];
  return (sum[0] + sum[1]) + (sum[2] + sum[3]);
}

}  // namespace

void jacobi_sweep(const StencilOperator& op, const FieldF& b, const FieldF& x_in, FieldF& x_out,
                  RowExecutor& ex, const UniformRows* uniform, Box2 region) {
  const Box2 cells = cells_of(op, region);
  const Cols c = cols_of(op, cells);
  if (on_block(op)) uniform = nullptr;  // analysed for whole rows
  const auto rows = [&](auto whole_row, int y0, int y1) {
    for (int j = cells.min.y + y0; j < cells.min.y + y1; ++j)
      jacobi_row<whole_row()>(row_refs(op, x_in, j, c), b.row(j), x_out.row(j), j, c, uniform);
  };
  ex.for_rows(cells.height(), cells.width(), [&](int y0, int y1) {
    if (c.begin == 0 && c.end == c.nx)
      rows(std::true_type{}, y0, y1);
    else
      rows(std::false_type{}, y0, y1);
  });
}

JacobiBlocking::JacobiBlocking(Int2 size, int bands)
    : size_(size),
      bands_(std::max(1, bands)),
      row_stride_((std::size_t(std::max(size.x, 1)) + 15) / 16 * 16 + 16),
      rings_(std::size_t(bands_) * std::size_t(kMaxSweeps) * 3 * row_stride_),
      residual_rows_(std::size_t(std::max(size.y, 0))),
      rhs_rows_(std::size_t(std::max(size.y, 0))) {}

// Band [y0, y1) of `sweeps` sweeps as a wavefront. Level s (x after s sweeps) is needed on the
// band grown by sweeps - s rows, plus one for the residual (clipped to the grid unless y wraps):
// level 0 is x_in itself, the band's own rows of the last level are x_out's, and every other
// row lives in a ring of three rows per level (row v in slot v mod 3). Once row t of level 0 is
// at hand, rows t - 1 of level 1, t - 2 of level 2, ... have all their inputs, so one ascending
// pass over t computes every level while the rows it reads are still in cache. Rows are virtual
// (v may leave [0, ny) when y wraps: v stands for row v mod ny); each is computed with
// jacobi_row, as the plain sweep computes it.
void JacobiBlocking::band(const StencilOperator& op, const FieldF& b, const FieldF& x_in,
                          FieldF& x_out, int sweeps, int y0, int y1, float* rings,
                          const UniformRows* uniform, bool norms) const {
  const int nx = op.size.x, ny = op.size.y;
  const Cols c = cols_of(op);  // the whole grid (JacobiBlocking's operators are)
  const bool py = op.boundary_y == BoundaryKind::kPeriodic;
  const int extra = norms ? 1 : 0;
  const auto wrap = [&](int v) { return ((v % ny) + ny) % ny; };
  // Rows of level s: [lo(s), hi(s)).
  const auto lo = [&](int s) {
    const int v = y0 - (sweeps - s) - extra;
    return py ? v : std::max(0, v);
  };
  const auto hi = [&](int s) {
    const int v = y1 + (sweeps - s) + extra;
    return py ? v : std::min(ny, v);
  };
  const auto ring_row = [&](int s, int v) {
    return rings + (std::size_t(s - 1) * 3 + std::size_t(((v % 3) + 3) % 3)) * row_stride_;
  };
  const auto in_band = [&](int v) { return v >= y0 && v < y1; };
  const auto level_row = [&](int s, int v) -> const float* {
    if (s == 0) return x_in.row(wrap(v));
    return s == sweeps && in_band(v) ? x_out.row(v) : ring_row(s, v);
  };
  // x's rows around row v of level s, for row j = v mod ny of the operator. Outside a wrapping
  // y the grid's first and last rows take themselves as the missing neighbour (weight 0), as
  // row_refs does.
  const auto refs = [&](int s, int v, int j) {
    const float* x0 = level_row(s, v);
    return RowRefs{v - 1 >= lo(s) ? level_row(s, v - 1) : x0,
                   x0,
                   v + 1 < hi(s) ? level_row(s, v + 1) : x0,
                   op.diag.row(j),
                   op.wx.row(j),
                   op.wy.row(j),
                   op.wy.row(j + 1)};
  };
  for (int t = lo(0); t <= y1 + sweeps + extra; ++t) {
    for (int s = 1; s <= sweeps; ++s) {
      const int v = t - s;
      if (v < lo(s) || v >= hi(s)) continue;
      const int j = wrap(v);
      float* out = s == sweeps && in_band(v) ? x_out.row(v) : ring_row(s, v);
      jacobi_row<true>(refs(s - 1, v, j), b.row(j), out, j, c, uniform);
    }
    // The residual of row v once the last level's row v + 1 exists.
    const int v = t - sweeps - 1;
    if (norms && in_band(v)) {
      residual_rows_[std::size_t(v)] = residual_row<true>(refs(sweeps, v, v), b.row(v), nullptr, c);
      rhs_rows_[std::size_t(v)] = norm2_row(b.row(v), nx);
    }
  }
}

void JacobiBlocking::sweeps(const StencilOperator& op, const FieldF& b, const FieldF& x_in,
                            FieldF& x_out, int sweeps, RowExecutor& ex, const UniformRows* uniform,
                            Norms* norms) {
  ARDCELL_CHECK(op.size == size_ && !on_block(op) && sweeps >= 1 && sweeps <= kMaxSweeps,
                "JacobiBlocking: a whole grid's operator, size or sweep count out of range");
  const int ny = size_.y;
  // A band per worker: each recomputes the levels of its neighbours' edge rows, so more bands
  // would cost more, and fewer would leave a core idle.
  const bool parallel = ex.workers() > 1 && long(size_.x) * ny >= RowExecutor::kMinParallelCells &&
                        ny >= 2 * RowExecutor::kMinRowsPerBand;
  const int bands =
      parallel ? std::min({bands_, ex.workers(), ny / RowExecutor::kMinRowsPerBand}) : 1;
  const std::size_t ring_floats = std::size_t(kMaxSweeps) * 3 * row_stride_;
  ex.for_tasks(bands, [&](int i) {
    band(op, b, x_in, x_out, sweeps, int(long(ny) * i / bands), int(long(ny) * (i + 1) / bands),
         rings_.data() + ring_floats * std::size_t(i), uniform, norms != nullptr);
  });
  if (norms) {
    *norms = Norms{};
    for (int y = 0; y < ny; ++y) {
      norms->residual2 += residual_rows_[std::size_t(y)];
      norms->rhs2 += rhs_rows_[std::size_t(y)];
    }
  }
}

void rbgs_half_sweep(const StencilOperator& op, const FieldF& b, FieldF& x, int color,
                     RowExecutor& ex, Box2 region) {
  const Box2 cells = cells_of(op, region);
  const Cols c = cols_of(op, cells);
  const int nx = c.nx, ny = op.size.y;
  const bool py = op.boundary_y == BoundaryKind::kPeriodic;
  // Cells of one colour read only the other colour, so rows are independent within a half
  // sweep - except across a periodic wrap of an odd number of rows, where rows 0 and ny - 1
  // hold the same colour side by side. Row 0 then reads row ny - 1 before its update and row
  // ny - 1 reads row 0 after it, as in order: rows 0 .. ny - 2 in bands, then row ny - 1. (So
  // along x within a row.) A block cannot keep that order with its neighbours' cells.
  const bool odd_wrap = py && ny % 2 == 1 && ny > 1;
  ARDCELL_CHECK(!on_block(op) || (!odd_wrap && !(c.periodic && nx % 2 == 1)),
                "rbgs_half_sweep: a block of a grid that wraps an odd number of cells");
  ARDCELL_CHECK(!odd_wrap || cells == op.diag.interior(),
                "rbgs_half_sweep: the whole of a grid that wraps an odd number of rows");
  const auto sweep_rows = [&](int y0, int y1) {
    for (int j = cells.min.y + y0; j < cells.min.y + y1; ++j) {
      const RowRefs r = row_refs(op, x, j, c);
      const float* bj = b.row(j);
      float* xj = x.row(j);
      auto update = [&](int i) {
        xj[i] = (bj[i] + neighbours(r, i, left_of(i, c), right_of(i, c))) / r.d[i];
      };
      int i = c.begin + ((color + j + c.begin) & 1);  // the first i with (i + j) % 2 == color
      if (i == 0) {
        update(0);
        i = 2;
      }
      for (const int mid_end = std::min(c.end, nx - 1); i < mid_end; i += 2)
        xj[i] = (bj[i] + r.wx[i] * r.x0[i - 1] + r.wx[i + 1] * r.x0[i + 1] + r.wyb[i] * r.xb[i] +
                 r.wya[i] * r.xa[i]) /
                r.d[i];
      if (i == nx - 1 && i < c.end) update(i);
    }
  };
  ex.for_rows(odd_wrap ? cells.height() - 1 : cells.height(), cells.width(), sweep_rows);
  if (odd_wrap) sweep_rows(ny - 1, ny);
}

void rbgs_sweep(const StencilOperator& op, const FieldF& b, FieldF& x, RowExecutor& ex) {
  rbgs_half_sweep(op, b, x, 0, ex);
  rbgs_half_sweep(op, b, x, 1, ex);
}

double residual(const StencilOperator& op, const FieldF& b, const FieldF& x, FieldF* res,
                RowExecutor& ex) {
  const Cols c = cols_of(op);
  const Box2 cells = op.diag.interior();
  const bool whole_rows = c.begin == 0 && c.end == c.nx;
  return ex.sum_rows(cells.height(), cells.width(), [&](int y0, int y1, double* partials) {
    for (int y = y0; y < y1; ++y) {
      const int j = cells.min.y + y;
      const RowRefs r = row_refs(op, x, j, c);
      float* out = res ? res->row(j) : nullptr;
      partials[y] = whole_rows ? residual_row<true>(r, b.row(j), out, c)
                               : residual_row<false>(r, b.row(j), out, c);
    }
  });
}

void residual_field(const StencilOperator& op, const FieldF& b, const FieldF& x, FieldF& res,
                    RowExecutor& ex) {
  ARDCELL_CHECK(!on_block(op), "residual_field: a whole grid's operator (multigrid's levels)");
  const Cols c = cols_of(op);
  const int nx = c.nx;
  ex.for_rows(op.size.y, nx, [&](int y0, int y1) {
    for (int j = y0; j < y1; ++j) {
      const RowRefs r = row_refs(op, x, j, c);
      const float* bj = b.row(j);
      float* out = res.row(j);
      out[0] = float(residual_cell(r, bj, 0, left_of(0, c), right_of(0, c)));
      for (int i = 1; i < nx - 1; ++i) out[i] = float(residual_cell(r, bj, i, i - 1, i + 1));
      if (nx > 1)
        out[nx - 1] = float(residual_cell(r, bj, nx - 1, left_of(nx - 1, c), right_of(nx - 1, c)));
    }
  });
}

double norm2_squared(const FieldF& f, RowExecutor& ex) {
  const Box2 cells = f.interior();
  return ex.sum_rows(cells.height(), cells.width(), [&](int y0, int y1, double* partials) {
    for (int y = y0; y < y1; ++y)
      partials[y] = norm2_row(f.row(cells.min.y + y) + cells.min.x, cells.width());
  });
}

void NullSpace::analyse(const StencilOperator& op, RowExecutor& ex) {
  const int nx = op.size.x, ny = op.size.y;
  ARDCELL_CHECK(in_null_.size() == op.size, "NullSpace: size mismatch");
  if (op.identity > 0.0) {  // every row sums to at least the identity (StencilOperator)
    if (count_ > 0) in_null_.fill(0);
    count_ = 0;
    singular_ = false;
    return;
  }
  double* coupled = ex.rows_scratch(ny, 0);  // per row: 1 when a coupled cell is outside Z
  const double count = ex.sum_rows(ny, nx, [&](int y0, int y1, double* partials) {
    for (int j = y0; j < y1; ++j) {
      double row_count = 0.0;
      bool row_coupled = false;
      for (int i = 0; i < nx; ++i) {
        const double faces =
            double(op.wx(i, j)) + op.wx(i + 1, j) + double(op.wy(i, j)) + op.wy(i, j + 1);
        const double row_sum = double(op.diag(i, j)) - faces;
        const bool zero =
            std::abs(row_sum) <= 1e-6 * std::abs(double(op.diag(i, j))) && op.diag(i, j) > 0.0f;
        in_null_(i, j) = zero ? 1 : 0;
        if (zero) {
          row_count += 1.0;
        } else if (faces != 0.0) {
          row_coupled = true;
        }
      }
      partials[j] = row_count;
      coupled[j] = row_coupled ? 1.0 : 0.0;
    }
  });
  count_ = int64_t(count);
  bool others_decoupled = true;
  for (int j = 0; j < ny; ++j) others_decoupled = others_decoupled && coupled[j] == 0.0;
  singular_ = count_ > 0 && others_decoupled;
}

double NullSpace::null_sum(const FieldF& f, RowExecutor& ex) const {
  return ex.sum_rows(f.ny(), f.nx(), [&](int y0, int y1, double* partials) {
    row_masked_sums(f.view(), in_null_.view(), f.nx(), y0, y1, partials);
  });
}

void NullSpace::remove_mean(FieldF& f, RowExecutor& ex) const {
  if (!singular_) return;
  const float mean = float(null_sum(f, ex) / double(count_));
  ex.for_rows(f.ny(), f.nx(), [&](int y0, int y1) {
    for (int j = y0; j < y1; ++j) {
      float* r = f.row(j);
      const uint8_t* z = in_null_.row(j);
      for (int i = 0; i < f.nx(); ++i)
        if (z[i]) r[i] -= mean;
    }
  });
}

double NullSpace::consistent_norm2(const FieldF& f, RowExecutor& ex) const {
  return consistent_part(norm2_squared(f, ex), f, ex);
}

double NullSpace::consistent_part(double all, const FieldF& f, RowExecutor& ex) const {
  if (!singular_) return all;
  const double sum = null_sum(f, ex);
  return std::max(0.0, all - sum * sum / double(count_));
}

}  // namespace ardcell::stencil
