#pragma once
// Shared by the OpenCL parity tests (tests/kernels/cl_parity_test.cpp, cl_frame_parity_test.cpp):
// every OpenCL twin against its C++ kernel on PoCL, at awkward sizes (not multiples of the tile
// or of a work-group) and over awkward regions.
//
// Norm: normwise relative error in the max norm over the written region,
//   err = max_cells |cl - cpp| / max(max_cells |cpp|, 1e-30),
// required <= 1e-5. Cells outside the region (halo and padding included) must be untouched:
// exact equality.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "kernels/cl/opencl_kernels.h"
#include "runtime/opencl/opencl_context.h"

namespace ardcell::cl_parity {

inline constexpr double kTolerance = 1e-5;

struct Fixture {
  std::unique_ptr<OpenClContext> ctx;
  std::unique_ptr<OpenClKernels> cl;
};

// Whether the device is PoCL's (a CPU with correctly rounded doubles and glibc-like maths), where
// the twins that repeat a C++ solver operation for operation must give its bits exactly.
inline bool is_pocl(const OpenClContext& ctx) {
  return ctx.device().platform_name.find("Portable Computing Language") != std::string::npos;
}

// The test program's device (opened once); a device that cannot build the program fails.
inline Fixture& device() {
  static Fixture f = [] {
    Fixture fx;
    std::string error;
    fx.ctx = OpenClContext::open(0, &error);
    if (fx.ctx) fx.cl = OpenClKernels::create(*fx.ctx, &error);
    if (!fx.cl) ADD_FAILURE() << error;
    return fx;
  }();
  return f;
}

inline void fill_random(FieldF& f, float lo, float hi, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> d(lo, hi);
  for (std::size_t i = 0; i < f.raw_size(); ++i) f.raw()[i] = d(rng);
}

// mean + amplitude * sin(2 pi (x / nx + phase)) cos(2 pi (y / ny) + phase), halo included.
inline void fill_smooth(FieldF& f, float mean, float amplitude, float phase) {
  const double two_pi = 6.283185307179586;
  for (int y = -f.halo(); y < f.ny() + f.halo(); ++y)
    for (int x = -f.halo(); x < f.nx() + f.halo(); ++x)
      f(x, y) = float(mean + amplitude * std::sin(two_pi * (double(x) / f.nx() + phase)) *
                                 std::cos(two_pi * double(y) / f.ny() + phase));
}

// Normwise relative max-norm error over `region`.
inline double region_error(const FieldF& cl, const FieldF& cpp, Box2 region) {
  double diff = 0, ref = 0;
  for (int y = region.min.y; y < region.max.y; ++y)
    for (int x = region.min.x; x < region.max.x; ++x) {
      diff = std::max(diff, std::abs(double(cl(x, y)) - double(cpp(x, y))));
      ref = std::max(ref, std::abs(double(cpp(x, y))));
    }
  return diff / std::max(ref, 1e-30);
}

// region_error; also checks every cell outside `region` is bit-identical to `before`.
inline double relative_error(const FieldF& cl, const FieldF& cpp, const FieldF& before,
                             Box2 region) {
  for (int y = -cl.halo(); y < cl.ny() + cl.halo(); ++y)
    for (int x = -cl.halo(); x < cl.nx() + cl.halo(); ++x)
      if (!region.contains(Int2{x, y}) && cl(x, y) != before(x, y)) {
        ADD_FAILURE() << "cell (" << x << ", " << y << ") outside " << region << " was written";
        return 1.0;
      }
  return region_error(cl, cpp, region);
}

inline const Int2 kSizes[] = {{37, 23}, {127, 93}, {129, 65}, {5, 3}};

inline std::vector<Box2> regions_of(Int2 size) {
  return {box_of_size(size), Box2{{1, size.y / 3}, {size.x - 1, size.y}}};
}

// Upload and download of whole fields.
struct Dev {
  OpenClContext& ctx;
  DeviceField up(const FieldF& f) {
    DeviceField d = ctx.allocate_like(f);
    ctx.upload(f, d);
    return d;
  }
  FieldF down(const DeviceField& d) {
    FieldF f(d.size, d.halo);
    ctx.download(d, f);
    return f;
  }
};

}  // namespace ardcell::cl_parity
