#pragma once
// The exact semi-implicit diffusion step of seed 003 (McGraw) on a periodic grid, by FFT:
//   seed 003, Eqn 28: u^{t+1} = (I - delta A)^{-1} (u^t + delta f(u^t))
// This solves the linear part, x <- (I - delta K)^{-1} x, in place, where K is any 25-point
// stencil (kernels/generalized_diffusion.h: Eqn 21 / Eqn 37's A, or the 3x3 special cases of
// Eqn 25 and Eqn 29)
// and the caller has already added delta f(u^t) to x.
// Reads NO halo: the periodic wrap (the tileable texture of seed 003, sec. 4) is implicit in the
// discrete Fourier transform, so only the interior [0, nx) x [0, ny) is read and written.
//
// Why FFT: a homogeneous operator on a periodic grid is circulant (block-circulant with
// circulant blocks), so the Fourier modes exp(i (kx x + ky y)), k = 2 pi (mx / nx, my / ny),
// are its eigenvectors and stencil_symbol(k) its eigenvalues. The inverse is then exact (no
// iteration, no tolerance), costs O(N log N), and works for non-symmetric stencils (odd ranks:
// complex symbol) on which CG does not apply: each mode is divided by 1 - delta symbol(k).
//
// Precision: float (fftw3f). Float storage is the engine's rule (DESIGN.md), and the solve's
// error against a double-precision iterative solve of the same system is a few 1e-7 of max |x|
// on Table 2's sequences (tests/kernels/periodic_stencil_solve_test.cpp asserts 1e-5), so double
// transforms would cost twice the memory traffic for digits the float field cannot hold. The
// symbol and the multiplier 1 / (1 - delta symbol) are computed in double and rounded once.
//
// Parallel, and the same bits for any worker count: the 2D transform is 1D real-to-complex
// transforms along x (one per row, nx / 2 + 1 outputs), then 1D complex transforms along y (one
// per column, gathered kColumnBlock columns at a time into per-worker scratch), the division,
// and the way back. Every 1D transform runs through ONE plan with fftwf_execute_dft_* on
// per-worker fftwf_malloc'd scratch with the same alignment as the planning buffers, so a row
// or column gives the same bits whichever worker transforms it. Plans are made once, with
// FFTW_ESTIMATE (FFTW_MEASURE would time candidates and make the bits depend on the machine's
// load), under fftw_planner_mutex() (FFTW's planner is not thread-safe).
//
// Well-posedness: (I - delta K) is singular where 1 - delta symbol(k) = 0 for some mode (e.g.
// backward hyperdiffusion, D_xxxx > 0, at a large delta). problem(delta) names such a delta;
// set_delta() refuses it, so solve() never divides by ~0 and, for a finite input, never writes
// NaN or Inf: every multiplier is at most 1 / kMinDenominator.
//
// Allocation: none in set_delta() or solve() (all scratch is sized in the constructor). FFTW
// itself may malloc() scratch inside an execute for some sizes (Rader's algorithm for large
// prime factors, buffered plans); that is C malloc, not operator new, and not this code's.
#include <complex>
#include <mutex>
#include <string>
#include <vector>

#include "kernels/savitzky_golay.h"
#include "runtime/field.h"
#include "runtime/row_executor.h"

namespace ardcell {

// The one process-wide lock around FFTW's planner (plan creation and destruction, and
// fftwf_malloc/free made next to them). Any other code that plans FFTW transforms must hold it.
std::mutex& fftw_planner_mutex();

// The four 1D FFTW plans of a 2D transform done as rows (real-to-complex and back, nx cells) and
// then columns (complex, ny, in place), kept opaque (fftwf_plan: no fftw3.h here); made and
// destroyed under fftw_planner_mutex() (kernels/fftw_buffers.h).
struct FftwRowColumnPlans {
  void* row_forward = nullptr;
  void* row_inverse = nullptr;
  void* column_forward = nullptr;
  void* column_inverse = nullptr;
};

class PeriodicStencilSolve {
 public:
  // Columns transformed per task of the y pass: 8 complex floats, one 64-byte cache line of
  // each spectral row, so the strided gather reads whole lines.
  static constexpr int kColumnBlock = 8;
  // set_delta() refuses a delta for which min_k |1 - delta symbol(k)| < kMinDenominator *
  // max(1, max_k |1 - delta symbol(k)|): (I - delta K) is normal, so that ratio is the inverse
  // of its condition number, and past 1e6 a float right-hand side (relative precision 6e-8)
  // determines the solution's worst mode to a few percent at best.
  static constexpr double kMinDenominator = 1e-6;

  // size: any nx, ny >= 5 (odd and non-powers of two included). The executor must outlive this
  // object; its worker count fixes the scratch (one set per worker). delta starts at 0.
  PeriodicStencilSolve(Int2 size, const Stencil5x5& stencil,
                       RowExecutor& executor = RowExecutor::serial());
  ~PeriodicStencilSolve();
  PeriodicStencilSolve(const PeriodicStencilSolve&) = delete;
  PeriodicStencilSolve& operator=(const PeriodicStencilSolve&) = delete;

  Int2 size() const { return size_; }
  const Stencil5x5& stencil() const { return stencil_; }
  // Spectral columns: mx in [0, nx / 2] (the real-to-complex half); my in [0, ny).
  int spectral_width() const { return width_; }

  // The signed wavenumber of index m on an axis of n cells: m for m <= n / 2, else m - n.
  static int signed_frequency(int m, int n) { return 2 * m <= n ? m : m - n; }
  // stencil_symbol at k = 2 pi (mx / nx, my / ny) (signed frequencies), for mx in [0, nx / 2],
  // my in [0, ny), as tabulated in the constructor (the phase is reduced to [0, n) cells before
  // the cosine, so exp(i k d) is exact at the quarter points and conjugate modes get conjugate
  // symbols bit for bit).
  std::complex<double> symbol(int mx, int my) const {
    return symbol_[std::size_t(mx) * std::size_t(size_.y) + std::size_t(my)];
  }
  // The multiplier the solve applies to mode (mx, my): 1 / (1 - delta symbol(mx, my)) (solve()
  // also folds in FFTW's 1 / (nx ny) and rounds the product to float once).
  std::complex<double> multiplier(int mx, int my, double delta) const {
    return 1.0 / (1.0 - delta * symbol(mx, my));
  }
  // The multiplier solve() applies to mode (mx, my) at delta(): multiplier(mx, my, delta()) / (nx
  // ny), rounded to float once (device twins upload this table: kernels/cl/opencl_fft.h).
  std::complex<float> applied_multiplier(int mx, int my) const {
    return multipliers_[std::size_t(mx) * std::size_t(size_.y) + std::size_t(my)];
  }

  // One line naming why (I - delta K)^{-1} is not defined (delta not finite, or the smallest
  // |1 - delta symbol| with its wavenumber, see kMinDenominator); "" when delta is fine.
  std::string problem(double delta) const;

  // Tabulates the multipliers for delta (O(N), on the executor, no allocation). Throws
  // std::invalid_argument carrying problem(delta) for a delta that problem() names; the
  // previous delta then stays in force.
  void set_delta(double delta);
  double delta() const { return delta_; }

  // x <- (I - delta() K)^{-1} x over x's interior (any halo, not read). x.size() must be size().
  void solve(FieldF& x);
  // The same with delta (set_delta(delta) first when it differs from delta()).
  void solve(FieldF& x, double delta) {
    if (delta != delta_) set_delta(delta);
    solve(x);
  }
  // solve_a.solve(a) and solve_b.solve(b) (the two chemicals of a step, each with its own delta;
  // one executor), the same bits. On two workers the two transforms run side by side, each
  // whole on one worker: split over both, a 2D transform's column pass reads half the spectrum
  // from the other core's cache and its row pass writes it back (+40% CPU in the columns on a
  // 2-vCPU Xeon VM), and each solve is three passes instead of one for both.
  static void solve_pair(PeriodicStencilSolve& solve_a, FieldF& a, PeriodicStencilSolve& solve_b,
                         FieldF& b);

 private:
  struct Scratch;  // one worker's FFTW buffers
  // solve(x) on `ex`: the object's executor, or the serial one inside a task of solve_pair.
  void transform(FieldF& x, RowExecutor& ex);
  struct Extremes {
    double min = 0, max = 0;  // of |1 - delta symbol| over one spectral column
  };
  // The same |1 - delta symbol| as problem() and set_delta() compare, computed one way.
  static double denominator(std::complex<double> s, double delta) {
    return std::abs(1.0 - delta * s);
  }
  bool well_posed(double min_denominator, double max_denominator) const;
  void forward_rows(const FieldF& x, int y0, int y1, int worker);
  void columns(int b0, int b1, int worker);
  void inverse_rows(FieldF& x, int y0, int y1, int worker);

  Int2 size_;
  Stencil5x5 stencil_;
  RowExecutor* executor_;
  int width_ = 0;                  // nx / 2 + 1
  std::ptrdiff_t col_stride_ = 0;  // ny rounded up to kColumnBlock complex (keeps alignment)
  double delta_ = 0;
  std::vector<std::complex<double>> symbol_;      // [mx][my]
  std::vector<std::complex<float>> multipliers_;  // [mx][my], 1 / ((1 - delta s) nx ny)
  std::vector<std::complex<float>> staging_;      // set_delta's table, swapped in when valid
  std::vector<Extremes> extremes_;                // per spectral column, for set_delta
  std::complex<float>* spectrum_ = nullptr;       // [my][mx], fftwf_malloc'd
  std::vector<Scratch*> scratch_;                 // one per worker
  FftwRowColumnPlans plans_;
};

}  // namespace ardcell
