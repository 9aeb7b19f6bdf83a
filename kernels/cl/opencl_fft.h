#pragma once
// The periodic FFT steps on the OpenCL device, by our own FFT kernels (kernels/cl/fft.cl):
//   OpenClPeriodicSolve: seed 003, Eqn 28's linear part, x <- (I - delta K)^{-1} x, the twin of
//     PeriodicStencilSolve::solve (kernels/periodic_stencil_solve.h);
//   OpenClEtdrk4: the twin of PeriodicEtdrk4::step (kernels/periodic_etdrk4.h).
// Both read and write a field's interior on the device (no halo read: the wrap is the DFT's).
// The spectral arithmetic is the CPU's: its tables (the multipliers, the ETDRK4 coefficients:
// computed in double, rounded to float once) are uploaded, transposed to the half spectrum's
// [my][mx] layout, when they change (a new delta, dt or rate), never per step; the transforms
// are fft.cl's (single precision, their own rounding: the result agrees with FFTW's to a few
// 1e-7 of max |x|, tests/kernels/cl_fft_parity_test.cpp).
//
// The device FFT transforms lengths whose prime factors are 2, 3, 5 and 7
// (device_fft_size_problem names another); the engine runs such a size on the CPU
// (host/engine/opencl_device_schemes.cpp).
//
// Resources: root tables and buffers are made in the constructors (the first use for a size in
// the engine); a transform, a solve or a step makes no heap allocation of ours and no device
// buffer: it sets kernel arguments and enqueues (tests/host/engine/frame_alloc_test.cpp counts
// operator new; what the OpenCL driver allocates inside an enqueue is the driver's).
#if defined(ARDCELL_WITH_OPENCL)
#include <memory>
#include <string>
#include <vector>

#include "kernels/cl/opencl_kernels.h"
#include "kernels/periodic_etdrk4.h"
#include "kernels/periodic_stencil_solve.h"
#include "runtime/opencl/opencl_context.h"

namespace ardcell {

// "" when the device FFT transforms an nx x ny grid, else one phrase naming why, e.g. "93 has a
// prime factor the device FFT lacks (31)".
std::string device_fft_size_problem(Int2 size);

// `batch` 2D real transforms of size nx x ny between packed fields and half spectra, forward
// (real-to-complex) and backward (complex-to-real, unscaled), out of place, on the context's
// queue (see spectral.cl for the layouts). Each is a few passes of fft.cl's mixed-radix Stockham
// kernels per dimension, each pass one launch over every row (or column) of the batch: forward,
// the rows, then the nx / 2 + 1 spectral columns; backward, the columns, then the rows. An even
// nx transforms each real row as a complex row of nx / 2 (pairs of reals), split into the row's
// half spectrum as the first column pass loads, merged back as the first backward row pass
// loads; an odd nx as a complex row of nx (the first pass reads the reals; the last keeps the
// half spectrum; backward, the first rebuilds each row from its Hermitian half, the last keeps
// the real part).
class ClFft2d {
 public:
  // Throws std::runtime_error with one line when the device FFT cannot transform the size (see
  // device_fft_size_problem) or the program cannot be built.
  ClFft2d(OpenClContext& ctx, Int2 size, int batch);
  ClFft2d(const ClFft2d&) = delete;
  ClFft2d& operator=(const ClFft2d&) = delete;

  Int2 size() const { return size_; }
  int batch() const { return batch_; }
  int width() const { return size_.x / 2 + 1; }    // spectral columns mx in [0, nx / 2]
  int modes() const { return width() * size_.y; }  // per field
  int cells() const { return size_.x * size_.y; }  // per field
  // Buffers of `batch` packed fields (floats) and of `batch` half spectra (float2).
  OpenClBuffer allocate_real() const;
  OpenClBuffer allocate_spectrum() const;

  // The forward transform keeps `real`; the backward one may use `spectrum` as scratch.
  void forward(const OpenClBuffer& real, const OpenClBuffer& spectrum);
  void backward(const OpenClBuffer& spectrum, const OpenClBuffer& real);

 private:
  // How a pass of fft.cl reads or writes one buffer (see its header).
  struct Layout {
    int kind;  // in: 0 complex, 1 real, 2 Hermitian half, 3 split, 4 merge; out: 0 complex, 1 real
    int stride;          // between a transform's elements
    int distance;        // between neighbouring transforms of a field
    int field_distance;  // between fields
    int keep;            // out, complex: the elements below keep are written
  };
  // One dimension's transforms: length, radices in pass order, root table and batch shape.
  struct Dimension {
    int n = 0;
    std::vector<int> radices;  // sized in the constructor
    OpenClBuffer roots;        // w_n^k, k < n, as float2
    int per_field = 0;         // transforms per field
    bool transforms_fastest = false;
  };
  struct Layouts;
  Layouts layouts() const;
  // Dimension d's passes from (in, in_layout) to (out, out_layout); pass p before the last
  // writes scratch[p % 2] in `between` (so each pass's input and output differ when in, out
  // and the scratch buffers allow it: see forward and backward).
  void run(const Dimension& d, bool inverse, const OpenClBuffer& in, const Layout& in_layout,
           const OpenClBuffer& out, const Layout& out_layout, const OpenClBuffer* const scratch[2],
           const Layout& between);

  OpenClContext& ctx_;
  Int2 size_;
  int batch_;
  std::unique_ptr<OpenClKernels> kernels_;  // the one program (fft.cl's kernels are in it)
  // fft_pass_radixR and fft_complex_pass_radixR at index R.
  cl_kernel pass_[17] = {}, complex_pass_[17] = {};
  Dimension rows_, columns_;
  int half_ = 0;              // nx / 2 for an even nx (rows_.n), else 0
  OpenClBuffer split_roots_;  // w_nx^k, k < nx: the split's and merge's twiddles
  // Two buffers of `batch` fields of complex rows (rows_.n or nx / 2 + 1, the larger, x ny
  // float2): the passes ping-pong between them and the spectrum.
  OpenClBuffer rows_a_, rows_b_;
};

// Twin of PeriodicStencilSolve::solve on a device field of the solve's size.
class OpenClPeriodicSolve {
 public:
  // fft: made for solve's size with batch 1, shared with other solves of that size (the
  // transforms run in queue order, so its scratch buffers are free between ops).
  OpenClPeriodicSolve(OpenClKernels& cl, ClFft2d& fft);

  // x <- (I - solve.delta() K)^{-1} x over x's interior. Uploads solve's multipliers first when
  // its stencil or delta differ from the last upload's.
  void solve(const PeriodicStencilSolve& solve, DeviceField& x);

 private:
  void upload(const PeriodicStencilSolve& solve);

  OpenClKernels& cl_;
  ClFft2d& fft_;
  OpenClBuffer real_, spectrum_, multipliers_;
  std::vector<float> staging_;  // the transposed table, sized once
  // spectral.cl's kernels, looked up once.
  cl_kernel pack_, unpack_, multiply_;
  bool uploaded_ = false;
  double delta_ = 0;
  Stencil5x5 stencil_{};
};

// Twin of PeriodicEtdrk4::step on device fields of the step's size.
class OpenClEtdrk4 {
 public:
  // fft: made for the step's size with batch 2 (A and B transform together).
  OpenClEtdrk4(OpenClKernels& cl, ClFft2d& fft);

  // One step of a and b (interiors) with etdrk4's coefficients (uploaded first when its dt or
  // rates differ from the last upload's). reaction null: N = 0.
  void step(const PeriodicEtdrk4& etdrk4, DeviceField& a, DeviceField& b,
            const ReactionParams* reaction_params);

 private:
  void upload(const PeriodicEtdrk4& etdrk4);
  // n_real_ = N(u_real_) in cells.
  void reaction(const ReactionParams* params);
  // etdrk4_combine's `stage` into next_, then next_ back to cells in u_real_.
  void combine(int stage);

  OpenClKernels& cl_;
  ClFft2d& fft_;
  OpenClBuffer u_real_, n_real_;                  // packed A and B, and their N
  OpenClBuffer v_, n_u_, n_ab_, n_stage_, next_;  // spectra (see spectral.cl)
  OpenClBuffer coefficients_;                     // [chemical][table][my][mx]
  std::vector<float> staging_;                    // sized once
  // spectral.cl's kernels, looked up once.
  cl_kernel pack_, unpack_, reaction_, combine_;
  bool uploaded_ = false;
  double dt_ = 0, rates_[2] = {0, 0};
};

}  // namespace ardcell
#endif
