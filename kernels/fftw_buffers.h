#pragma once
// The FFTW float plumbing the periodic FFT kernels share (periodic_stencil_solve.cpp,
// periodic_etdrk4.cpp), in .cpp files only. std::complex<float> and fftwf_complex share a
// layout, which FFTW documents: buffers are std::complex<float>, cast at the execute calls.
#include <complex>
#include <cstddef>
#include <new>

#include <fftw3.h>

#include "kernels/periodic_stencil_solve.h"  // FftwRowColumnPlans, fftw_planner_mutex
#include "runtime/check.h"

namespace ardcell {

inline fftwf_plan plan_of(void* p) { return static_cast<fftwf_plan>(p); }

// fftwf_malloc'd storage (FFTW's SIMD alignment); throws std::bad_alloc when none is left.
template <class T>
T* fftw_alloc(std::size_t count) {
  void* p = fftwf_malloc(count * sizeof(T));
  if (!p) throw std::bad_alloc();
  return static_cast<T*>(p);
}

inline fftwf_complex* fftw_of(std::complex<float>* p) {
  return reinterpret_cast<fftwf_complex*>(p);
}

// A plan made on one buffer runs on another through fftwf_execute_* only when both have the
// same alignment (FFTW's new-array execute rule): each worker's scratch is checked against the
// planning buffers'.
inline bool same_fftw_alignment(const void* a, const void* b) {
  return fftwf_alignment_of(static_cast<float*>(const_cast<void*>(a))) ==
         fftwf_alignment_of(static_cast<float*>(const_cast<void*>(b)));
}

// Plans for rows of nx (out of place, real <-> row) and columns of ny (in place in column), made
// on the planning buffers (FFTW_ESTIMATE does not touch them; c2r may destroy its input: the
// row is scratch). The caller holds fftw_planner_mutex().
inline FftwRowColumnPlans make_row_column_plans(int nx, int ny, float* real,
                                                std::complex<float>* row,
                                                std::complex<float>* column) {
  FftwRowColumnPlans p;
  p.row_forward = fftwf_plan_dft_r2c_1d(nx, real, fftw_of(row), FFTW_ESTIMATE);
  p.row_inverse = fftwf_plan_dft_c2r_1d(nx, fftw_of(row), real, FFTW_ESTIMATE);
  p.column_forward =
      fftwf_plan_dft_1d(ny, fftw_of(column), fftw_of(column), FFTW_FORWARD, FFTW_ESTIMATE);
  p.column_inverse =
      fftwf_plan_dft_1d(ny, fftw_of(column), fftw_of(column), FFTW_BACKWARD, FFTW_ESTIMATE);
  ARDCELL_CHECK(p.row_forward && p.row_inverse && p.column_forward && p.column_inverse,
                "FFTW could not plan");
  return p;
}

// The caller holds fftw_planner_mutex().
inline void destroy_row_column_plans(FftwRowColumnPlans& p) {
  for (void* plan : {p.row_forward, p.row_inverse, p.column_forward, p.column_inverse})
    if (plan) fftwf_destroy_plan(plan_of(plan));
  p = {};
}

}  // namespace ardcell
