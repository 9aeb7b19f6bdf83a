#include "kernels/periodic_stencil_solve.h"

// The buffers are std::complex<float>, cast at the execute calls (kernels/fftw_buffers.h).
#include "kernels/fftw_buffers.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <numbers>
#include <stdexcept>

#include "runtime/check.h"

namespace ardcell {

std::mutex& fftw_planner_mutex() {
  static std::mutex mutex;
  return mutex;
}

namespace {

using Complex = std::complex<float>;

// exp(2 pi i r / n) for r in [0, n), with r reduced to [0, n / 2] before the cosine: the
// quarter points are exact and exp(2 pi i (n - r) / n) is the exact conjugate of the r one, so
// the symbols of the conjugate modes k and -k are exact conjugates (the real-to-complex
// transform relies on that symmetry in its columns mx = 0 and mx = nx / 2).
std::complex<double> unit_root(long r, long n) {
  if (2 * r > n) return std::conj(unit_root(n - r, n));
  if (r == 0) return {1.0, 0.0};
  if (2 * r == n) return {-1.0, 0.0};
  if (4 * r == n) return {0.0, 1.0};
  return std::polar(1.0, 2 * std::numbers::pi * double(r) / double(n));
}

// exp(i k d) for k = 2 pi m / n, d in [-2, 2]: the phase m d reduced modulo n.
std::complex<double> phase(int m, int d, int n) {
  const long r = ((long(m) * d) % n + n) % n;
  return unit_root(r, n);
}

}  // namespace

// One worker's buffers, each fftwf_malloc'd (FFTW's SIMD alignment), so every worker's buffers
// have the alignment of worker 0's, on which the plans were made.
struct PeriodicStencilSolve::Scratch {
  float* real = nullptr;       // nx: one row of x
  Complex* row = nullptr;      // nx / 2 + 1: its half spectrum
  Complex* columns = nullptr;  // kColumnBlock columns of col_stride_ (ny used)
};

PeriodicStencilSolve::PeriodicStencilSolve(Int2 size, const Stencil5x5& stencil,
                                           RowExecutor& executor)
    : size_(size), stencil_(stencil), executor_(&executor) {
  ARDCELL_CHECK(size.x >= 5 && size.y >= 5, "PeriodicStencilSolve: grid must be >= 5 x 5");
  const int nx = size.x, ny = size.y;
  width_ = nx / 2 + 1;
  col_stride_ = (std::ptrdiff_t(ny) + kColumnBlock - 1) / kColumnBlock * kColumnBlock;
  const std::size_t modes = std::size_t(width_) * std::size_t(ny);

  // The symbol, [mx][my]: s(k) = sum_dy exp(i ky dy) sum_dx w(dx, dy) exp(i kx dx).
  symbol_.resize(modes);
  std::complex<double> ex[5], ey[5];
  for (int mx = 0; mx < width_; ++mx) {
    for (int d = -2; d <= 2; ++d) ex[d + 2] = phase(mx, d, nx);
    for (int my = 0; my < ny; ++my) {
      const int sy = signed_frequency(my, ny);
      for (int d = -2; d <= 2; ++d) ey[d + 2] = phase(sy, d, ny);
      std::complex<double> s = 0;
      for (int dy = -2; dy <= 2; ++dy) {
        std::complex<double> row = 0;
        for (int dx = -2; dx <= 2; ++dx) row += stencil.at(dx, dy) * ex[dx + 2];
        s += ey[dy + 2] * row;
      }
      symbol_[std::size_t(mx) * std::size_t(ny) + std::size_t(my)] = s;
    }
  }
  multipliers_.resize(modes);
  staging_.resize(modes);
  extremes_.resize(std::size_t(width_));

  const int workers = std::max(1, executor.workers());
  std::lock_guard<std::mutex> lock(fftw_planner_mutex());
  spectrum_ = fftw_alloc<Complex>(std::size_t(ny) * std::size_t(width_));
  scratch_.reserve(std::size_t(workers));
  for (int w = 0; w < workers; ++w) {
    auto* s = new Scratch;
    scratch_.push_back(s);
    s->real = fftw_alloc<float>(std::size_t(nx));
    s->row = fftw_alloc<Complex>(std::size_t(width_));
    s->columns = fftw_alloc<Complex>(std::size_t(kColumnBlock) * std::size_t(col_stride_));
    // Same alignment as the planning buffers (worker 0's): the plans' codelets may assume it.
    ARDCELL_CHECK(same_fftw_alignment(s->real, scratch_[0]->real) &&
                      same_fftw_alignment(s->row, scratch_[0]->row) &&
                      same_fftw_alignment(s->columns, scratch_[0]->columns),
                  "PeriodicStencilSolve: FFTW scratch alignment differs between workers");
  }
  Scratch& s0 = *scratch_[0];
  plans_ = make_row_column_plans(nx, ny, s0.real, s0.row, s0.columns);
  // delta = 0: the identity (times FFTW's 1 / (nx ny)), always well-posed.
  const float scale = float(1.0 / (double(nx) * double(ny)));
  std::fill(multipliers_.begin(), multipliers_.end(), Complex(scale, 0.0f));
}

PeriodicStencilSolve::~PeriodicStencilSolve() {
  std::lock_guard<std::mutex> lock(fftw_planner_mutex());
  destroy_row_column_plans(plans_);
  for (Scratch* s : scratch_) {
    fftwf_free(s->real);
    fftwf_free(s->row);
    fftwf_free(s->columns);
    delete s;
  }
  fftwf_free(spectrum_);
}

bool PeriodicStencilSolve::well_posed(double min_denominator, double max_denominator) const {
  return min_denominator >= kMinDenominator * std::max(1.0, max_denominator);
}

std::string PeriodicStencilSolve::problem(double delta) const {
  char line[320];
  if (!std::isfinite(delta)) {
    std::snprintf(line, sizeof line, "PeriodicStencilSolve: delta = %g is not finite", delta);
    return line;
  }
  double lo = INFINITY, hi = 0;
  int at_x = 0, at_y = 0;
  for (int mx = 0; mx < width_; ++mx)
    for (int my = 0; my < size_.y; ++my) {
      const double d = denominator(symbol(mx, my), delta);
      if (d < lo) lo = d, at_x = mx, at_y = my;
      hi = std::max(hi, d);
    }
  if (well_posed(lo, hi)) return "";
  const int sx = signed_frequency(at_x, size_.x), sy = signed_frequency(at_y, size_.y);
  const double kx = 2 * std::numbers::pi * sx / size_.x, ky = 2 * std::numbers::pi * sy / size_.y;
  std::snprintf(line, sizeof line,
                "PeriodicStencilSolve: I - delta K is singular at delta = %.9g on %dx%d: "
                "min |1 - delta symbol| = %.3g (< %g x max(1, %.3g)) at wavenumber (mx, my) = "
                "(%d, %d), k = (%.6f, %.6f) rad/cell",
                delta, size_.x, size_.y, lo, kMinDenominator, hi, sx, sy, kx, ky);
  return line;
}

void PeriodicStencilSolve::set_delta(double delta) {
  const int ny = size_.y;
  const double scale = 1.0 / (double(size_.x) * double(ny));
  bool finite = std::isfinite(delta);
  if (finite) {
    executor_->for_rows(width_, ny, [&](int x0, int x1) {
      for (int mx = x0; mx < x1; ++mx) {
        Extremes e{INFINITY, 0};
        const std::size_t base = std::size_t(mx) * std::size_t(ny);
        for (int my = 0; my < ny; ++my) {
          const std::complex<double> s = symbol_[base + std::size_t(my)];
          const double d = denominator(s, delta);
          e.min = std::min(e.min, d);
          e.max = std::max(e.max, d);
          // A vanishing d makes Inf or NaN here; such a table is never swapped in.
          staging_[base + std::size_t(my)] = Complex(scale / (1.0 - delta * s));
        }
        extremes_[std::size_t(mx)] = e;
      }
    });
  }
  double lo = INFINITY, hi = 0;
  for (const Extremes& e : extremes_) lo = std::min(lo, e.min), hi = std::max(hi, e.max);
  if (!finite || !well_posed(lo, hi)) throw std::invalid_argument(problem(delta));
  multipliers_.swap(staging_);
  delta_ = delta;
}

void PeriodicStencilSolve::forward_rows(const FieldF& x, int y0, int y1, int worker) {
  const Scratch& s = *scratch_[std::size_t(worker)];
  const std::size_t nx = std::size_t(size_.x), w = std::size_t(width_);
  for (int y = y0; y < y1; ++y) {
    std::memcpy(s.real, x.row(y), nx * sizeof(float));
    fftwf_execute_dft_r2c(plan_of(plans_.row_forward), s.real, fftw_of(s.row));
    std::memcpy(spectrum_ + std::size_t(y) * w, s.row, w * sizeof(Complex));
  }
}

void PeriodicStencilSolve::columns(int b0, int b1, int worker) {
  const Scratch& s = *scratch_[std::size_t(worker)];
  const int ny = size_.y;
  const std::size_t w = std::size_t(width_);
  for (int b = b0; b < b1; ++b) {
    const int x0 = b * kColumnBlock, count = std::min(kColumnBlock, width_ - x0);
    // Gather: each spectral row contributes `count` adjacent values (one cache line).
    for (int my = 0; my < ny; ++my) {
      const Complex* src = spectrum_ + std::size_t(my) * w + std::size_t(x0);
      for (int c = 0; c < count; ++c) s.columns[c * col_stride_ + my] = src[c];
    }
    for (int c = 0; c < count; ++c) {
      Complex* col = s.columns + c * col_stride_;
      fftwf_execute_dft(plan_of(plans_.column_forward), fftw_of(col), fftw_of(col));
      const Complex* m = multipliers_.data() + std::size_t(x0 + c) * std::size_t(ny);
      for (int my = 0; my < ny; ++my) col[my] *= m[my];
      fftwf_execute_dft(plan_of(plans_.column_inverse), fftw_of(col), fftw_of(col));
    }
    for (int my = 0; my < ny; ++my) {
      Complex* dst = spectrum_ + std::size_t(my) * w + std::size_t(x0);
      for (int c = 0; c < count; ++c) dst[c] = s.columns[c * col_stride_ + my];
    }
  }
}

void PeriodicStencilSolve::inverse_rows(FieldF& x, int y0, int y1, int worker) {
  const Scratch& s = *scratch_[std::size_t(worker)];
  const std::size_t nx = std::size_t(size_.x), w = std::size_t(width_);
  for (int y = y0; y < y1; ++y) {
    std::memcpy(s.row, spectrum_ + std::size_t(y) * w, w * sizeof(Complex));
    fftwf_execute_dft_c2r(plan_of(plans_.row_inverse), fftw_of(s.row), s.real);
    std::memcpy(x.row(y), s.real, nx * sizeof(float));
  }
}

void PeriodicStencilSolve::solve_pair(PeriodicStencilSolve& solve_a, FieldF& a,
                                      PeriodicStencilSolve& solve_b, FieldF& b) {
  ARDCELL_CHECK(solve_a.executor_ == solve_b.executor_ && &solve_a != &solve_b,
                "PeriodicStencilSolve::solve_pair: two solves on one executor");
  RowExecutor& ex = *solve_a.executor_;
  if (ex.workers() != 2) {
    solve_a.solve(a);
    solve_b.solve(b);
    return;
  }
  // Each task transforms on its own thread, with worker 0's scratch of its own object.
  ex.for_tasks(2, [&](int t) {
    if (t == 0)
      solve_a.transform(a, RowExecutor::serial());
    else
      solve_b.transform(b, RowExecutor::serial());
  });
}

void PeriodicStencilSolve::solve(FieldF& x) { transform(x, *executor_); }

void PeriodicStencilSolve::transform(FieldF& x, RowExecutor& ex) {
  ARDCELL_CHECK(x.size() == size_, "PeriodicStencilSolve::solve: field size differs from plan");
  ARDCELL_CHECK(ex.workers() <= int(scratch_.size()),
                "PeriodicStencilSolve: executor has more workers than at construction");
  const int nx = size_.x, ny = size_.y;
  const int blocks = (width_ + kColumnBlock - 1) / kColumnBlock;
  // cells_per_row counts the work of a task (a block: kColumnBlock columns there and back), so
  // the executor's "worth dispatching" threshold sees the same work in both directions.
  ex.for_rows(ny, nx, [&](int y0, int y1, int w) { forward_rows(x, y0, y1, w); });
  ex.for_rows(blocks, 2 * kColumnBlock * ny, [&](int b0, int b1, int w) { columns(b0, b1, w); });
  ex.for_rows(ny, nx, [&](int y0, int y1, int w) { inverse_rows(x, y0, y1, w); });
}

}  // namespace ardcell
