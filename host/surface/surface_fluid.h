#pragma once
// Stable fluids on a patched surface (seed 004, Sec. 5 and 7.3.1, after Stam 2003): a velocity
// field on the patches' MAC grids, a passive dye s per cell with sources, and one step in the
// seed's order (the per-patch operators are kernels/surface_mac.h):
//   dye:      s1 = s + dt S (clamped to 1),  (I - dt kappa lap) s2 = s1,  s3 = s2 advected by u^n
//   velocity: u^A = u^n advected by itself,  u^F = u^A + dt f,  (I - dt nu A) u^V = u^F,
//             lap phi = div u^V,  u^{n+1} = u^V - grad phi
// (the seed's Sec. 5: advection from a divergence-free field, projection last).
//
// Convention: u holds contravariant components, u = u^i X_i with X_i = dX/dx^i, as the seed's
// divergence 1/sqrt(G) d_i (sqrt(G) u^i) and gradient g^ij d_j phi require. A point moving with
// the fluid moves in the parameter plane at dx^i/dt = u^i, so the semi-Lagrangian trace uses u
// itself. The seed traces with ubar = (g^11 u^1 + g^12 u^2, g^12 u^1 + g^22 u^2), which is the
// parametric velocity of covariant components u_i; with its own contravariant u it applies the
// inverse metric twice (on a patch stretched by L it moves the dye L^2 times too slowly).
// tests/host/surface/surface_fluid_test.cpp carries dye around a torus and back with u, and not
// with the seed's ubar (FluidTrace::kSeedInverseMetric, kept for that comparison).
//
// Across patch edges: a vector maps by the transition's Jacobian, v' = R v (patch_topology.h).
// A ghost face of p at point x lies at y = R x + t in the neighbour q, on a face of q: an
// x1-face of p lands on an x1-face of q where R keeps the axes and on an x2-face where it swaps
// them. Since u_p = R^T u_q, the ghost's u^1 is R_11 u_q^1 (axes kept) or R_21 u_q^2 (swapped):
// a component may become the other component, with a sign. Corner ghosts: the diagonal patch's
// face at a regular corner, the bilinear extrapolation g1 + g2 - c at an extraordinary or
// boundary vertex (as PatchGrid). The faces on a shared edge are stored by both patches; after
// every update each takes the mean of the two outward fluxes h sqrt(G) u^n, so what leaves one
// patch enters the other and the divergence is conservative. On a boundary edge (open mesh) the
// normal component is 0 and the ghosts mirror it (a free-slip wall).
//
// Advection: from each sample (face or cell) the trace goes back along the velocity by the
// midpoint rule, x_mid = x - dt/2 u(x), x_back = x - dt u(x_mid), walking the segment across
// patch edges one edge at a time (as many patches as it takes), carrying the displacement
// through each transition; the value at the end is bilinear in the patch where it lands and a
// vector is turned back by the quarter turns accumulated on the way (the seed's M_s). The
// velocity's contravariant components are carried along the trace as scalars in that frame: the
// connection terms (Gamma^i_jk u^j u^k) are ignored, as the viscosity ignores them; this is not
// parallel transport.
//
// Forces (Sec. 8): gravity, f = strength s down_T with down_T the downward unit vector projected
// on the tangent plane, f^i = g^ij <down, X_j> (the seed's, where down follows the viewer; here
// down is a direction in the mesh's coordinates, set_down changes it: `ardcell live --fluid
// gravity` sets it to the screen's down as the view turns, host/surface/surface_simulation.h); and
// "walking": in every patch a point circles the patch's centre in its parameter plane and
// pushes the fluid along its path, f = strength T / |T| exp(-|x - w|^2 / width^2), T the circle's
// tangent, |T| its length on the surface.
//
// The projection solves the Poisson problem by multigrid V-cycles (SurfaceMultigrid::
// solve_poisson; the seed's Sec. 7.3.1): phi to a relative residual; the projected field's
// divergence is that residual (kernels/surface_mac.h: div grad = lap, the same operator).
//
// Dye total: semi-Lagrangian advection is not conservative (bilinear interpolation along
// converging and diverging traces): the total sum sqrt(G) h^2 s drifts at each advection. With
// conserve_dye each advection keeps the total it started from: the advected dye is clamped to
// [0, 1] and multiplied by the one global factor c with sum sqrt(G) h^2 min(1, c s) = the total
// before (c = before / after unless cells reach 1: those are held at 1 and the others carry the
// rest), so the dye stays within [0, 1] and the total is kept to rounding whenever it fits, i.e.
// the total before is at most the area of the cells the advected dye covers (otherwise every
// such cell ends at 1). Sources (capped at 1) and the dye's diffusion change the total; only
// advection is corrected.
//
// Work runs per patch (per shared edge when stitching) on the operator's RowExecutor: the same
// bits for any number of workers. Nothing allocates in a step after construction (the first
// projection and dye diffusion run in the constructor to size the solvers' scratch).
#include <array>
#include <cstdint>
#include <vector>

#include "host/surface/limit_surface.h"
#include "host/surface/patch_metric.h"
#include "host/surface/surface_laplacian.h"
#include "host/surface/surface_multigrid.h"
#include "kernels/surface_mac.h"

namespace ardcell {

// The number of connected pieces of the patches (across shared edges; patch_pieces).
int connected_pieces(const PatchTopology& topo);

enum class FluidForce : std::uint8_t { kNone, kGravity, kWalk };
// The parametric velocity of the semi-Lagrangian trace: u itself (contravariant components), or
// the seed's ubar = g^-1 u (g^ij at the nearest cell centre), kept to show what it does.
enum class FluidTrace : std::uint8_t { kContravariant, kSeedInverseMetric };

struct SurfaceFluidParams {
  double dt = 0.05;
  FluidForce force = FluidForce::kGravity;
  double strength = 1;                   // gravity: acceleration per unit s; walk: acceleration
  std::array<double, 3> down{0, 0, -1};  // gravity's direction (need not be unit)
  double walk_radius = 0.25;             // the walker's circle, parameter units
  double walk_width = 0.08;              // the push's Gaussian width, parameter units
  double walk_period = 4;                // time of one turn
  double viscosity = 0;                  // nu, surface area per unit time (0: none)
  double dye_diffusion = 0;              // kappa, surface area per unit time (0: none)
  double source_rate = 1;                // dye added per unit time at the sources (0: none)
  double source_radius = 0.15;           // around each patch's centre, parameter units (at
                                         // least the cells at the centre)
  bool conserve_dye = false;             // each advection keeps the dye's total (in [0, 1])
  FluidTrace trace = FluidTrace::kContravariant;
  DiffusionSolve projection{1e-6, 100};  // relative residual, V-cycles
  DiffusionSolve viscous{1e-6, 200};     // relative residual, Jacobi sweeps
};

struct FluidReport {
  int cycles = 0;            // the projection's V-cycles
  int viscosity_sweeps = 0;  // Jacobi sweeps of the viscosity
  double residual = 0;       // the projection's relative residual: div after / div before
};

// Seconds spent in each sub-step since construction (the seed's Table 2).
struct FluidTimings {
  double sources = 0, dye_diffusion = 0, dye_advection = 0, velocity_advection = 0, forces = 0,
         viscosity = 0, projection = 0;
};

class SurfaceFluid {
 public:
  // `metric` must be the one `op` was built from (op's grid is the dye's); `surface` gives the
  // faces' tangents and the patches' topology. Keeps references to surface's topology, op and
  // multigrid, which must all outlive it (metric is read here only). The surface may be in
  // several pieces (the projection fixes one pressure constant on each).
  SurfaceFluid(const LimitSurface& surface, const PatchMetric& metric, const SurfaceLaplacian& op,
               const SurfaceMultigrid& multigrid, const SurfaceFluidParams& params);

  // One step dt (the order above).
  FluidReport step();

  // The sub-steps, in the step's order.
  void add_sources();
  void diffuse_dye();
  void advect_dye();       // s by u
  void advect_velocity();  // u by itself
  void add_forces();
  int apply_viscosity();  // returns the sweeps
  FluidReport project();

  // Gravity's direction (recomputes its tangential components).
  void set_down(const std::array<double, 3>& down);
  // Live changes (`ardcell live --fluid`): every parameter but source_radius, whose cells were
  // chosen at construction. Allocates nothing; the viscosity's and the dye diffusion's solves
  // allocate at their first run unless the constructor ran them (params with both above 0).
  void set_params(const SurfaceFluidParams& params);
  // Back to rest: no velocity, no dye, time 0, every buffer 0 (a live reset; the constructor's
  // end, after sizing the solvers' scratch).
  void clear();
  // Sets the dye to `value` in every patch's source disc (source_radius around its centre): the
  // seed's Fig. 8 start, a spot of dye on each patch, without a source adding more (a live
  // start). Allocates nothing.
  void fill_sources(double value);
  // The tangential part of v (in the mesh's coordinates) as the u^1 of x1-face (p, i, j),
  // 0 <= i <= N, 0 <= j < N, or as the u^2 of x2-face (p, i, j), 0 <= i < N, 0 <= j <= N:
  // g^ij <v, X_j> (what a live stroke pushes the fluid towards).
  double tangential_u1(int p, int i, int j, const std::array<double, 3>& v) const;
  double tangential_u2(int p, int i, int j, const std::array<double, 3>& v) const;
  double time() const { return time_; }

  // Fills every face ghost from the neighbours (edges, then corners).
  void exchange_velocity();
  // Each shared edge face's two copies to the mean outward flux; boundary faces to 0.
  void stitch_velocity();
  // out = div u on every cell (u as stored: stitch first).
  void divergence(PatchField& out) const;
  double max_divergence() const;
  // sum sqrt(G) h^2 s over the cells.
  double dye_total() const;

  // The velocity: u1(p, i, j) is u^1 at the x1-face (i - 1/2, j), point (i h, (j + 1/2) h),
  // -1 <= i <= N+1, -1 <= j <= N; u2(p, i, j) is u^2 at ((i + 1/2) h, j h), -1 <= i <= N,
  // -1 <= j <= N+1.
  double& u1(int p, int i, int j) { return vel_[u1_index(p, i, j)]; }
  double& u2(int p, int i, int j) { return vel_[u2_index(p, i, j)]; }
  double u1(int p, int i, int j) const { return vel_[u1_index(p, i, j)]; }
  double u2(int p, int i, int j) const { return vel_[u2_index(p, i, j)]; }
  const std::vector<double>& velocity() const { return vel_; }
  PatchField& dye() { return s_; }
  const PatchField& dye() const { return s_; }
  const PatchField& pressure() const { return phi_; }  // phi = dt p / rho, total 0

  const SurfaceLaplacian& op() const { return op_; }
  const SurfaceFluidParams& params() const { return params_; }
  const FluidTimings& timings() const { return timings_; }
  int n() const { return n_; }
  int patches() const { return patches_; }

 private:
  std::size_t u1_index(int p, int i, int j) const {
    return std::size_t(p) * face_block_ + std::size_t(j + 1) * (n_ + 3) + (i + 1);
  }
  std::size_t u2_index(int p, int i, int j) const {
    return u2_offset_ + std::size_t(p) * face_block_ + std::size_t(j + 1) * (n_ + 2) + (i + 1);
  }
  View<double> u1_view(std::vector<double>& v, int p) const;
  View<double> u2_view(std::vector<double>& v, int p) const;
  View<const double> u1_view(const std::vector<double>& v, int p) const;
  View<const double> u2_view(const std::vector<double>& v, int p) const;
  MacStencil stencil(int p) const;
  void build_exchange();
  // Face m (counted along the edge's direction) of edge e of patch p: its index in the velocity,
  // sqrt(G) there and the sign that makes its component outward.
  struct EdgeFace {
    std::size_t index;
    double sqrt_g;
    int sign;
  };
  EdgeFace edge_face(int p, int e, int m) const;
  void exchange_velocity(std::vector<double>& v, int p) const;
  // conserve_dye: the advected dye back to the total `before`, within [0, 1].
  void conserve_dye(double before);
  void stitch(std::vector<double>& v) const;
  // Where a trace from x in patch p by the displacement d ends (patch, point, quarter turns).
  struct Landing {
    int patch;
    double x[2];
    int turns;
  };
  Landing walk(int p, double x0, double x1, double d0, double d1) const;
  // u at point (x0, x1) of patch q, in q's frame; the trace's velocity there (u or g^-1 u).
  void velocity_at(int q, double x0, double x1, double out[2]) const;
  void trace_velocity_at(int q, double x0, double x1, double out[2]) const;
  // The midpoint-rule trace back from (x0, x1) of patch p.
  Landing trace_back(int p, double x0, double x1) const;

  const PatchTopology& topo_;
  const SurfaceLaplacian& op_;
  const SurfaceMultigrid& mg_;
  SurfaceFluidParams params_;
  int n_ = 0, patches_ = 0;
  std::size_t face_block_ = 0, u2_offset_ = 0;  // (N+3)(N+2) a patch; u2 after every u1
  std::size_t faces1_ = 0;                      // (N+1) N coefficients a patch
  // Face coefficients (MacStencil), patch after patch.
  std::vector<double> s1_, a1_, b1_, gii1_, gjj1_, s2_, a2_, b2_, gii2_, gjj2_;
  // The tangential part of the unit axes x, y, z as contravariant components: at the x1-faces
  // its u^1 (3 a face), at the x2-faces its u^2.
  std::vector<double> axis1_, axis2_;
  std::vector<double> down1_, down2_;  // gravity's f^i / strength per unit s
  // The ghost faces: dst = sum w_k src_k over up to three faces (edges first, then the corners
  // that read them), patch by patch from ghost_begin_[p].
  struct Ghost {
    std::size_t dst, src[3];
    double w[3];
  };
  std::vector<Ghost> ghosts_;
  std::vector<std::size_t> ghost_begin_;
  std::vector<std::size_t> boundary_faces_;
  std::vector<std::array<int, 2>> source_cells_;  // (i, j) inside every patch's source disc
  std::vector<double> area_;                      // sqrt(G) h^2 of each cell, N x N a patch
  std::vector<double> cell_gi_;  // g^11, g^12, g^22 of each cell (FluidTrace::kSeedInverseMetric)
  std::vector<double> vel_, vel_next_, vel_rhs_;
  PatchField s_, s_next_, s_rhs_, phi_;
  mutable PatchField div_;
  mutable std::vector<double> patch_max_;
  std::vector<double> patch_sums_;  // two a patch (conserve_dye)
  double time_ = 0;
  FluidTimings timings_;
};

}  // namespace ardcell
