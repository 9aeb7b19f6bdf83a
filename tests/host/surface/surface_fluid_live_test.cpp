// Stable fluids live on a surface (`ardcell live --shape torus --fluid gravity|walk`,
// host/surface/surface_simulation.h): the dye drawn and painted, gravity following the view,
// live changes and reset, the presets it refuses, the same bits on any number of workers and no
// allocation per frame.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <set>
#include <stdexcept>
#include <vector>

#include "host/surface/patch_metric.h"
#include "host/surface/procedural_mesh.h"
#include "host/surface/surface_simulation.h"
#include "tests/host/surface/surface_live_test_util.h"
#include "tests/support/alloc_counter.h"

namespace ardcell {
namespace {

using namespace surface_live_test;  // NOLINT: the shared helpers of the live surface tests

std::shared_ptr<const LimitSurface> torus() { return live_surface(torus_mesh(8, 4, 2.0, 0.8)); }

// A clean surface (no start dye) unless `start_dye`: the strokes' tests count what they paint.
SurfaceLiveOptions fluid_options(FluidForce force, int workers = 2, bool start_dye = false) {
  SurfaceLiveOptions o;
  o.patch_cells = 8;
  o.workers = workers;
  o.view = {320, 240};
  o.fluid.force = force;
  o.fluid.start_dye = start_dye;
  return o;
}

InputMapping brush(double radius, double strength) {
  InputMapping input;
  input.brush_radius = radius;
  input.strength = strength;
  return input;
}

// Over the cells (not the ghosts): the dye's sum, its largest value, how many cells hold any.
struct DyeSummary {
  double sum = 0, max = 0;
  long cells = 0, total = 0;
};
DyeSummary summarize(const SurfaceSimulation& sim) {
  const PatchGrid& g = sim.grid();
  const PatchField& s = sim.fluid()->dye();
  DyeSummary d;
  for (int p = 0; p < g.patches(); ++p)
    for (int j = 0; j < g.n(); ++j)
      for (int i = 0; i < g.n(); ++i) {
        const double v = s[g.index(p, i, j)];
        d.sum += v;
        d.max = std::max(d.max, v);
        d.cells += v > 0;
        ++d.total;
      }
  return d;
}

double max_speed(const SurfaceFluid& fluid) {
  double m = 0;
  for (double u : fluid.velocity()) m = std::max(m, std::abs(u));
  return m;
}

// The tip paints dye (towards 1) under the stroke and nowhere else; the view shows it.
TEST(SurfaceFluidLive, PaintsDyeUnderTheStrokeAndDrawsIt) {
  SurfaceSimulation sim(preset("cavity"), torus(), fluid_options(FluidForce::kGravity));
  ASSERT_NE(sim.fluid(), nullptr);
  EXPECT_NE(sim.backend().find("32 patches of 8^2, fluid gravity"), std::string_view::npos)
      << sim.backend();
  ImageRgb8 empty, painted;
  sim.render(empty);
  EXPECT_EQ(summarize(sim).sum, 0.0) << "the start: no dye";
  const long cell = sim.cell_at(0.5f, 0.35f);
  ASSERT_GE(cell, 0);
  const StrokeSample stroke[] = {sample(0.47f, 0.35f, true), sample(0.53f, 0.35f, true),
                                 sample(0.53f, 0.35f, false)};
  sim.paint(stroke, brush(0.03, 1.0), 0);
  const DyeSummary d = summarize(sim);
  EXPECT_DOUBLE_EQ(sim.fluid()->dye()[std::size_t(cell)], 1.0) << "the brush's centre: 100%";
  EXPECT_LE(d.max, 1.0);
  EXPECT_GT(d.cells, 3);
  EXPECT_LT(d.cells, d.total / 10) << "a brush, not the whole surface";
  std::printf("painted %ld of %ld cells, sum %.3f\n", d.cells, d.total, d.sum);
  // At half strength a second dab on the same cell closes half the rest of the way to 1.
  const long other = sim.cell_at(0.5f, 0.25f);
  ASSERT_GE(other, 0);
  ASSERT_EQ(sim.fluid()->dye()[std::size_t(other)], 0.0);
  const StrokeSample dab[] = {sample(0.5f, 0.25f, true), sample(0.5f, 0.25f, false)};
  sim.paint(dab, brush(0.001, 0.5), 0);
  EXPECT_DOUBLE_EQ(sim.fluid()->dye()[std::size_t(other)], 0.5);
  sim.paint(dab, brush(0.001, 0.5), 0);
  EXPECT_DOUBLE_EQ(sim.fluid()->dye()[std::size_t(other)], 0.75);
  sim.render(painted);
  // The pixel under the stroke changes colour; the corner (background) does not.
  const int px = int(0.5f * 320), py = int(0.35f * 240);
  const uint8_t* a = empty.row(py) + 3 * px;
  const uint8_t* b = painted.row(py) + 3 * px;
  EXPECT_TRUE(a[0] != b[0] || a[1] != b[1] || a[2] != b[2]) << "the dye drawn where painted";
  EXPECT_EQ(empty.row(0)[0], painted.row(0)[0]);
  long changed = 0;
  for (std::size_t k = 0; k < empty.rgb.size(); k += 3)
    changed += empty.rgb[k] != painted.rgb[k] || empty.rgb[k + 1] != painted.rgb[k + 1] ||
               empty.rgb[k + 2] != painted.rgb[k + 2];
  EXPECT_GT(changed, 20);
  EXPECT_LT(changed, long(empty.rgb.size() / 3) / 5) << "the stroke's pixels, not the view";
  std::printf("pixels changed by the stroke: %ld of %zu, colours %d -> %d\n", changed,
              empty.rgb.size() / 3, distinct_colours(empty), distinct_colours(painted));
  // Hovering paints nothing; the eraser turns the view and paints nothing.
  const PatchField before = sim.fluid()->dye();
  const StrokeSample hover[] = {sample(0.3f, 0.35f, false), sample(0.3f, 0.4f, true, true),
                                sample(0.4f, 0.4f, true, true)};
  sim.paint(hover, brush(0.03, 1.0), 0);
  EXPECT_EQ(sim.fluid()->dye(), before);
}

// Where the same dab of dye falls with gravity from elevation 60, the view turned after the dab
// when `turn` (a right-button drag of half the canvas: 180 degrees about the vertical axis): the
// centroid's displacement in the mesh's coordinates, the screen's down axis of the view, and
// the dye-weighted mean pixel row before and after (from the pick buffer: what the screen
// shows).
struct Fall {
  std::array<double, 3> moved{}, down{};
  double row_before = 0, row_after = 0;
};

std::array<double, 3> centroid(const SurfaceSimulation& sim,
                               const std::array<PatchField, 3>& positions) {
  const PatchGrid& g = sim.grid();
  const PatchField& s = sim.fluid()->dye();
  std::array<double, 3> c{};
  double total = 0;
  for (int p = 0; p < g.patches(); ++p)
    for (int j = 0; j < g.n(); ++j)
      for (int i = 0; i < g.n(); ++i) {
        const std::size_t k = g.index(p, i, j);
        for (int a = 0; a < 3; ++a) c[std::size_t(a)] += s[k] * positions[std::size_t(a)][k];
        total += s[k];
      }
  for (double& v : c) v /= total;
  return c;
}

// The dye-weighted mean pixel (x, y) from the pick buffer: where the screen shows the dye.
std::array<double, 2> dye_pixel(const SurfaceSimulation& sim) {
  const Int2 size = sim.view_size();
  double wx = 0, wy = 0, total = 0;
  for (int y = 0; y < size.y; ++y)
    for (int x = 0; x < size.x; ++x) {
      const long c =
          sim.cell_at((float(x) + 0.5f) / float(size.x), (float(y) + 0.5f) / float(size.y));
      if (c < 0) continue;
      const double s = sim.fluid()->dye()[std::size_t(c)];
      wx += s * x;
      wy += s * y;
      total += s;
    }
  return {wx / total, wy / total};
}
double dye_row(const SurfaceSimulation& sim) { return dye_pixel(sim)[1]; }
double dye_column(const SurfaceSimulation& sim) { return dye_pixel(sim)[0]; }

Fall fall(bool turn) {
  const std::shared_ptr<const LimitSurface> surface = torus();
  SurfaceLiveOptions o = fluid_options(FluidForce::kGravity);
  o.elevation_deg = 60;
  o.fluid.strength = 4;
  SurfaceSimulation sim(preset("cavity"), surface, o);
  const std::array<PatchField, 3> positions = cell_positions(*surface, sim.grid());
  ImageRgb8 image;
  sim.render(image);
  // A dab on the middle of the torus's far ring, above the hole as the screen shows it.
  float top = -1, bottom = -1;
  for (float y = 0.02f; y < 0.5f && bottom < 0; y += 0.005f) {
    const bool hit = sim.cell_at(0.5f, y) >= 0;
    if (hit && top < 0) top = y;
    if (!hit && top >= 0) bottom = y;
  }
  EXPECT_GT(bottom, top + 0.05f) << "the ring's band in the middle column";
  const float y = 0.5f * (top + bottom);
  const StrokeSample dab[] = {sample(0.5f, y, true), sample(0.5f, y, false)};
  sim.paint(dab, brush(0.05, 1.0), 0);
  if (turn) {
    const StrokeSample drag[] = {sample(0.2f, 0.5f, true, true), sample(0.7f, 0.5f, true, true),
                                 sample(0.7f, 0.5f, false)};
    sim.paint(drag, {}, 0);
    sim.render(image);
  }
  Fall f;
  f.down = SurfaceSimulation::screen_down(sim.view());
  f.row_before = dye_row(sim);
  const std::array<double, 3> c0 = centroid(sim, positions);
  for (int k = 0; k < 30; ++k) sim.step();
  const std::array<double, 3> c1 = centroid(sim, positions);
  for (int a = 0; a < 3; ++a) f.moved[std::size_t(a)] = c1[std::size_t(a)] - c0[std::size_t(a)];
  sim.render(image);
  f.row_after = dye_row(sim);
  return f;
}

double dot(const std::array<double, 3>& a, const std::array<double, 3>& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

// The seed's viewer-relative gravity: the dye falls towards the bottom of the screen, in both
// views; the same dye with the view turned by 180 degrees drifts the other way horizontally (a
// fixed down would move it alike in both).
TEST(SurfaceFluidLive, GravityFollowsTheView) {
  const Fall a = fall(false), b = fall(true);
  // The screen's down axis: (sin el cos az, sin el sin az, -cos el); turned 180 degrees in
  // azimuth its horizontal part flips, its vertical part stays.
  EXPECT_NEAR(a.down[0], -b.down[0], 1e-9);
  EXPECT_NEAR(a.down[1], -b.down[1], 1e-9);
  EXPECT_NEAR(a.down[2], b.down[2], 1e-9);
  EXPECT_NEAR(a.down[2], -0.5, 1e-9);
  const std::array<double, 3> horizontal{a.down[0], a.down[1], 0};
  std::printf("view A: centroid along down %+.4f, along A's horizontal %+.4f, row %.1f -> %.1f\n",
              dot(a.moved, a.down), dot(a.moved, horizontal), a.row_before, a.row_after);
  std::printf("view B: centroid along down %+.4f, along A's horizontal %+.4f, row %.1f -> %.1f\n",
              dot(b.moved, b.down), dot(b.moved, horizontal), b.row_before, b.row_after);
  EXPECT_GT(dot(a.moved, a.down), 0.05);
  EXPECT_GT(dot(b.moved, b.down), 0.05);
  EXPECT_GT(dot(a.moved, horizontal), 0.02) << "A: along A's horizontal down";
  EXPECT_LT(dot(b.moved, horizontal), -0.02) << "B: the other way";
  // What the screen shows: the dye moves down the image (rows grow) in both views.
  EXPECT_GT(a.row_after, a.row_before + 2);
  EXPECT_GT(b.row_after, b.row_before + 2);
}

// In push mode a drag blends the velocity under the brush towards the stroke's direction: a
// drag to the right carries painted dye to the right on the screen, one to the left to the left
// (no gravity: --force 0); in erase mode the brush takes the dye away.
TEST(SurfaceFluidLive, PushModeDragsTheFluidAndEraseTakesDyeAway) {
  const std::shared_ptr<const LimitSurface> surface = torus();
  double moved[2] = {0, 0};
  for (int side = 0; side < 2; ++side) {
    SurfaceLiveOptions o = fluid_options(FluidForce::kGravity);
    o.fluid.strength = 0;
    SurfaceSimulation sim(preset("cavity"), surface, o);
    ImageRgb8 image;
    sim.render(image);
    const StrokeSample dab[] = {sample(0.5f, 0.35f, true), sample(0.5f, 0.35f, false)};
    sim.paint(dab, brush(0.04, 1.0), 0);
    const double before = dye_column(sim);
    InputMapping push = brush(0.06, 1.0);
    push.mode = std::string("push");  // not a literal: GCC 12's false -Wrestrict
    const float x0 = side == 0 ? 0.42f : 0.58f, x1 = side == 0 ? 0.58f : 0.42f;
    StrokeSample drag[9];
    for (int k = 0; k < 8; ++k) drag[k] = sample(x0 + (x1 - x0) * float(k) / 7, 0.35f, true);
    drag[8] = sample(x1, 0.35f, false);
    const PatchField dye = sim.fluid()->dye();
    sim.paint(drag, push, 0);
    EXPECT_EQ(sim.fluid()->dye(), dye) << "a push moves no dye by itself";
    EXPECT_GT(max_speed(*sim.fluid()), 0.1);
    for (int k = 0; k < 10; ++k) sim.step();
    sim.render(image);
    moved[side] = dye_column(sim) - before;
  }
  std::printf("dye column moved by a push to the right %+.1f px, to the left %+.1f px\n", moved[0],
              moved[1]);
  EXPECT_GT(moved[0], 2.0);
  EXPECT_LT(moved[1], -2.0);
  // Erase: the dye under the brush back to 0 at full strength.
  SurfaceSimulation sim(preset("cavity"), surface, fluid_options(FluidForce::kGravity));
  ImageRgb8 image;
  sim.render(image);
  const long cell = sim.cell_at(0.5f, 0.35f);
  ASSERT_GE(cell, 0);
  const StrokeSample dab[] = {sample(0.5f, 0.35f, true), sample(0.5f, 0.35f, false)};
  sim.paint(dab, brush(0.04, 1.0), 0);
  ASSERT_EQ(sim.fluid()->dye()[std::size_t(cell)], 1.0);
  InputMapping erase = brush(0.04, 1.0);
  erase.mode = std::string("erase");
  sim.paint(dab, erase, 0);
  EXPECT_EQ(sim.fluid()->dye()[std::size_t(cell)], 0.0);
}

// A push across patch seams whose parametrisations meet with every quarter turn (high edges
// meet low and high ones). One straight drag blends every face under the brush towards the
// tangential part of one velocity v, at the brush's core (half its radius around a dab) all the
// way: a face's weight, its u over that target, is 1 there. A seam face is stored by both
// patches, each copy blended by its own patch's cell, and the stitch averages the two fluxes, so
// a seam face inside the core has weight 1 as its neighbours do. Blending the low faces only
// left 1/2 where a high edge meets a low one, and 0 where two high edges meet.
TEST(SurfaceFluidLive, PushReachesSeamFaces) {
  const std::shared_ptr<const LimitSurface> surface = live_surface(rotate_faces(cube_mesh(2), 5));
  SurfaceLiveOptions o = fluid_options(FluidForce::kGravity);
  o.fluid.strength = 0;
  SurfaceSimulation sim(preset("cavity"), surface, o);
  ImageRgb8 image;
  sim.render(image);
  InputMapping push = brush(0.14, 1.0);
  push.mode = std::string("push");
  // A diagonal drag across the cube's front (both components pushed), in equal segments.
  const float x0 = 0.3f, y0 = 0.3f, x1 = 0.7f, y1 = 0.7f;
  StrokeSample drag[9];
  for (int k = 0; k < 8; ++k) {
    const float t = float(k) / 7;
    drag[k] = sample(x0 + (x1 - x0) * t, y0 + (y1 - y0) * t, true);
  }
  drag[8] = sample(x1, y1, false);
  sim.paint(drag, push, 0);
  // v's direction: the drag on the screen in the mesh's coordinates, as paint maps it (its
  // length, paint's speed, is the weight's unit below).
  const CameraAxes axes = camera_axes(sim.view());
  const double px = double(x1 - x0) * o.view.x, py = double(y1 - y0) * o.view.y;
  std::array<double, 3> v{};
  for (std::size_t a = 0; a < 3; ++a) v[a] = px * axes.right[a] - py * axes.up[a];
  const SurfaceFluid& f = *sim.fluid();
  const int n = f.n();
  // Face m of edge e of patch p, counted as the stitch counts them, at depth 0 (the seam) or 1
  // (one cell inside): u and the target.
  struct Face {
    double u, target;
  };
  const auto face = [&](int p, int e, int m, int depth) {
    const auto x1_face = [&](int i, int j) {
      return Face{f.u1(p, i, j), f.tangential_u1(p, i, j, v)};
    };
    const auto x2_face = [&](int i, int j) {
      return Face{f.u2(p, i, j), f.tangential_u2(p, i, j, v)};
    };
    switch (e) {
      case 0:
        return x2_face(m, depth);
      case 1:
        return x1_face(n - depth, m);
      case 2:
        return x2_face(n - 1 - m, n - depth);
      default:
        return x1_face(depth, n - 1 - m);
    }
  };
  // The largest target on the seams and beside them, and weight 1 (u over the target at the
  // brush's core).
  const auto& shared = sim.grid().shared_edges();
  double largest = 0, full = 0;
  for (const PatchGrid::SharedEdge& s : shared)
    for (int m = 0; m < n; ++m)
      for (int depth = 0; depth < 2; ++depth)
        largest = std::max({largest, std::abs(face(s.p, s.e, m, depth).target),
                            std::abs(face(s.q, s.f, m, depth).target)});
  const auto weight = [&](const Face& x) {
    return std::abs(x.target) >= 0.1 * largest ? x.u / x.target : 0.0;
  };
  for (const PatchGrid::SharedEdge& s : shared)
    for (int m = 0; m < n; ++m) full = std::max(full, weight(face(s.p, s.e, m, 1)));
  ASSERT_GT(full, 0.0);
  // The seam faces with targets not small beside the others' (a component across the drag)
  // whose neighbours one cell inside, on both sides, are in the core (on a high edge the cell
  // that blends that neighbour blends the seam's copy too): their weight, by the kind of seam.
  double sum[3] = {0, 0, 0};  // high meets high, high meets low, low meets low
  int count[3] = {0, 0, 0};
  for (const PatchGrid::SharedEdge& s : shared) {
    const int kind = 2 - (s.e == 1 || s.e == 2) - (s.f == 1 || s.f == 2);
    for (int m = 0; m < n; ++m) {
      const bool core = std::abs(face(s.p, s.e, m, 0).target) >= 0.1 * largest &&
                        weight(face(s.p, s.e, m, 1)) > 0.99 * full &&
                        weight(face(s.q, s.f, n - 1 - m, 1)) > 0.99 * full;
      if (!core) continue;
      sum[kind] += weight(face(s.p, s.e, m, 0)) / full;
      ++count[kind];
    }
  }
  std::printf(
      "push across seams: the weight of seam faces in the brush's core, where high meets "
      "high %.3f (%d faces), high meets low %.3f (%d), low meets low %.3f (%d)\n",
      sum[0] / count[0], count[0], sum[1] / count[1], count[1], sum[2] / count[2], count[2]);
  for (int kind = 0; kind < 3; ++kind)
    ASSERT_GE(count[kind], 3) << "the drag crosses every kind of seam: " << kind;
  EXPECT_GT(sum[0] / count[0], 0.8) << "where two high edges meet";
  EXPECT_GT(sum[1] / count[1], 0.8) << "where a high edge meets a low one";
  EXPECT_GT(sum[2] / count[2], 0.8) << "where two low edges meet";
}

// Walkers push the painted dye around; reset stops the fluid and clears the dye; live changes
// reach the viscosity, the dye's diffusion and conserve_dye (unless --conserve-dye set it).
TEST(SurfaceFluidLive, WalkersResetAndLiveChanges) {
  const Preset p = preset("cavity");
  SurfaceSimulation sim(p, torus(), fluid_options(FluidForce::kWalk));
  EXPECT_EQ(sim.fluid()->params().force, FluidForce::kWalk);
  EXPECT_EQ(sim.fluid()->params().viscosity, p.scene.fluid.viscosity);
  EXPECT_EQ(sim.fluid()->params().conserve_dye, p.scene.fluid.conserve_dye);
  EXPECT_EQ(sim.fluid()->params().projection.tolerance, 1e-4);
  ImageRgb8 image;
  sim.render(image);
  const StrokeSample dab[] = {sample(0.5f, 0.35f, true), sample(0.5f, 0.35f, false)};
  sim.paint(dab, brush(0.05, 1.0), 0);
  const PatchField painted = sim.fluid()->dye();
  for (int k = 0; k < 10; ++k) sim.step();
  EXPECT_GT(max_speed(*sim.fluid()), 0.01);
  EXPECT_NE(sim.fluid()->dye(), painted) << "the walkers move the dye";
  SceneConfig next = p.scene;
  next.fluid.viscosity = 0.02;
  next.fluid.dye_diffusion = 0.005;
  next.fluid.conserve_dye = !p.scene.fluid.conserve_dye;
  sim.apply(next);
  EXPECT_EQ(sim.fluid()->params().viscosity, 0.02);
  EXPECT_EQ(sim.fluid()->params().dye_diffusion, 0.005);
  EXPECT_EQ(sim.fluid()->params().conserve_dye, next.fluid.conserve_dye);
  EXPECT_EQ(sim.fluid()->params().force, FluidForce::kWalk) << "--fluid stays";
  sim.reset();
  EXPECT_EQ(max_speed(*sim.fluid()), 0.0);
  EXPECT_EQ(summarize(sim).sum, 0.0);
  EXPECT_EQ(sim.fluid()->time(), 0.0);
  // --conserve-dye (here =false) holds against the preset.
  SurfaceLiveOptions o = fluid_options(FluidForce::kGravity);
  o.fluid.conserve_dye = false;
  SurfaceSimulation fixed(p, torus(), o);
  EXPECT_FALSE(fixed.fluid()->params().conserve_dye);
  next.fluid.conserve_dye = true;
  fixed.apply(next);
  EXPECT_FALSE(fixed.fluid()->params().conserve_dye);
}

// By default the surface starts with a spot of dye on every patch (the seed's Fig. 8 sources,
// filled once), which gravity then carries: the view shows a flow before anyone paints; reset
// brings the spots back.
TEST(SurfaceFluidLive, StartsWithASpotOfDyeOnEveryPatch) {
  EXPECT_TRUE(SurfaceLiveOptions{}.fluid.start_dye) << "what `ardcell live --fluid` gets";
  SurfaceSimulation sim(preset("cavity"), torus(), fluid_options(FluidForce::kGravity, 2, true));
  const PatchGrid& g = sim.grid();
  const PatchField start = sim.fluid()->dye();
  int dyed = 0;
  for (int p = 0; p < g.patches(); ++p) {
    int on_patch = 0;
    for (int j = 0; j < g.n(); ++j)
      for (int i = 0; i < g.n(); ++i) on_patch += start[g.index(p, i, j)] == 1.0 ? 1 : 0;
    EXPECT_GT(on_patch, 0) << "patch " << p;
    dyed += on_patch;
  }
  EXPECT_LT(dyed, g.patches() * g.n() * g.n() / 4) << "spots, not a coat";
  EXPECT_GT(summarize(sim).sum, 0.0);
  for (int k = 0; k < 10; ++k) sim.step();
  EXPECT_GT(max_speed(*sim.fluid()), 0.0) << "gravity pulls the dye";
  EXPECT_NE(sim.fluid()->dye(), start);
  sim.reset();
  EXPECT_EQ(sim.fluid()->dye(), start);
  EXPECT_EQ(max_speed(*sim.fluid()), 0.0);
}

TEST(SurfaceFluidLive, RefusesAPresetWithoutAFluid) {
  try {
    SurfaceSimulation sim(preset("turing-spots"), torus(), fluid_options(FluidForce::kGravity));
    ADD_FAILURE() << "turing-spots was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()),
              "fluid.scene is none: --fluid runs a preset's fluid (expected a preset whose "
              "fluid.scene is cavity, obstacle, ink or table1)");
  }
  EXPECT_FALSE(runs_on_surfaces(preset("turing-spots"), true));
  EXPECT_TRUE(runs_on_surfaces(preset("cavity"), true));
  EXPECT_TRUE(runs_on_surfaces(preset("obstacle-rd-gray-scott"), true));
  EXPECT_FALSE(runs_on_surfaces(preset("cavity"), false)) << "its RD: none";
  FluidForce force = FluidForce::kNone;
  EXPECT_EQ(parse_fluid_force("swirl", force).message(),
            "--fluid 'swirl': expected gravity or walk");
  EXPECT_TRUE(parse_fluid_force("walk", force));
  EXPECT_EQ(force, FluidForce::kWalk);
}

// Switching presets live: the factory makes each preset with a fluid a fluid on the same surface.
TEST(SurfaceFluidLive, TheFactoryMakesEachPresetAFluid) {
  const SimulationFactory factory = surface_simulations(torus(), fluid_options(FluidForce::kWalk));
  for (const char* name : {"cavity", "ink", "obstacle-rd-gray-scott"}) {
    const Preset p = preset(name);
    const std::unique_ptr<LiveSimulation> sim = factory(p);
    const auto* surface = dynamic_cast<const SurfaceSimulation*>(sim.get());
    ASSERT_NE(surface, nullptr) << name;
    ASSERT_NE(surface->fluid(), nullptr) << name;
    EXPECT_EQ(surface->fluid()->params().force, FluidForce::kWalk) << name;
    EXPECT_EQ(surface->fluid()->params().viscosity, p.scene.fluid.viscosity) << name;
  }
  EXPECT_THROW(factory(preset("turing-spots")), std::invalid_argument);
}

// The patches run side by side: 1 and 2 workers step the same velocity and dye bit for bit.
TEST(SurfaceFluidLive, SameBitsOnOneAndTwoWorkers) {
  const std::shared_ptr<const LimitSurface> surface = torus();
  SurfaceSimulation one(preset("cavity"), surface, fluid_options(FluidForce::kGravity, 1));
  SurfaceSimulation two(preset("cavity"), surface, fluid_options(FluidForce::kGravity, 2));
  const StrokeSample stroke[] = {sample(0.45f, 0.35f, true), sample(0.55f, 0.3f, true),
                                 sample(0.55f, 0.3f, false), sample(0.2f, 0.5f, true, true),
                                 sample(0.3f, 0.45f, true, true)};
  for (SurfaceSimulation* sim : {&one, &two}) {
    ImageRgb8 image;
    sim->render(image);
    sim->paint(stroke, brush(0.04, 0.8), 0);
    for (int k = 0; k < 8; ++k) sim->step();
  }
  EXPECT_GT(max_speed(*one.fluid()), 0.01);
  EXPECT_EQ(one.fluid()->velocity(), two.fluid()->velocity());
  EXPECT_EQ(one.fluid()->dye(), two.fluid()->dye());
}

TEST(SurfaceFluidLive, SteadyFramesDoNotAllocate) {
  // The preset's viscosity and dye diffusion 0 at the start and above 0 after apply: their
  // solves' first run must not allocate in a frame.
  Preset p = preset("cavity");
  p.scene.fluid.viscosity = 0;
  p.scene.fluid.dye_diffusion = 0;
  // With the start's dye: reset refills it, and the steps after carry it.
  SurfaceSimulation sim(p, torus(), fluid_options(FluidForce::kGravity, 2, true));
  SceneConfig changed = p.scene;
  changed.fluid.viscosity = 0.01;
  changed.fluid.dye_diffusion = 0.01;
  ImageRgb8 image;
  const StrokeSample stroke[] = {sample(0.5f, 0.35f, true), sample(0.52f, 0.36f, true),
                                 sample(0.3f, 0.5f, true, true), sample(0.35f, 0.5f, true, true)};
  const InputMapping input = brush(0.03, 1.0);
  InputMapping push = input;
  push.mode = std::string("push");
  for (int i = 0; i < 2; ++i) {  // the first frames size the solver's and renderer's buffers
    sim.paint(stroke, input, 0);
    sim.paint(stroke, push, 1);
    sim.step();
    sim.render(image);
  }
  const long before = g_allocations.load();
  for (int i = 0; i < 3; ++i) {
    sim.paint(stroke, input, 0);  // paints and turns the view: gravity's down changes
    sim.paint(stroke, push, 1);
    sim.apply(changed);
    sim.step();
    sim.render(image);
  }
  sim.reset();
  sim.step();
  EXPECT_EQ(g_allocations.load() - before, 0);
  EXPECT_EQ(sim.fluid()->params().viscosity, 0.01);
}

}  // namespace
}  // namespace ardcell
