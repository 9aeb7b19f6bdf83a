#pragma once
// OpenCL plumbing for the OpenCL back end: device enumeration, one context and in-order queue
// per device, programs built once from embedded sources (build log on failure, a build counter
// for tests), device buffers that live across frames, and kernel arguments set by value (so a
// parameter change never rebuilds a program). OpenCL 1.2 API only: PoCL in CI, any ICD on a GPU.
//
// Device numbering: `--cl-device N` counts devices over all platforms in the loader's platform
// order, 0-based (the order `ardcell devices` prints).
#include <CL/cl.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "runtime/field.h"

namespace ardcell {

struct OpenClDeviceInfo {
  int index = -1;           // flat index over all platforms (--cl-device)
  int platform_index = -1;  // index of its platform
  std::string platform_name;
  std::string platform_version;
  std::string device_name;
  std::string device_version;
  std::string driver_version;
  std::string type;  // "gpu", "cpu", "accelerator", "other"
  unsigned compute_units = 0;
  uint64_t local_mem_bytes = 0;
  bool local_mem_dedicated = false;  // CL_LOCAL: on-chip (a GPU); CL_GLOBAL: emulated (PoCL)
  uint64_t global_mem_bytes = 0;
  std::size_t max_work_group_size = 0;
  cl_platform_id platform = nullptr;
  cl_device_id device = nullptr;
};

// The symbolic name of an OpenCL error code, e.g. "CL_BUILD_PROGRAM_FAILURE (-11)".
std::string opencl_error_name(cl_int code);

// Every device of every platform. When there is none, returns an empty list and sets *error to
// one line saying why (no ICD loader vendor file, no platform, no device).
std::vector<OpenClDeviceInfo> list_opencl_devices(std::string* error);

// A device buffer (cl_mem) owned by RAII.
class OpenClBuffer {
 public:
  OpenClBuffer() = default;
  OpenClBuffer(cl_mem mem, std::size_t bytes) : mem_(mem), bytes_(bytes) {}
  OpenClBuffer(OpenClBuffer&& o) noexcept : mem_(o.mem_), bytes_(o.bytes_) { o.mem_ = nullptr; }
  OpenClBuffer& operator=(OpenClBuffer&& o) noexcept;
  OpenClBuffer(const OpenClBuffer&) = delete;
  OpenClBuffer& operator=(const OpenClBuffer&) = delete;
  ~OpenClBuffer();

  cl_mem get() const { return mem_; }
  std::size_t bytes() const { return bytes_; }
  explicit operator bool() const { return mem_ != nullptr; }

 private:
  cl_mem mem_ = nullptr;
  std::size_t bytes_ = 0;
};

// A Field<float> mirrored on the device with the host layout (same stride, halo and padding),
// so upload and download are one contiguous copy and kernels index it like the host does:
// cell (x, y) is at data[origin + y * stride + x] with origin = halo * stride + halo.
struct DeviceField {
  OpenClBuffer buffer;
  Int2 size{};
  int halo = 0;
  int stride = 0;
  int origin = 0;

  Box2 interior() const { return box_of_size(size); }
  Box2 with_halo() const { return interior().grown(halo); }
};

class OpenClContext {
 public:
  // Opens device `index` of list_opencl_devices(); index < 0 picks the first GPU, else the
  // first device. Returns null and sets *error to one line when that is not possible.
  static std::unique_ptr<OpenClContext> open(int index, std::string* error);
  ~OpenClContext();
  OpenClContext(const OpenClContext&) = delete;
  OpenClContext& operator=(const OpenClContext&) = delete;

  const OpenClDeviceInfo& device() const { return info_; }
  cl_context context() const { return context_; }
  cl_command_queue queue() const { return queue_; }

  // Builds the program named `key` from `sources` (concatenated in order) the first time it is
  // asked for; later calls with the same key return the built program and build nothing. On a
  // failed build returns null and sets *error to the error line followed by the build log.
  cl_program program(std::string_view key, std::span<const std::string_view> sources,
                     std::string_view options, std::string* error);
  // How many times clBuildProgram ran on this context (tests assert it stays constant).
  int build_count() const { return build_count_; }

  // A kernel of a built program, created once and cached. Null (and *error) when absent.
  cl_kernel kernel(cl_program program, std::string_view name, std::string* error);

  // A read-write device buffer; throws std::runtime_error with one line on failure.
  OpenClBuffer allocate(std::size_t bytes);
  DeviceField allocate_like(const FieldF& host);
  // Blocking copies of the whole allocation (halo and padding included).
  void upload(const FieldF& host, DeviceField& dev);
  void download(const DeviceField& dev, FieldF& host);
  void write(const OpenClBuffer& buffer, const void* data, std::size_t bytes);
  void read(const OpenClBuffer& buffer, void* data, std::size_t bytes);

  // Enqueues `kernel` over `global` work-items in work-groups of `local` (1D), non-blocking.
  void enqueue(cl_kernel kernel, std::size_t global, std::size_t local);
  void enqueue_2d(cl_kernel kernel, const std::size_t global[2], const std::size_t local[2]);
  void finish();

 private:
  OpenClContext() = default;
  struct CachedProgram {
    std::string key;
    cl_program program;
  };
  struct CachedKernel {
    cl_program program;
    std::string name;
    cl_kernel kernel;
  };
  OpenClDeviceInfo info_;
  cl_context context_ = nullptr;
  cl_command_queue queue_ = nullptr;
  std::vector<CachedProgram> programs_;
  std::vector<CachedKernel> kernels_;
  int build_count_ = 0;
};

// Throws std::runtime_error("<what>: <error name>") when code is not CL_SUCCESS.
void opencl_check(cl_int code, const char* what);

// Kernel arguments by value: set_kernel_args(k, buf.get(), 3, 0.5f, ...). Device fields pass as
// (buffer, stride, origin).
namespace detail {
inline void set_one_arg(cl_kernel k, cl_uint& i, const DeviceField& f) {
  cl_mem m = f.buffer.get();
  opencl_check(clSetKernelArg(k, i++, sizeof(cl_mem), &m), "clSetKernelArg(field)");
  opencl_check(clSetKernelArg(k, i++, sizeof(int), &f.stride), "clSetKernelArg(stride)");
  opencl_check(clSetKernelArg(k, i++, sizeof(int), &f.origin), "clSetKernelArg(origin)");
}
inline void set_one_arg(cl_kernel k, cl_uint& i, const OpenClBuffer& b) {
  cl_mem m = b.get();
  opencl_check(clSetKernelArg(k, i++, sizeof(cl_mem), &m), "clSetKernelArg(buffer)");
}
// OpenCL vector types (cl_float4, cl_int4, cl_int2) by value.
template <class T>
requires(std::is_same_v<T, cl_float4> || std::is_same_v<T, cl_int4> ||
         std::is_same_v<T, cl_int2>) void set_one_arg(cl_kernel k, cl_uint& i, const T& v) {
  opencl_check(clSetKernelArg(k, i++, sizeof(T), &v), "clSetKernelArg(vector)");
}
// A plain struct by value, for an OpenCL C struct argument of the same layout (4-byte members
// only, so no padding differs between the host and device compilers).
template <class T>
struct ByValue {
  const T& value;
};
template <class T>
void set_one_arg(cl_kernel k, cl_uint& i, ByValue<T> v) {
  static_assert(std::is_trivially_copyable_v<T> && alignof(T) == 4);
  opencl_check(clSetKernelArg(k, i++, sizeof(T), &v.value), "clSetKernelArg(struct)");
}
// __local scratch of n bytes.
struct LocalBytes {
  std::size_t bytes;
};
inline void set_one_arg(cl_kernel k, cl_uint& i, LocalBytes l) {
  opencl_check(clSetKernelArg(k, i++, l.bytes, nullptr), "clSetKernelArg(local)");
}
template <class T>
requires std::is_arithmetic_v<T>
void set_one_arg(cl_kernel k, cl_uint& i, T v) {
  opencl_check(clSetKernelArg(k, i++, sizeof(T), &v), "clSetKernelArg(value)");
}
}  // namespace detail

using detail::ByValue;
using detail::LocalBytes;

template <class... Args>
void set_kernel_args(cl_kernel kernel, const Args&... args) {
  cl_uint i = 0;
  (detail::set_one_arg(kernel, i, args), ...);
}

}  // namespace ardcell
