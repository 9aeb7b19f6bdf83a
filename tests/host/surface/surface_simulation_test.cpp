// A flat preset's reaction-diffusion live on a surface (host/surface/surface_simulation.h): the
// 3D view it draws, painting by picking the cell under the pointer, turning the view with the
// right button, live parameter changes, the presets it refuses, and no allocation per frame.
#include "host/surface/surface_simulation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <stdexcept>

#include "host/surface/procedural_mesh.h"
#include "tests/host/surface/surface_live_test_util.h"
#include "tests/support/alloc_counter.h"

namespace ardcell {
namespace {

using namespace surface_live_test;  // NOLINT: the shared helpers of the live surface tests

SurfaceLiveOptions small_options() {
  SurfaceLiveOptions o;
  o.patch_cells = 8;
  o.workers = 2;
  o.view = {320, 240};
  return o;
}

TEST(SurfaceSimulation, DrawsTheSurfaceAndItsPattern) {
  SurfaceSimulation sim(preset("turing-spots"), live_surface(torus_mesh(8, 4, 2.0, 0.8)),
                        small_options());
  EXPECT_EQ(sim.view_size(), (Int2{320, 240}));
  for (int i = 0; i < 20; ++i) sim.step();
  ImageRgb8 image;
  sim.render(image);
  ASSERT_EQ(image.width, 320);
  ASSERT_EQ(image.height, 240);
  EXPECT_GT(distinct_colours(image), 50) << "a shaded surface with a pattern on it";
  EXPECT_EQ(sim.cell_at(0.01f, 0.01f), -1) << "the corner shows the background";
  EXPECT_GE(sim.cell_at(0.5f, 0.35f), 0) << "the torus's far side, above its hole";
}

// A stroke at the view's centre blends the picked cell and its neighbourhood towards the
// preset's seed values and leaves the far side of the surface alone.
TEST(SurfaceSimulation, PaintsTheCellUnderThePointer) {
  const Preset p = preset("turing-spots");
  SurfaceSimulation sim(p, live_surface(torus_mesh(8, 4, 2.0, 0.8)), small_options());
  ImageRgb8 image;
  sim.render(image);
  const float x = 0.5f, y = 0.35f;
  const long cell = sim.cell_at(x, y);
  ASSERT_GE(cell, 0);
  const PatchField before = sim.rd().b();
  const StrokeSample down = sample(x, y, true);
  InputMapping input = p.input;
  input.strength = 1.0;
  sim.paint(std::span(&down, 1), input, 0);
  const PatchField& after = sim.rd().b();
  const double seed_b = p.scene.rd.seed_b;
  EXPECT_NEAR(after[std::size_t(cell)], seed_b, 1e-12) << "full strength at the brush's centre";
  long changed = 0, total = 0;
  const PatchGrid& g = sim.grid();
  for (int q = 0; q < g.patches(); ++q)
    for (int j = 0; j < g.n(); ++j)
      for (int i = 0; i < g.n(); ++i) {
        const std::size_t c = g.index(q, i, j);
        ++total;
        if (after[c] != before[c]) ++changed;
      }
  EXPECT_GT(changed, 1);
  EXPECT_LT(changed, total / 10) << "a brush, not the whole surface";
  // The pointer moving without a button paints nothing.
  const PatchField painted = sim.rd().b();
  const StrokeSample hover = sample(0.6f, 0.4f, false);
  sim.paint(std::span(&hover, 1), input, 0);
  EXPECT_EQ(sim.rd().b(), painted);
}

// Strokes on the torus's far side, above its hole, at a given brush: the preset, the
// simulation drawn once (so points pick cells), and b at a cell.
class SurfaceStroke : public testing::Test {
 protected:
  SurfaceStroke()
      : p_(preset("turing-spots")),
        sim_(p_, live_surface(torus_mesh(8, 4, 2.0, 0.8)), small_options()) {
    ImageRgb8 image;
    sim_.render(image);
  }
  InputMapping brush(double radius, double strength) const {
    InputMapping input = p_.input;
    input.brush_radius = radius;
    input.strength = strength;
    return input;
  }
  double b_at(long cell) const { return sim_.rd().b()[std::size_t(cell)]; }

  const Preset p_;
  SurfaceSimulation sim_;
};

// Two samples of a fast stroke far apart (32 pixels, about 15 brush radii on the screen): the 30
// dabs between them paint the cell under the midpoint too, a line and not two dots; a hover,
// the eraser or a reset between two tips ends the stroke.
TEST_F(SurfaceStroke, AFastStrokePaintsALine) {
  const long middle = sim_.cell_at(0.5f, 0.35f);
  ASSERT_GE(middle, 0);
  ASSERT_NE(sim_.cell_at(0.45f, 0.35f), middle);
  const InputMapping input = brush(0.01, 1.0);
  const double before = b_at(middle);
  const double seed_b = p_.scene.rd.seed_b;
  ASSERT_GT(std::abs(before - seed_b), 1e-3);
  // Each end alone does not reach the middle.
  const StrokeSample ends[] = {sample(0.45f, 0.35f, true), sample(0.45f, 0.35f, false),
                               sample(0.55f, 0.35f, true), sample(0.55f, 0.35f, false)};
  sim_.paint(ends, input, 0);
  EXPECT_EQ(b_at(middle), before);
  const StrokeSample turned[] = {sample(0.45f, 0.35f, true), sample(0.5f, 0.35f, true, true),
                                 sample(0.5f, 0.35f, false), sample(0.55f, 0.35f, true)};
  sim_.paint(std::span(turned).first(2), input, 0);
  sim_.paint(std::span(turned).last(1), input, 0);  // tip, eraser, tip: not joined
  EXPECT_EQ(b_at(middle), before);
  sim_.paint(std::span(turned).first(1), input, 0);
  sim_.reset();
  const double after_reset = b_at(middle);
  sim_.paint(std::span(turned).last(1), input, 0);  // tip, reset, tip: not joined
  EXPECT_EQ(b_at(middle), after_reset);
  const StrokeSample stroke[] = {sample(0.45f, 0.35f, true), sample(0.55f, 0.35f, true)};
  sim_.paint(stroke, input, 0);
  EXPECT_NEAR(b_at(middle), seed_b, 1e-12);
}

// At half strength a slow stroke blends the cells it passes over about once each: the cell under
// its start, dabbed at the first sample, is not blended again by the segment's first dabs that
// still fall on it.
TEST_F(SurfaceStroke, ASlowStrokeBlendsEachCellOncePerSample) {
  const long start = sim_.cell_at(0.45f, 0.35f);
  ASSERT_GE(start, 0);
  ASSERT_NE(sim_.cell_at(0.47f, 0.35f), start);
  // A brush within the cell: only the dab's own cell changes.
  const InputMapping input = brush(0.001, 0.5);
  const double b0 = b_at(start), seed_b = p_.scene.rd.seed_b;
  const StrokeSample stroke[] = {sample(0.45f, 0.35f, true), sample(0.47f, 0.35f, true)};
  sim_.paint(stroke, input, 0);
  const double once = b0 + 0.5 * (seed_b - b0);
  EXPECT_NEAR(b_at(start), once, 1e-12) << "blended once, not per dab";
}

// A right-button drag across a quarter of the canvas turns the view by 90 degrees about the
// vertical axis; the image changes, the fields do not.
TEST(SurfaceSimulation, TheRightButtonTurnsTheView) {
  SurfaceSimulation sim(preset("turing-spots"), live_surface(cube_mesh(2)), small_options());
  ImageRgb8 before, after;
  sim.render(before);
  const double azimuth = sim.view().azimuth_deg, elevation = sim.view().elevation_deg;
  const PatchField a = sim.rd().a();
  const StrokeSample drag[] = {sample(0.2f, 0.5f, true, true), sample(0.45f, 0.6f, true, true),
                               sample(0.45f, 0.6f, false)};
  sim.paint(drag, {}, 0);
  EXPECT_NEAR(sim.view().azimuth_deg, azimuth - 90.0, 1e-4);
  EXPECT_NEAR(sim.view().elevation_deg, elevation + 18.0, 1e-4);
  EXPECT_EQ(sim.rd().a(), a) << "turning paints nothing";
  sim.render(after);
  EXPECT_NE(before.rgb, after.rgb);
  // Elevation stops short of the poles.
  const StrokeSample up[] = {sample(0.5f, 0.0f, true, true), sample(0.5f, 1.0f, true, true)};
  sim.paint(up, {}, 0);
  EXPECT_DOUBLE_EQ(sim.view().elevation_deg, 89.0);
}

// Presets switched in (the live loop's factory, one per session) start where the user left the
// view, not at the options' angles.
TEST(SurfaceSimulation, APresetSwitchedInKeepsTheView) {
  const SimulationFactory factory =
      surface_simulations(live_surface(torus_mesh(8, 4, 2.0, 0.8)), small_options());
  std::unique_ptr<LiveSimulation> first = factory(preset("turing-spots"));
  const auto& one = static_cast<SurfaceSimulation&>(*first);
  const double azimuth = one.view().azimuth_deg, elevation = one.view().elevation_deg;
  const StrokeSample drag[] = {sample(0.2f, 0.5f, true, true), sample(0.45f, 0.6f, true, true)};
  first->paint(drag, {}, 0);
  ASSERT_NEAR(one.view().azimuth_deg, azimuth - 90.0, 1e-4);
  std::unique_ptr<LiveSimulation> second = factory(preset("meinhardt-spots"));
  const auto& two = static_cast<SurfaceSimulation&>(*second);
  EXPECT_EQ(two.view().azimuth_deg, one.view().azimuth_deg);
  EXPECT_EQ(two.view().elevation_deg, one.view().elevation_deg);
  EXPECT_NE(two.view().elevation_deg, elevation);
  // Turned again after the next one was built (the loop builds it ahead, on its worker thread):
  // it shows the new view from its first frame.
  std::unique_ptr<LiveSimulation> third = factory(preset("turing-spots"));
  const StrokeSample more[] = {sample(0.5f, 0.5f, true, true), sample(0.6f, 0.5f, true, true)};
  first->paint(more, {}, 0);
  ImageRgb8 image;
  third->render(image);
  EXPECT_EQ(static_cast<SurfaceSimulation&>(*third).view().azimuth_deg, one.view().azimuth_deg);
  // A simulation made on its own keeps the options' angles.
  SurfaceSimulation alone(preset("turing-spots"), live_surface(torus_mesh(8, 4, 2.0, 0.8)),
                          small_options());
  EXPECT_EQ(alone.view().azimuth_deg, azimuth);
}

TEST(SurfaceSimulation, LiveChangesReachTheReaction) {
  const Preset p = preset("turing-spots");
  SurfaceSimulation sim(p, live_surface(torus_mesh(8, 4, 2.0, 0.8)), small_options());
  SceneConfig next = p.scene;
  next.rd.dt = p.scene.rd.dt * 0.5;
  next.rd.diffusion_b = p.scene.rd.diffusion_b * 2;
  ImageRgb8 shows_a, shows_b;
  sim.render(shows_a);
  next.output.show = std::string(1, 'B');  // a literal warns falsely under GCC 12 (-Wrestrict)
  sim.apply(next);
  EXPECT_DOUBLE_EQ(sim.rd().params().dt, next.rd.dt);
  EXPECT_NEAR(sim.rd().params().diffusion_b / sim.rd().params().diffusion_a,
              next.rd.diffusion_b / next.rd.diffusion_a, 1e-12);
  sim.render(shows_b);
  EXPECT_NE(shows_a.rgb, shows_b.rgb) << "the output's field follows the preset";
  // A reaction out of range keeps the running values.
  SceneConfig bad = next;
  bad.rd.dt = 0.25;
  bad.rd.reaction.turing_s = -1;
  ASSERT_NE(reaction_params_problem(bad.rd.reaction), nullptr);
  sim.apply(bad);
  EXPECT_DOUBLE_EQ(sim.rd().params().dt, next.rd.dt);
}

TEST(SurfaceSimulation, RefusesWhatASurfaceCannotRun) {
  for (const auto& [name, expected] :
       {std::pair{"cavity", "rd.enabled is false (expected a scene with RD)"},
        std::pair{"fig3-orient",
                  "rd.anisotropy: the surface's diffusion is isotropic (expected isotropic)"}}) {
    try {
      SurfaceSimulation sim(preset(name), live_surface(torus_mesh(8, 4, 2.0, 0.8)),
                            small_options());
      ADD_FAILURE() << name << " was accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_EQ(std::string(e.what()), expected);
    }
  }
  EXPECT_FALSE(runs_on_surfaces(preset("cavity")));
  LimitSurface unused;
  EXPECT_EQ(build_live_surface(torus_mesh(8, 4, 2.0, 0.8), 12, unused).message(),
            "--patch-cells 12: expected a power of two in 2..1024");
  EXPECT_EQ(build_live_surface(torus_mesh(8, 4, 2.0, 0.8), 256, unused).message(),
            "32 patches of 256^2 cells are 2097152 cells (expected at most 1048576 live: a "
            "smaller --patch-cells)");
  EXPECT_TRUE(runs_on_surfaces(preset("turing-spots")));
}

TEST(SurfaceSimulation, SteadyFramesDoNotAllocate) {
  // A name past std::string's small buffer: apply() must not copy it.
  const Preset p = preset("obstacle-rd-gray-scott");
  SurfaceSimulation sim(p, live_surface(torus_mesh(8, 4, 2.0, 0.8)), small_options());
  SceneConfig changed = p.scene;
  changed.rd.reaction.F *= 1.01f;
  ImageRgb8 image;
  const StrokeSample stroke[] = {sample(0.5f, 0.35f, true), sample(0.52f, 0.36f, true),
                                 sample(0.3f, 0.5f, true, true), sample(0.35f, 0.5f, true, true)};
  InputMapping input;
  for (int i = 0; i < 2; ++i) {  // the first frames size the solver's and renderer's buffers
    sim.paint(stroke, input, 0);
    sim.step();
    sim.render(image);
  }
  const long before = g_allocations.load();
  for (int i = 0; i < 3; ++i) {
    sim.paint(stroke, input, 0);
    sim.apply(changed);
    sim.step();
    sim.render(image);
  }
  EXPECT_EQ(g_allocations.load() - before, 0);
}

}  // namespace
}  // namespace ardcell
