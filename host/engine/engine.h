#pragma once
// Engine: runs one scene. Owns the simulation state, the solvers, the back end they run on and
// the scene's FramePlan (host/engine/frame_plan.h), built once from a SceneConfig; step() runs the
// plan (one frame) and does no heap allocation once the first frame has run.
//
// The plan holds the scene's steps: the Table 1 scenes' fused tile passes (Table1Plan), or the
// stages of the fluid (FluidStep) and then of the RD (RdStepper), which run as the ops of the
// engine's Device (host/engine/device.h): on the CPU, per-cell kernels, solver sweeps and
// reductions in bands of rows (runtime/row_executor.h), so `serial` and `threads` with any
// number of workers give the same bits (tests/host/engine/engine_backend_parity_test.cpp).
#include <memory>
#include <span>
#include <string>
#include <string_view>

#include "host/config/scene_config.h"
#include "host/config/sim_state.h"
#include "host/config/status.h"
#include "host/engine/frame_plan.h"

namespace ardcell {

struct RdStepStats;
class FluidStep;
class Backend;
class Device;
class RowExecutor;
class Table1Plan;

class OpenClContext;

// Where the engine runs: the serial reference, the threads back end (workers 0: one per
// hardware thread), or an OpenCL device (`opencl`: a context the caller keeps open for longer
// than the engine, so that switching scenes builds no program again; ops it cannot run use the
// threads back end).
struct EngineOptions {
  enum class Backend : uint8_t { kSerial, kThreads, kOpenCl };
  Backend backend = Backend::kThreads;
  int workers = 0;
  OpenClContext* opencl = nullptr;
  // Pins the threads back end for the engine's life: the calling thread (worker 0) to core 0,
  // worker w to core w. For a process that runs nothing else (`ardcell run`): unpinned, the
  // scheduler's wake-affine placement puts a woken worker on the core of the thread that woke
  // it, so a short run starts with both on one core (seed001: 4.3 ms for the first 20 frames
  // against 1.8 pinned). Off by default: the live display and a kiosk's other processes share
  // the cores, and a pinned thread cannot leave one.
  bool pin_workers = false;
  // Scenes of tile passes (fluid.scene table1, host/engine/table1_plan.h): the schedule,
  // the local store per worker and the residency. The serial back end runs the serial schedule.
  // With plan.block and plan.halo the engine runs one block of a decomposed grid (its state's
  // fields cover the block; runtime/block_layout.h), on the CPU, for the scenes
  // block_support() accepts; it refuses the others.
  PlanOptions plan = {};
};

// How a scene runs as blocks of a decomposed grid: `problem` is one line saying why it cannot
// ("" when it can), `halo` the width its blocks' halos exchange (HaloExchange, HaloChannel),
// and the axes along which its grid wraps (BlockLayout::split's periodic axes). Blocks run every
// scene: the scenes of tile passes (table1: their passes exchange, host/engine/frame_plan.h),
// and the scenes of stages, whose ops exchange a block's halos themselves or gather the grid
// (host/engine/rd_step.h; a fluid's stages run on the gathered grid, fluid_step.h).
struct BlockSupport {
  std::string problem;
  int halo = 1;
  bool periodic_x = false, periodic_y = false;
  // Whether its blocks run ops on the gathered grid (rd_block_gathers): every block then computes
  // those over the whole grid, so the blocks are for one process's bits, not for speed.
  bool gathers = false;
};
BlockSupport block_support(const SceneConfig& scene);

class Engine {
 public:
  explicit Engine(const SceneConfig& config, const EngineOptions& options = {});
  ~Engine();
  Engine(const Engine&) = delete;
  Engine& operator=(const Engine&) = delete;

  // Back to the scene's initial conditions (time 0, step 0).
  void reset();
  // Advances one frame of config().dt. On a device that queues its work (OpenCL) it may return
  // before the frame is done: finish() waits (state() does too).
  void step();
  void finish();
  // The same frame without the plan's rd stages (fluid, time and step count only): for a caller
  // that advances A and B itself, as the live display does on a coarser RD grid. A plan whose
  // RD rides in its fluid passes (table1) runs all of them.
  void step_without_rd();

  // Applies the non-structural parameters of `next` from the next frame on, with no reset and
  // no heap allocation: dt, fluid viscosity, lid / inflow speed, dye diffusion, emitters (same
  // count), solver iterations and tolerances, RD reaction parameters (F, k, ...), diffusion
  // rates, anisotropy, RD dt / cell size / steps per frame, initial pattern (used by the next
  // reset), frame count and output. Structural changes (grid size or width, fluid scene, walls,
  // obstacle, solver kinds, RD on/off, model, scheme, boundary, react/diffuse, reaction table)
  // are refused: nothing changes and the message names the first such key and says to rebuild.
  // An invalid RD parameter is refused the same way. (A reaction table, when on, is rebuilt on
  // a change of reaction parameters or dt: the one case that allocates.)
  Status update_parameters(const SceneConfig& next);

  // The state on the host. On a device that keeps its own copies (OpenCL) the fields are
  // downloaded first; the non-const one also takes whatever the caller writes into them to
  // the device before the next frame (painting, a loaded state), and restarts the RD's
  // multistep history (rd.scheme sbdf2: its next step is SBDF1; RdStepper::restart): read
  // through the const one.
  SimState& state();
  const SimState& state() const;
  // The same for the named fields only (SimState::for_each_field names: "u", "v", "p", "dye",
  // "A", "B", "theta0"); the others may be stale on such a device, and sizes are always right.
  // For a caller that looks at a few fields each frame, as the live display draws one.
  SimState& state(std::span<const std::string_view> fields);
  const SimState& state(std::span<const std::string_view> fields) const;
  const SceneConfig& config() const { return config_; }
  // "serial", "threads" or "opencl", and its number of workers (compute units for OpenCL).
  const char* backend_name() const;
  int workers() const;
  // What the engine's stages run on (for a caller that steps more on the same workers, as the
  // live display's coarse RD grids do): the Device and its CPU executor.
  Device& device() { return *device_; }
  const Device& device() const { return *device_; }
  RowExecutor& executor() { return *executor_; }
  // What the last RD step's solves did (iterations, residuals); nullptr when the scene has no RD.
  const RdStepStats* rd_stats() const;
  // The fluid solver (its masks, the physical pressure for probes); nullptr without a fluid.
  FluidStep* fluid_step();
  // The scene's frame: its steps and their timings (FramePlan::print_stats).
  FramePlan& plan() { return *plan_; }
  const FramePlan& plan() const { return *plan_; }
  // The Table 1 scenes' passes (fluid.scene table1): the schedule, the local store; nullptr for
  // the other scenes.
  Table1Plan* table1_plan();

 private:
  struct Solvers;  // the fluid and RD solvers and their scratch (host/engine/engine.cpp)
  void run_plan(bool with_rd);
  SceneConfig config_;
  std::unique_ptr<Backend> backend_;
  std::unique_ptr<RowExecutor> executor_;
  std::unique_ptr<Device> device_;
  SimState state_;
  std::unique_ptr<FramePlan> plan_;
  // Where the plan's tile passes run: backend_, a serial back end of the plan's own (the serial
  // schedule on a threads engine), or null: whole-field on the device (OpenCL).
  std::unique_ptr<Backend> plan_serial_backend_;
  Backend* plan_backend_ = nullptr;
  std::unique_ptr<Solvers> solvers_;
};

}  // namespace ardcell
