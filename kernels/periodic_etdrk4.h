#pragma once
// Fourth-order exponential time differencing (ETDRK4) of a two-chemical reaction-diffusion
// system on a periodic, homogeneous, isotropic grid:
//   u_t = L u + N(u),  L = diag(c_A, c_B) lap5 (seed 000, Eqn 4: c = D / h^2 in cells, per unit
//   time),  N = (R_A, R_B) of Eqn 7, Eqn 8 / App. A (kernels/reaction.h reaction_rates)
// Cox & Matthews 2002 ("Exponential time differencing for stiff systems", their ETD4RK), per
// Fourier mode k (z = dt L(k), v = u^(k), N_u = N(u)^(k)):
//   a = E2 v + Q N_u                      b = E2 v + Q N_a
//   c = E2 a + Q (2 N_b - N_u)
//   v' = E v + f1 N_u + 2 f2 (N_a + N_b) + f3 N_c
//   E = e^z, E2 = e^(z/2), Q = dt (e^(z/2) - 1) / z,
//   f1 = dt (-4 - z + e^z (4 - 3z + z^2)) / z^3,  f2 = dt (2 + z + e^z (z - 2)) / z^3,
//   f3 = dt (-4 - 3z - z^2 + e^z (4 - z)) / z^3
// The coefficients are evaluated as Kassam & Trefethen 2005 ("Fourth-order time-stepping for
// stiff PDEs", sec. 5) do: each the mean of the same expression at 32 points of the circle of
// radius 1 around z (the functions are entire; the direct forms cancel catastrophically near
// z = 0), in double, rounded to float once. The diffusion is exact in each mode, so any dt is
// stable in it; the reaction enters explicitly (a fourth-order Runge-Kutta in it), so dt is
// bounded by the reaction's rates (|lambda dt| below about 2.8 for a real decay rate lambda).
//
// L's symbol is the 5-point Laplacian's, 2 cos(2 pi mx / nx) + 2 cos(2 pi my / ny) - 4, so
// the Fourier modes are exact eigenvectors of the engine's own discrete diffusion (the same
// dispersion relation as the other schemes). Reads no halo: the periodic wrap is the discrete
// Fourier transform's.
//
// Same bits on any worker count, no allocation per step, float transforms: as
// kernels/periodic_stencil_solve.h (one FFTW plan per 1D transform, executed on per-worker
// scratch with the planning buffers' alignment; rows and blocks of kColumnBlock spectral columns
// are the tasks; everything sized in the constructor). A step is nine passes: rows (transform
// u and N(u)), then, four times, columns (transform, combine, transform back) and rows (back to
// cells, N of the stage, forward again); the stages' fields never exist in cells, only one row
// at a time in each worker's scratch.
#include <complex>
#include <cstdint>
#include <vector>

#include "kernels/periodic_stencil_solve.h"  // FftwRowColumnPlans
#include "kernels/reaction.h"
#include "runtime/field.h"
#include "runtime/row_executor.h"

namespace ardcell {

class PeriodicEtdrk4 {
 public:
  static constexpr int kColumnBlock = 8;     // spectral columns per column task (a cache line)
  static constexpr int kContourPoints = 32;  // Kassam & Trefethen's M

  // size: any nx, ny >= 3. The executor must outlive this object; its worker count fixes the
  // scratch. Coefficients start at dt = 0 (the identity): call set_step.
  PeriodicEtdrk4(Int2 size, RowExecutor& executor = RowExecutor::serial());
  ~PeriodicEtdrk4();
  PeriodicEtdrk4(const PeriodicEtdrk4&) = delete;
  PeriodicEtdrk4& operator=(const PeriodicEtdrk4&) = delete;

  Int2 size() const { return size_; }

  // The coefficient tables for step dt and diffusion rates c_A, c_B (D / h^2, per unit time).
  // O(N) work on the executor, no allocation. dt, c_A, c_B finite and >= 0.
  void set_step(double dt, double rate_a, double rate_b);
  double dt() const { return dt_; }
  // The diffusion rate set_step took for chemical 0 (A) or 1 (B).
  double rate(int chemical) const { return rates_[chemical]; }

  // The coefficients the step applies to mode (mx, my) of chemical 0 (A) or 1 (B), as floats
  // (device twins upload these tables: kernels/cl/opencl_fft.h).
  struct ModeCoefficients {
    float e, e2, q, f1, f2, f3;
  };
  ModeCoefficients coefficients(int chemical, int mx, int my) const {
    const Coefficients& c = coef_[chemical];
    const std::size_t i = spectral_index(mx, my);
    return {c.e[i], c.e2[i], c.q[i], c.f1[i], c.f2[i], c.f3[i]};
  }

  // The 5-point Laplacian's symbol at mode (mx, my) in cells (mx in [0, nx / 2], my in [0, ny)).
  double symbol(int mx, int my) const;

  // One step of a and b in place (interiors). reaction null: N = 0 (exact diffusion).
  void step(FieldF& a, FieldF& b, const ReactionParams* reaction);

 private:
  struct Scratch;  // one worker's FFTW buffers
  // The coefficient tables of one chemical, each [mx][my] (the column pass's order).
  struct Coefficients {
    std::vector<float> e, e2, q, f1, f2, f3;
  };
  enum class Stage : uint8_t { kA, kB, kC, kFinal };

  std::size_t spectral_index(int mx, int my) const {
    return std::size_t(mx) * std::size_t(col_stride_) + std::size_t(my);
  }
  void forward_rows(const FieldF& a, const FieldF& b, int y0, int y1, int worker);
  void stage_rows(int y0, int y1, int worker);
  void final_rows(FieldF& a, FieldF& b, int y0, int y1, int worker);
  void columns(Stage stage, int b0, int b1, int worker);
  // N of one row of cells (both chemicals, in place), the current reaction.
  void reaction_row(float* a, float* b, int n) const;
  // Columns [x0, x0 + count) of a row-layout spectrum to/from a column block's scratch.
  void gather_columns(const std::complex<float>* rows, int x0, int count,
                      std::complex<float>* cols) const;
  void scatter_columns(const std::complex<float>* cols, int x0, int count,
                       std::complex<float>* rows) const;

  Int2 size_;
  RowExecutor* executor_;
  int width_ = 0;                  // nx / 2 + 1
  std::ptrdiff_t col_stride_ = 0;  // ny rounded up to kColumnBlock (keeps the alignment)
  double dt_ = 0;
  double rates_[2] = {0, 0};
  Coefficients coef_[2];
  const ReactionParams* reaction_ = nullptr;  // during step()
  // Row layout [y][mx] (after the row transforms): the stage's field and its N, per chemical.
  std::complex<float>* rows_u_[2] = {nullptr, nullptr};
  std::complex<float>* rows_n_[2] = {nullptr, nullptr};
  // Column layout [mx][my] (whole 2D spectra): v = u^, N_u, and N_a (N_a + N_b from stage C).
  std::complex<float>* v_[2] = {nullptr, nullptr};
  std::complex<float>* n_u_[2] = {nullptr, nullptr};
  std::complex<float>* n_ab_[2] = {nullptr, nullptr};
  std::vector<Scratch*> scratch_;  // one per worker
  FftwRowColumnPlans plans_;
};

}  // namespace ardcell
