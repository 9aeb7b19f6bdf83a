// Stable fluids on patched surfaces (host/surface/surface_fluid.h), forces and the dye:
// viscosity's backward-Euler decay of a Fourier mode, a surface of several pieces refused, the
// dye total under advection and conserved within [0, 1], gravity pulls the dye down, the same bits
// on 1, 2 and 3 workers, and no allocation in a step.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>

#include "host/surface/patch_metric.h"
#include "host/surface/procedural_mesh.h"
#include "host/surface/surface_fluid.h"
#include "runtime/row_executor.h"
#include "runtime/thread/thread_backend.h"
#include "tests/host/surface/surface_fluid_test_util.h"
#include "tests/host/surface/surface_test_util.h"
#include "tests/support/alloc_counter.h"

namespace ardcell {
namespace {

using namespace surface_fluid_test;

// Viscosity on the flat torus (the unit square, periodic, as 4 x 4 patches rotated at random):
// the velocity U = (f, f), f = cos 2 pi (X + Y), is a Fourier mode of every component in every
// patch's frame, and one backward-Euler step (I - dt nu A) u = u^n damps it by
// 1 / (1 + dt nu k^2), k^2 = 8 pi^2, at every face: to the solver's tolerance against the
// discrete eigenvalue, and to a discretisation error falling as h^2 against the exact one.
TEST(SurfaceFluid, ViscosityDampsAFourierModeByBackwardEuler) {
  constexpr double kPi = 3.14159265358979323846;
  const int k = 4;
  double previous = 0;
  for (int n : {8, 16}) {
    const PolyMesh mesh = rotate_faces(torus_mesh(k, k, 2, 1), 17);
    SurfaceFluidParams params = quiet();
    params.dt = 0.1;
    params.viscosity = 0.5 / (params.dt * 8 * kPi * kPi);  // dt nu k^2 = 1/2
    params.viscous = DiffusionSolve{1e-12, 5000};
    Sim sim;
    ASSERT_TRUE(LimitSurface::build(PolyMesh(mesh), {}, sim.surface).is_ok());
    const PatchMetric metric = flat_metric(sim.surface.topology(), n, 1.0 / k);
    sim.op = std::make_unique<SurfaceLaplacian>(sim.surface.topology(), metric);
    sim.mg = std::make_unique<SurfaceMultigrid>(sim.surface, *sim.op);
    sim.fluid = std::make_unique<SurfaceFluid>(sim.surface, metric, *sim.op, *sim.mg, params);
    SurfaceFluid& f = *sim.fluid;
    // Each patch's corners on the lattice of the k x k torus (unwrapped around corner 0), its
    // axes du, dv (unit lattice vectors) and a point's global (X, Y) in [0, 1)^2.
    const auto place = [&](int p, double x, double y, double out[2], double du[2], double dv[2]) {
      double corner[4][2];
      surface_test::flat_torus_corners(mesh, k, p, corner);
      for (int d = 0; d < 2; ++d) {
        out[d] = ((1 - x) * (1 - y) * corner[0][d] + x * (1 - y) * corner[1][d] +
                  x * y * corner[2][d] + (1 - x) * y * corner[3][d]) /
                 k;
        du[d] = corner[1][d] - corner[0][d], dv[d] = corner[3][d] - corner[0][d];
      }
    };
    for_faces(f.patches(), n, [&](int p, int c, int i, int j, double x0, double x1) {
      double at[2], du[2], dv[2];
      place(p, x0, x1, at, du, dv);
      const double m = std::cos(2 * kPi * (at[0] + at[1]));
      face(f, p, c, i, j) = c == 0 ? m * (du[0] + du[1]) : m * (dv[0] + dv[1]);
    });
    const std::vector<double> start = f.velocity();
    const int sweeps = f.apply_viscosity();
    const double h = 1.0 / (k * n), c = params.dt * params.viscosity;
    const double discrete = 8 / (h * h) * std::pow(std::sin(kPi * h), 2);
    const double exact = 8 * kPi * kPi;
    double worst_discrete = 0, worst_exact = 0;
    for_faces(f.patches(), n, [&](int p, int comp, int i, int j, double, double) {
      const double was = start[&face(f, p, comp, i, j) - f.velocity().data()];
      const double now = face(f, p, comp, i, j);
      worst_discrete = std::max(worst_discrete, std::abs(now - was / (1 + c * discrete)));
      worst_exact = std::max(worst_exact, std::abs(now - was / (1 + c * exact)));
    });
    std::printf(
        "flat torus N=%d: mode damped in %d sweeps, off 1/(1 + dt nu k^2) = %.6f by %.3g "
        "(discrete eigenvalue: %.3g)\n",
        n, sweeps, 1 / (1 + c * exact), worst_exact, worst_discrete);
    EXPECT_LT(sweeps, params.viscous.max_sweeps);
    EXPECT_LT(worst_discrete, 1e-8);
    EXPECT_LT(worst_exact, 2e-3);
    if (previous > 0) {
      EXPECT_NEAR(previous / worst_exact, 4.0, 0.3);
    }
    previous = worst_exact;
  }
}

// A surface in several pieces: connected_pieces counts them (the projection fixes one pressure
// constant on each: SurfaceFluid.ProjectionRemovesTheDivergence).
TEST(SurfaceFluid, ConnectedPieces) {
  const auto pieces = [](const PolyMesh& mesh) {
    LimitSurface surface;
    EXPECT_TRUE(LimitSurface::build(PolyMesh(mesh), {}, surface).is_ok());
    return connected_pieces(surface.topology());
  };
  EXPECT_EQ(pieces(cube()), 1);
  EXPECT_EQ(pieces(open_box()), 1);
  EXPECT_EQ(pieces(two_pieces()), 2);
}

// Semi-Lagrangian advection does not keep the dye's total; conserve_dye restores it to rounding.
TEST(SurfaceFluid, DyeTotalUnderAdvection) {
  for (bool conserve : {false, true}) {
    SurfaceFluidParams params = quiet();
    params.dt = 0.1;
    params.conserve_dye = conserve;
    auto sim = make_sim(cube(), 8, params);
    SurfaceFluid& f = *sim->fluid;
    random_velocity(f, 5);
    f.project();
    PatchField& dye = f.dye();
    std::mt19937 rng(9);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (double& v : dye) v = u(rng);
    const double total = f.dye_total();
    for (int k = 0; k < 20; ++k) {
      f.advect_dye();
      f.advect_velocity();  // projection-free steps
    }
    const double drift = std::abs(f.dye_total() - total) / total;
    std::printf("conserve_dye %d: total drifts by %.3g (relative) in 20 steps\n", conserve, drift);
    if (conserve)
      EXPECT_LT(drift, 1e-13);
    else
      EXPECT_LT(drift, 0.05);
  }
}

// conserve_dye keeps the dye within [0, 1]: full steps of gravity on the dye from the sources
// (held at 1 there) on the torus; every advection keeps the total it started from (to rounding:
// the dye never fills the cells it covers here), and no cell ends above 1 (scaling the advected
// dye by before / after alone takes it to 1.02 here).
TEST(SurfaceFluid, ConservedDyeStaysWithinZeroAndOne) {
  SurfaceFluidParams params;
  params.dt = 0.1;
  params.strength = 4;
  params.source_rate = 10;  // the sources at 1 from the first step
  params.conserve_dye = true;
  auto sim = make_sim(torus(), 8, params);
  SurfaceFluid& f = *sim->fluid;
  double worst = 0, high = 0, low = 1;
  for (int k = 0; k < 40; ++k) {
    f.add_sources();
    const double total = f.dye_total();
    f.advect_dye();
    worst = std::max(worst, std::abs(f.dye_total() - total) / total);
    const auto [lo, hi] = dye_range(f);
    high = std::max(high, hi), low = std::min(low, lo);
    f.advect_velocity();
    f.add_forces();
    f.project();
  }
  std::printf(
      "conserve_dye, 40 steps of gravity: total kept to %.3g (relative), s in [%g, %.17g]\n", worst,
      low, high);
  EXPECT_LT(worst, 1e-13);
  EXPECT_LE(high, 1.0);
  EXPECT_GE(low, 0.0);
}

// Implicit viscosity (the simplified per-component operator) converges and damps a random
// field's grid-scale noise, the more the larger nu; nu = 0 leaves the field alone.
TEST(SurfaceFluid, ViscositySmoothsTheVelocity) {
  double previous = 0;
  for (double nu : {0.0, 0.05, 0.3}) {
    SurfaceFluidParams params = quiet();
    params.dt = 0.1;
    params.viscosity = nu;
    auto sim = make_sim(torus(), 8, params);
    SurfaceFluid& f = *sim->fluid;
    random_velocity(f, 7);
    const auto largest = [&] {
      double m = 0;
      for (double v : f.velocity()) m = std::max(m, std::abs(v));
      return m;
    };
    const double before = largest();
    const int sweeps = f.apply_viscosity();
    const double after = largest();
    std::printf("nu %g: max |u| %.3f -> %.3f in %d Jacobi sweeps\n", nu, before, after, sweeps);
    if (nu == 0) {
      EXPECT_EQ(sweeps, 0);
      EXPECT_EQ(after, before);
    } else {
      EXPECT_LT(sweeps, params.viscous.max_sweeps);
      EXPECT_LT(after, previous);
    }
    previous = after;
  }
  EXPECT_LT(previous, 0.5);
}

// Gravity proportional to the dye: the dye from the patches' sources sinks (its centroid's z
// falls), with down = -z; with down = +z it rises.
TEST(SurfaceFluid, GravityPullsTheDyeDown) {
  for (double down : {-1.0, 1.0}) {
    SurfaceFluidParams params;
    params.dt = 0.05;
    params.down = {0, 0, down};
    params.strength = 4;
    auto sim = make_sim(cube(), 8, params);
    SurfaceFluid& f = *sim->fluid;
    const auto positions = cell_positions(sim->surface, f.op().grid());
    const auto centroid_z = [&] {
      PatchField z = f.dye();
      for (std::size_t k = 0; k < z.size(); ++k) z[k] *= positions[2][k];
      return f.op().total(z) / f.dye_total();
    };
    for (int k = 0; k < 5; ++k) f.step();
    const double z0 = centroid_z();
    for (int k = 0; k < 30; ++k) f.step();
    const double z1 = centroid_z();
    std::printf("down %+g: dye centroid z %.4f -> %.4f\n", down, z0, z1);
    EXPECT_LT(down * (z0 - z1), -0.02);
  }
}

// Full steps (sources, dye diffusion, gravity or the walkers, viscosity, projection) give the
// same bits on 1, 2 and 3 workers, and allocate nothing: gravity on the double torus, the walkers
// on a surface of two pieces (the projection's per-piece means and bordered coarse solve). The
// field moved and is left divergence-free to the projection's tolerance (relative to |u| N, the
// divergence of a field of that size).
TEST(SurfaceFluid, AnyNumberOfWorkersGivesTheSameBitsAndNoAllocation) {
  for (FluidForce force : {FluidForce::kGravity, FluidForce::kWalk}) {
    SurfaceFluidParams params;
    params.force = force;
    params.viscosity = 1e-3;
    params.dye_diffusion = 1e-3;
    params.dt = 0.1;
    params.conserve_dye = force == FluidForce::kGravity;  // its passes' sums too
    std::unique_ptr<ThreadBackend> backends[3];
    std::unique_ptr<RowExecutor> executors[3];
    std::unique_ptr<Sim> sims[3];
    for (int w = 0; w < 3; ++w) {
      ThreadBackendOptions o;
      o.workers = w + 1, o.pin = false;
      backends[w] = std::make_unique<ThreadBackend>(o);
      executors[w] = std::make_unique<RowExecutor>(*backends[w]);
      sims[w] = make_sim(force == FluidForce::kGravity ? genus2_mesh(1.0) : two_pieces(), 16,
                         params, executors[w].get());
    }
    for (int k = 0; k < 3; ++k)
      for (auto& sim : sims) {
        const long before = g_allocations.load();
        sim->fluid->step();
        EXPECT_EQ(g_allocations.load(), before) << "step " << k;
      }
    const SurfaceFluid& f = *sims[0]->fluid;
    for (int w = 1; w < 3; ++w) {
      EXPECT_TRUE(sims[w]->fluid->velocity() == f.velocity()) << w + 1 << " workers";
      EXPECT_TRUE(sims[w]->fluid->dye() == f.dye()) << w + 1 << " workers";
    }
    EXPECT_GT(dye_range(f)[1], 0.1);
    double largest = 0;
    for (double v : f.velocity()) largest = std::max(largest, std::abs(v));
    const double div = f.max_divergence();
    std::printf("%s: max |u| %.3g, max |div u| %.3g (%.2g |u| N)\n",
                force == FluidForce::kGravity ? "gravity" : "walk", largest, div,
                div / (largest * 16));
    EXPECT_GT(largest, 1e-3);
    EXPECT_LT(div, 10 * params.projection.tolerance * largest * 16);
  }
}

}  // namespace
}  // namespace ardcell
