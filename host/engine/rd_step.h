#pragma once
// One reaction-diffusion frame on a SimState. The equations (seed 000; a, b the diffusion
// constants, R_A, R_B the reaction terms, u the fluid's velocity):
//   Eqn 1   dA/dt = div(a grad A) + R
//   Eqn 2   dA/dt = div(a grad A) + R_A(A, B)
//   Eqn 3   dB/dt = div(b grad B) + R_B(A, B)
//   Eqn 18  dA/dt = -(u . grad) A + R_A(A, B) + div(a(theta) grad A)
// integrated in the paper's order (section 5):
//   implicit reaction (Eqn 6, Newton per cell or the precomputed table)
//   -> implicit anisotropic diffusion of A and B (Eqn 19; Eqn 13 when isotropic)
//   -> semi-Lagrangian advection of A and B by the fluid velocity (Eqn 20), when the scene has
//      a fluid (u, v allocated) and rd.advect is on; with fluid.advection = maccormack, corrected
//      as the fluid's own advection is (kernels/advect.h maccormack_correct).
// The explicit schemes (RdScheme::kExplicit5/9) replace the first two stages by forward Euler.
// With seed 003's generalized operator (rd.operator generalized, periodic) the diffusion is the
// 25-point stencil K of the tensor sequence (kernels/generalized_rd.h): `explicit` is Eqn 27 in
// one pass; `semi-implicit` is Eqn 28 (explicit reaction, then (I - dt D K)^-1 by FFT,
// kernels/periodic_stencil_solve.h); `implicit` is Eqn 6's reaction, then the same solve.
// rd.generalized.field vortex or radial replaces the sequence by a per-cell rank-2 tensor (seed
// 003's Table 1, last row): div(D(x) grad u) in flux form, explicit (Eqn 27:
// kernels/generalized_rd.h tensor_field_rd_rows, Device::tensor_field_rd) or semi-implicit and
// implicit (Eqn 28's solve by BiCGSTAB to rd.diffusion_solver's iterations and tolerance:
// kernels/tensor_field_solve.h, Device::tensor_field_solve).
// The second-order schemes (Laplacian operator; docs/numerics.md, "Reaction-diffusion in
// time") replace the first two stages:
//   crank-nicolson-am2  Strang splitting of sec. 3.2's suggestion: the trapezoidal reaction
//                       (Adams-Moulton 2, Newton per cell like Eqn 6) over dt/2, Crank-Nicolson
//                       diffusion over dt, the trapezoidal reaction over dt/2
//   sbdf2               IMEX: BDF2 diffusion with the implicit solvers (any boundary, anisotropy,
//                       obstacles), the reaction extrapolated, 2 f^n - f^(n-1)
//                       (kernels/imex_rd.h). It keeps u^(n-1) here, not in the state: the first
//                       step, and the first after restart() (a reset, a loaded or painted state,
//                       a new dt), is SBDF1 (IMEX Euler)
//   etdrk4              exponential time differencing, fourth order, by FFT on the periodic grid
//                       (kernels/periodic_etdrk4.h; isotropic, no solid cells)
// rd.steps_per_frame RD steps run per frame; advection runs once per frame with the scene's dt.
// Seed 001's case (explicit 9-point Gray-Scott, periodic) runs a frame's steps as one op where the
// device has it (Device::gray_scott9_steps: the CPU's temporally blocked kernels/gray_scott9.h,
// whose A and B have halo GrayScott9Blocked::kHalo) - on a block of whole rows as one op per
// halo exchange, its rows above and below from the halo; the other explicit cases, and seed
// 001's scheme on OpenCL, on a block that splits rows or with walls, step whole fields one step
// at a time - seed 001's skipping, on the CPU, the cells that cannot change
// (kernels/explicit_rd.h QuiescentBox). On a periodic grid a block steps kExplicitBlockSteps
// steps per halo exchange. Every stage is an op of
// the engine's Device (host/engine/device.h: the CPU in bands of rows, same bits on any number of
// workers, or OpenCL). The frame is the stages append_stages() adds to the scene's FramePlan
// (host/engine/frame_plan.h): the RD steps of the frame, then the advection. Nothing is
// allocated in a frame once constructed.
#include <memory>
#include <string>

#include "host/config/scene_config.h"
#include "host/config/sim_state.h"
#include "host/engine/device.h"
#include "host/engine/frame_plan.h"
#include "kernels/aniso_diffusion.h"
#include "kernels/gray_scott9.h"
#include "kernels/periodic_etdrk4.h"
#include "kernels/periodic_stencil_solve.h"
#include "kernels/reaction_table.h"
#include "kernels/tensor_field_solve.h"

namespace ardcell {

// One line naming the first bad RD parameter of the scene, or "" when it can run.
std::string rd_config_problem(const SceneConfig& scene);

// Every RD scheme runs as one block of a decomposed grid (a Device on a block,
// host/engine/device.h): the explicit 5- and 9-point steps read a halo (Device::exchange_halos),
// the reactions are per cell, the conductivity reads a halo of A one cell deep, the implicit
// diffusion's Jacobi sweeps exchange the iterate's halo between sweeps (rd_block_sweeps), and the
// ops that read the whole grid (the other solvers, seed 003's wrapping stencils and FFTs, ETDRK4,
// the advection's back-trace) run on the gathered grid (CpuDevice).
// On a periodic grid, where every edge of a block is a neighbour's, a block runs up to this many
// explicit steps between exchanges: the exchange is that many cells deep, and each step also
// steps the halo cells the steps after it read (seed 001's frame of 10 steps: two exchanges,
// not ten). Walls are filled a cell deep each step, so a block of a walled grid exchanges
// before every step.
inline constexpr int kExplicitBlockSteps = 5;
// The halo a block of the scene's RD exchanges (block_support): kExplicitBlockSteps for the
// explicit schemes on a periodic grid, else 1.
int rd_block_halo(const SceneConfig& scene);
// Whether a block's implicit diffusion (the implicit, Crank-Nicolson and SBDF2 schemes with the
// Laplacian) sweeps the block's own cells: a Jacobi solver (as `--realtime-solvers` sets) or
// red-black Gauss-Seidel on a grid that wraps an even number of cells
// (ImplicitDiffusion::runs_on_block), and no obstacle.
bool rd_block_sweeps(const SceneConfig& scene);
// Whether a block of the scene's RD runs ops on the gathered grid: every scheme but the explicit
// 5- and 9-point ones and the diffusion solves of rd_block_sweeps with the Laplacian, and
// advected RD.
bool rd_block_gathers(const SceneConfig& scene);

// For the generalized operator, one line a run prints before it starts: the explicit update's
// spectral radius rho(I + dt D K) for A and B (seed 003, Eqn 27), with a warning when it
// exceeds 1; "" for the other schemes and operators.
std::string generalized_stability_line(const SceneConfig& scene);

struct RdStepStats {
  int diffusion_iterations_a = 0, diffusion_iterations_b = 0;
  double diffusion_residual_a = 0, diffusion_residual_b = 0;
};

class RdStepper {
 public:
  // Throws std::invalid_argument with rd_config_problem()'s line on a bad configuration.
  explicit RdStepper(const SceneConfig& scene, Device& device = CpuDevice::serial());
  ~RdStepper();

  // Allocates A, B when absent (and theta0 when absent: filled with rd.anisotropy.theta0; a
  // painted theta0 is kept) over the device's cells (its block, or the grid) and writes the
  // initial pattern. Deterministic for a given rd.seed; a block gets its cells of the grid's
  // pattern. Restarts the multistep history (restart()).
  void init_state(SimState& s);

  // The state's A and B were written by someone else (a reset, a loaded state, painting): the
  // multistep scheme (sbdf2) forgets u^(n-1) and takes its next step as SBDF1, and seed 001's
  // per-step scheme computes every cell again before it skips quiescent ones (QuiescentBox).
  // The other schemes keep no history. Allocates nothing.
  void restart() {
    history_ = false;
    restart_skipping();
  }
  // Whether the next sbdf2 step is SBDF2 (true) or its SBDF1 start (false).
  bool has_history() const { return history_; }

  // Appends the frame's stages to `plan`, on `s` (kept by reference; A, B allocated by
  // init_state): the RD steps, then, when s has a velocity of the scene's size, the advection.
  // Both are rd stages (FramePlan::run's with_rd).
  void append_stages(FramePlan& plan, SimState& s);

  // Takes the RD parameters of `scene` (reaction parameters, diffusion rates, anisotropy,
  // dt, cell size, steps per frame, solver iterations and tolerance, initial pattern for the
  // next reset). The caller (Engine) has refused structural changes (size, model, scheme,
  // boundary, react/diffuse, table settings) and checked rd_config_problem(). Allocates nothing,
  // except that a reaction table is rebuilt when the reaction parameters or dt change.
  void update_parameters(const SceneConfig& scene);
  // One line when `scene`'s steps cannot be solved (a periodic solve whose (I - dt D K) is
  // singular at the new dt or rates), "" otherwise. No allocation when "".
  std::string parameter_problem(const SceneConfig& scene) const;

  const RdStepStats& stats() const { return stats_; }
  double rd_dt() const { return dt_; }
  double rd_h() const { return h_; }

 private:
  // The halo init_state() gives A and B, and the fields they swap with: GrayScott9Blocked::kHalo
  // for seed 001's blocked steps, a block's channel width (which may exceed its steps between
  // exchanges when the channel was made for another scene), else 1 (theta0's).
  int chemical_halo() const;
  // The scene's initial A and B, laid out over the whole grid, into A and B's cells (the grid or
  // a block; the same interior).
  void write_initial_pattern(FieldF& A, FieldF& B) const;
  void fill_chemical_ghosts(SimState& s);
  void react(SimState& s);
  // The conductivity k = a(theta) of A as it is now (null when isotropic).
  const FieldF* conductivity(SimState& s);
  // The implicit diffusion of A and B over `fraction` of dt (Eqn 13, Eqn 19; Crank-Nicolson with
  // `crank_nicolson`), with conductivity k (null: isotropic).
  void diffuse(SimState& s, const FieldF* k, double fraction, bool crank_nicolson);
  // One explicit step, `steps_left` of the frame's steps left (this one included).
  void explicit_step(SimState& s, int steps_left);
  // The stats of a step's A and B solves.
  void record_solves(const SolveReport& a, const SolveReport& b);
  void crank_nicolson_am2_step(SimState& s);
  void sbdf2_step(SimState& s);
  // The ETDRK4 coefficients for the current dt, rates and cell size.
  void set_etdrk4_step();
  // Whether react_diffuse runs explicit generalized steps several at a time
  // (Device::generalized_rd_steps).
  bool fuses_generalized_steps() const;
  // One step of seed 003's generalized RD (Eqn 27, Eqn 28).
  void generalized_step(SimState& s);
  GeneralizedRdParams generalized_params(bool react, bool diffuse) const;
  GrayScott9Params gray_scott9_params() const;
  void advect(SimState& s);
  // The frame's rd.steps_per_frame steps of reaction and diffusion.
  void react_diffuse(SimState& s);

  SceneConfig scene_;
  Device* dev_;
  RdConfig rd_;
  Box2 cells_;  // the cells the device computes: its block, or the whole grid
  double dt_, h_;
  std::unique_ptr<ImplicitDiffusion> diff_a_, diff_b_;
  std::unique_ptr<GeneralizedTaps> generalized_;                   // rd.operator generalized
  std::unique_ptr<Rank2FaceField> tensor_field_;                   // rd.generalized.field
  std::unique_ptr<PeriodicStencilSolve> periodic_a_, periodic_b_;  // its implicit solves
  std::unique_ptr<TensorFieldSolve> tensor_solve_;  // the tensor field's (A's and B's)
  ReactionTable table_;
  FieldF conductivity_, scratch_a_, scratch_b_;
  FieldF back_a_, back_b_;  // MacCormack's backward step (fluid.advection); else empty
  std::unique_ptr<GrayScott9Blocked> gray_scott9_;  // seed 001's scheme (gray_scott9_steps)
  // A and B are as gray_scott9_'s last run left them: its next run resumes (scans no row).
  bool gray_scott9_resumes_ = false;
  // A and B were written other than by seed 001's steps: both skippers look at every cell again.
  void restart_skipping() {
    quiescent_.restart();
    gray_scott9_resumes_ = false;
  }
  std::unique_ptr<PeriodicEtdrk4> etdrk4_;  // rd.scheme etdrk4
  FieldF prev_a_, prev_b_;                  // sbdf2: u^(n-1)
  bool history_ = false;                    // sbdf2: prev_a_, prev_b_ hold u^(n-1)
  // Seed 001's quiescent cells on the per-step schedule (explicit_step): A, B and the scratch
  // pair they swap with; advection and restart() restart it.
  QuiescentBox quiescent_;
  // A block's explicit steps between halo exchanges (rd_block_halo; 1 on the whole grid), and
  // how many more the halo A and B hold now serves.
  int block_steps_ = 1;
  int halo_left_ = 0;
  RdStepStats stats_;
};

}  // namespace ardcell
