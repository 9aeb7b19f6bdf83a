#pragma once
// OpenClDevice: the Device (host/engine/device.h) whose ops are the OpenCL twins of the kernels
// (kernels/cl/opencl_kernels.h), on fields resident in device memory across frames.
//
// Residency: each host field an op names gets a device copy the first time (allocated then:
// the first frame allocates, later ones do not) and a note of which side is current. A device op
// uploads an input only when the host wrote it since (host_wrote: painting, a loaded state, a
// reset), and leaves its outputs current on the device only; sync_to_host downloads a field
// when the host asks for it (the shown field, a saved state). So a frame moves nothing between
// host and device unless someone looks.
//
// Every op has a twin; the periodic FFT steps (seed 003's semi-implicit solve, ETDRK4) run by
// the device FFT (kernels/cl/opencl_fft.h), set up on the first step of a size, and the tensor
// field's semi-implicit solve by the device BiCGSTAB (kernels/cl/opencl_tensor_field_solve.h),
// set up on its first solve. A setting a twin lacks (ICCG or the tensor field's BiCGSTAB on a
// device without doubles; implicit diffusion with multigrid, or with Jacobi or RBGS sweeps to a
// tolerance; an FFT size with a prime factor above 7, which the device FFT cannot transform)
// runs that op on the CPU device instead: its inputs come to the host, its outputs go back when a
// device op next reads them, and the first time each op falls back, one line says so on stderr.
#if defined(ARDCELL_WITH_OPENCL)
#include <array>
#include <deque>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "host/engine/device.h"
#include "kernels/cl/opencl_diffusion.h"
#include "kernels/cl/opencl_fft.h"
#include "kernels/cl/opencl_iccg.h"
#include "kernels/cl/opencl_kernels.h"
#include "kernels/cl/opencl_tensor_field_solve.h"
#include "kernels/stencil_sweeps.h"

namespace ardcell {

class OpenClDevice final : public Device {
 public:
  // Builds (or takes from ctx's cache) the kernels' program; ops that fall back run on `cpu`.
  // Throws std::runtime_error with one line when the program cannot be built.
  OpenClDevice(OpenClContext& ctx, RowExecutor& cpu);
  ~OpenClDevice() override;

  const char* name() const override { return "opencl"; }
  int workers() const override;
  bool supports(DeviceOp op) const override;
  RowExecutor& executor() override { return cpu_.executor(); }
  bool fields_on_host() const override { return false; }
  void reserve(Int2 grid) override;

  void copy(const FieldF& from, FieldF& to) override;
  void swap(FieldF& a, FieldF& b) override;
  void sync_to_host(const FieldF& f) override;
  void host_wrote(const FieldF& f) override;
  void host_wrote(const Field<uint8_t>& mask) override;
  void host_wrote(const ReactionTable& table) override;
  using Device::host_wrote;
  void finish() override;
  // The whole grid: a block of a decomposed grid runs on the CPU (Engine refuses one here).
  const DeviceBlock& block() const override { return cpu_.block(); }
  void exchange_halos(std::span<FieldF* const>, int) override {}

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
  // One launch a sweep, or (sweeps > 1, a fill that is not periodic) ghost-zone temporal
  // blocking in __local memory, as many sweeps a launch as the local memory holds.
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
  // Computes every cell (no QuiescentBox: one launch over the fields is cheaper than finding
  // the box on the device); the whole grid only (grow 0).
  void explicit_rd(const FieldF& a, const FieldF& b, FieldF& a_out, FieldF& b_out,
                   ExplicitScheme scheme, const ExplicitRdParams& p, QuiescentBox*,
                   int grow) override;
  // On the CPU (the engine steps seed 001 with the 9-point twin here instead), with one line.
  void gray_scott9_steps(GrayScott9Blocked& blocked, FieldF& a, FieldF& b, int steps,
                         const GrayScott9Params& p, bool resume) override;
  void generalized_rd(const FieldF& a, const FieldF& b, FieldF& a_out, FieldF& b_out,
                      const GeneralizedTaps& k, const GeneralizedRdParams& p) override;
  // The per-cell tensor field's explicit step, on the device.
  void tensor_field_rd(const FieldF& a, const FieldF& b, FieldF& a_out, FieldF& b_out,
                       const Rank2FaceField& d, const GeneralizedRdParams& p) override;
  // By the device FFT (OpenClPeriodicSolve); on the CPU, with one line, at a size it lacks.
  void periodic_solve(PeriodicStencilSolve& solve_a, FieldF& a, PeriodicStencilSolve& solve_b,
                      FieldF& b) override;
  // By the device BiCGSTAB (OpenClTensorFieldSolve, made on the solve's first use) on the
  // resident faces; on the CPU, with one line, on a device without doubles.
  SolveReport tensor_field_solve(TensorFieldSolve& solve, FieldF& x, double s) override;
  void reaction_trapezoidal(FieldF& a, FieldF& b, const ReactionParams& p, float dt) override;
  void sbdf_rhs(FieldF& a, FieldF& b, FieldF& a_prev, FieldF& b_prev,
                const SbdfRhsParams& p) override;
  // By the device FFT (OpenClEtdrk4); on the CPU, with one line, at a size it lacks.
  void etdrk4_step(PeriodicEtdrk4& etdrk4, FieldF& a, FieldF& b,
                   const ReactionParams* reaction) override;

  OpenClKernels& kernels() { return *cl_; }
  // Bytes moved between host and device so far (tests: a steady frame moves none).
  std::int64_t uploaded_bytes() const { return uploaded_; }
  std::int64_t downloaded_bytes() const { return downloaded_; }

 private:
  enum class Current : uint8_t { kHost, kDevice, kBoth };
  struct Mirror {
    const void* host = nullptr;  // the FieldF (or mask) this copies
    DeviceField device;
    Current current = Current::kBoth;
  };
  struct MaskMirror {
    const Field<uint8_t>* host = nullptr;
    DeviceField device;  // 1.0 where solid (upload_mask)
    bool stale = true;
  };
  struct DiffusionTwin {
    const ImplicitDiffusion* cpu = nullptr;
    std::unique_ptr<OpenClDiffusion> device;
  };
  // One coarse grid of a multigrid V-cycle: the CPU solver's operator, uploaded, and the
  // level's correction, right-hand side and residual.
  struct CoarseLevel {
    ClStencilOperator op;
    DeviceField x, b, r;
  };
  // A StencilOperator's coefficients on the device, its null space (analysed on the host), the
  // solver scratch of its size and, for multigrid, the coarse levels of `levels_of`; for ICCG,
  // the solver's vectors and pivots (factored: of the operator uploaded last).
  struct OperatorTwin {
    const StencilOperator* host = nullptr;
    ClStencilOperator device;
    std::unique_ptr<stencil::NullSpace> null_space;
    DeviceField null_mask, other, r;
    std::vector<CoarseLevel> levels;
    const LinearSolver* levels_of = nullptr;
    std::unique_ptr<OpenClIccg> iccg;
    bool factored = false;
    bool stale = true;
  };

  // A generalized stencil's weights on the device, uploaded again when they change.
  struct StencilTwin {
    const GeneralizedTaps* host = nullptr;
    GeneralizedTaps uploaded;
    OpenClBuffer weights;
  };
  const OpenClBuffer& stencil_weights(const GeneralizedTaps& k);

  // The device twin of a TensorFieldSolve (its vectors: made on its first solve).
  struct TensorSolveTwin {
    const TensorFieldSolve* cpu = nullptr;
    std::unique_ptr<OpenClTensorFieldSolve> device;
  };

  // The FFT twins of a CPU solve or ETDRK4 step (made on its first use: tables and buffers), or
  // none (device null) and why, for a size the device FFT cannot transform.
  template <class Cpu, class OnDevice>
  struct FftTwin {
    const Cpu* cpu = nullptr;
    Int2 size{};
    std::unique_ptr<OnDevice> device;
    std::string why_not;
  };
  using PeriodicSolveTwin = FftTwin<PeriodicStencilSolve, OpenClPeriodicSolve>;
  using Etdrk4Twin = FftTwin<PeriodicEtdrk4, OpenClEtdrk4>;
  // The twin of `cpu` in `twins`, made on its first use with transforms of `batch` fields.
  template <class Cpu, class OnDevice>
  FftTwin<Cpu, OnDevice>& fft_twin(std::deque<FftTwin<Cpu, OnDevice>>& twins, const Cpu& cpu,
                                   int batch);
  // The transforms of `batch` fields of `size`, shared by the twins of that size (made once).
  ClFft2d& fft(Int2 size, int batch);

  Mirror& mirror(const FieldF& f);
  // f's mirror, uploaded first when the host wrote f since.
  Mirror& current_on_device(const FieldF& f);
  const DeviceField& mask(const Field<uint8_t>& m);
  // op's twin, uploaded first when the host wrote op since; with the coarse operators of
  // `solver` when it is a multigrid solver (prepare()d on op).
  OperatorTwin& operator_twin(const StencilOperator& op, const LinearSolver& solver);
  // Subtracts f's mean over the null space from its cells (NullSpace::remove_mean); a no-op
  // when op is not singular.
  void remove_null_mean(DeviceField& f, const OperatorTwin& t);
  SolveReport solve_sweeps(const SolverSettings& settings, OperatorTwin& t, const DeviceField& b,
                           DeviceField& x);
  SolveReport solve_multigrid(const SolverSettings& settings, OperatorTwin& t, const DeviceField& b,
                              DeviceField& x);
  SolveReport solve_iccg(const SolverSettings& settings, OperatorTwin& t, const DeviceField& b,
                         DeviceField& x);
  // One V-cycle on x for A x = b, A = op; `coarser` are the levels below op's grid, r op's
  // residual scratch.
  void v_cycle(const ClStencilOperator& op, const DeviceField& b, DeviceField& x, DeviceField& r,
               std::span<CoarseLevel> coarser);
  // |f|^2 without its null-space component (stencil::NullSpace::consistent_part).
  double consistent_part(double all, const DeviceField& f, const OperatorTwin& t);
  double relative_residual(OperatorTwin& t, const DeviceField& b, const DeviceField& x, double bb);
  // The device copy, current (uploaded if the host wrote it): for an op that reads f, or writes
  // part of it.
  const DeviceField& in(const FieldF& f);
  DeviceField& out(FieldF& f);
  // The host copy, current (downloaded if a device op wrote it), for an op run on the CPU.
  void host_in(const FieldF& f);
  void host_out(FieldF& f);
  // One line on stderr the first time `op` runs on the CPU instead, naming the setting and why.
  void say_fallback(DeviceOp op, const char* setting, const char* why);

  OpenClContext& ctx_;
  std::unique_ptr<OpenClKernels> cl_;
  CpuDevice cpu_;
  std::deque<Mirror> mirrors_;  // a deque: references stay valid as mirrors are added
  std::deque<MaskMirror> masks_;
  std::deque<DiffusionTwin> diffusions_;
  std::deque<OperatorTwin> operators_;
  std::deque<StencilTwin> stencils_;
  std::deque<std::unique_ptr<ClFft2d>> ffts_;
  std::deque<PeriodicSolveTwin> periodic_twins_;
  std::deque<Etdrk4Twin> etdrk4_twins_;
  std::deque<TensorSolveTwin> tensor_solves_;
  ClRowPartials partial_sum_, partial_lo_, partial_hi_;
  std::vector<double> host_lo_, host_hi_;
  ClReactionTable table_;
  bool table_stale_ = true;
  std::array<bool, std::size_t(DeviceOp::kCount)> said_{};
  std::int64_t uploaded_ = 0, downloaded_ = 0;
};

}  // namespace ardcell
#endif
