#pragma once
// The one place `run`, `live` and `texture` turn --backend / --cl-device into the engine's back
// end: serial, threads, or an OpenCL device when asked (`auto`: a GPU when one is registered,
// else threads), printing the fallback line (and a failed build's log) on ctx.err.
#include "drivers/cli.h"
#include "host/engine/engine.h"
#include "runtime/opencl/backend_choice.h"

namespace ardcell {

// Sets options.backend (and options.opencl) for `backend`. The returned choice owns the OpenCL
// context: keep it alive for as long as any engine built with `options`.
BackendChoice choose_engine_backend(BackendKind backend, int cl_device, EngineOptions& options,
                                    CliContext& ctx);

}  // namespace ardcell
