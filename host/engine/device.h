#pragma once
// Device: what the frame's stages (host/engine/fluid_step.h, rd_step.h) run their operations on.
// The stages say WHAT happens to which fields, in the paper's order; a Device says HOW (ggml's
// backend: one small set of ops, `supports`, one parity test over every op and device):
//   CpuDevice    - the kernels of kernels/ in bands of rows on a RowExecutor (the serial
//                  reference or the threads back end: same bits on any number of workers);
//   OpenClDevice - the OpenCL twins of those kernels on device-resident fields
//                  (host/engine/opencl_device.h).
// Ops take whole fields (their interiors, the ghost ring where the op says so) and never see
// tiles, rows or back ends. Fields are named by their host objects: a device that keeps its own
// copies maps each FieldF to its copy and moves data only when the other side needs it
// (sync_to_host / host_wrote). swap() exchanges two fields on every side, as std::swap does on
// the host.
// A device may run one BLOCK of a decomposed grid (runtime/block_layout.h; DeviceBlock): its
// fields cover the block with a halo, its ops compute the block's cells, boundary fills write the
// domain's ghost ring only where the block touches it, and exchange_halos() - the halo exchange,
// a step the stages call before an op that reads across the block's edges - fills the rest from
// the other blocks. Which scenes' stages run so: host/engine/engine.h block_support(); which ops
// a block runs: supports().
#include <array>
#include <cstdint>
#include <span>
#include <type_traits>
#include <vector>

#include "kernels/advect.h"
#include "kernels/aniso_diffusion.h"
#include "kernels/anisotropy.h"
#include "kernels/explicit_rd.h"
#include "kernels/generalized_rd.h"
#include "kernels/imex_rd.h"
#include "kernels/linear_solver.h"
#include "kernels/project.h"
#include "kernels/reaction.h"
#include "kernels/reaction_table.h"
#include "kernels/sources.h"
#include "kernels/stam_sweeps.h"
#include "runtime/block_layout.h"
#include "runtime/boundary.h"
#include "runtime/field.h"
#include "runtime/row_executor.h"

namespace ardcell {

class PeriodicEtdrk4;
class GrayScott9Blocked;
class PeriodicStencilSolve;
class TensorFieldSolve;

// The ops a device may or may not run natively (Device::supports). An op a device does not run
// falls back to the CPU for that op (its fields move to the host and back), with one line.
enum class DeviceOp : uint8_t {
  kCopy,
  kFillBoundary,
  kFillObstacle,
  kAddBoundaryValues,
  kAddSplat,
  kInflowStripes,
  kPressureRhs,
  kFaceVelocities,
  kSubtractGradient,
  kAdvectVelocity,
  kAdvectScalar,
  kAdvectScalarMac,
  kMacCormack,
  kRange,
  kRestoreMass,
  kSolve,
  kReactionImplicit,
  kReactionTable,
  kConductivity,
  kImplicitDiffusion,
  kExplicitRd,
  kGrayScott9Steps,
  kGeneralizedRd,
  kTensorFieldRd,
  kPeriodicSolve,
  kTensorFieldSolve,
  kReactionTrapezoidal,
  kSbdfRhs,
  kEtdrk4,
  kStamJacobi,
  kCount
};
const char* device_op_name(DeviceOp op);

// Sum (rows added in order), minimum and maximum of a field's interior.
struct FieldRange {
  double sum = 0.0;
  float lo = 0.0f, hi = 0.0f;
};

// Where a device's fields lie: the whole grid (no halo channel), or the block `block` of the
// grid, whose halos `halo` fills from the blocks that own those cells (collective: every block
// of the group exchanges the same fields in the same order).
struct DeviceBlock {
  Int2 grid{};
  Box2 block{};
  HaloChannel* halo = nullptr;
};

class Device {
 public:
  virtual ~Device() = default;
  // "serial", "threads" or "opencl".
  virtual const char* name() const = 0;
  virtual int workers() const = 0;
  // Whether `op` runs on this device itself (false: on the CPU, moving its fields).
  virtual bool supports(DeviceOp op) const = 0;
  // The CPU executor: solvers are made for it, and ops that fall back run on it.
  virtual RowExecutor& executor() = 0;
  // True when the ops work on the host fields themselves (no copies to keep in step).
  virtual bool fields_on_host() const = 0;
  // Sizes the scratch of ops on grids of up to `grid` cells, so that they allocate nothing.
  virtual void reserve(Int2 grid) = 0;
  // Returns when every op issued so far has finished (a device may queue them).
  virtual void finish() = 0;
  // The block this device computes (DeviceBlock::halo null: the whole grid).
  virtual const DeviceBlock& block() const = 0;
  bool on_block() const { return block().halo != nullptr; }

  // --- the halo exchange (runtime/block_layout.h HaloChannel): fills each field's halo `depth`
  // cells deep around the block from the blocks that own those cells. Nothing on the whole grid.
  virtual void exchange_halos(std::span<FieldF* const> fields, int depth) = 0;

  // --- fields
  // Whole allocations (halo included); same layout.
  virtual void copy(const FieldF& from, FieldF& to) = 0;
  virtual void swap(FieldF& a, FieldF& b) = 0;
  // Makes the host copy of f current (a device with its own copies downloads it).
  virtual void sync_to_host(const FieldF& f) = 0;
  // The host copy of f (or of a mask) was written: the device's copy is stale.
  virtual void host_wrote(const FieldF& f) = 0;
  virtual void host_wrote(const Field<uint8_t>& mask) = 0;
  // A reaction table was (re)built.
  virtual void host_wrote(const ReactionTable& table) = 0;

  // --- boundaries (runtime/boundary.h)
  // The ghost ring of the domain (the whole grid's, where the field holds it).
  virtual void fill_boundary(FieldF& f, const BoundaryFill& fill) = 0;
  // Solid cells of the interior from their fluid neighbours.
  virtual void fill_obstacle(FieldF& f, const Field<uint8_t>& solid, ObstacleRule rule) = 0;
  // b += the boundary values' share on the boundary cells (kernels/stencil_operator.h).
  virtual void add_boundary_values(FieldF& b, const BoundaryFill& fill, double scale) = 0;

  // --- fluid (kernels/sources.h, project.h, advect.h), over the interior
  virtual void add_splat(FieldF& f, const SplatParams& splat) = 0;
  virtual void set_inflow_stripes(FieldF& dye, int stripes, BoundarySide side) = 0;
  // With open fractions (both or neither), the cut-cell form (kernels/project.h
  // pressure_rhs_cut).
  virtual void pressure_rhs(const FieldF& u, const FieldF& v, FieldF& rhs, const ProjectParams& p,
                            const FieldF* open_x = nullptr, const FieldF* open_y = nullptr) = 0;
  // Every face of the grid; with `periodic`, the ghost rows of uf and columns of vf wrapped.
  virtual void face_velocities(const FieldF& u, const FieldF& v, const FieldF& p, FieldF& uf,
                               FieldF& vf, const ProjectParams& params, bool periodic) = 0;
  virtual void subtract_gradient(const FieldF& p, FieldF& u, FieldF& v,
                                 const ProjectParams& params) = 0;
  virtual void advect_velocity(const FieldF& u0, const FieldF& v0, FieldF& u, FieldF& v,
                               const AdvectParams& p) = 0;
  // q[i] from q0[i] for every i (at most kMaxAdvectFields): one back-trace for all of them.
  virtual void advect_scalars(std::span<const FieldF* const> q0, const FieldF& u, const FieldF& v,
                              std::span<FieldF* const> q, const AdvectParams& p) = 0;
  virtual void advect_scalar_mac(const FieldF& q0, const FieldF& uf, const FieldF& vf, FieldF& q,
                                 const AdvectParams& p) = 0;
  // MacCormack's limited correction (kernels/advect.h maccormack_correct): q[i] from q0[i], the
  // forward step's q_hat[i] and the backward step's q_back[i], bounded at the departure point
  // of (u, v) - or of the face velocities (u, v) = (uf, vf) with `mac` (one field then). q[i]
  // may be q_hat[i].
  virtual void maccormack_correct(std::span<const FieldF* const> q0,
                                  std::span<const FieldF* const> q_hat,
                                  std::span<const FieldF* const> q_back, const FieldF& u,
                                  const FieldF& v, std::span<FieldF* const> q,
                                  const AdvectParams& p, bool mac) = 0;
  // The interior's sum (rows added in order), minimum and maximum.
  virtual FieldRange range(const FieldF& f) = 0;
  // Puts `missing` mass back with weights (q - lo)(hi - q), clamped to [lo, hi]
  // (host/engine/fluid_step.cpp says why).
  virtual void restore_mass(FieldF& f, double missing, float lo, float hi) = 0;

  // Stam's constant-coefficient Jacobi sweeps (kernels/stam_sweeps.h; the Table 1 plan's
  // solves): `sweeps` sweeps from a with right-hand side rhs, ping-ponging between a and b,
  // each followed by `fill`; the result in a (sweeps even) or b (odd), as FramePlan's Jacobi op.
  // With `start`, the first sweep reads it instead of a (as if it had been copied into a).
  virtual void stam_jacobi_sweeps(const FieldF& rhs, FieldF& a, FieldF& b, int sweeps,
                                  const StamSweepParams& p, const BoundaryFill& fill,
                                  const FieldF* start = nullptr) = 0;

  // --- linear systems (kernels/linear_solver.h): improves x towards A x = b. The operator's
  // coefficients are host data (assembled by the stage; host_wrote(op) after a change).
  virtual SolveReport solve(LinearSolver& solver, const StencilOperator& op, const FieldF& b,
                            FieldF& x) = 0;
  void host_wrote(const StencilOperator& op) {
    host_wrote(op.diag);
    host_wrote(op.wx);
    host_wrote(op.wy);
  }

  // --- reaction-diffusion (kernels/reaction.h, reaction_table.h, anisotropy.h,
  // aniso_diffusion.h, explicit_rd.h), over the interior, in place where outputs are inputs
  virtual void reaction_implicit(FieldF& a, FieldF& b, const ReactionParams& p, float dt) = 0;
  virtual void reaction_table(FieldF& a, FieldF& b, const ReactionTable& table) = 0;
  virtual void conductivity(const FieldF& a, const FieldF& theta0, FieldF& k,
                            const AnisotropyParams& p) = 0;
  // One implicit step of `field` with `diffusion`'s operator and solver (Eqn 13; Eqn 17 and Eqn 19
  // with a conductivity).
  virtual SolveReport implicit_diffusion(ImplicitDiffusion& diffusion, FieldF& field,
                                         const FieldF* conductivity, const DiffusionStep& s) = 0;
  // Forward Euler (Eqn 5, seed 001's 9-point scheme): a_out, b_out from a, b over the interior
  // grown by `grow` cells (a block's halo cells that a deeper exchange lets it step on its own;
  // the fields' halo holds grow + 1). With `quiet` (seed 001's scheme; the caller's, restart()ed
  // whenever the four fields are written other than by these steps, and told halo_exchanged()
  // whenever a's and b's halo was exchanged or filled), a device may compute only the cells it
  // says can change (kernels/explicit_rd.h QuiescentBox): the same bits.
  enum class ExplicitScheme : uint8_t { k5, k9, kGrayScott9 };
  virtual void explicit_rd(const FieldF& a, const FieldF& b, FieldF& a_out, FieldF& b_out,
                           ExplicitScheme scheme, const ExplicitRdParams& p, QuiescentBox* quiet,
                           int grow) = 0;
  // Seed 001's scheme (explicit 9-point Gray-Scott, periodic): `steps` steps of a and b in place,
  // temporally blocked (kernels/gray_scott9.h; `blocked` made for the grid on the device's
  // executor). A and B should have GrayScott9Blocked::kHalo; others are given it (an allocation).
  // resume: a and b are as the last call left them (GrayScott9Blocked::run's resume).
  virtual void gray_scott9_steps(GrayScott9Blocked& blocked, FieldF& a, FieldF& b, int steps,
                                 const GrayScott9Params& p, bool resume) = 0;
  // seed 003, Eqn 27 on a periodic grid (kernels/generalized_rd.h): a_out, b_out from a, b.
  virtual void generalized_rd(const FieldF& a, const FieldF& b, FieldF& a_out, FieldF& b_out,
                              const GeneralizedTaps& k, const GeneralizedRdParams& p) = 0;
  // `steps` steps of generalized_rd (1 .. kGeneralizedFusedSteps), the same bits: a_out, b_out
  // get the last; a, b are left with anything (the caller swaps them out). Here one call a step;
  // a device that fuses them (the CPU: kernels/generalized_rd.h generalized_rd_fused_rows) moves
  // the fields through memory once.
  virtual void generalized_rd_steps(FieldF& a, FieldF& b, FieldF& a_out, FieldF& b_out,
                                    const GeneralizedTaps& k, const GeneralizedRdParams& p,
                                    int steps) {
    generalized_rd(a, b, a_out, b_out, k, p);
    for (int i = 1; i < steps; ++i) {
      generalized_rd(a_out, b_out, a, b, k, p);
      swap(a, a_out);
      swap(b, b_out);
    }
  }
  // seed 003's Table 1, last row at rank 2: div(D(x) grad u) with a per-cell tensor, in flux form,
  // fused with the reaction like generalized_rd (kernels/generalized_rd.h tensor_field_rd_rows).
  virtual void tensor_field_rd(const FieldF& a, const FieldF& b, FieldF& a_out, FieldF& b_out,
                               const Rank2FaceField& d, const GeneralizedRdParams& p) = 0;
  // a <- (I - delta_A K)^-1 a and b <- (I - delta_B K)^-1 b on the periodic grid, each with its
  // solve's delta, exactly (seed 003, Eqn 28; kernels/periodic_stencil_solve.h): one op for both
  // chemicals, so that the CPU can run the two transforms side by side.
  virtual void periodic_solve(PeriodicStencilSolve& solve_a, FieldF& a,
                              PeriodicStencilSolve& solve_b, FieldF& b) = 0;
  // x <- (I - s L)^-1 x with L the per-cell tensor's div(D(x) grad) (seed 003, Eqn 28 with
  // Table 1's last row; kernels/tensor_field_solve.h: BiCGSTAB to the solve's limits).
  virtual SolveReport tensor_field_solve(TensorFieldSolve& solve, FieldF& x, double s) = 0;

  // --- the second-order schemes (docs/numerics.md, "Reaction-diffusion in time")
  // The trapezoidal rule (Adams-Moulton 2) of the reaction over dt, per cell, in place
  // (kernels/reaction.h reaction_trapezoidal_tile).
  virtual void reaction_trapezoidal(FieldF& a, FieldF& b, const ReactionParams& p, float dt) = 0;
  // SBDF1/2's right-hand side over a, b; a_prev, b_prev take a, b (kernels/imex_rd.h).
  virtual void sbdf_rhs(FieldF& a, FieldF& b, FieldF& a_prev, FieldF& b_prev,
                        const SbdfRhsParams& p) = 0;
  // One ETDRK4 step of a and b on the periodic grid (kernels/periodic_etdrk4.h); reaction null:
  // diffusion alone.
  virtual void etdrk4_step(PeriodicEtdrk4& etdrk4, FieldF& a, FieldF& b,
                           const ReactionParams* reaction) = 0;
};

// The CPU device over a RowExecutor (the engine's serial or threads back end): every op in bands
// of rows; reductions add per-row partials in row order. Fields are the host's own.
class CpuDevice final : public Device {
 public:
  // On a block (block.halo set), ops compute block.block, boundary fills apply on the edges of
  // block.grid it touches, and exchange_halos() goes through block.halo.
  explicit CpuDevice(RowExecutor& ex, const DeviceBlock& block = {});
  ~CpuDevice() override;
  // The calling thread's serial device (RowExecutor::serial()), for tools and tests.
  static CpuDevice& serial();

  const char* name() const override;
  int workers() const override;
  // Every op on the whole grid; on a block, the ops that compute a block's cells from its own
  // cells and halo (copies, boundary fills, per-cell kernels, the explicit stencils) and those
  // that run on the gathered grid (gathers(); MacCormack's cell-centred form). An op it does not
  // support aborts (require): a fluid's own ops run on its gathered grid's device instead
  // (host/engine/fluid_step.h).
  bool supports(DeviceOp op) const override;
  RowExecutor& executor() override { return *ex_; }
  bool fields_on_host() const override { return true; }
  void reserve(Int2 grid) override;
  void finish() override {}
  const DeviceBlock& block() const override { return block_; }
  void exchange_halos(std::span<FieldF* const> fields, int depth) override;

  void copy(const FieldF& from, FieldF& to) override;
  void swap(FieldF& a, FieldF& b) override;
  void sync_to_host(const FieldF&) override {}
  void host_wrote(const FieldF&) override {}
  void host_wrote(const Field<uint8_t>&) override {}
  void host_wrote(const ReactionTable&) override {}
  using Device::host_wrote;

  void fill_boundary(FieldF& f, const BoundaryFill& fill) override;
  void fill_obstacle(FieldF& f, const Field<uint8_t>& solid, ObstacleRule rule) override;
  void add_boundary_values(FieldF& b, const BoundaryFill& fill, double scale) override;

  void add_splat(FieldF& f, const SplatParams& splat) override;
  void set_inflow_stripes(FieldF& dye, int stripes, BoundarySide side) override;
  void pressure_rhs(const FieldF& u, const FieldF& v, FieldF& rhs, const ProjectParams& p,
                    const FieldF* open_x, const FieldF* open_y) override;
  void face_velocities(const FieldF& u, const FieldF& v, const FieldF& p, FieldF& uf, FieldF& vf,
                       const ProjectParams& params, bool periodic) override;
  void subtract_gradient(const FieldF& p, FieldF& u, FieldF& v,
                         const ProjectParams& params) override;
  void advect_velocity(const FieldF& u0, const FieldF& v0, FieldF& u, FieldF& v,
                       const AdvectParams& p) override;
  void advect_scalars(std::span<const FieldF* const> q0, const FieldF& u, const FieldF& v,
                      std::span<FieldF* const> q, const AdvectParams& p) override;
  void advect_scalar_mac(const FieldF& q0, const FieldF& uf, const FieldF& vf, FieldF& q,
                         const AdvectParams& p) override;
  void maccormack_correct(std::span<const FieldF* const> q0, std::span<const FieldF* const> q_hat,
                          std::span<const FieldF* const> q_back, const FieldF& u, const FieldF& v,
                          std::span<FieldF* const> q, const AdvectParams& p, bool mac) override;
  FieldRange range(const FieldF& f) override;
  void restore_mass(FieldF& f, double missing, float lo, float hi) override;
  void stam_jacobi_sweeps(const FieldF& rhs, FieldF& a, FieldF& b, int sweeps,
                          const StamSweepParams& p, const BoundaryFill& fill,
                          const FieldF* start) override;

  SolveReport solve(LinearSolver& solver, const StencilOperator& op, const FieldF& b,
                    FieldF& x) override;

  void reaction_implicit(FieldF& a, FieldF& b, const ReactionParams& p, float dt) override;
  void reaction_table(FieldF& a, FieldF& b, const ReactionTable& table) override;
  void conductivity(const FieldF& a, const FieldF& theta0, FieldF& k,
                    const AnisotropyParams& p) override;
  SolveReport implicit_diffusion(ImplicitDiffusion& diffusion, FieldF& field,
                                 const FieldF* conductivity, const DiffusionStep& s) override;
  // Skips seed 001's quiescent cells with `quiet`.
  void explicit_rd(const FieldF& a, const FieldF& b, FieldF& a_out, FieldF& b_out,
                   ExplicitScheme scheme, const ExplicitRdParams& p, QuiescentBox* quiet,
                   int grow) override;
  void gray_scott9_steps(GrayScott9Blocked& blocked, FieldF& a, FieldF& b, int steps,
                         const GrayScott9Params& p, bool resume) override;
  void generalized_rd(const FieldF& a, const FieldF& b, FieldF& a_out, FieldF& b_out,
                      const GeneralizedTaps& k, const GeneralizedRdParams& p) override;
  void generalized_rd_steps(FieldF& a, FieldF& b, FieldF& a_out, FieldF& b_out,
                            const GeneralizedTaps& k, const GeneralizedRdParams& p,
                            int steps) override;
  void tensor_field_rd(const FieldF& a, const FieldF& b, FieldF& a_out, FieldF& b_out,
                       const Rank2FaceField& d, const GeneralizedRdParams& p) override;
  void periodic_solve(PeriodicStencilSolve& solve_a, FieldF& a, PeriodicStencilSolve& solve_b,
                      FieldF& b) override;
  SolveReport tensor_field_solve(TensorFieldSolve& solve, FieldF& x, double s) override;
  void reaction_trapezoidal(FieldF& a, FieldF& b, const ReactionParams& p, float dt) override;
  void sbdf_rhs(FieldF& a, FieldF& b, FieldF& a_prev, FieldF& b_prev,
                const SbdfRhsParams& p) override;
  void etdrk4_step(PeriodicEtdrk4& etdrk4, FieldF& a, FieldF& b,
                   const ReactionParams* reaction) override;

 private:
  // The rows of `cells` (a field's interior) in bands: f(Box2 rows) or f(Box2 rows, worker).
  template <class F>
  void for_bands(Box2 cells, const F& f);
  // Aborts, naming `op`, when this device does not support it: on a block, a fluid's own op (its
  // reductions, solves and face-velocity back-traces), which FluidStep runs on the gathered grid.
  void require(DeviceOp op) const;
  // The grid whose ghost ring the boundary fills write: the block's grid, or f's own size.
  Int2 domain_of(const FieldF& f) const { return block_.halo ? block_.grid : f.size(); }
  // Worker w's row scratch (seed 001's row sums): row_scratch_stride_ floats (reserve()).
  float* row_scratch(int worker) { return row_scratch_.data() + row_scratch_stride_ * worker; }

  RowExecutor* ex_;
  DeviceBlock block_;
  std::vector<float> row_scratch_;
  std::size_t row_scratch_stride_ = 0;
  // Per worker, the boxes of a step's cells that differ from seed 001's fixed point: its output
  // [w] and its input [workers() + w] (explicit_rd with a QuiescentBox).
  std::vector<Box2> band_boxes_;
  // On a block, the ops whose kernels read the whole grid (a global solve, an FFT, a stencil
  // that wraps its indices) run on the grid gathered from every block (HaloChannel::gather_all),
  // as every other block does: the same bits as one process, at one process's speed
  // (docs/scale-out.md); the block takes its cells back. A back-trace reads its gathered inputs
  // and computes only the block's cells. gathers(f): f covers a block that is not the whole
  // grid. gather(f, slot) fills whole-grid scratch `slot` (made at the first use) from every
  // block's f; take(whole, f) copies f's cells from it. The back-trace of kMaxAdvectFields
  // fields and their velocity uses the most slots.
  bool gathers(const FieldF& f) const;
  FieldF& gather(const FieldF& f, int slot);
  FieldF& whole_scratch(int slot);
  void take(const FieldF& whole, FieldF& f);
  static constexpr int kWholeSlots = kMaxAdvectFields + 2;
  std::array<FieldF, kWholeSlots> whole_;
};

template <class F>
void CpuDevice::for_bands(Box2 cells, const F& f) {
  ex_->for_rows(cells.height(), cells.width(), [&](int y0, int y1, int worker) {
    const Box2 rows{{cells.min.x, cells.min.y + y0}, {cells.max.x, cells.min.y + y1}};
    if constexpr (std::is_invocable_v<const F&, Box2, int>)
      f(rows, worker);
    else
      f(rows);
  });
}

}  // namespace ardcell
