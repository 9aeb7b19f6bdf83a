#pragma once
// One frame of Stam's stable fluids on a SimState (Stam 1999; seed 000 section 5):
//   forces and sources -> implicit viscosity (I - dt nu Lap) u = u* -> project -> self-advect
//   (semi-Lagrangian) -> project; then the dye: implicit diffusion (when dye_diffusion > 0) and
//   advection by the new velocity.
// The implicit solves use the 5-point StencilOperator and the LinearSolver chosen in the
// FluidConfig (jacobi | rbgs | iccg | mg); the per-cell work is the tile kernels of kernels/
// (advect.h, project.h, sources.h), run as the ops of the Device it is made with
// (host/engine/device.h: the CPU in bands of rows, same bits on any number of workers, or
// OpenCL). The frame is the stages append_stages() adds to the scene's FramePlan
// (host/engine/frame_plan.h). Everything is allocated in the constructor: a frame does no heap
// allocation.
// On a device that runs one block of a decomposed grid (Device::on_block), the fluid runs on the
// gathered grid: the state's u, v, p and dye cover the block, every block gathers them into a
// whole-grid state of the fluid's own (HaloChannel::gather_all, the domain's ghost ring
// included), runs the frame's fluid stages there on a CpuDevice of the same executor, and takes
// its block's cells and halo back: one process's bits, at one process's speed for the fluid.
// Decomposing its ops (solves that exchange between sweeps, reductions whose bits do not depend
// on the layout, back-traces within a CFL-wide halo) is what would make them scale.
#include <memory>
#include <string>

#include "host/config/fluid_config.h"
#include "host/config/sim_state.h"
#include "host/engine/device.h"
#include "host/engine/frame_plan.h"
#include "kernels/linear_solver.h"
#include "runtime/boundary.h"

namespace ardcell {

struct SceneConfig;

// One line naming a fluid setting the solver cannot run (empty when it can): the obstacle
// channel's walls and probes.
std::string fluid_config_problem(const SceneConfig& scene);

// What the last frame's solves reported.
struct FluidStepReport {
  SolveReport viscosity_u, viscosity_v, pressure_first, pressure_second, dye;
};

class FluidStep {
 public:
  FluidStep(const FluidConfig& config, Int2 size, double h, double dt,
            Device& device = CpuDevice::serial());
  ~FluidStep();
  FluidStep(const FluidStep&) = delete;
  FluidStep& operator=(const FluidStep&) = delete;

  // Allocates the fluid fields of `state` (u, v, p, dye over the device's cells, and the
  // obstacle mask over the grid when the scene has one), halo 1, when they are missing or of
  // another size.
  void allocate(SimState& state);
  // The scene's initial conditions (fluid at rest, the initial dye, the obstacle mask).
  void reset(SimState& state);
  // Appends the frame's stages to `plan`, in the order above, on `state` (kept by reference):
  // together they advance the fluid and the dye by state.dt (re-preparing the operators if dt
  // changed). None for a scene without a fluid.
  void append_stages(FramePlan& plan, SimState& state);
  // Takes the non-structural parameters of `config` (viscosity, lid and inflow speed, dye
  // diffusion, solver iterations and tolerances, emitters when their count is unchanged); the
  // operators are re-prepared on the next step. Allocates nothing. The caller (Engine) refuses
  // structural changes (scene kind, walls, obstacle, solver kinds).
  void update_parameters(const FluidConfig& config);
  // The pressure projection alone (fills boundaries, solves, subtracts the gradient): exposed for
  // tests and tools (on the whole grid).
  SolveReport project(SimState& state);

  // With `on`, each step keeps the first projection's pressure too (one copy a frame), so that
  // physical_pressure() can give the step's whole pressure. Allocates when turned on.
  void record_pressure(bool on);
  // The physical (kinematic) pressure of the last step, ghosts included: the two projections'
  // potentials (each u -= grad p) over dt, P = (p_first + p) / dt, on the host (on the whole
  // grid).
  void physical_pressure(const SimState& state, FieldF& out) const;
  // The obstacle's solid cells (centre inside the disc; empty when none).
  const Field<uint8_t>& solid() const { return solid_; }
  // With cut cells, the faces' open fractions ((nx + 1) x ny and nx x (ny + 1)); else empty.
  const FieldF& open_x() const { return open_x_; }
  const FieldF& open_y() const { return open_y_; }

  const FluidStepReport& last_report() const { return report_; }
  // Boundary rules of each field in this scene.
  const BoundaryFill& u_fill() const { return fill_u_; }
  const BoundaryFill& v_fill() const { return fill_v_; }
  const BoundaryFill& p_fill() const { return fill_p_; }
  const BoundaryFill& dye_fill() const { return fill_dye_; }
  // Fills the ghost cells (and obstacle cells) of u and v, or of a scalar with its rule.
  void fill_velocity(SimState& state) const;
  // The divergence-free MAC face velocities of the last projection (kernels/project.h
  // face_velocities): what the dye is advected with (kernels/advect.h advect_scalar_mac), and
  // what any other passive quantity should be advected with to keep its mass.
  const FieldF& face_u() const { return face_u_; }
  const FieldF& face_v() const { return face_v_; }

 private:
  struct Operators;
  void prepare(double dt);
  void add_forces_and_sources(SimState& state);
  void diffuse_velocity(SimState& state);
  void diffuse_dye(SimState& state);
  // The dye's stage: diffusion, then advection by the last projection's face velocities (and
  // the closed scenes' mass fix).
  void step_dye(SimState& state);
  void advect(SimState& state);
  void advect_dye(SimState& state, const AdvectParams& params);
  void cut_cells(double cx, double cy, double r);
  // The cells the pressure equation leaves out: every solid cell, or with cut cells only the
  // covered ones.
  const Field<uint8_t>& pressure_solid() const { return covered_.empty() ? solid_ : covered_; }
  // The state the stages step: the engine's, or on a block the gathered one (whole_).
  SimState& stepped(SimState& state) { return block_.halo ? whole_ : state; }
  void allocate_whole(SimState& state) const;
  // On a block: the state's u, v, p, dye into whole_ (every block's cells), and back (the
  // block's cells and halo).
  void gather(const SimState& state);
  void take(SimState& state) const;

  FluidConfig config_;
  // On a block: the block, and the whole-grid device and state the stages run on.
  DeviceBlock block_;
  std::unique_ptr<CpuDevice> whole_device_;
  SimState whole_;
  Device* dev_;
  Int2 size_;
  double h_;
  double prepared_dt_ = -1.0;
  BoundaryFill fill_u_, fill_v_, fill_p_, fill_dye_;
  Field<uint8_t> solid_;  // the obstacle mask (empty when none)
  // Cut cells (FluidConfig::obstacle_boundary): the faces' open fractions, (nx + 1) x ny and
  // nx x (ny + 1), and the cells with no open face; empty otherwise.
  FieldF open_x_, open_y_;
  Field<uint8_t> covered_;
  FieldF p_first_;  // the first projection's pressure (record_pressure)
  std::unique_ptr<Operators> ops_;
  FieldF scratch_u_, scratch_v_, scratch_b_, rhs_;
  FieldF back_;  // MacCormack's backward step (with rhs_); empty for semi-Lagrangian advection
  FieldF face_u_, face_v_;  // (nx + 1) x ny and nx x (ny + 1), halo 1
  FluidStepReport report_;
};

// Builds the FluidStep of a scene (size, h = domain_width / size.x, dt).
std::unique_ptr<FluidStep> make_fluid_step(const SceneConfig& scene,
                                           Device& device = CpuDevice::serial());

}  // namespace ardcell
