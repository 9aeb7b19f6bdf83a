#include "host/surface/surface_multigrid.h"

#include <algorithm>
#include <cmath>

#include "runtime/check.h"

namespace ardcell {

// One grid of the hierarchy: its operator (the finest is the caller's), and the right-hand
// side, iterate and residual of the correction equation solved on it.
struct SurfaceMultigrid::Level {
  std::unique_ptr<SurfaceLaplacian> own;  // coarser levels
  const SurfaceLaplacian* op = nullptr;
  mutable PatchField b, x, r;
};

SurfaceMultigrid::SurfaceMultigrid(const LimitSurface& surface, const SurfaceLaplacian& fine,
                                   CornerGhosts corners) {
  const int n = fine.n();
  ARDCELL_CHECK(n >= 1 && (n & (n - 1)) == 0, "SurfaceMultigrid: N must be a power of two");
  for (int m = n; m >= std::min(n, kCoarsestCells); m /= 2) {
    auto l = std::make_unique<Level>();
    if (m == n) {
      l->op = &fine;
    } else {
      l->own = std::make_unique<SurfaceLaplacian>(surface.topology(),
                                                  sample_limit_metric(surface, m), corners);
      l->own->set_executor(fine.executor());
      l->op = l->own.get();
    }
    l->b = l->op->grid().make_field();
    l->x = l->op->grid().make_field();
    l->r = l->op->grid().make_field();
    levels_.push_back(std::move(l));
    if (m == kCoarsestCells || m == 1) break;
  }
  b_ = fine.grid().make_field();
  fine_krylov_.each([&](PatchField& f) { f = fine.grid().make_field(); });
  pieces_ = patch_pieces(surface.topology());
  piece_sums_.assign(std::size_t(*std::max_element(pieces_.begin(), pieces_.end()) + 1), 0.0);
  patch_sums_.assign(pieces_.size(), 0.0);
  sparse_.push_back(probe_patch_level(*levels_.back()->op, surface.topology(), pieces_));
  while (sparse_.back().cells > kMaxDirectCells) {
    SparseLevel next = aggregate_level(sparse_.back());
    // Stalled (a level that shrinks by less than a third and is still too large for the dense
    // solve): sweeps at the bottom instead.
    if (next.cells > kMaxDirectCells && 3 * next.cells > 2 * sparse_.back().cells) {
      sparse_.back().coarse.clear();
      break;
    }
    sparse_.push_back(std::move(next));
  }
}

SurfaceMultigrid::~SurfaceMultigrid() = default;

namespace {

// coarse = the area-weighted mean of each 2 x 2 block of fine (interior cells, per patch).
void restrict_mean(const SurfaceLaplacian& fine_op, const PatchField& fine,
                   const SurfaceLaplacian& coarse_op, PatchField& coarse) {
  const PatchGrid &fg = fine_op.grid(), &cg = coarse_op.grid();
  const int m = cg.n();
  fine_op.executor().for_rows(cg.patches(), m * m * 4, [&](int p0, int p1) {
    for (int p = p0; p < p1; ++p)
      for (int j = 0; j < m; ++j)
        for (int i = 0; i < m; ++i) {
          double sum = 0, area = 0;
          for (int dj = 0; dj < 2; ++dj)
            for (int di = 0; di < 2; ++di) {
              const double a = fine_op.cell_area(p, 2 * i + di, 2 * j + dj);
              sum += a * fine[fg.index(p, 2 * i + di, 2 * j + dj)];
              area += a;
            }
          coarse[cg.index(p, i, j)] = sum / area;
        }
  });
}

// fine += coarse, bilinear: a fine cell takes 9/16 of its coarse parent, 3/16 of the parent's
// neighbours on its side along each axis and 1/16 of the one diagonally on its side (the coarse
// ghost ring, filled first, across patch edges).
void prolong_add(const SurfaceLaplacian& coarse_op, PatchField& coarse,
                 const SurfaceLaplacian& fine_op, PatchField& fine) {
  const PatchGrid &fg = fine_op.grid(), &cg = coarse_op.grid();
  cg.exchange(coarse);
  const int n = fg.n();
  fine_op.executor().for_rows(fg.patches(), n * n, [&](int p0, int p1) {
    for (int p = p0; p < p1; ++p)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          const int ci = i / 2, cj = j / 2;
          const int si = (i % 2) ? 1 : -1, sj = (j % 2) ? 1 : -1;
          fine[fg.index(p, i, j)] +=
              (9 * coarse[cg.index(p, ci, cj)] + 3 * coarse[cg.index(p, ci + si, cj)] +
               3 * coarse[cg.index(p, ci, cj + sj)] + coarse[cg.index(p, ci + si, cj + sj)]) /
              16;
        }
  });
}

// sum over interior cells of a b, per-patch partials added in patch order (the same bits on any
// number of workers).
double patch_dot(const SurfaceLaplacian& op, const PatchField& a, const PatchField& b) {
  const PatchGrid& g = op.grid();
  const int n = g.n();
  return op.executor().sum_rows(g.patches(), n * n, [&](int p0, int p1, double* partial) {
    for (int p = p0; p < p1; ++p) {
      double sum = 0;
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) sum += a[g.index(p, i, j)] * b[g.index(p, i, j)];
      partial[p] = sum;
    }
  });
}

// f(cell index) on every interior cell, per patch on the executor.
template <class F>
void for_cells(const SurfaceLaplacian& op, const F& f) {
  const PatchGrid& g = op.grid();
  const int n = g.n();
  op.executor().for_rows(g.patches(), n * n, [&](int p0, int p1) {
    for (int p = p0; p < p1; ++p)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) f(g.index(p, i, j));
  });
}

// In place: a (k x k, row-major) becomes its LU factors with partial pivoting, row swaps in
// pivot.
void lu_factor(std::vector<double>& a, std::vector<int>& pivot, int k) {
  pivot.assign(std::size_t(k), 0);
  for (int col = 0; col < k; ++col) {
    int best = col;
    for (int r = col + 1; r < k; ++r)
      if (std::abs(a[std::size_t(r) * k + col]) > std::abs(a[std::size_t(best) * k + col]))
        best = r;
    pivot[std::size_t(col)] = best;
    if (best != col)
      std::swap_ranges(a.begin() + std::ptrdiff_t(col) * k, a.begin() + std::ptrdiff_t(col + 1) * k,
                       a.begin() + std::ptrdiff_t(best) * k);
    const double d = a[std::size_t(col) * k + col];
    ARDCELL_CHECK(d != 0, "SurfaceMultigrid: the coarsest matrix is singular");
    for (int r = col + 1; r < k; ++r) {
      double& e = a[std::size_t(r) * k + col];
      e /= d;
      for (int j = col + 1; j < k; ++j)
        a[std::size_t(r) * k + j] -= e * a[std::size_t(col) * k + j];
    }
  }
}

// rhs = (LU)^-1 rhs.
void lu_solve(const std::vector<double>& lu, const std::vector<int>& pivot, int k,
              std::vector<double>& rhs) {
  for (int q = 0; q < k; ++q) std::swap(rhs[std::size_t(q)], rhs[std::size_t(pivot[q])]);
  for (int r = 0; r < k; ++r)
    for (int j = 0; j < r; ++j)
      rhs[std::size_t(r)] -= lu[std::size_t(r) * k + j] * rhs[std::size_t(j)];
  for (int r = k - 1; r >= 0; --r) {
    for (int j = r + 1; j < k; ++j)
      rhs[std::size_t(r)] -= lu[std::size_t(r) * k + j] * rhs[std::size_t(j)];
    rhs[std::size_t(r)] /= lu[std::size_t(r) * k + r];
  }
}

}  // namespace

void SurfaceMultigrid::cycle(int level, double c) const {
  const Level& l = *levels_[std::size_t(level)];
  if (level + 1 == levels()) {
    coarse_correction(c, false);
    return;
  }
  l.op->smoothing_sweeps(l.x, l.b, c, kPreSweeps);
  l.op->residual(l.x, l.b, c, l.r);
  const Level& next = *levels_[std::size_t(level) + 1];
  restrict_mean(*l.op, l.r, *next.op, next.b);
  std::fill(next.x.begin(), next.x.end(), 0.0);
  cycle(level + 1, c);
  prolong_add(*next.op, next.x, *l.op, l.x);
  l.op->smoothing_sweeps(l.x, l.b, c, kPostSweeps);
}

void SurfaceMultigrid::coarse_correction(double c, bool poisson) const {
  const Level& l = *levels_.back();
  const PatchGrid& g = l.op->grid();
  const SparseLevel& top = sparse_.front();
  for (int p = 0; p < top.cells; ++p) {
    top.b[std::size_t(p)] = l.b[g.index(p, 0, 0)];
    top.x[std::size_t(p)] = l.x[g.index(p, 0, 0)];
  }
  sparse_cycle(0, c, poisson);
  for (int p = 0; p < top.cells; ++p) l.x[g.index(p, 0, 0)] = top.x[std::size_t(p)];
}

void SurfaceMultigrid::sparse_cycle(int level, double c, bool poisson) const {
  // a I + s lap: I - c lap, or lap for the Poisson problem.
  const double a = poisson ? 0 : 1, s = poisson ? 1 : -c;
  const SparseLevel& l = sparse_[std::size_t(level)];
  if (level + 1 == int(sparse_.size())) {
    if (!(poisson ? solve_coarsest_poisson() : solve_coarsest(c)))
      sparse_sweeps(l, a, s, kCoarseSweeps);
    return;
  }
  sparse_sweeps(l, a, s, kPreSweeps);
  sparse_residual(l, a, s);
  const SparseLevel& next = sparse_[std::size_t(level) + 1];
  // The residual's area-weighted mean on each aggregate, the correction from 0.
  std::fill(next.b.begin(), next.b.end(), 0.0);
  for (int i = 0; i < l.cells; ++i)
    next.b[std::size_t(l.coarse[std::size_t(i)])] += l.area[std::size_t(i)] * l.r[std::size_t(i)];
  for (int I = 0; I < next.cells; ++I) next.b[std::size_t(I)] /= next.area[std::size_t(I)];
  std::fill(next.x.begin(), next.x.end(), 0.0);
  sparse_cycle(level + 1, c, poisson);
  for (int i = 0; i < l.cells; ++i)
    l.x[std::size_t(i)] += kProlongationScale * next.x[std::size_t(l.coarse[std::size_t(i)])];
  sparse_sweeps(l, a, s, kPostSweeps);
}

namespace {

// The sparse level's a I + s lap as a dense row-major matrix of k x k.
void dense_matrix(const SparseLevel& l, double a, double s, std::vector<double>& out) {
  const int k = l.cells;
  out.assign(std::size_t(k) * k, 0.0);
  for (int r = 0; r < k; ++r) {
    out[std::size_t(r) * k + r] = a;
    for (int e = l.start[std::size_t(r)]; e < l.start[std::size_t(r) + 1]; ++e)
      out[std::size_t(r) * k + l.col[std::size_t(e)]] =
          (l.col[std::size_t(e)] == r ? a : 0.0) + s * l.lap[std::size_t(e)];
  }
}

}  // namespace

const SurfaceMultigrid::Factor& SurfaceMultigrid::factor_for(double c) const {
  for (const Factor& f : factors_)
    if (f.c == c) return f;
  const SparseLevel& l = sparse_.back();
  Factor& f = factors_[next_factor_];
  next_factor_ = (next_factor_ + 1) % kFactors;
  dense_matrix(l, 1, -c, f.lu);
  lu_factor(f.lu, f.pivot, l.cells);
  f.c = c;
  return f;
}

bool SurfaceMultigrid::solve_coarsest(double c) const {
  const SparseLevel& l = sparse_.back();
  const int k = l.cells;
  if (k > kMaxDirectCells) return false;
  const Factor& f = factor_for(c);
  rhs_ = l.b;  // same size after the first: a copy
  lu_solve(f.lu, f.pivot, k, rhs_);
  std::copy(rhs_.begin(), rhs_.end(), l.x.begin());
  return true;
}

void SurfaceMultigrid::precondition(const PatchField& q, PatchField& y, double c,
                                    bool poisson) const {
  Level& top = *levels_.front();
  top.b = q;  // same size: a copy
  std::fill(top.x.begin(), top.x.end(), 0.0);
  if (poisson)
    poisson_cycle(0);
  else
    cycle(0, c);
  std::swap(top.x, y);
}

namespace {

// The fine grid's cells as BiCGSTAB's space (kernels/bicgstab.h): the stopping norm is
// max |r|, as SurfaceLaplacian::implicit_diffusion's.
struct SurfaceSpace {
  using Vector = PatchField;
  const SurfaceLaplacian& op;
  double dot(const PatchField& a, const PatchField& b) const { return patch_dot(op, a, b); }
  double norm(const PatchField& a) const { return op.max_abs(a); }
  template <class F>
  void each(const F& f) const {
    for_cells(op, f);
  }
};

}  // namespace

template <class Residual, class Apply, class Precondition>
DiffusionReport SurfaceMultigrid::bicgstab(const SurfaceLaplacian& op, Krylov& k, PatchField& x,
                                           double bmax, const DiffusionSolve& solve,
                                           const Residual& residual, const Apply& apply,
                                           const Precondition& precondition) const {
  const BicgstabReport r =
      ardcell::bicgstab(SurfaceSpace{op}, k, x, bmax, {solve.tolerance, solve.max_sweeps}, residual,
                        apply, precondition);
  DiffusionReport report;
  report.cycles = r.applications;
  report.sweeps = r.applications * (kPreSweeps + kPostSweeps);
  report.residual = r.residual;
  return report;
}

DiffusionReport SurfaceMultigrid::implicit_diffusion(PatchField& x, const PatchField& b, double c,
                                                     const DiffusionSolve& solve) const {
  const SurfaceLaplacian& op = *levels_.front()->op;
  Level& top = *levels_.front();
  double bmax = op.max_abs(b);
  if (bmax == 0) bmax = 1;
  ARDCELL_CHECK(b.size() == top.b.size() && x.size() == top.x.size(),
                "SurfaceMultigrid: fields of another grid");
  b_ = b;  // same size: a copy (x may be b)
  const DiffusionReport report = bicgstab(
      op, fine_krylov_, x, bmax, solve,
      [&](PatchField& y, PatchField& r) { return op.residual(y, b_, c, r); },
      [&](PatchField& y, PatchField& out) {
        op.apply(y, out);
        for_cells(op, [&](std::size_t q) { out[q] = y[q] - c * out[q]; });
      },
      [&](const PatchField& q, PatchField& y) { precondition(q, y, c, false); });
  // As SurfaceLaplacian::implicit_diffusion: the total of the exact solution, which a finished
  // iterate keeps only to its residual (a constant is in lap's null space).
  op.add(x, (op.total(b_) - op.total(x)) / op.area());
  return report;
}

void SurfaceMultigrid::poisson_cycle(int level) const {
  const Level& l = *levels_[std::size_t(level)];
  if (level + 1 == levels()) {
    coarse_correction(0, true);
    return;
  }
  l.op->poisson_sweeps(l.x, l.b, kPreSweeps);
  l.op->poisson_residual(l.x, l.b, l.r);
  const Level& next = *levels_[std::size_t(level) + 1];
  restrict_mean(*l.op, l.r, *next.op, next.b);
  std::fill(next.x.begin(), next.x.end(), 0.0);
  poisson_cycle(level + 1);
  prolong_add(*next.op, next.x, *l.op, l.x);
  l.op->poisson_sweeps(l.x, l.b, kPostSweeps);
}

const std::vector<double>& SurfaceMultigrid::piece_areas() const {
  // In the order of SurfaceLaplacian::area (cells of every patch in turn), so that one piece's
  // area is area()'s bits.
  const SurfaceLaplacian& op = *levels_.front()->op;
  std::vector<double>& areas = fine_piece_areas_;
  if (areas.empty()) {
    areas.assign(piece_sums_.size(), 0.0);
    const int n = op.n();
    for (int p = 0; p < op.patches(); ++p)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i)
          areas[std::size_t(pieces_[std::size_t(p)])] += op.cell_area(p, i, j);
  }
  return areas;
}

void SurfaceMultigrid::remove_piece_means(const SurfaceLaplacian& op, PatchField& f) const {
  ARDCELL_CHECK(&op == levels_.front()->op, "remove_piece_means: the finest grid's fields only");
  // Each patch's integral on the executor, added per piece in patch order (SurfaceLaplacian::
  // total's order and bits for one piece).
  const PatchGrid& g = op.grid();
  const int n = g.n();
  op.executor().for_rows(g.patches(), n * n, [&](int p0, int p1) {
    for (int p = p0; p < p1; ++p) {
      double sum = 0;
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) sum += op.cell_area(p, i, j) * f[g.index(p, i, j)];
      patch_sums_[std::size_t(p)] = sum;
    }
  });
  piece_sums_.assign(piece_sums_.size(), 0.0);
  for (int p = 0; p < g.patches(); ++p)
    piece_sums_[std::size_t(pieces_[std::size_t(p)])] += patch_sums_[std::size_t(p)];
  const std::vector<double>& area = piece_areas();
  for (std::size_t k = 0; k < piece_sums_.size(); ++k) piece_sums_[k] /= area[k];
  for_cells(op,
            [&](std::size_t q) { f[q] -= piece_sums_[std::size_t(pieces_[q / g.patch_cells()])]; });
}

bool SurfaceMultigrid::solve_coarsest_poisson() const {
  const SparseLevel& l = sparse_.back();
  const int k = l.cells;
  if (k > kMaxDirectCells) return false;
  const auto piece = [&](int q) { return l.piece[std::size_t(q)]; };
  std::vector<double>& w = poisson_weight_;
  Factor& f = poisson_factor_;
  if (f.lu.empty()) {
    // Each piece's area in cell order, w its cells' share of it.
    std::vector<double> area(piece_sums_.size(), 0.0);
    for (int q = 0; q < k; ++q) area[std::size_t(piece(q))] += l.area[std::size_t(q)];
    w.resize(std::size_t(k));
    for (int q = 0; q < k; ++q)
      w[std::size_t(q)] = l.area[std::size_t(q)] / area[std::size_t(piece(q))];
    // lap + sum over pieces of 1_piece w_piece^T: w_q added in every row of q's piece.
    dense_matrix(l, 0, 1, f.lu);
    for (int r = 0; r < k; ++r)
      for (int q = 0; q < k; ++q)
        if (piece(r) == piece(q)) f.lu[std::size_t(r) * k + q] += w[std::size_t(q)];
    lu_factor(f.lu, f.pivot, k);
  }
  // The restricted residual's total on each piece is 0 only to the levels' differences: take
  // each piece's mean out, so that the bordered system's solution solves lap x = b.
  rhs_.resize(std::size_t(k));
  piece_sums_.assign(piece_sums_.size(), 0.0);
  for (int q = 0; q < k; ++q)
    piece_sums_[std::size_t(piece(q))] += w[std::size_t(q)] * l.b[std::size_t(q)];
  for (int q = 0; q < k; ++q)
    rhs_[std::size_t(q)] = l.b[std::size_t(q)] - piece_sums_[std::size_t(piece(q))];
  lu_solve(f.lu, f.pivot, k, rhs_);
  std::copy(rhs_.begin(), rhs_.end(), l.x.begin());
  return true;
}

DiffusionReport SurfaceMultigrid::solve_poisson(PatchField& x, const PatchField& b,
                                                const DiffusionSolve& solve) const {
  const SurfaceLaplacian& op = *levels_.front()->op;
  Level& top = *levels_.front();
  ARDCELL_CHECK(b.size() == top.b.size() && x.size() == top.x.size(),
                "SurfaceMultigrid: fields of another grid");
  b_ = b;  // same size: a copy (x may be b)
  remove_piece_means(op, b_);
  double bmax = op.max_abs(b_);
  if (bmax == 0) bmax = 1;
  const DiffusionReport report = bicgstab(
      op, fine_krylov_, x, bmax, solve,
      [&](PatchField& y, PatchField& r) { return op.poisson_residual(y, b_, r); },
      [&](PatchField& y, PatchField& out) { op.apply(y, out); },
      [&](const PatchField& q, PatchField& y) { precondition(q, y, 0, true); });
  remove_piece_means(op, x);
  return report;
}

}  // namespace ardcell
