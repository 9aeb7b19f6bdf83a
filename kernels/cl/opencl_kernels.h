#pragma once
// Host side of the OpenCL twins in kernels/cl/*.cl: one program built once from every embedded
// source (common.cl first), and one launcher per tile kernel, with the C++ kernel's parameters
// passed as kernel arguments (changing one never rebuilds). A launcher takes device fields and
// the region of cells to write, like its C++ twin takes Views and a Box2; it cuts the region
// into tiles (Tiling) that the work-groups walk SPE-style, double-buffered in __local memory.
// Launchers only enqueue: OpenClContext::finish() (or a read) waits.
#if defined(ARDCELL_WITH_OPENCL)
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "kernels/advect.h"
#include "kernels/anisotropy.h"
#include "kernels/explicit_rd.h"
#include "kernels/generalized_rd.h"
#include "kernels/imex_rd.h"
#include "kernels/project.h"
#include "kernels/reaction.h"
#include "kernels/reaction_table.h"
#include "kernels/sources.h"
#include "kernels/stam_sweeps.h"
#include "kernels/stencil_operator.h"
#include "runtime/boundary.h"
#include "runtime/opencl/opencl_context.h"

namespace ardcell {

// How a launch maps onto the device: tiles of tile_w x tile_h cells (the local store of one
// work-group holds two slots of them, plus halos), work_group work-items per work-group, and
// groups_per_unit persistent work-groups per compute unit (each walks many tiles).
struct ClTiling {
  int tile_w = 64;
  int tile_h = 16;
  int work_group = 128;
  int groups_per_unit = 16;
};

// The tiling OpenClKernels starts with on a device. A GPU (on-chip __local memory): 128
// work-items per group, each group striding over the cells of a 64 x 16 tile, so neighbouring
// work-items touch neighbouring cells (coalesced), and 16 groups per compute unit, so a 1024^2
// grid is one tile per group and enough warps are resident to hide memory latency (on an H200,
// Table 1 fluid+RD at 1024^2 ran 1.9x (stream) and 1.7x (blocked) faster than with 64
// work-items and 4 groups per unit; bench/RESULTS_OPENCL.md). A CPU (PoCL; __local emulated in
// cached global memory): ONE work-item per group, so the group's loop over a tile row is an
// ordinary contiguous loop that the kernel compiler vectorises, and the copy into the local store
// is a memcpy; bigger tiles (256 x 32: two slots of two fields stay in L2) amortise the per-tile
// overhead. With 64 work-items a PoCL group runs each work-item's strided walk in turn (no
// vectorisation, a cache line touched once per work-item): 3-4x slower than the threads back end at
// 1024^2, against 0.5-0.8x with this choice (bench/RESULTS_OPENCL.md).
ClTiling default_tiling(const OpenClDeviceInfo& device);

// A reaction model's parameters as reaction.cl's p0..p4 (see its table; rd_rates' order).
void cl_reaction_args(const ReactionParams& p, float q[5]);

// AnisotropyParams as diffusion.cl's aniso_t (passed by value: one kernel argument).
struct ClAnisotropyArgs {
  cl_int kind;
  cl_float isotropic_value, a1, a2;
  cl_int lobes;
  cl_float lobe_speed[kMaxLobes];
  cl_int samples;
  cl_float sample[kMaxPolarSamples];
  cl_float theta0, gradient_epsilon;
};
ClAnisotropyArgs cl_anisotropy_args(const AnisotropyParams& p);

// A StencilOperator (kernels/stencil_operator.h) in device memory, each field with the host
// field's layout (diag: size, wx: size + (1, 0), wy: size + (0, 1), halo 1).
struct ClStencilOperator {
  Int2 size{};
  DeviceField diag, wx, wy;
  BoundaryKind boundary_x = BoundaryKind::kNeumann;
  BoundaryKind boundary_y = BoundaryKind::kNeumann;

  static ClStencilOperator allocate(OpenClContext& ctx, Int2 size, BoundaryKind boundary_x,
                                    BoundaryKind boundary_y);
  // Copies a host operator of the same size and boundaries (tests; the frame assembles).
  void upload(OpenClContext& ctx, const StencilOperator& op);
};

// A reaction table (kernels/reaction_table.h) in device memory.
struct ClReactionTable {
  OpenClBuffer data;  // n * n pairs (A^, B^)
  int n = 0;
  float a_lo = 0, a_hi = 1, b_lo = 0, b_hi = 1;

  // Copies `table` in, allocating only when its size changed (a new F, k or dt: a write).
  void upload(OpenClContext& ctx, const ReactionTableView& table);
};

// A solid (or null-space) mask on the device: a DeviceField of floats, 1 where mask != 0 and 0
// elsewhere, with the layout of a FieldF of the mask's size and halo 1 (so it shares stride and
// origin with the fields it masks). The mask's own halo, when it has one, is copied too; a
// halo-0 mask gets a halo of zeros. Converted and uploaded once (blocking).
DeviceField upload_mask(OpenClContext& ctx, const Field<uint8_t>& mask);

// Per-row partials of a reduction on the device: row j at element j, in the device's `real`
// (double where it has cl_khr_fp64, float otherwise; common.cl). Allocated by
// OpenClKernels::row_partials; read() returns them as doubles, sum() adds rows [y0, y1) in row
// order from 0.0 (as RowExecutor::sum_rows), so with doubles on the device the total has the
// C++ reduction's bits.
struct ClRowPartials {
  OpenClBuffer data;
  int rows = 0;
  std::size_t real_bytes = sizeof(double);
  // Host copies the reads land in (sized once, so reading allocates nothing).
  mutable std::vector<double> host;
  mutable std::vector<float> host_floats;

  // Blocking reads (they wait for the kernels that write the partials): out[j] for j in
  // [y0, y1), out indexed by the absolute row as the C++ kernels' partials.
  void read(OpenClContext& ctx, int y0, int y1, double* out) const;
  double sum(OpenClContext& ctx, int y0, int y1) const;
  // Rows [y0, y1) of `host` (where read(..., host.data()) left them) added in row order: for
  // kernels that write several reductions side by side, read once.
  double added(int y0, int y1) const;
  // Two reductions of `rows` rows written side by side (rows [0, rows) and [rows, 2 rows)): one
  // read, each added in row order.
  std::array<double, 2> sum_pair(OpenClContext& ctx, int rows) const;
};

class OpenClKernels {
 public:
  // The program's name in OpenClContext's cache: building it twice on one context is a no-op.
  static constexpr const char* kProgramKey = "ardcell";

  // Builds (once per context) the program of every embedded .cl file. Null + *error (summary
  // line, then the build log) on failure. The tiling is default_tiling's, or the environment's
  // ARDCELL_CL_TILING="tile_w,tile_h,work_group,groups_per_unit" (tuning on a new device; a
  // malformed value is an error).
  static std::unique_ptr<OpenClKernels> create(OpenClContext& ctx, std::string* error);
  // For choose_backend's OpenClPrepare: builds the program, true on success.
  static bool prepare(OpenClContext& ctx, std::string* error);

  OpenClContext& context() { return ctx_; }
  cl_kernel kernel(const char* name);
  ClTiling& tiling() { return tiling_; }
  // Whether the device has doubles (cl_khr_fp64): common.cl's `real` is double, and the kernels
  // that need double vectors (iccg.cl) are built.
  bool has_fp64() const { return real_bytes_ == sizeof(double); }
  // One work-item per cell of region (2D), for gathers and halo-0 kernels.
  void enqueue_cells(cl_kernel k, Box2 region);
  // One work-item per row of [y0, y1) (1D), for the row reductions.
  void enqueue_rows(cl_kernel k, int y0, int y1);
  // One work-item per element of a vector of n (1D, work-groups of 64: PoCL compiles a kernel
  // once per work-group size).
  void enqueue_items(cl_kernel k, int n);

  // Twin of reaction_implicit_tile (Eqn 6; gray_scott_implicit_tile when p.model is
  // Gray-Scott). Outputs may alias inputs.
  void reaction_implicit(const DeviceField& a, const DeviceField& b, DeviceField& a_out,
                         DeviceField& b_out, Box2 region, const ReactionParams& p, float dt);

  // Twin of reaction_trapezoidal_tile (the trapezoidal rule over dt; outputs may alias inputs).
  void reaction_trapezoidal(const DeviceField& a, const DeviceField& b, DeviceField& a_out,
                            DeviceField& b_out, Box2 region, const ReactionParams& p, float dt);
  // Twin of sbdf_rhs_tile (kernels/imex_rd.h), in place over region.
  void sbdf_rhs(DeviceField& a, DeviceField& b, DeviceField& a_prev, DeviceField& b_prev,
                Box2 region, const SbdfRhsParams& p);

  // Twin of reaction_table_tile (outputs may alias inputs).
  void reaction_table(const DeviceField& a, const DeviceField& b, DeviceField& a_out,
                      DeviceField& b_out, Box2 region, const ClReactionTable& table);

  // Twin of conductivity_tile (Eqns 15, 16, polar samples): k = a(theta(A) + theta0) over
  // region. theta0 null: p.theta0 everywhere. Reads a over region grown by 1 (fill it first).
  void conductivity(const DeviceField& a, const DeviceField* theta0, DeviceField& k, Box2 region,
                    const AnisotropyParams& p);
  // Twin of reassemble_stencil_operator (Eqns 13, 17/19): identity I - scale div(k grad .),
  // k per cell averaged onto faces; conductivity null means k = 1. With a solid mask
  // (upload_mask, op's layout), then isolate_solid_cells(op, solid, 0): the solid cells' faces
  // cut, their fluid neighbours' diagonals without them, their rows the identity.
  void assemble_stencil_operator(ClStencilOperator& op, float identity, float scale,
                                 const DeviceField* conductivity,
                                 const DeviceField* solid = nullptr);
  // Twins of kernels/stencil_sweeps.h (whole interior; x_out must differ from x_in).
  void stencil_jacobi_sweep(const ClStencilOperator& op, const DeviceField& b,
                            const DeviceField& x_in, DeviceField& x_out);
  void stencil_rbgs_half_sweep(const ClStencilOperator& op, const DeviceField& b, DeviceField& x,
                               int color);
  void apply_stencil_operator(const ClStencilOperator& op, const DeviceField& x, DeviceField& y);
  // `sweeps` x stencil_rbgs_half_sweep (colour 0, then 1) in one launch of one work-group: for
  // small multigrid levels, whose cells cost less than a launch per half sweep.
  void stencil_rbgs_sweeps_one_group(const ClStencilOperator& op, const DeviceField& b,
                                     DeviceField& x, int sweeps);
  // Twins of kernels/multigrid_solver.cpp's transfers (multigrid.cl): coarse = the 2x2 sums of
  // fine (coarse.size = (fine.size + 1) / 2), and fine += the coarse value of each cell's
  // aggregate.
  void restrict_sum(const DeviceField& fine, DeviceField& coarse);
  void prolong_add(const DeviceField& coarse, DeviceField& fine);
  // ImplicitDiffusion::step's right-hand side: field (or 2 field - ax, Crank-Nicolson), plus
  // the Dirichlet boundary value's flux g k on each boundary side of a cell (g = 0: none) that
  // is not solid (solid: upload_mask, field's layout; null: none). g in the device's `real`.
  void diffusion_rhs(const DeviceField& field, const DeviceField* ax, DeviceField& rhs,
                     const DeviceField* conductivity, double g, const DeviceField* solid = nullptr);

  // Twin of fill_boundary on a whole field: the ghost ring of the domain (f.size).
  void fill_boundary(DeviceField& f, const BoundaryFill& fill);
  // Twins of kernels/stam_sweeps.h (x_out must differ from x_in).
  void stam_jacobi_sweep(const DeviceField& x0, const DeviceField& x_in, DeviceField& x_out,
                         Box2 region, const StamSweepParams& p);
  // `sweeps` Jacobi sweeps (each followed by `fill`, which must not be periodic) in one
  // residency of each tile (ghost-zone temporal blocking) over the whole interior: equal to
  // `sweeps` x (stam_jacobi_sweep + fill_boundary). tile: core size (see blocked_tile).
  void stam_jacobi_blocked(const DeviceField& rhs, const DeviceField& x_in, DeviceField& x_out,
                           int sweeps, const StamSweepParams& p, const BoundaryFill& fill,
                           Int2 tile);
  // A tile for stam_jacobi_blocked that fits the device's local memory ({0, 0}: none does).
  Int2 blocked_tile(int sweeps) const;
  // The sweeps per residency (at most `wanted`, at least 1) whose tile fits the local memory
  // and is at least half of the cells a residency computes.
  int blocked_sweeps(int wanted) const;
  void stam_rbgs_half_sweep(const DeviceField& x0, DeviceField& x, Box2 region, int color,
                            const StamSweepParams& p);
  // Twins of kernels/project.h.
  void pressure_rhs(const DeviceField& u, const DeviceField& v, DeviceField& rhs, Box2 region,
                    const ProjectParams& p);
  // Twin of pressure_rhs_cut: open_x, open_y have their own layouts (face fields).
  void pressure_rhs_cut(const DeviceField& u, const DeviceField& v, const DeviceField& open_x,
                        const DeviceField& open_y, DeviceField& rhs, Box2 region,
                        const ProjectParams& p);
  void subtract_gradient(const DeviceField& p, DeviceField& u, DeviceField& v, Box2 region,
                         const ProjectParams& params);
  // Twins of kernels/advect.h (q0 read over its whole allocation, as a whole-field View).
  void advect_scalar(const DeviceField& q0, const DeviceField& u, const DeviceField& v,
                     DeviceField& q, Box2 region, const AdvectParams& p);
  void advect_velocity(const DeviceField& u0, const DeviceField& v0, DeviceField& u, DeviceField& v,
                       Box2 region, const AdvectParams& p);
  // Three scalars along one shared back-trace: bit for bit three advect_scalar calls, with the
  // velocity read and the departure point computed once (outputs must not alias the sources).
  void advect_scalar3(const DeviceField& q0a, const DeviceField& q0b, const DeviceField& q0c,
                      const DeviceField& u, const DeviceField& v, DeviceField& qa, DeviceField& qb,
                      DeviceField& qc, Box2 region, const AdvectParams& p);
  // Twins of kernels/sources.h.
  void add_scaled(const DeviceField& s, DeviceField& x, Box2 region, float scale);
  void add_splat(DeviceField& f, Box2 region, const SplatParams& splat);
  // Twin of set_inflow_stripes (kernels/sources.h): the boundary cells of `side`.
  void set_inflow_stripes(DeviceField& dye, int stripes, BoundarySide side);

  // Twin of face_velocities (kernels/project.h) with top_faces = true. u, v, p share one
  // layout (read over region grown by 1); uf is a field of (nx + 1) x ny, vf of nx x (ny + 1).
  void face_velocities(const DeviceField& u, const DeviceField& v, const DeviceField& p,
                       DeviceField& uf, DeviceField& vf, Box2 region, const ProjectParams& params);
  // Twin of advect_scalar_mac (kernels/advect.h): q0, uf, vf read over their whole allocations
  // (as whole-field Views). q0 and q share one layout; q must not alias q0.
  void advect_scalar_mac(const DeviceField& q0, const DeviceField& uf, const DeviceField& vf,
                         DeviceField& q, Box2 region, const AdvectParams& p);
  // Twins of maccormack_correct and maccormack_correct_mac (kernels/advect.h): one field; q may
  // be q_hat. (u, v): the cell-centred velocity, or the face velocities with `mac`.
  void maccormack_correct(const DeviceField& q0, const DeviceField& q_hat,
                          const DeviceField& q_back, const DeviceField& u, const DeviceField& v,
                          DeviceField& q, Box2 region, const AdvectParams& p, bool mac);
  // Twin of fill_obstacle (runtime/boundary.h); solid from upload_mask, f's layout. Reads f
  // and solid over region grown by 1.
  void fill_obstacle(DeviceField& f, const DeviceField& solid, Box2 region, ObstacleRule rule);
  // The whole allocation, halo and padding included (fluid_step's copy_all); same layout.
  void copy_field(const DeviceField& from, DeviceField& to);
  // Every float of the allocation, halo and padding included, set to `value` (FieldF::fill).
  void fill_field(DeviceField& f, float value);
  // Twin of add_boundary_values (kernels/stencil_operator.h) on the domain b.size.
  void add_boundary_values(DeviceField& b, const BoundaryFill& fill, double scale);

  // Per-row partials of the reductions (see ClRowPartials), rows [0, rows).
  ClRowPartials row_partials(int rows) const;
  // Twins of kernels/field_reductions.h over rows [y0, y1) of f, x in [0, f.size.x); the
  // partials buffers need at least y1 rows.
  void row_sums(const DeviceField& f, int y0, int y1, ClRowPartials& partials);
  void row_ranges(const DeviceField& f, int y0, int y1, ClRowPartials& sum, ClRowPartials& lo,
                  ClRowPartials& hi);
  void row_mass_weights(const DeviceField& f, int y0, int y1, float lo, float hi,
                        ClRowPartials& partials);
  void row_masked_sums(const DeviceField& f, const DeviceField& mask, int y0, int y1,
                       ClRowPartials& partials);
  void restore_mass_rows(DeviceField& f, int y0, int y1, double k, float lo, float hi);
  // Twins of kernels/stencil_sweeps.cpp's reductions over the whole interior: residual (r =
  // b - A x when r is not null, the row sums of r^2 into partials: their sum() is residual()'s
  // return), norm2_squared's row sums of squares, and NullSpace::remove_mean's map (f -= mean
  // where mask != 0; the mean from row_masked_sums over the null-space mask).
  void residual(const ClStencilOperator& op, const DeviceField& b, const DeviceField& x,
                DeviceField* r, ClRowPartials& partials);
  void row_sums_of_squares(const DeviceField& f, int y0, int y1, ClRowPartials& partials);
  void subtract_masked(DeviceField& f, const DeviceField& mask, float mean);

  // Twins of kernels/explicit_rd.h (read halo 1; outputs must not alias inputs).
  void explicit_rd5(const DeviceField& a, const DeviceField& b, DeviceField& a_out,
                    DeviceField& b_out, Box2 region, const ExplicitRdParams& p);
  void explicit_rd9(const DeviceField& a, const DeviceField& b, DeviceField& a_out,
                    DeviceField& b_out, Box2 region, const ExplicitRdParams& p);
  // Twin of kernels/generalized_rd.h over the whole interior (periodic, reads no halo); the
  // stencil's groups as stencil_groups() uploaded them: kStencilGroupFloats floats, the number of
  // groups, then per group its tap count n, its weight and n pairs (dx, dy), as
  // GeneralizedTaps orders them.
  static constexpr int kStencilGroupFloats = 1 + 2 * 25 + 2 * 25;
  OpenClBuffer stencil_groups(const GeneralizedTaps& k);
  void generalized_rd(const DeviceField& a, const DeviceField& b, DeviceField& a_out,
                      DeviceField& b_out, const OpenClBuffer& weights,
                      const GeneralizedRdParams& p);
  // Twin of tensor_field_rd_rows (kernels/generalized_rd.h) over the whole interior (periodic,
  // reads no halo); the four face fields (Rank2FaceField's, halo 0) share one layout.
  void tensor_field_rd(const DeviceField& a, const DeviceField& b, DeviceField& a_out,
                       DeviceField& b_out, const DeviceField& x_xx, const DeviceField& x_xy,
                       const DeviceField& y_xy, const DeviceField& y_yy,
                       const GeneralizedRdParams& p);
  // gray_scott9_explicit_tile's twin (no scratch: each work-item sums its own columns).
  void gray_scott9_explicit(const DeviceField& a, const DeviceField& b, DeviceField& a_out,
                            DeviceField& b_out, Box2 region, const GrayScott9Params& p);

 private:
  OpenClKernels(OpenClContext& ctx, cl_program program) : ctx_(ctx), program_(program) {}
  // Work-groups for `tiles` tiles, and the global size.
  std::size_t groups_for(int tiles) const;
  void check_same_layout(const DeviceField& a, const DeviceField& b) const;
  // The four fields of a per-cell reaction launch share a's layout.
  void check_same_layout(const DeviceField& a, const DeviceField& b, const DeviceField& c,
                         const DeviceField& d) const {
    check_same_layout(a, b);
    check_same_layout(a, c);
    check_same_layout(a, d);
  }
  // The explicit RD twins' argument checks; false when the region is empty (nothing to do).
  bool check_explicit_rd_args(const DeviceField& a, const DeviceField& b, const DeviceField& a_out,
                              const DeviceField& b_out, Box2 region) const;
  void check_operator_layout(const ClStencilOperator& op, const DeviceField& f) const;
  // A tiled launch: persistent work-groups walk the region's tiles (common.cl).
  void enqueue_tiled(cl_kernel k, Box2 region);
  void row_reduction(const char* name, const DeviceField& f, int y0, int y1,
                     ClRowPartials& partials);
  void check_partials(const ClRowPartials& partials, int y1) const;
  void explicit_rd(const DeviceField& a, const DeviceField& b, DeviceField& a_out,
                   DeviceField& b_out, Box2 region, const ExplicitRdParams& p, bool nine_point);

  OpenClContext& ctx_;
  cl_program program_;
  ClTiling tiling_;
  std::size_t real_bytes_ = sizeof(double);  // the device's `real` (common.cl)
};

}  // namespace ardcell
#endif
