#include "kernels/periodic_etdrk4.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>

#include "kernels/fftw_buffers.h"
#include "runtime/check.h"

namespace ardcell {

namespace {

using Complex = std::complex<float>;

// The ETDRK4 coefficients at z = dt L (Kassam & Trefethen's contour means), each times dt.
struct Etd {
  double e, e2, q, f1, f2, f3;
};
Etd etd_coefficients(double z, double dt) {
  using C = std::complex<double>;
  constexpr int m = PeriodicEtdrk4::kContourPoints;
  C q = 0, f1 = 0, f2 = 0, f3 = 0;
  // The upper half circle: for real z the lower half gives the conjugates, so the real part of
  // the mean over the upper half is the mean over the whole circle.
  for (int j = 1; j <= m; ++j) {
    const C w = z + std::polar(1.0, std::numbers::pi * (j - 0.5) / m);
    const C ew = std::exp(w), w3 = w * w * w;
    q += (std::exp(0.5 * w) - 1.0) / w;
    f1 += (-4.0 - w + ew * (4.0 - 3.0 * w + w * w)) / w3;
    f2 += (2.0 + w + ew * (w - 2.0)) / w3;
    f3 += (-4.0 - 3.0 * w - w * w + ew * (4.0 - w)) / w3;
  }
  return {std::exp(z),        std::exp(0.5 * z),  dt * q.real() / m,
          dt * f1.real() / m, dt * f2.real() / m, dt * f3.real() / m};
}

}  // namespace

struct PeriodicEtdrk4::Scratch {
  float* real[2] = {nullptr, nullptr};  // nx: one row of each chemical
  Complex* row = nullptr;               // nx / 2 + 1: a row's half spectrum
  Complex* columns = nullptr;           // kColumnBlock columns of col_stride_ (ny used)
};

PeriodicEtdrk4::PeriodicEtdrk4(Int2 size, RowExecutor& executor)
    : size_(size), executor_(&executor) {
  ARDCELL_CHECK(size.x >= 3 && size.y >= 3, "PeriodicEtdrk4: grid must be >= 3 x 3");
  const int nx = size.x, ny = size.y;
  width_ = nx / 2 + 1;
  col_stride_ = (std::ptrdiff_t(ny) + kColumnBlock - 1) / kColumnBlock * kColumnBlock;
  const std::size_t modes = std::size_t(width_) * std::size_t(col_stride_);
  for (Coefficients& c : coef_)
    for (std::vector<float>* t : {&c.e, &c.e2, &c.q, &c.f1, &c.f2, &c.f3}) t->assign(modes, 0.0f);

  const int workers = std::max(1, executor.workers());
  std::lock_guard<std::mutex> lock(fftw_planner_mutex());
  const std::size_t row_layout = std::size_t(ny) * std::size_t(width_);
  for (int c = 0; c < 2; ++c) {
    rows_u_[c] = fftw_alloc<Complex>(row_layout);
    rows_n_[c] = fftw_alloc<Complex>(row_layout);
    v_[c] = fftw_alloc<Complex>(modes);
    n_u_[c] = fftw_alloc<Complex>(modes);
    n_ab_[c] = fftw_alloc<Complex>(modes);
  }
  scratch_.reserve(std::size_t(workers));
  for (int w = 0; w < workers; ++w) {
    auto* s = new Scratch;
    scratch_.push_back(s);
    s->real[0] = fftw_alloc<float>(std::size_t(nx));
    s->real[1] = fftw_alloc<float>(std::size_t(nx));
    s->row = fftw_alloc<Complex>(std::size_t(width_));
    s->columns = fftw_alloc<Complex>(std::size_t(kColumnBlock) * std::size_t(col_stride_));
    const Scratch& s0 = *scratch_[0];
    ARDCELL_CHECK(same_fftw_alignment(s->real[0], s0.real[0]) &&
                      same_fftw_alignment(s->real[1], s0.real[0]) &&
                      same_fftw_alignment(s->row, s0.row) &&
                      same_fftw_alignment(s->columns, s0.columns),
                  "PeriodicEtdrk4: FFTW scratch alignment differs between workers");
  }
  Scratch& s0 = *scratch_[0];
  plans_ = make_row_column_plans(nx, ny, s0.real[0], s0.row, s0.columns);
}

PeriodicEtdrk4::~PeriodicEtdrk4() {
  std::lock_guard<std::mutex> lock(fftw_planner_mutex());
  destroy_row_column_plans(plans_);
  for (Scratch* s : scratch_) {
    fftwf_free(s->real[0]);
    fftwf_free(s->real[1]);
    fftwf_free(s->row);
    fftwf_free(s->columns);
    delete s;
  }
  for (int c = 0; c < 2; ++c)
    for (Complex* p : {rows_u_[c], rows_n_[c], v_[c], n_u_[c], n_ab_[c]}) fftwf_free(p);
}

double PeriodicEtdrk4::symbol(int mx, int my) const {
  // cos(2 pi m / n) of min(m, n - m), so that the conjugate modes m and n - m get the same bits
  // (the real-to-complex transform's columns mx = 0 and nx / 2 hold both).
  const auto c = [](int m, int n) {
    const int r = std::min(m % n, n - m % n);
    return std::cos(2 * std::numbers::pi * double(r) / n);
  };
  return 2.0 * c(mx, size_.x) + 2.0 * c(my, size_.y) - 4.0;
}

void PeriodicEtdrk4::set_step(double dt, double rate_a, double rate_b) {
  ARDCELL_CHECK(std::isfinite(dt) && dt >= 0 && std::isfinite(rate_a) && rate_a >= 0 &&
                    std::isfinite(rate_b) && rate_b >= 0,
                "PeriodicEtdrk4::set_step: dt and the rates must be finite and >= 0");
  const int ny = size_.y;
  const double rates[2] = {rate_a, rate_b};
  executor_->for_rows(width_, ny * kContourPoints, [&](int x0, int x1) {
    for (int mx = x0; mx < x1; ++mx)
      for (int my = 0; my < ny; ++my) {
        const double s = symbol(mx, my);
        for (int c = 0; c < 2; ++c) {
          const Etd k = etd_coefficients(dt * rates[c] * s, dt);
          const std::size_t i = spectral_index(mx, my);
          Coefficients& t = coef_[c];
          t.e[i] = float(k.e), t.e2[i] = float(k.e2), t.q[i] = float(k.q);
          t.f1[i] = float(k.f1), t.f2[i] = float(k.f2), t.f3[i] = float(k.f3);
        }
      }
  });
  dt_ = dt;
  rates_[0] = rate_a;
  rates_[1] = rate_b;
}

void PeriodicEtdrk4::reaction_row(float* a, float* b, int n) const {
  if (!reaction_) {
    std::fill(a, a + n, 0.0f);
    std::fill(b, b + n, 0.0f);
    return;
  }
  for (int x = 0; x < n; ++x) {
    double ra, rb;
    reaction_rates(*reaction_, a[x], b[x], ra, rb);
    a[x] = float(ra);
    b[x] = float(rb);
  }
}

// Rows: u -> rows_u_, N(u) -> rows_n_ (half spectra along x).
void PeriodicEtdrk4::forward_rows(const FieldF& a, const FieldF& b, int y0, int y1, int worker) {
  const Scratch& s = *scratch_[std::size_t(worker)];
  const std::size_t nx = std::size_t(size_.x), w = std::size_t(width_);
  const auto forward = [&](float* real, Complex* dst) {
    fftwf_execute_dft_r2c(plan_of(plans_.row_forward), real, fftw_of(s.row));
    std::memcpy(dst, s.row, w * sizeof(Complex));
  };
  for (int y = y0; y < y1; ++y) {
    const std::size_t at = std::size_t(y) * w;
    std::memcpy(s.real[0], a.row(y), nx * sizeof(float));
    std::memcpy(s.real[1], b.row(y), nx * sizeof(float));
    forward(s.real[0], rows_u_[0] + at);
    forward(s.real[1], rows_u_[1] + at);
    reaction_row(s.real[0], s.real[1], size_.x);
    forward(s.real[0], rows_n_[0] + at);
    forward(s.real[1], rows_n_[1] + at);
  }
}

// Rows: a stage's field (rows_u_) back to cells, its N forward into rows_n_.
void PeriodicEtdrk4::stage_rows(int y0, int y1, int worker) {
  const Scratch& s = *scratch_[std::size_t(worker)];
  const std::size_t w = std::size_t(width_);
  for (int y = y0; y < y1; ++y) {
    const std::size_t at = std::size_t(y) * w;
    for (int c = 0; c < 2; ++c) {
      std::memcpy(s.row, rows_u_[c] + at, w * sizeof(Complex));
      fftwf_execute_dft_c2r(plan_of(plans_.row_inverse), fftw_of(s.row), s.real[c]);
    }
    reaction_row(s.real[0], s.real[1], size_.x);
    for (int c = 0; c < 2; ++c) {
      fftwf_execute_dft_r2c(plan_of(plans_.row_forward), s.real[c], fftw_of(s.row));
      std::memcpy(rows_n_[c] + at, s.row, w * sizeof(Complex));
    }
  }
}

void PeriodicEtdrk4::final_rows(FieldF& a, FieldF& b, int y0, int y1, int worker) {
  const Scratch& s = *scratch_[std::size_t(worker)];
  const std::size_t nx = std::size_t(size_.x), w = std::size_t(width_);
  FieldF* out[2] = {&a, &b};
  for (int y = y0; y < y1; ++y)
    for (int c = 0; c < 2; ++c) {
      std::memcpy(s.row, rows_u_[c] + std::size_t(y) * w, w * sizeof(Complex));
      fftwf_execute_dft_c2r(plan_of(plans_.row_inverse), fftw_of(s.row), s.real[c]);
      std::memcpy(out[c]->row(y), s.real[c], nx * sizeof(float));
    }
}

void PeriodicEtdrk4::gather_columns(const Complex* rows, int x0, int count, Complex* cols) const {
  const std::size_t w = std::size_t(width_);
  for (int my = 0; my < size_.y; ++my) {
    const Complex* src = rows + std::size_t(my) * w + std::size_t(x0);
    for (int c = 0; c < count; ++c) cols[c * col_stride_ + my] = src[c];
  }
}

void PeriodicEtdrk4::scatter_columns(const Complex* cols, int x0, int count, Complex* rows) const {
  const std::size_t w = std::size_t(width_);
  for (int my = 0; my < size_.y; ++my) {
    Complex* dst = rows + std::size_t(my) * w + std::size_t(x0);
    for (int c = 0; c < count; ++c) dst[c] = cols[c * col_stride_ + my];
  }
}

// Columns of one stage, per block of kColumnBlock spectral columns and per chemical: the rows'
// N (and at stage A the field) transformed along y, the stage's combination (Cox & Matthews'
// a, b, c or the new v, FFTW's 1 / (nx ny) folded in), transformed back into rows_u_.
void PeriodicEtdrk4::columns(Stage stage, int b0, int b1, int worker) {
  const Scratch& s = *scratch_[std::size_t(worker)];
  const int ny = size_.y;
  const float scale = float(1.0 / (double(size_.x) * double(ny)));
  const auto fftw_forward = [&](Complex* col) {
    fftwf_execute_dft(plan_of(plans_.column_forward), fftw_of(col), fftw_of(col));
  };
  const auto fftw_inverse = [&](Complex* col) {
    fftwf_execute_dft(plan_of(plans_.column_inverse), fftw_of(col), fftw_of(col));
  };
  for (int blk = b0; blk < b1; ++blk) {
    const int x0 = blk * kColumnBlock, count = std::min(kColumnBlock, width_ - x0);
    for (int ch = 0; ch < 2; ++ch) {
      const Coefficients& k = coef_[ch];
      if (stage == Stage::kA) {  // v = u^ and N_u, kept for the later stages
        gather_columns(rows_u_[ch], x0, count, s.columns);
        for (int c = 0; c < count; ++c) {
          Complex* col = s.columns + c * col_stride_;
          fftw_forward(col);
          std::memcpy(v_[ch] + spectral_index(x0 + c, 0), col, std::size_t(ny) * sizeof(Complex));
        }
      }
      gather_columns(rows_n_[ch], x0, count, s.columns);
      for (int c = 0; c < count; ++c) {
        Complex* col = s.columns + c * col_stride_;
        fftw_forward(col);  // N of the stage's field: N_u, N_a, N_b or N_c
        const std::size_t i0 = spectral_index(x0 + c, 0);
        const Complex* v = v_[ch] + i0;
        Complex* nu = n_u_[ch] + i0;
        Complex* nab = n_ab_[ch] + i0;
        const float *e = k.e.data() + i0, *e2 = k.e2.data() + i0, *q = k.q.data() + i0;
        const float *f1 = k.f1.data() + i0, *f2 = k.f2.data() + i0, *f3 = k.f3.data() + i0;
        switch (stage) {
          case Stage::kA:  // a = E2 v + Q N_u
            for (int my = 0; my < ny; ++my) {
              nu[my] = col[my];
              col[my] = (e2[my] * v[my] + q[my] * nu[my]) * scale;
            }
            break;
          case Stage::kB:  // b = E2 v + Q N_a
            for (int my = 0; my < ny; ++my) {
              nab[my] = col[my];
              col[my] = (e2[my] * v[my] + q[my] * nab[my]) * scale;
            }
            break;
          case Stage::kC:  // c = E2 a + Q (2 N_b - N_u), a recomputed; N_a + N_b kept
            for (int my = 0; my < ny; ++my) {
              const Complex nb = col[my];
              const Complex a = e2[my] * v[my] + q[my] * nu[my];
              nab[my] += nb;
              col[my] = (e2[my] * a + q[my] * (2.0f * nb - nu[my])) * scale;
            }
            break;
          case Stage::kFinal:  // v' = E v + f1 N_u + 2 f2 (N_a + N_b) + f3 N_c
            for (int my = 0; my < ny; ++my)
              col[my] =
                  (e[my] * v[my] + f1[my] * nu[my] + 2.0f * f2[my] * nab[my] + f3[my] * col[my]) *
                  scale;
            break;
        }
        fftw_inverse(col);
      }
      scatter_columns(s.columns, x0, count, rows_u_[ch]);
    }
  }
}

void PeriodicEtdrk4::step(FieldF& a, FieldF& b, const ReactionParams* reaction) {
  ARDCELL_CHECK(a.size() == size_ && b.size() == size_,
                "PeriodicEtdrk4::step: field size differs from the plan's");
  ARDCELL_CHECK(executor_->workers() <= int(scratch_.size()),
                "PeriodicEtdrk4: executor has more workers than at construction");
  reaction_ = reaction;
  const int nx = size_.x, ny = size_.y;
  const int blocks = (width_ + kColumnBlock - 1) / kColumnBlock;
  // Work per task as PeriodicStencilSolve counts it, so the dispatch threshold sees the same.
  const int row_cells = 2 * nx, block_cells = 4 * kColumnBlock * ny;
  executor_->for_rows(ny, row_cells, [&](int y0, int y1, int w) { forward_rows(a, b, y0, y1, w); });
  for (Stage stage : {Stage::kA, Stage::kB, Stage::kC}) {
    executor_->for_rows(blocks, block_cells,
                        [&](int b0, int b1, int w) { columns(stage, b0, b1, w); });
    executor_->for_rows(ny, row_cells, [&](int y0, int y1, int w) { stage_rows(y0, y1, w); });
  }
  executor_->for_rows(blocks, block_cells,
                      [&](int b0, int b1, int w) { columns(Stage::kFinal, b0, b1, w); });
  executor_->for_rows(ny, row_cells, [&](int y0, int y1, int w) { final_rows(a, b, y0, y1, w); });
  reaction_ = nullptr;
}

}  // namespace ardcell
