#include "drivers/cli_backend.h"

#if defined(ARDCELL_WITH_OPENCL)
#include "kernels/cl/opencl_kernels.h"
#endif

namespace ardcell {

BackendChoice choose_engine_backend(BackendKind backend, int cl_device, EngineOptions& options,
                                    CliContext& ctx) {
  BackendChoice choice;
  if (backend == BackendKind::kSerial) options.backend = EngineOptions::Backend::kSerial;
  if (backend != BackendKind::kOpenCl && backend != BackendKind::kAuto) return choice;
#if defined(ARDCELL_WITH_OPENCL)
  choice = choose_backend(backend, cl_device, &OpenClKernels::prepare);
#else
  choice = choose_backend(backend, cl_device);
#endif
  if (!choice.message.empty()) std::fprintf(ctx.err, "%s\n", choice.message.c_str());
  if (!choice.detail.empty()) std::fprintf(ctx.err, "%s\n", choice.detail.c_str());
  if (choice.kind == BackendKind::kOpenCl) {
    options.backend = EngineOptions::Backend::kOpenCl;
    options.opencl = choice.opencl.get();
  }
  return choice;
}

}  // namespace ardcell
