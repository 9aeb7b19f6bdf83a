#pragma once
// The OpenCL device of a test program (PoCL in CI): opened once, on first use, and kept for the
// program's life (programs are built once). Null when the machine has no OpenCL device: the
// tests then skip. A device that is listed but cannot build the program is a test failure.
#if defined(ARDCELL_WITH_OPENCL)
#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "kernels/cl/opencl_kernels.h"
#include "runtime/opencl/opencl_context.h"

namespace ardcell {

struct TestOpenClDevice {
  std::unique_ptr<OpenClContext> ctx;
  std::unique_ptr<OpenClKernels> cl;
};

inline TestOpenClDevice* test_opencl_device() {
  static TestOpenClDevice* d = [] {
    std::string error;
    if (list_opencl_devices(&error).empty()) return static_cast<TestOpenClDevice*>(nullptr);
    auto* dev = new TestOpenClDevice;  // lives as long as the program (no exit-time teardown)
    dev->ctx = OpenClContext::open(0, &error);
    if (dev->ctx) dev->cl = OpenClKernels::create(*dev->ctx, &error);
    EXPECT_TRUE(dev->cl) << error;
    return dev;
  }();
  return d && d->cl ? d : nullptr;
}

}  // namespace ardcell
#endif
