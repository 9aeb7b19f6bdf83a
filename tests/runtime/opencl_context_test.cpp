// The OpenCL plumbing on PoCL: enumeration, programs built once, kernel arguments by value, device
// fields that round-trip exactly, and the fallback line for each way OpenCL can be missing.
#include "runtime/opencl/opencl_context.h"

#include <gtest/gtest.h>
#include <stdlib.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string_view>

#include "runtime/opencl/backend_choice.h"
#include "runtime/opencl/opencl_backend.h"

namespace ardcell {
namespace {

constexpr std::string_view kScaleSource = R"(
__kernel void scale_add(__global float* y, __global const float* x, float a, int n) {
  const int i = get_global_id(0);
  if (i < n) y[i] = a * x[i] + y[i];
}
)";

std::unique_ptr<OpenClContext> open_first_device() {
  std::string error;
  std::unique_ptr<OpenClContext> ctx = OpenClContext::open(0, &error);
  EXPECT_TRUE(ctx) << error;
  return ctx;
}

TEST(OpenClContext, ListsPoclWithItsResources) {
  std::string error;
  const std::vector<OpenClDeviceInfo> devices = list_opencl_devices(&error);
  ASSERT_FALSE(devices.empty()) << error;
  for (std::size_t i = 0; i < devices.size(); ++i) {
    EXPECT_EQ(devices[i].index, int(i));
    EXPECT_GT(devices[i].compute_units, 0u);
    EXPECT_GT(devices[i].local_mem_bytes, 0u);
    EXPECT_GT(devices[i].global_mem_bytes, devices[i].local_mem_bytes);
    EXPECT_FALSE(devices[i].device_name.empty());
  }
}

TEST(OpenClContext, BuildsAProgramOnceAndArgumentsNeverRebuild) {
  auto ctx = open_first_device();
  ASSERT_TRUE(ctx);
  std::string error;
  const std::array<std::string_view, 1> sources{kScaleSource};
  cl_program program = ctx->program("scale", sources, "-cl-std=CL1.2", &error);
  ASSERT_TRUE(program) << error;
  EXPECT_EQ(ctx->build_count(), 1);
  EXPECT_EQ(ctx->program("scale", sources, "-cl-std=CL1.2", &error), program);
  EXPECT_EQ(ctx->build_count(), 1);
  cl_kernel k = ctx->kernel(program, "scale_add", &error);
  ASSERT_TRUE(k) << error;
  EXPECT_EQ(ctx->kernel(program, "scale_add", &error), k);

  constexpr int n = 1000;
  std::vector<float> x(n), y(n, 1.0f);
  for (int i = 0; i < n; ++i) x[std::size_t(i)] = float(i);
  OpenClBuffer dx = ctx->allocate(n * sizeof(float));
  OpenClBuffer dy = ctx->allocate(n * sizeof(float));
  ctx->write(dx, x.data(), n * sizeof(float));
  ctx->write(dy, y.data(), n * sizeof(float));
  // Three different parameter values: each is a kernel argument, none is a rebuild.
  for (float a : {2.0f, -0.5f, 0.25f}) {
    set_kernel_args(k, dy, dx, a, n);
    ctx->enqueue(k, 1024, 0);
  }
  ctx->read(dy, y.data(), n * sizeof(float));
  for (int i = 0; i < n; ++i) EXPECT_EQ(y[std::size_t(i)], 1.0f + 1.75f * float(i)) << i;
  EXPECT_EQ(ctx->build_count(), 1);
}

TEST(OpenClContext, FailedBuildReturnsTheLog) {
  auto ctx = open_first_device();
  ASSERT_TRUE(ctx);
  const std::array<std::string_view, 1> sources{
      "__kernel void broken(__global float* y) { y[0] = undeclared_name; }"};
  std::string error;
  EXPECT_EQ(ctx->program("broken", sources, "", &error), nullptr);
  EXPECT_NE(error.find("CL_BUILD_PROGRAM_FAILURE"), std::string::npos) << error;
  EXPECT_NE(error.find("undeclared_name"), std::string::npos) << error;
}

TEST(OpenClContext, DeviceFieldRoundTripsHaloAndPadding) {
  auto ctx = open_first_device();
  ASSERT_TRUE(ctx);
  FieldF host({37, 11}, 2), back({37, 11}, 2);
  for (std::size_t i = 0; i < host.raw_size(); ++i) host.raw()[i] = float(i) * 0.37f - 5.0f;
  DeviceField dev = ctx->allocate_like(host);
  EXPECT_EQ(dev.origin, 2 * int(host.stride()) + 2);
  ctx->upload(host, dev);
  ctx->download(dev, back);
  for (std::size_t i = 0; i < host.raw_size(); ++i) ASSERT_EQ(host.raw()[i], back.raw()[i]);
}

TEST(OpenClContext, InvalidDeviceIndexNamesTheRange) {
  std::string error;
  EXPECT_EQ(OpenClContext::open(999, &error), nullptr);
  EXPECT_NE(error.find("--cl-device 999"), std::string::npos) << error;
}

// The Backend interface: a pass bound to an encoder runs on the device; dispatch only
// enqueues, sync waits; tiles reach the encoder unchanged.
struct ScaleJob {
  cl_kernel kernel;
  OpenClBuffer* y;
  OpenClBuffer* x;
  int tiles_seen = 0;
};

void encode_scale(void* user, OpenClContext& ctx, const Pass& pass, std::span<const Tile> tiles) {
  auto& job = *static_cast<ScaleJob*>(user);
  for (const Tile& t : tiles) {
    // One tile = a range of elements [core.min.x, core.max.x); the pass's halo is the factor.
    set_kernel_args(job.kernel, *job.y, *job.x, float(pass.halo), t.core.max.x);
    ctx.enqueue(job.kernel, std::size_t(t.core.max.x), 0);
    ++job.tiles_seen;
  }
}

TEST(OpenClBackend, DispatchesBoundPassesAndSyncs) {
  std::string error;
  auto ctx = OpenClContext::open(0, &error);
  ASSERT_TRUE(ctx) << error;
  const std::array<std::string_view, 1> sources{kScaleSource};
  cl_program program = ctx->program("scale", sources, "", &error);
  ASSERT_TRUE(program) << error;
  ScaleJob job{ctx->kernel(program, "scale_add", &error), nullptr, nullptr};
  constexpr int n = 256;
  OpenClBuffer x = ctx->allocate(n * sizeof(float)), y = ctx->allocate(n * sizeof(float));
  std::vector<float> ones(n, 1.0f), zeros(n, 0.0f), out(n);
  ctx->write(x, ones.data(), n * sizeof(float));
  ctx->write(y, zeros.data(), n * sizeof(float));
  job.x = &x;
  job.y = &y;
  OpenClBackend backend(std::move(ctx));
  EXPECT_STREQ(backend.name(), "opencl");
  EXPECT_GE(backend.workers(), 1);
  backend.bind(3, &encode_scale, &job);
  EXPECT_TRUE(backend.bound(3));
  EXPECT_FALSE(backend.bound(2));
  Pass pass;
  pass.name = "scale";
  pass.kernel_id = 3;
  pass.halo = 2;
  const Tile tiles[] = {Tile{{{0, 0}, {n, 1}}, 0}, Tile{{{0, 0}, {n, 1}}, 0}};
  backend.dispatch(pass, tiles);
  backend.sync();
  backend.context().read(y, out.data(), n * sizeof(float));
  for (float v : out) EXPECT_EQ(v, 4.0f);  // two tiles, each adds 2 * 1
  EXPECT_EQ(job.tiles_seen, 2);
  EXPECT_EQ(backend.dispatched(), 1);
}

TEST(OpenClBackendDeathTest, UnboundPassStopsWithItsName) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_DEATH(
      {
        std::string error;
        OpenClBackend backend(OpenClContext::open(0, &error));
        Pass pass;
        pass.name = "advect:dye";
        pass.kernel_id = 7;
        backend.dispatch(pass, {});
      },
      "pass 'advect:dye' \\(kernel 7\\) has no OpenCL twin");
}

TEST(BackendChoice, ParsesTheFourNames) {
  BackendKind k{};
  for (std::string_view name : {"auto", "serial", "threads", "opencl"}) {
    ASSERT_TRUE(parse_backend_kind(name, k));
    EXPECT_EQ(backend_kind_name(k), name);
  }
  EXPECT_FALSE(parse_backend_kind("cuda", k));
}

TEST(BackendChoice, ExplicitOpenClOnPoclGivesAContext) {
  BackendChoice c = choose_backend(BackendKind::kOpenCl, -1);
  EXPECT_EQ(c.kind, BackendKind::kOpenCl) << c.message;
  EXPECT_TRUE(c.opencl);
  EXPECT_TRUE(c.message.empty());
}

// auto asks the ICD loader only when a registered vendor can be a GPU (not PoCL alone).
TEST(BackendChoice, AutoLooksForAGpuVendorBeforeLoadingTheVendors) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("ardcell_vendors_" + std::to_string(getpid()));
  fs::create_directories(dir);
  const char* saved = std::getenv("OCL_ICD_VENDORS");
  const std::string restore = saved ? saved : "";
  setenv("OCL_ICD_VENDORS", dir.c_str(), 1);
  EXPECT_FALSE(opencl_gpu_vendor_registered()) << "no vendor";
  std::ofstream(dir / "pocl.icd") << "libpocl.so.2.10.0\n";
  EXPECT_FALSE(opencl_gpu_vendor_registered()) << "PoCL alone drives the CPU";
  BackendChoice c = choose_backend(BackendKind::kAuto, -1);
  EXPECT_EQ(c.kind, BackendKind::kThreads);
  EXPECT_TRUE(c.message.empty());
  std::ofstream(dir / "nvidia.icd") << "libnvidia-opencl.so.1\n";
  EXPECT_TRUE(opencl_gpu_vendor_registered());
  if (saved)
    setenv("OCL_ICD_VENDORS", restore.c_str(), 1);
  else
    unsetenv("OCL_ICD_VENDORS");
  fs::remove_all(dir);
}

TEST(BackendChoice, InvalidDeviceFallsBackToThreadsWithOneLine) {
  for (BackendKind k : {BackendKind::kOpenCl, BackendKind::kAuto}) {
    BackendChoice c = choose_backend(k, 999);
    EXPECT_EQ(c.kind, BackendKind::kThreads);
    EXPECT_FALSE(c.opencl);
    EXPECT_NE(c.message.find("--cl-device 999"), std::string::npos) << c.message;
    EXPECT_NE(c.message.find("falling back to the threads back end"), std::string::npos);
    EXPECT_EQ(c.message.find('\n'), std::string::npos) << "one line";
  }
}

TEST(BackendChoice, FailedBuildFallsBackAndKeepsTheLog) {
  const OpenClPrepare prepare = [](OpenClContext& ctx, std::string* error) {
    const std::array<std::string_view, 1> src{"__kernel void k() { nonsense; }"};
    return ctx.program("bad", src, "", error) != nullptr;
  };
  BackendChoice c = choose_backend(BackendKind::kOpenCl, 0, prepare);
  EXPECT_EQ(c.kind, BackendKind::kThreads);
  EXPECT_NE(c.message.find("CL_BUILD_PROGRAM_FAILURE"), std::string::npos) << c.message;
  EXPECT_EQ(c.message.find('\n'), std::string::npos);
  EXPECT_NE(c.detail.find("nonsense"), std::string::npos) << c.detail;
}

TEST(BackendChoice, SerialAndThreadsNeverTouchOpenCl) {
  EXPECT_EQ(choose_backend(BackendKind::kSerial, 999).kind, BackendKind::kSerial);
  EXPECT_EQ(choose_backend(BackendKind::kThreads, 999).message, "");
}

// The ICD loader reads OCL_ICD_VENDORS once per process, so the no-ICD case runs in a child.
TEST(BackendChoiceDeathTest, NoIcdFallsBackToThreadsWithOneLine) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  const std::filesystem::path empty =
      std::filesystem::temp_directory_path() / "ardcell_no_icd_vendors";
  std::filesystem::create_directories(empty);
  EXPECT_EXIT(
      {
        setenv("OCL_ICD_VENDORS", empty.c_str(), 1);
        BackendChoice c = choose_backend(BackendKind::kOpenCl, -1);
        std::cerr << c.message << "\n";
        std::exit(c.kind == BackendKind::kThreads && !c.opencl ? 0 : 1);
      },
      testing::ExitedWithCode(0),
      "ardcell: no OpenCL platform found .*; falling back to the threads back end");
}

}  // namespace
}  // namespace ardcell
