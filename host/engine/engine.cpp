#include "host/engine/engine.h"

#include "host/engine/device.h"
#include "host/engine/fluid_step.h"
#include "host/engine/frame_plan.h"
#include "host/engine/rd_step.h"
#include "host/engine/table1_plan.h"
#include "runtime/row_executor.h"
#include "runtime/thread/thread_backend.h"
#if defined(ARDCELL_WITH_OPENCL)
#include "host/engine/opencl_device.h"
#endif

#include <algorithm>
#include <stdexcept>
#include <string>

namespace ardcell {

// The solvers of one scene, built once in the constructor.
struct Engine::Solvers {
  std::unique_ptr<FluidStep> fluid;  // when the scene has a fluid
  std::unique_ptr<RdStepper> rd;     // when config.rd.enabled (host/engine/rd_step.h)
  // Instead of both, for a scene of tile passes (fluid.scene table1).
  std::unique_ptr<Table1Plan> table1;
};

namespace {

// A scene of stages on a block: the device computes the block and exchanges its halos (a scene
// of tile passes exchanges in its passes: its device keeps the whole grid).
DeviceBlock device_block(const SceneConfig& config, const EngineOptions& options) {
  if (options.plan.block.empty() || config.fluid.kind == FluidSceneKind::kTable1) return {};
  if (std::string why = block_support(config).problem; !why.empty())
    throw std::invalid_argument("blocks: " + why);
  if (options.backend == EngineOptions::Backend::kOpenCl)
    throw std::invalid_argument(
        "blocks: a block of a decomposed grid runs on the serial or threads back end (expected "
        "--backend serial or threads)");
  ARDCELL_CHECK(options.plan.halo != nullptr, "Engine: a block needs its halo channel");
  // A layout cut for another scene (a split wall switching presets) must wrap as this one does.
  const BlockSupport support = block_support(config);
  if (support.periodic_x != options.plan.halo->periodic_x() ||
      support.periodic_y != options.plan.halo->periodic_y())
    throw std::invalid_argument(
        std::string("blocks: rd.boundary: these blocks were cut for a grid that ") +
        (options.plan.halo->periodic_x() ? "wraps" : "has walls") + " (expected a scene with " +
        (options.plan.halo->periodic_x() ? "rd.boundary periodic" : "walls") + ")");
  return {config.size, options.plan.block, options.plan.halo};
}

std::unique_ptr<Device> make_engine_device(const EngineOptions& options, RowExecutor& cpu,
                                           const DeviceBlock& block) {
  if (options.backend == EngineOptions::Backend::kOpenCl) {
#if defined(ARDCELL_WITH_OPENCL)
    ARDCELL_CHECK(options.opencl != nullptr, "Engine: the OpenCL back end needs a context");
    return std::make_unique<OpenClDevice>(*options.opencl, cpu);
#else
    ARDCELL_CHECK(false, "Engine: this build has no OpenCL");
#endif
  }
  return std::make_unique<CpuDevice>(cpu, block);
}

std::unique_ptr<Backend> make_engine_backend(const EngineOptions& options) {
  if (options.backend == EngineOptions::Backend::kSerial) return std::make_unique<SerialBackend>();
  ThreadBackendOptions t;
  t.workers = options.workers;
  t.pin = options.pin_workers;
  t.local_store_bytes = options.plan.local_store_bytes;
  return std::make_unique<ThreadBackend>(t);
}

}  // namespace

Engine::Engine(const SceneConfig& config, const EngineOptions& options)
    : config_(config),
      backend_(make_engine_backend(options)),
      executor_(std::make_unique<RowExecutor>(*backend_)),
      device_(make_engine_device(options, *executor_, device_block(config, options))),
      solvers_(std::make_unique<Solvers>()) {
  ARDCELL_CHECK(config.size.x > 0 && config.size.y > 0, "Engine: grid size must be positive");
  ARDCELL_CHECK(config.domain_width > 0.0 && config.dt > 0.0,
                "Engine: domain width and dt must be positive");
  state_.size = config_.size;
  state_.h = config_.domain_width / config_.size.x;
  state_.dt = config_.dt;
  const bool on_device = !device_->fields_on_host();
  if (config_.fluid.kind == FluidSceneKind::kTable1) {
    PlanOptions plan = options.plan;
    if (options.backend == EngineOptions::Backend::kSerial) plan.schedule = PlanSchedule::kSerial;
    if (!on_device && plan.schedule == PlanSchedule::kSerial &&
        options.backend != EngineOptions::Backend::kSerial)
      plan_serial_backend_ = std::make_unique<SerialBackend>();
    plan_backend_ = on_device              ? nullptr
                    : plan_serial_backend_ ? plan_serial_backend_.get()
                                           : backend_.get();
    plan_ = std::make_unique<FramePlan>(
        table1_frame_plan_options(config_, plan, plan_backend_ ? plan_backend_->workers() : 1));
    // Throws std::invalid_argument with one line naming a setting the plan cannot run.
    solvers_->table1 = std::make_unique<Table1Plan>(config_, state_, *plan_, *device_, plan);
    reset();
    return;
  }
  FramePlanOptions po;
  po.grid = config_.size;
  plan_ = std::make_unique<FramePlan>(po);
  plan_backend_ = on_device ? nullptr : backend_.get();
  if (config_.fluid.kind != FluidSceneKind::kNone) {
    if (std::string why = fluid_config_problem(config_); !why.empty())
      throw std::invalid_argument(why);
    solvers_->fluid = make_fluid_step(config_, *device_);
    solvers_->fluid->allocate(state_);
    solvers_->fluid->append_stages(*plan_, state_);
  }
  if (config_.rd.enabled) {
    // Throws std::invalid_argument with one line naming a bad RD parameter.
    solvers_->rd = std::make_unique<RdStepper>(config_, *device_);
    solvers_->rd->init_state(state_);  // allocates A, B, theta0
    // Fluid first: the RD is advected by this frame's velocity.
    solvers_->rd->append_stages(*plan_, state_);
  }
  reset();
}

Engine::~Engine() = default;

BlockSupport block_support(const SceneConfig& scene) {
  BlockSupport b;
  if (scene.fluid.kind == FluidSceneKind::kTable1) {
    b.halo = table1_block_halo(scene);
    return b;
  }
  if (!scene.rd.enabled && scene.fluid.kind == FluidSceneKind::kNone)
    b.problem = "rd.enabled: a scene without a fluid or RD has nothing to run as blocks";
  // The gathered back-trace reads the ghosts of A and B, which wrap on one process's grid only.
  else if (scene.fluid.kind != FluidSceneKind::kNone && scene.rd.enabled && scene.rd.advect &&
           scene.rd.boundary == BoundaryKind::kPeriodic)
    b.problem =
        "rd.boundary: chemicals that wrap while a fluid advects them run on one process's grid "
        "(expected rd.boundary dirichlet or neumann, or rd.advect false)";
  b.halo = rd_block_halo(scene);
  // A fluid runs on the gathered grid (host/engine/fluid_step.h).
  b.gathers = scene.fluid.kind != FluidSceneKind::kNone || rd_block_gathers(scene);
  b.periodic_x = b.periodic_y = scene.rd.boundary == BoundaryKind::kPeriodic;
  return b;
}

const char* Engine::backend_name() const {
  // A plan's serial schedule runs on a serial back end of its own.
  return plan_backend_ ? plan_backend_->name() : device_->name();
}
int Engine::workers() const {
  return plan_backend_ ? plan_backend_->workers() : device_->workers();
}

namespace {
// Brings the fields `wanted(name)` picks to the host; with `will_write`, the device also takes
// what the caller writes into them before its next op.
template <class Wanted>
void sync_fields(Device& device, const SimState& state, const Wanted& wanted, bool will_write) {
  if (device.fields_on_host()) return;
  state.for_each_field([&](std::string_view name, const FieldF& f) {
    if (!wanted(name)) return;
    device.sync_to_host(f);
    if (will_write) device.host_wrote(f);
  });
}
constexpr auto kEveryField = [](std::string_view) { return true; };
auto among(std::span<const std::string_view> fields) {
  return [fields](std::string_view name) {
    return std::find(fields.begin(), fields.end(), name) != fields.end();
  };
}
}  // namespace

// The non-const forms hand the fields to a caller that may write them (painting, a loaded
// state): a multistep RD scheme then starts again from A and B as they will be.
SimState& Engine::state() {
  sync_fields(*device_, state_, kEveryField, true);
  if (solvers_->rd) solvers_->rd->restart();
  return state_;
}

const SimState& Engine::state() const {
  sync_fields(*device_, state_, kEveryField, false);
  return state_;
}

SimState& Engine::state(std::span<const std::string_view> fields) {
  sync_fields(*device_, state_, among(fields), true);
  if (solvers_->rd && (among(fields)("A") || among(fields)("B"))) solvers_->rd->restart();
  return state_;
}

const SimState& Engine::state(std::span<const std::string_view> fields) const {
  sync_fields(*device_, state_, among(fields), false);
  return state_;
}

void Engine::reset() {
  state_.time = 0.0;
  state_.rd_time = 0.0;
  state_.step = 0;
  state_.dt = config_.dt;
  if (solvers_->table1) solvers_->table1->reset();
  if (solvers_->fluid) solvers_->fluid->reset(state_);
  if (solvers_->rd) solvers_->rd->init_state(state_);
}

namespace {

// The first structural difference between a and b (the key of host/scenes/preset.cpp), or nullptr.
const char* structural_change(const SceneConfig& a, const SceneConfig& b) {
  const FluidConfig &fa = a.fluid, &fb = b.fluid;
  const RdConfig &ra = a.rd, &rb = b.rd;
  if (!(a.size == b.size)) return "grid.size";
  if (a.domain_width != b.domain_width) return "grid.domain_width";
  if (fa.kind != fb.kind) return "fluid.scene";
  if (fa.walls != fb.walls) return "fluid.walls";
  if (fa.advection != fb.advection) return "fluid.advection";
  if (fa.obstacle_x != fb.obstacle_x) return "fluid.obstacle_x";
  if (fa.obstacle_y != fb.obstacle_y) return "fluid.obstacle_y";
  if (fa.obstacle_radius != fb.obstacle_radius) return "fluid.obstacle_radius";
  if (fa.kind == FluidSceneKind::kObstacle) {
    if (fa.inflow_side != fb.inflow_side) return "fluid.inflow_side";
    if (fa.inflow_profile != fb.inflow_profile) return "fluid.inflow_profile";
    if (fa.wall_low != fb.wall_low) return "fluid.wall_low";
    if (fa.wall_high != fb.wall_high) return "fluid.wall_high";
    if (fa.obstacle_boundary != fb.obstacle_boundary) return "fluid.obstacle_boundary";
  }
  if (fa.emitters.size() != fb.emitters.size()) return "fluid.emitters (their number)";
  if (fa.viscosity_solver.kind != fb.viscosity_solver.kind) return "fluid.viscosity_solver.kind";
  if (fa.pressure_solver.kind != fb.pressure_solver.kind) return "fluid.pressure_solver.kind";
  if (fa.kind == FluidSceneKind::kTable1 && !(table1_coefficients(a) == table1_coefficients(b)))
    return "fluid.scene table1 (its dt, rates and sweeps are built into its frame plan)";
  if (ra.enabled != rb.enabled) return "rd.enabled";
  if (!ra.enabled) return nullptr;
  if (ra.reaction.model != rb.reaction.model) return "rd.reaction.model";
  if (ra.scheme != rb.scheme) return "rd.scheme";
  if (ra.boundary != rb.boundary) return "rd.boundary";
  if (ra.diffusion_operator != rb.diffusion_operator) return "rd.operator";
  if (ra.diffusion_operator == RdOperator::kGeneralized) {
    const GeneralizedRdConfig &ga = ra.generalized, &gb = rb.generalized;
    for (int nx = 0; nx <= 4; ++nx)
      for (int ny = 0; nx + ny <= 4; ++ny)
        if (nx + ny >= 2 && ga.tensors.component(nx, ny) != gb.tensors.component(nx, ny))
          return "rd.generalized (the tensor sequence)";
    if (ra.cell_size != rb.cell_size) return "rd.cell_size (the generalized stencil holds it)";
    if (ga.savitzky_golay_degree != gb.savitzky_golay_degree) return "rd.generalized.sg_degree";
    if (ga.second_derivatives != gb.second_derivatives) return "rd.generalized.second_derivatives";
    if (ga.field != gb.field || ga.d_along != gb.d_along || ga.d_across != gb.d_across)
      return "rd.generalized.field (the tensor field)";
  }
  if (ra.react != rb.react) return "rd.react";
  if (ra.diffuse != rb.diffuse) return "rd.diffuse";
  if (ra.diffusion_solver.kind != rb.diffusion_solver.kind) return "rd.diffusion_solver.kind";
  if (ra.use_table != rb.use_table) return "rd.table.enabled";
  if (ra.use_table && ra.table_resolution != rb.table_resolution) return "rd.table.resolution";
  if (ra.use_table &&
      (ra.table_range_auto != rb.table_range_auto || ra.table_range.a_lo != rb.table_range.a_lo ||
       ra.table_range.a_hi != rb.table_range.a_hi || ra.table_range.b_lo != rb.table_range.b_lo ||
       ra.table_range.b_hi != rb.table_range.b_hi))
    return "rd.table range";
  return nullptr;
}

}  // namespace

Status Engine::update_parameters(const SceneConfig& next) {
  if (const char* key = structural_change(config_, next))
    return Status::error(std::string(key) +
                         ": changes the simulation's structure; rebuild the engine (switch "
                         "presets) to change it");
  if (!(next.dt > 0.0)) return Status::error("grid.dt: expected a positive time step");
  if (std::string why = fluid_config_problem(next); !why.empty()) return Status::error(why);
  if (next.fluid.kind == FluidSceneKind::kTable1) {
    if (std::string why = table1_config_problem(next); !why.empty()) return Status::error(why);
  } else if (next.rd.enabled) {
    if (std::string why = rd_config_problem(next); !why.empty()) return Status::error(why);
    if (solvers_->rd)
      if (std::string why = solvers_->rd->parameter_problem(next); !why.empty())
        return Status::error(why);
  }
  // Field by field: the strings (name, description) are left alone so nothing allocates.
  config_.dt = next.dt;
  config_.default_steps = next.default_steps;
  config_.output.show = next.output.show;  // short names: no allocation (SSO)
  config_.output.colormap = next.output.colormap;
  FluidConfig& f = config_.fluid;
  f.viscosity = next.fluid.viscosity;
  f.lid_speed = next.fluid.lid_speed;
  f.dye_diffusion = next.fluid.dye_diffusion;
  f.conserve_dye = next.fluid.conserve_dye;
  f.inflow_speed = next.fluid.inflow_speed;
  f.inflow_dye_stripes = next.fluid.inflow_dye_stripes;
  f.probes = next.fluid.probes;
  std::copy(next.fluid.emitters.begin(), next.fluid.emitters.end(), f.emitters.begin());
  f.viscosity_solver = next.fluid.viscosity_solver;
  f.pressure_solver = next.fluid.pressure_solver;
  config_.rd = next.rd;
  if (solvers_->fluid) solvers_->fluid->update_parameters(config_.fluid);
  if (solvers_->rd) solvers_->rd->update_parameters(config_);
  state_.dt = config_.dt;
  return Status::ok();
}

void Engine::run_plan(bool with_rd) {
  if (plan_backend_)
    plan_->run(*plan_backend_, with_rd);
  else
    plan_->run(*device_, with_rd);
  state_.time += state_.dt;
  ++state_.step;
}

void Engine::step() { run_plan(true); }

void Engine::finish() { device_->finish(); }

// A plan's RD that rides in its fluid passes (table1) runs all the same.
void Engine::step_without_rd() { run_plan(false); }

FluidStep* Engine::fluid_step() { return solvers_->fluid.get(); }

Table1Plan* Engine::table1_plan() { return solvers_->table1.get(); }

const RdStepStats* Engine::rd_stats() const {
  return solvers_->rd ? &solvers_->rd->stats() : nullptr;
}

}  // namespace ardcell
