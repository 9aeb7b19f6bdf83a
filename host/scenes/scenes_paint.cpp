// Kim & Lin Fig. 3: a spiral stroke painted into Gray-Scott. Render with
//   ardcell run fig3-deposit --strokes presets/strokes/fig3_spiral.jsonl --paint-radius 8
//       --steps 3000 --every 200 --out out/fig3-deposit
//   ardcell run fig3-orient --strokes presets/strokes/fig3_spiral.jsonl --paint-radius 12
//       --steps 3000 --every 200 --out out/fig3-orient
// Deposition only: the stroke seeds B once, the pattern grows out and stops. Orientation: the
// stroke's tangent sets theta0 everywhere (fast marching extension) with a single cosine lobe
// (Eqn 16, j = 1) opposite to the stroke on A's diffusion (Eqn 14), and the stroke seeds
// separate dabs (paint_config_for), which grow into stripes across the stroke that radiate from
// it and keep travelling against the stroke, inwards along the spiral. The two scenes share
// every RD parameter except the lobe.
#include <string>

#include "host/scenes/scene_registry.h"

namespace ardcell {

namespace {

SceneConfig fig3(bool orient) {
  SceneConfig s;
  s.name = orient ? "fig3-orient" : "fig3-deposit";
  s.description = orient ? "Fig. 3 bottom: spiral stroke sets theta0, single lobe opposite the "
                           "stroke (paint with --strokes, orient mode)"
                         : "Fig. 3 top: spiral stroke deposits Gray-Scott B once, isotropic "
                           "(paint with --strokes, deposit mode)";
  s.size = {256, 256};
  s.domain_width = 256.0;
  s.dt = 1.0;
  s.default_steps = 3000;
  s.fluid.kind = FluidSceneKind::kNone;
  RdConfig& rd = s.rd;
  rd.enabled = true;
  rd.reaction.model = ReactionModel::kGrayScott;
  // Stripe-forming Gray-Scott (F 0.042, k 0.059): a deposited line grows into stripes that
  // follow it, the stripes fill the canvas and then hold still. (At F 0.0367, k 0.0649 the
  // painted line broke into a few spots or decayed.) D_A = 0.8 cells^2 per unit time gives
  // stripes about 16 cells apart on the 256^2 grid; paint with --paint-radius 8 so the stroke
  // is about one stripe wide (narrower strokes decay before they can grow).
  rd.reaction.F = 0.042f;
  rd.reaction.k = 0.059f;
  rd.diffusion_a = 0.8;
  rd.diffusion_b = 0.4;
  rd.dt = 1.0;
  rd.cell_size = 1.0;
  rd.steps_per_frame = 2;
  rd.diffusion_solver = {SolverKind::kIccg, 40, 1e-5};
  rd.background_a = 1.0f;
  rd.background_b = 0.0f;
  rd.seed_a = 0.5f;
  rd.seed_b = 0.25f;
  rd.initial = RdInitialPattern::kUniform;  // the stroke seeds the pattern
  rd.spots = 40;
  rd.seed_radius = 3;
  rd.noise = 0.01;
  if (orient) {
    rd.anisotropy.kind = AnisotropyKind::kCosineLobes;
    rd.anisotropy.lobes = 1;
    // a(phi) = 1 + cos phi: A's rate averages D_A over all directions, 2 D_A along the lobe
    // and 0 against it, so fronts only advance against the stroke.
    rd.anisotropy.lobe_speed[0] = 2.0f;
    // Eqn 14 as printed: a(theta) replaces A's diffusion constant only; B keeps D_B. (With the
    // same a(theta) on both chemicals the stripes settle into a stretched copy of a steady
    // pattern and stop once they fill the canvas.)
    rd.anisotropy_on_b = false;
  }
  // (Not `= "B"`: GCC 12 -O3 warns -Wrestrict on that one-character assignment, bug 105329.)
  s.output.show = std::string("B");
  s.output.colormap = "magma";
  return s;
}

}  // namespace

void register_paint_scenes(SceneRegistry& registry) {
  for (bool orient : {false, true}) {
    const SceneConfig s = fig3(orient);
    registry.add({s.name, s.description, [orient] { return fig3(orient); }});
  }
}

}  // namespace ardcell
