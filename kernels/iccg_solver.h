#pragma once
// ICCG's fixed choices (kernels/iccg_solver.cpp), shared with its OpenCL twin
// (kernels/cl/opencl_iccg.h, iccg.cl), which makes the same ones so that it computes the same
// iterates.
#include <cmath>

namespace ardcell::iccg {

// Rows per block of the block IC(0) preconditioner (fixed by the grid, not by the workers).
inline constexpr int kBlockRows = 32;

// Whether the triangular solves' recurrences along a row fuse their multiply-adds (std::fma):
// where fma is fast (FP_FAST_FMA: the CPU has FMA instructions), since the latency of those
// recurrences is the solve's critical path (unfused, a turing-spots frame at 512^2 ran 15%
// slower on serial). Every other product and sum of the solver is rounded on its own
// (-ffp-contract=off), as in the twin.
#if defined(FP_FAST_FMA)
inline constexpr bool kFusedRecurrences = true;
#else
inline constexpr bool kFusedRecurrences = false;
#endif

}  // namespace ardcell::iccg
