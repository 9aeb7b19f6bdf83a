#pragma once
// `ardcell live --backend opencl`: a reaction-diffusion-only preset runs on an OpenCL device
// (host/engine/opencl_rd_engine.h) under the live loop.
//  - step() enqueues the frame and downloads only the chemical the preset shows (A or B; both
//    when it shows another field).
//  - apply(): OpenClRdEngine::update_parameters (kernel arguments; no program is built). The
//    adaptive quality's sweeps reach the device this way; the RD resolution does not adapt on
//    the device (lowest_rd_scale() is 1).
//  - paint(): the live Painter (paint_live_samples, as EngineSimulation) on the host mirror:
//    A and B come down first, A, B and theta0 go up after (orient strokes seed dabs of
//    chemicals too); orient strokes without deposits upload theta0 only. Strokes on layers the
//    device does not simulate (push, obstacle) change nothing.
//  - A preset switch builds a new OpenClRdEngine on the same OpenClKernels: the context and its
//    programs are built once (OpenClContext::build_count() stays the same). The loop builds the
//    next simulation on its worker thread while the current one runs: building only creates
//    buffers and writes them (thread-safe OpenCL calls); stepping, painting and parameter
//    changes of the simulations of one OpenClLiveSimulations (kernel arguments on the shared
//    kernels) are serialised by its mutex.
//  - A preset the device cannot run (OpenClRdEngine::device_problem: a fluid, ICCG / multigrid,
//    stopping on a residual, ...) runs on the CPU EngineSimulation instead, with ONE line naming
//    why in the log: the kiosk keeps running.
#if defined(ARDCELL_WITH_OPENCL)
#include <cstdio>
#include <memory>
#include <mutex>
#include <string>

#include "host/live/live_loop.h"
#include "kernels/cl/opencl_kernels.h"

namespace ardcell {

// Makes the live simulations of one OpenCL device; must outlive every simulation it made (and
// so the LiveLoop running them).
class OpenClLiveSimulations {
 public:
  // Borrows `cl` (tests share one device between suites).
  OpenClLiveSimulations(OpenClKernels& cl, std::FILE* log);
  // Owns the context and its kernels.
  OpenClLiveSimulations(std::unique_ptr<OpenClContext> ctx, std::unique_ptr<OpenClKernels> cl,
                        std::FILE* log);
  ~OpenClLiveSimulations();
  OpenClLiveSimulations(const OpenClLiveSimulations&) = delete;
  OpenClLiveSimulations& operator=(const OpenClLiveSimulations&) = delete;

  // The preset on the device, or on the CPU (EngineSimulation) with the fallback line logged.
  // Throws what the engines throw for an invalid preset (the loop reports it).
  std::unique_ptr<LiveSimulation> make(const Preset& preset);
  // make() as the loop's factory (this object must outlive the loop).
  SimulationFactory factory();

  OpenClKernels& kernels() { return cl_; }
  const std::string& device_name() const { return device_name_; }
  // Presets sent to the CPU, and the last line saying why ("" when none).
  int64_t cpu_fallbacks() const;
  std::string last_fallback() const;

 private:
  class Simulation;
  std::unique_ptr<OpenClContext> ctx_;
  std::unique_ptr<OpenClKernels> owned_;
  OpenClKernels& cl_;
  std::FILE* log_;
  std::string device_name_;
  std::mutex device_mutex_;  // one device user at a time (loop thread, preset builder)
  mutable std::mutex fallback_mutex_;
  int64_t fallbacks_ = 0;
  std::string last_fallback_;
};

}  // namespace ardcell
#endif
