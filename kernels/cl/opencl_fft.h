#pragma once
// The periodic FFT steps on the OpenCL device, by clFFT (Debian's libclfft-dev):
//   OpenClPeriodicSolve: seed 003, Eqn 28's linear part, x <- (I - delta K)^{-1} x, the twin of
//     PeriodicStencilSolve::solve (kernels/periodic_stencil_solve.h);
//   OpenClEtdrk4: the twin of PeriodicEtdrk4::step (kernels/periodic_etdrk4.h).
// Both read and write a field's interior on the device (no halo read: the wrap is the DFT's).
// The spectral arithmetic is the CPU's: its tables (the multipliers, the ETDRK4 coefficients:
// computed in double, rounded to float once) are uploaded, transposed to clFFT's [my][mx]
// layout, when they change (a new delta, dt or rate), never per step; the transforms are
// clFFT's (single precision, their own rounding: the result agrees with FFTW's to a few 1e-7 of
// max |x|, tests/kernels/cl_fft_parity_test.cpp).
//
// clFFT transforms lengths whose prime factors are 2, 3, 5, 7, 11 and 13 (clfft_size_problem
// names another); the engine runs such a size on the CPU
// (host/engine/opencl_device_schemes.cpp).
//
// Resources: plans are baked and buffers allocated in the constructors (the first use for a size
// in the engine); a step allocates no device memory. clFFT's library state is set up once per
// process before the first plan (clfftSetup) and torn down at exit (clfftTeardown). Each
// clfftEnqueueTransform makes a few small heap allocations of clFFT's own (std::vector, lock
// names: about 38 per 2D real transform, freed before it returns); nothing else here does.
#if defined(ARDCELL_WITH_OPENCL)
#include <string>
#include <vector>

#include "kernels/cl/opencl_kernels.h"
#include "kernels/periodic_etdrk4.h"
#include "kernels/periodic_stencil_solve.h"
#include "runtime/opencl/opencl_context.h"

namespace ardcell {

// "" when clFFT transforms an nx x ny grid, else one phrase naming why, e.g. "93 has a prime
// factor clFFT lacks (31)".
std::string clfft_size_problem(Int2 size);

// The packed fields and half spectra of `batch` 2D real transforms of size nx x ny, and the
// forward (real-to-complex) and backward (complex-to-real, unscaled: scale 1) clFFT plans
// between them, out of place, on the context's queue. See spectral.cl for the layouts.
class ClFft2d {
 public:
  // Throws std::runtime_error with one line when clFFT cannot plan (see clfft_size_problem).
  ClFft2d(OpenClContext& ctx, Int2 size, int batch);
  ~ClFft2d();
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

  void forward(const OpenClBuffer& real, const OpenClBuffer& spectrum);
  // clFFT may use either transform's input as scratch: neither is kept.
  void backward(const OpenClBuffer& spectrum, const OpenClBuffer& real);

 private:
  void enqueue(std::size_t plan, int direction, const OpenClBuffer& in, const OpenClBuffer& out);
  void destroy_plans();

  OpenClContext& ctx_;
  Int2 size_;
  int batch_;
  // clfftPlanHandles (std::size_t: clFFT.h stays in the .cpp); made_plans_ of them exist.
  std::size_t forward_plan_ = 0, backward_plan_ = 0;
  int made_plans_ = 0;
  OpenClBuffer scratch_;  // clFFT's temporary buffer (the larger plan's), when it needs one
};

// Twin of PeriodicStencilSolve::solve on a device field of the solve's size.
class OpenClPeriodicSolve {
 public:
  // fft: made for solve's size with batch 1, shared with other solves of that size (the
  // transforms run in queue order, so its temporary buffer is free between ops).
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
  bool uploaded_ = false;
  double dt_ = 0, rates_[2] = {0, 0};
};

}  // namespace ardcell
#endif
