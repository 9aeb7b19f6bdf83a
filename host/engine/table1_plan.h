#pragma once
// The Table 1 scenes' frame (fluid.scene = table1; seed 000 section 7.2, bench/README.md): Stam's
// stable fluid in a free-slip box stirred by four turning splats, alone (`table1`) or with
// Gray-Scott reaction-diffusion riding on it (`table1-ard`), built once as the fused passes of the
// Engine's FramePlan and run by the Engine (host/engine/engine.h) every frame, under one of three
// schedules of the same kernels (PlanSchedule, host/engine/frame_plan.h):
//   serial  - whole-grid reference: every stage a global loop on the calling thread, no tiling;
//   stream  - Cell-faithful: every solver sweep streams the tiles through the local stores
//             (threads back end); the RD work is fused into passes the fluid makes anyway
//             (reaction with the sources pass, A's and B's diffusion sweeps in store with
//             the projections' divergence passes, their advection with the dye's);
//   blocked - ghost-zone temporal blocking: each solve loads its tile with a halo of its sweeps
//             once, sweeps in store and writes the core once; the projection (divergence,
//             solve, gradient) is one pass.
// All three give the same fields bit for bit (tests/host/engine/tiling_parity_test.cpp), and so
// does the grid cut into blocks (PlanOptions::block / halo, runtime/block_layout.h), each block a
// plan of its own on its own thread exchanging halos with the others
// (tests/host/engine/table1_blocks_test.cpp). On a
// device with fields of its own (OpenCL) the same plan runs whole-field, each op as its Device
// twin (FramePlan::run(Device&)), the fields resident on the device; its Jacobi ops run one sweep
// a launch (stream, serial) or as many as the local memory holds (blocked).
//
// The plan reads the scene's dt, fluid.viscosity, fluid.dye_diffusion, the Jacobi sweeps of its
// solvers and, with RD, the Gray-Scott F and k, rd.dt and the diffusion rates;
// table1_config_problem names any other setting it cannot run.
#include <cstdint>
#include <memory>
#include <span>
#include <string>

#include "host/config/scene_config.h"
#include "host/config/sim_state.h"
#include "host/engine/frame_plan.h"
#include "kernels/advect.h"
#include "kernels/project.h"
#include "kernels/reaction.h"
#include "kernels/stam_sweeps.h"
#include "runtime/backend.h"

namespace ardcell {

class Device;

// The Table 1 workload's fixed parts (bench/README.md): its splats and the traffic figures.
struct Table1Constants {
  static constexpr int kSplats = 4;
  static constexpr float kSplatForce = 0.1f, kSplatDye = 0.1f;
  // Bytes per cell per frame a sweep-by-sweep implementation must move (each stage reads its
  // inputs once and writes its outputs once, float32); the bytes_per_s counter's numerator.
  static constexpr double kFluidBytesPerCell = 1328;
  static constexpr double kRdBytesPerCell = 520;
};

// "" when the Table 1 plan can run `config` (fluid.scene table1), else one line naming the first
// setting it cannot and what it expects.
std::string table1_config_problem(const SceneConfig& config);

// What the plan's passes compute with, derived from the scene (cell units): a change of any of
// these needs the plan built again.
struct Table1Coefficients {
  int sweeps = 20;  // Jacobi sweeps of every solve
  StamSweepParams viscosity, dye_diffusion, pressure, rd_a, rd_b;
  ProjectParams project;
  AdvectParams advect;
  GrayScottImplicitParams reaction;
};
Table1Coefficients table1_coefficients(const SceneConfig& config);
// The halo of the fields of one block of a decomposed grid (PlanOptions::block): the deepest
// pass halo of every schedule (a solve's sweeps + 2) and a cell for the advection's reach.
int table1_block_halo(const SceneConfig& config);
// The options of the FramePlan the Table 1 passes go into: its block (the whole grid when
// options.block is empty), the fields' halo (1, or the exchange's width), the local store, and
// tiles cut for `workers` (1: whole-field on a device or the serial schedule).
FramePlanOptions table1_frame_plan_options(const SceneConfig& config, const PlanOptions& options,
                                           int workers);
bool operator==(const Table1Coefficients& a, const Table1Coefficients& b);

class Table1Plan {
 public:
  // Appends the scene's passes to `plan` (empty, made with table1_frame_plan_options), whose
  // passes run on a back end, or whole-field on `device` when the device keeps fields of its own.
  // Allocates the scene's fields u, v, dye (and A, B with RD) on `state`, which must keep them
  // at the same addresses; state.step turns the splats.
  Table1Plan(const SceneConfig& config, SimState& state, FramePlan& plan, Device& device,
             const PlanOptions& options);
  ~Table1Plan();
  Table1Plan(const Table1Plan&) = delete;
  Table1Plan& operator=(const Table1Plan&) = delete;

  // The initial conditions in state's fields (handed to the device).
  void reset();

  PlanSchedule schedule() const { return options_.schedule; }
  std::size_t local_store_bytes() const { return options_.local_store_bytes; }
  // The sweep-by-sweep minimum traffic of one frame (bench/README.md).
  double bytes_per_frame() const;

 private:
  struct Fields;
  struct Params;
  void init(const SceneConfig& config);
  void build();
  void add_sources_pass(bool with_reaction);
  struct DiffusionSpec {
    FieldF* x;    // initial guess and right-hand side (kept)
    FieldF* out;  // result
    FieldF* tmp;  // ping-pong partner of out
    const StamSweepParams* params;
    int b;  // Stam's set_bnd kind
  };
  void add_diffusion(const char* name, std::span<const DiffusionSpec> solves, bool with_sources);
  void append_residency(PassDesc& d, const DiffusionSpec& sv, const FieldF* cur, FieldF* next,
                        int sweeps, bool whole, bool with_sources);
  void add_projection(const char* name, FieldF& u, FieldF& v, FieldF& u_out, FieldF& v_out,
                      int pressure_pass_with_rider);
  void add_rd_diffusion_pass();
  // A pressure Jacobi op whose first iterate the pass zeroes: on a device, it sweeps from the
  // plan's field of zeros instead.
  void start_from_zeros(PassOpDesc& op);

  SimState& state_;
  PlanOptions options_;
  Int2 grid_{};
  int field_halo_ = 1;
  bool rd_ = false;
  int sweeps_ = 20;  // Jacobi sweeps of every solve
  FramePlan* plan_;
  std::unique_ptr<Fields> f_;
  std::unique_ptr<Params> p_;
  Device* device_ = nullptr;  // when the plan runs on a device's own fields
};

}  // namespace ardcell
