#pragma once
// Which back end runs the frame: `--backend opencl|threads|serial|auto` and `--cl-device N`.
// auto (the default) takes an OpenCL GPU when there is one (or the device --cl-device names),
// else threads. When OpenCL was asked for (opencl, or auto with --cl-device) and cannot be had -
// no platform, no such device, a failed context or program build - the choice falls back to
// threads and `message` holds ONE line saying why; the caller prints it.
// Asking the ICD loader for its devices loads every vendor's library (PoCL brings LLVM: a
// quarter of a second), so auto first looks at the registered vendors and asks only when one of
// them can be a GPU (any but PoCL, whose Debian build drives the CPU only).
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <string>
#include <string_view>

#if defined(ARDCELL_WITH_OPENCL)
#include "runtime/opencl/opencl_context.h"
#endif

namespace ardcell {

enum class BackendKind : uint8_t { kAuto, kSerial, kThreads, kOpenCl };

inline bool parse_backend_kind(std::string_view name, BackendKind& out) {
  if (name == "auto")
    out = BackendKind::kAuto;
  else if (name == "serial")
    out = BackendKind::kSerial;
  else if (name == "threads")
    out = BackendKind::kThreads;
  else if (name == "opencl")
    out = BackendKind::kOpenCl;
  else
    return false;
  return true;
}

inline std::string_view backend_kind_name(BackendKind kind) {
  switch (kind) {
    case BackendKind::kAuto:
      return "auto";
    case BackendKind::kSerial:
      return "serial";
    case BackendKind::kThreads:
      return "threads";
    case BackendKind::kOpenCl:
      return "opencl";
  }
  return "auto";
}

#if !defined(ARDCELL_WITH_OPENCL)
class OpenClContext {};
#endif

struct BackendChoice {
  BackendKind kind = BackendKind::kThreads;  // never kAuto once chosen
  std::unique_ptr<OpenClContext> opencl;     // set when kind == kOpenCl
  std::string message;                       // one line when a fallback happened, else empty
  std::string detail;                        // a failed build's log (print after message)
};

// Builds what an OpenCL back end needs on a fresh context (its programs); false + *error on
// failure (the error may span lines: the first is the summary, the rest the build log).
using OpenClPrepare = std::function<bool(OpenClContext&, std::string* error)>;

// False when no registered OpenCL vendor can offer a GPU: the ICD loader's vendor files
// (/etc/OpenCL/vendors/*.icd, or OCL_ICD_VENDORS when set) name PoCL's library only, or none.
inline bool opencl_gpu_vendor_registered() {
  namespace fs = std::filesystem;
  const char* dir = std::getenv("OCL_ICD_VENDORS");
  std::error_code ec;
  const fs::path vendors = dir ? fs::path(dir) : fs::path("/etc/OpenCL/vendors");
  if (dir && !fs::is_directory(vendors, ec)) return true;  // one vendor named directly
  for (const fs::directory_entry& e : fs::directory_iterator(vendors, ec)) {
    if (e.path().extension() != ".icd") continue;
    std::ifstream in(e.path());
    std::string library;
    std::getline(in, library);
    if (library.find("libpocl") == std::string::npos) return true;
  }
  return false;
}

// cl_device < 0: not given. `prepare` may be empty.
inline BackendChoice choose_backend(BackendKind requested, int cl_device,
                                    const OpenClPrepare& prepare = {}) {
  BackendChoice choice;
  if (requested == BackendKind::kSerial || requested == BackendKind::kThreads) {
    choice.kind = requested;
    return choice;
  }
  choice.kind = BackendKind::kThreads;
#if defined(ARDCELL_WITH_OPENCL)
  std::string why;
  if (requested == BackendKind::kAuto && cl_device < 0) {
    // Without a GPU, OpenCL on the CPU (PoCL) brings nothing the threads back end lacks.
    if (!opencl_gpu_vendor_registered()) return choice;
    std::vector<OpenClDeviceInfo> devices = list_opencl_devices(&why);
    bool has_gpu = false;
    for (const OpenClDeviceInfo& d : devices) has_gpu = has_gpu || d.type == "gpu";
    if (!has_gpu) return choice;
  }
  std::unique_ptr<OpenClContext> ctx = OpenClContext::open(cl_device, &why);
  if (ctx && prepare && !prepare(*ctx, &why)) ctx.reset();
  if (!ctx) {
    // The first line only: a build log goes to the caller through OpenClPrepare's error.
    const std::size_t eol = why.find('\n');
    choice.message = "ardcell: " + why.substr(0, eol) + "; falling back to the threads back end";
    if (eol != std::string::npos) choice.detail = why.substr(eol + 1);
    return choice;
  }
  choice.kind = BackendKind::kOpenCl;
  choice.opencl = std::move(ctx);
#else
  (void)prepare;
  if (requested == BackendKind::kOpenCl || cl_device >= 0)
    choice.message =
        "ardcell: this build has no OpenCL (ARDCELL_WITH_OPENCL=OFF); falling back to the "
        "threads back end";
#endif
  return choice;
}

}  // namespace ardcell
