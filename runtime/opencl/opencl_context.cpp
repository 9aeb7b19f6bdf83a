#include "runtime/opencl/opencl_context.h"

#include <CL/cl_ext.h>

#include <stdexcept>
#include <string>

// LeakSanitizer: the OpenCL driver (PoCL and its LLVM) keeps compiler state for the life of the
// process and never frees it. Suppress leaks whose stack passes through the driver only, in any
// sanitizer build that links the OpenCL back end; our own leaks are still reported.
#if defined(__SANITIZE_ADDRESS__)
extern "C" const char* __lsan_default_suppressions() {
  return "leak:libpocl.so\nleak:libLLVM\nleak:libOpenCL.so\nleak:libclang-cpp\n";
}
#endif

namespace ardcell {

std::string opencl_error_name(cl_int code) {
  const char* name = "unknown OpenCL error";
  switch (code) {
#define ARDCELL_CL_ERROR(e) \
  case e:                   \
    name = #e;              \
    break;
    ARDCELL_CL_ERROR(CL_SUCCESS)
    ARDCELL_CL_ERROR(CL_DEVICE_NOT_FOUND)
    ARDCELL_CL_ERROR(CL_DEVICE_NOT_AVAILABLE)
    ARDCELL_CL_ERROR(CL_COMPILER_NOT_AVAILABLE)
    ARDCELL_CL_ERROR(CL_MEM_OBJECT_ALLOCATION_FAILURE)
    ARDCELL_CL_ERROR(CL_OUT_OF_RESOURCES)
    ARDCELL_CL_ERROR(CL_OUT_OF_HOST_MEMORY)
    ARDCELL_CL_ERROR(CL_BUILD_PROGRAM_FAILURE)
    ARDCELL_CL_ERROR(CL_INVALID_VALUE)
    ARDCELL_CL_ERROR(CL_INVALID_DEVICE)
    ARDCELL_CL_ERROR(CL_INVALID_PLATFORM)
    ARDCELL_CL_ERROR(CL_INVALID_CONTEXT)
    ARDCELL_CL_ERROR(CL_INVALID_COMMAND_QUEUE)
    ARDCELL_CL_ERROR(CL_INVALID_MEM_OBJECT)
    ARDCELL_CL_ERROR(CL_INVALID_BINARY)
    ARDCELL_CL_ERROR(CL_INVALID_BUILD_OPTIONS)
    ARDCELL_CL_ERROR(CL_INVALID_PROGRAM)
    ARDCELL_CL_ERROR(CL_INVALID_PROGRAM_EXECUTABLE)
    ARDCELL_CL_ERROR(CL_INVALID_KERNEL_NAME)
    ARDCELL_CL_ERROR(CL_INVALID_KERNEL)
    ARDCELL_CL_ERROR(CL_INVALID_ARG_INDEX)
    ARDCELL_CL_ERROR(CL_INVALID_ARG_VALUE)
    ARDCELL_CL_ERROR(CL_INVALID_ARG_SIZE)
    ARDCELL_CL_ERROR(CL_INVALID_KERNEL_ARGS)
    ARDCELL_CL_ERROR(CL_INVALID_WORK_DIMENSION)
    ARDCELL_CL_ERROR(CL_INVALID_WORK_GROUP_SIZE)
    ARDCELL_CL_ERROR(CL_INVALID_WORK_ITEM_SIZE)
    ARDCELL_CL_ERROR(CL_INVALID_GLOBAL_OFFSET)
    ARDCELL_CL_ERROR(CL_INVALID_EVENT_WAIT_LIST)
    ARDCELL_CL_ERROR(CL_INVALID_OPERATION)
    ARDCELL_CL_ERROR(CL_INVALID_BUFFER_SIZE)
    ARDCELL_CL_ERROR(CL_INVALID_GLOBAL_WORK_SIZE)
    ARDCELL_CL_ERROR(CL_PLATFORM_NOT_FOUND_KHR)
#undef ARDCELL_CL_ERROR
    default:
      break;
  }
  return std::string(name) + " (" + std::to_string(code) + ")";
}

void opencl_check(cl_int code, const char* what) {
  if (code != CL_SUCCESS)
    throw std::runtime_error(std::string("OpenCL: ") + what +
                             " failed: " + opencl_error_name(code));
}

namespace {

std::string platform_string(cl_platform_id p, cl_platform_info what) {
  std::size_t n = 0;
  if (clGetPlatformInfo(p, what, 0, nullptr, &n) != CL_SUCCESS || n == 0) return {};
  std::string s(n, '\0');
  if (clGetPlatformInfo(p, what, n, s.data(), nullptr) != CL_SUCCESS) return {};
  while (!s.empty() && (s.back() == '\0' || s.back() == ' ')) s.pop_back();
  return s;
}

std::string device_string(cl_device_id d, cl_device_info what) {
  std::size_t n = 0;
  if (clGetDeviceInfo(d, what, 0, nullptr, &n) != CL_SUCCESS || n == 0) return {};
  std::string s(n, '\0');
  if (clGetDeviceInfo(d, what, n, s.data(), nullptr) != CL_SUCCESS) return {};
  while (!s.empty() && (s.back() == '\0' || s.back() == ' ')) s.pop_back();
  return s;
}

template <class T>
T device_value(cl_device_id d, cl_device_info what) {
  T v{};
  if (clGetDeviceInfo(d, what, sizeof(T), &v, nullptr) != CL_SUCCESS) return T{};
  return v;
}

std::string type_name(cl_device_type t) {
  if (t & CL_DEVICE_TYPE_GPU) return "gpu";
  if (t & CL_DEVICE_TYPE_CPU) return "cpu";
  if (t & CL_DEVICE_TYPE_ACCELERATOR) return "accelerator";
  return "other";
}

}  // namespace

std::vector<OpenClDeviceInfo> list_opencl_devices(std::string* error) {
  std::vector<OpenClDeviceInfo> out;
  cl_uint num_platforms = 0;
  const cl_int rc = clGetPlatformIDs(0, nullptr, &num_platforms);
  if (rc != CL_SUCCESS || num_platforms == 0) {
    if (error)
      *error = "no OpenCL platform found (" + opencl_error_name(rc) +
               "): install an ICD such as pocl-opencl-icd, or check /etc/OpenCL/vendors and "
               "OCL_ICD_VENDORS";
    return out;
  }
  std::vector<cl_platform_id> platforms(num_platforms);
  opencl_check(clGetPlatformIDs(num_platforms, platforms.data(), nullptr), "clGetPlatformIDs");
  for (cl_uint pi = 0; pi < num_platforms; ++pi) {
    cl_uint num_devices = 0;
    if (clGetDeviceIDs(platforms[pi], CL_DEVICE_TYPE_ALL, 0, nullptr, &num_devices) != CL_SUCCESS ||
        num_devices == 0)
      continue;
    std::vector<cl_device_id> devices(num_devices);
    if (clGetDeviceIDs(platforms[pi], CL_DEVICE_TYPE_ALL, num_devices, devices.data(), nullptr) !=
        CL_SUCCESS)
      continue;
    for (cl_device_id d : devices) {
      OpenClDeviceInfo info;
      info.index = int(out.size());
      info.platform_index = int(pi);
      info.platform = platforms[pi];
      info.device = d;
      info.platform_name = platform_string(platforms[pi], CL_PLATFORM_NAME);
      info.platform_version = platform_string(platforms[pi], CL_PLATFORM_VERSION);
      info.device_name = device_string(d, CL_DEVICE_NAME);
      info.device_version = device_string(d, CL_DEVICE_VERSION);
      info.driver_version = device_string(d, CL_DRIVER_VERSION);
      info.type = type_name(device_value<cl_device_type>(d, CL_DEVICE_TYPE));
      info.compute_units = device_value<cl_uint>(d, CL_DEVICE_MAX_COMPUTE_UNITS);
      info.local_mem_bytes = device_value<cl_ulong>(d, CL_DEVICE_LOCAL_MEM_SIZE);
      info.local_mem_dedicated =
          device_value<cl_device_local_mem_type>(d, CL_DEVICE_LOCAL_MEM_TYPE) == CL_LOCAL;
      info.global_mem_bytes = device_value<cl_ulong>(d, CL_DEVICE_GLOBAL_MEM_SIZE);
      info.max_work_group_size = device_value<std::size_t>(d, CL_DEVICE_MAX_WORK_GROUP_SIZE);
      out.push_back(std::move(info));
    }
  }
  if (out.empty() && error)
    *error = "OpenCL: " + std::to_string(num_platforms) +
             " platform(s) found but no device on any of them";
  return out;
}

OpenClBuffer& OpenClBuffer::operator=(OpenClBuffer&& o) noexcept {
  if (this != &o) {
    if (mem_) clReleaseMemObject(mem_);
    mem_ = o.mem_;
    bytes_ = o.bytes_;
    o.mem_ = nullptr;
  }
  return *this;
}

OpenClBuffer::~OpenClBuffer() {
  if (mem_) clReleaseMemObject(mem_);
}

std::unique_ptr<OpenClContext> OpenClContext::open(int index, std::string* error) {
  std::string why;
  std::vector<OpenClDeviceInfo> devices = list_opencl_devices(&why);
  if (devices.empty()) {
    if (error) *error = why;
    return nullptr;
  }
  const OpenClDeviceInfo* chosen = nullptr;
  if (index < 0) {
    for (const OpenClDeviceInfo& d : devices)
      if (d.type == "gpu") {
        chosen = &d;
        break;
      }
    if (!chosen) chosen = &devices.front();
  } else if (index < int(devices.size())) {
    chosen = &devices[std::size_t(index)];
  } else {
    if (error)
      *error = "OpenCL: --cl-device " + std::to_string(index) + " does not exist (expected 0.." +
               std::to_string(devices.size() - 1) + "; see `ardcell devices`)";
    return nullptr;
  }
  std::unique_ptr<OpenClContext> ctx(new OpenClContext());
  ctx->info_ = *chosen;
  cl_int rc = CL_SUCCESS;
  const cl_context_properties props[] = {
      CL_CONTEXT_PLATFORM, reinterpret_cast<cl_context_properties>(chosen->platform), 0};
  ctx->context_ = clCreateContext(props, 1, &chosen->device, nullptr, nullptr, &rc);
  if (rc != CL_SUCCESS || !ctx->context_) {
    if (error)
      *error = "OpenCL: cannot create a context on device " + std::to_string(chosen->index) + " (" +
               chosen->device_name + "): " + opencl_error_name(rc);
    return nullptr;
  }
  ctx->queue_ = clCreateCommandQueue(ctx->context_, chosen->device, 0, &rc);
  if (rc != CL_SUCCESS || !ctx->queue_) {
    if (error)
      *error = "OpenCL: cannot create a command queue on device " + std::to_string(chosen->index) +
               " (" + chosen->device_name + "): " + opencl_error_name(rc);
    return nullptr;
  }
  return ctx;
}

OpenClContext::~OpenClContext() {
  if (queue_) clFinish(queue_);
  for (CachedKernel& k : kernels_) clReleaseKernel(k.kernel);
  for (CachedProgram& p : programs_) clReleaseProgram(p.program);
  if (queue_) clReleaseCommandQueue(queue_);
  if (context_) clReleaseContext(context_);
}

cl_program OpenClContext::program(std::string_view key, std::span<const std::string_view> sources,
                                  std::string_view options, std::string* error) {
  for (const CachedProgram& p : programs_)
    if (p.key == key) return p.program;
  std::vector<const char*> texts;
  std::vector<std::size_t> lengths;
  for (std::string_view s : sources) {
    texts.push_back(s.data());
    lengths.push_back(s.size());
  }
  cl_int rc = CL_SUCCESS;
  cl_program program =
      clCreateProgramWithSource(context_, cl_uint(texts.size()), texts.data(), lengths.data(), &rc);
  if (rc != CL_SUCCESS) {
    if (error)
      *error = "OpenCL: cannot create program '" + std::string(key) + "': " + opencl_error_name(rc);
    return nullptr;
  }
  const std::string opts(options);
  ++build_count_;
  rc = clBuildProgram(program, 1, &info_.device, opts.c_str(), nullptr, nullptr);
  if (rc != CL_SUCCESS) {
    std::size_t n = 0;
    clGetProgramBuildInfo(program, info_.device, CL_PROGRAM_BUILD_LOG, 0, nullptr, &n);
    std::string log(n, '\0');
    if (n)
      clGetProgramBuildInfo(program, info_.device, CL_PROGRAM_BUILD_LOG, n, log.data(), nullptr);
    while (!log.empty() && (log.back() == '\0' || log.back() == '\n')) log.pop_back();
    if (error)
      *error = "OpenCL: building program '" + std::string(key) + "' for " + info_.device_name +
               " failed: " + opencl_error_name(rc) + "\n" + log;
    clReleaseProgram(program);
    return nullptr;
  }
  programs_.push_back({std::string(key), program});
  return program;
}

cl_kernel OpenClContext::kernel(cl_program program, std::string_view name, std::string* error) {
  for (const CachedKernel& k : kernels_)
    if (k.program == program && k.name == name) return k.kernel;
  cl_int rc = CL_SUCCESS;
  const std::string n(name);
  cl_kernel k = clCreateKernel(program, n.c_str(), &rc);
  if (rc != CL_SUCCESS) {
    if (error) *error = "OpenCL: no kernel '" + n + "': " + opencl_error_name(rc);
    return nullptr;
  }
  kernels_.push_back({program, n, k});
  return k;
}

OpenClBuffer OpenClContext::allocate(std::size_t bytes) {
  cl_int rc = CL_SUCCESS;
  cl_mem m = clCreateBuffer(context_, CL_MEM_READ_WRITE, bytes ? bytes : 4, nullptr, &rc);
  opencl_check(rc, "clCreateBuffer");
  return OpenClBuffer(m, bytes);
}

DeviceField OpenClContext::allocate_like(const FieldF& host) {
  DeviceField f;
  f.buffer = allocate(host.raw_size() * sizeof(float));
  f.size = host.size();
  f.halo = host.halo();
  f.stride = int(host.stride());
  f.origin = f.halo * f.stride + f.halo;
  return f;
}

void OpenClContext::upload(const FieldF& host, DeviceField& dev) {
  ARDCELL_CHECK(
      host.size() == dev.size && host.halo() == dev.halo && int(host.stride()) == dev.stride,
      "upload: host and device field layouts differ");
  write(dev.buffer, host.raw(), host.raw_size() * sizeof(float));
}

void OpenClContext::download(const DeviceField& dev, FieldF& host) {
  ARDCELL_CHECK(
      host.size() == dev.size && host.halo() == dev.halo && int(host.stride()) == dev.stride,
      "download: host and device field layouts differ");
  read(dev.buffer, host.raw(), host.raw_size() * sizeof(float));
}

void OpenClContext::write(const OpenClBuffer& buffer, const void* data, std::size_t bytes) {
  ARDCELL_CHECK(bytes <= buffer.bytes(), "write past the end of a device buffer");
  if (bytes == 0) return;
  opencl_check(
      clEnqueueWriteBuffer(queue_, buffer.get(), CL_TRUE, 0, bytes, data, 0, nullptr, nullptr),
      "clEnqueueWriteBuffer");
}

void OpenClContext::read(const OpenClBuffer& buffer, void* data, std::size_t bytes) {
  ARDCELL_CHECK(bytes <= buffer.bytes(), "read past the end of a device buffer");
  if (bytes == 0) return;
  opencl_check(
      clEnqueueReadBuffer(queue_, buffer.get(), CL_TRUE, 0, bytes, data, 0, nullptr, nullptr),
      "clEnqueueReadBuffer");
}

void OpenClContext::enqueue(cl_kernel kernel, std::size_t global, std::size_t local) {
  opencl_check(clEnqueueNDRangeKernel(queue_, kernel, 1, nullptr, &global, local ? &local : nullptr,
                                      0, nullptr, nullptr),
               "clEnqueueNDRangeKernel");
}

void OpenClContext::enqueue_2d(cl_kernel kernel, const std::size_t global[2],
                               const std::size_t local[2]) {
  opencl_check(
      clEnqueueNDRangeKernel(queue_, kernel, 2, nullptr, global, local, 0, nullptr, nullptr),
      "clEnqueueNDRangeKernel");
}

void OpenClContext::finish() { opencl_check(clFinish(queue_), "clFinish"); }

}  // namespace ardcell
