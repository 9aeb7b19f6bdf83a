// Kim & Lin Fig. 3: a spiral stroke painted into Gray-Scott. Play the recorded stroke with
//   ardcell tablet play fig3-deposit --strokes presets/strokes/fig3_spiral.jsonl --png top.png
//   ardcell tablet play fig3-orient  --strokes presets/strokes/fig3_spiral.jsonl --png bottom.png
// (or `ardcell run ... --strokes` where the run loop paints). Deposition only: the stroke
// seeds B once, the pattern grows out and stops. Orientation: the stroke's tangent sets theta0
// everywhere (fast marching extension) with a single cosine lobe (Eqn 16, j = 1) opposite to
// the stroke, so stripes keep travelling.
#include "host/scene_registry.h"

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
  s.default_steps = 2000;
  s.fluid.kind = FluidSceneKind::kNone;
  RdConfig& rd = s.rd;
  rd.enabled = true;
  rd.reaction.model = ReactionModel::kGrayScott;
  rd.reaction.F = 0.0367f;
  rd.reaction.k = 0.0649f;
  rd.diffusion_a = 1.0;
  rd.diffusion_b = 0.5;
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
    rd.anisotropy.lobe_speed[0] = 2.0f;
  }
  s.output.show = "B";
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
