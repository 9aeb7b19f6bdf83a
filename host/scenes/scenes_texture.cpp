// Seed 003 (McGraw): generalized reaction-diffusion textures, one preset per Table 2 tensor
// sequence (a)-(f) with Turing's (Eqn 2) and Gray-Scott's (Eqns 3-4) reaction. Periodic, so every
// texture tiles; semi-implicit (Eqn 28, solved exactly by FFT), so the steps are large. Two more
// with a per-cell tensor field (Table 1's last row): vortex (explicit) and radial (semi-implicit,
// by BiCGSTAB).
// The cell size h is fixed (rd.cell_size), so a larger grid is a larger texture of the same look:
// h sets the length at which the rank-4 terms overtake the rank-2 ones (host/engine/rd_step.cpp),
// and the values below put the oriented, sharp-cornered labyrinths of the paper's Figs. 2-5 a few
// cells wide. A finer cell would resolve more of the anti-diffusive directions of (d), (e), (f)
// (docs/numerics.md), and they take over at the grid scale.
#include "host/scenes/scene_registry.h"

namespace ardcell {
namespace {

struct TextureSpec {
  const char* letter;
  TensorSequence tensors;
  double h;  // cell size
};

// (d)'s anti-diffusion lies on the axes, where the 5x5 stencil resolves it best: it needs a
// coarser cell than the others to stay above the grid scale.
constexpr TextureSpec kSpecs[] = {{"a", kTable2A, 1.5}, {"b", kTable2B, 1.5}, {"c", kTable2C, 1.5},
                                  {"d", kTable2D, 2.4}, {"e", kTable2E, 1.5}, {"f", kTable2F, 1.5}};

SceneConfig texture_base(const TextureSpec& t) {
  SceneConfig s;
  s.size = {128, 128};
  s.domain_width = 128.0 * t.h;
  s.dt = 1.0;
  s.default_steps = 200;
  s.fluid.kind = FluidSceneKind::kNone;
  RdConfig& rd = s.rd;
  rd.enabled = true;
  rd.diffusion_operator = RdOperator::kGeneralized;
  rd.generalized.tensors = t.tensors;
  rd.scheme = RdScheme::kSemiImplicit;
  rd.boundary = BoundaryKind::kPeriodic;
  rd.cell_size = t.h;
  rd.steps_per_frame = 10;
  s.output.colormap = "gray";
  return s;
}

// Eqn 2 with seed 003's alpha 12, beta 15 (ardcell's Turing with beta 12, supply 15) at rate
// s = 1/16 and step 1.6: seed 003's delta 0.1 in its own time. u = v = 4 + U(-2, 2).
SceneConfig turing_texture(const TextureSpec& t) {
  SceneConfig s = texture_base(t);
  s.name = std::string("mcgraw-turing-") + t.letter;
  s.description = std::string("seed 003 Fig. 2(") + t.letter +
                  "): Turing (alpha 12, beta 15) with Table 2's tensor sequence (" + t.letter +
                  "), periodic, semi-implicit by FFT";
  RdConfig& rd = s.rd;
  rd.reaction.model = ReactionModel::kTuring;
  rd.reaction.turing_s = 1.0f / 16.0f;
  rd.reaction.turing_beta = 12.0f;
  rd.reaction.turing_supply = 15.0f;
  rd.dt = 1.6;
  // Rates in the domain's units: 0.25 and 1.25 cells^2 per unit time at h.
  rd.diffusion_a = 0.25 * t.h * t.h;
  rd.diffusion_b = 1.25 * t.h * t.h;
  rd.initial = RdInitialPattern::kUniform;
  rd.background_a = 4.0f;
  rd.background_b = 4.0f;
  rd.noise = 0.5;  // relative: 4 +- 2
  // Built, then moved in: assigning "A" warns falsely under GCC 12 -O3 (-Wrestrict).
  s.output.show = std::string(1, 'A');
  return s;
}

// Eqns 3-4 (Pearson's F 0.04, k 0.06), u = 1, v = 0 with a central square of (1/2, 1/4) and
// relative noise 0.25, as seed 003's Figs. 3-5 start.
SceneConfig gray_scott_texture(const TextureSpec& t) {
  SceneConfig s = texture_base(t);
  s.name = std::string("mcgraw-gray-scott-") + t.letter;
  s.description = std::string(
                      "seed 003 Figs. 3-5: Gray-Scott (F 0.04, k 0.06) with Table 2's "
                      "tensor sequence (") +
                  t.letter + "), periodic, semi-implicit by FFT";
  s.default_steps = 400;
  RdConfig& rd = s.rd;
  rd.reaction.model = ReactionModel::kGrayScott;
  rd.reaction.F = 0.04f;
  rd.reaction.k = 0.06f;
  rd.dt = 1.0;
  rd.diffusion_a = 0.2 * t.h * t.h;
  rd.diffusion_b = 0.1 * t.h * t.h;
  rd.initial = RdInitialPattern::kCentreSquare;
  rd.seed_size = 0.25;
  rd.background_a = 1.0f;
  rd.background_b = 0.0f;
  rd.seed_a = 0.5f;
  rd.seed_b = 0.25f;
  rd.noise = 0.25;
  s.output.show = std::string(1, 'B');  // (as in turing_texture)
  return s;
}

// Fig. 6: Gray-Scott's parameter map with sequence (e): F from 0.01 at the left to 0.06 at the
// right, k from 0.05 at the bottom to 0.07 at the top (spots, diagonal worms and labyrinths
// between the two uniform states), started from spots everywhere so that every part of the map
// grows its own pattern.
SceneConfig gray_scott_map() {
  SceneConfig s = gray_scott_texture(kSpecs[4]);
  s.name = "mcgraw-gray-scott-map";
  s.description =
      "seed 003 Fig. 6: Gray-Scott parameter map with Table 2's sequence (e), F 0.01-0.06 "
      "along x, k 0.05-0.07 along y";
  s.size = {256, 256};
  s.domain_width = 256.0 * kSpecs[4].h;
  s.default_steps = 1000;
  RdConfig& rd = s.rd;
  rd.reaction.F = 0.01f;
  rd.reaction.k = 0.05f;
  rd.map = true;
  rd.map_f = 0.06f;
  rd.map_k = 0.07f;
  rd.initial = RdInitialPattern::kRandomSpots;
  rd.spots = 400;
  rd.seed_radius = 3;
  return s;
}

// Table 1's last row at rank 2: Turing (the presets' alpha 12, beta 15) with a per-cell tensor
// whose principal direction is tangential around the centre (rd.generalized.field vortex), so the
// stripes run in circles. Explicit (Eqn 27 with div(D(x) grad u)): rd.dt 0.1, 100 steps a frame
// (rho(I + dt D_B K) <= 1; the run prints it).
SceneConfig turing_vortex() {
  SceneConfig s = turing_texture(kSpecs[0]);
  s.name = "mcgraw-turing-vortex";
  s.description =
      "seed 003 Table 1, last row: Turing with a per-cell rank-2 tensor turning around the "
      "centre (vortex), explicit";
  RdConfig& rd = s.rd;
  rd.generalized.field = TensorFieldKind::kVortex;
  rd.generalized.d_along = 2.0;
  rd.generalized.d_across = 0.5;
  rd.scheme = RdScheme::kExplicit;
  rd.dt = 0.1;
  rd.steps_per_frame = 100;
  return s;
}

// The same with the principal direction along the rays (stripes run outwards), semi-implicit
// (Eqn 28: (I - dt D L) solved by BiCGSTAB, kernels/tensor_field_solve.h) at the Table 2
// presets' step, rd.dt 1.6 and 10 steps a frame: 16 times the explicit step, which it could not
// take (rho(I + dt D_B L) > 1).
SceneConfig turing_radial() {
  SceneConfig s = turing_vortex();
  s.name = "mcgraw-turing-radial";
  s.description =
      "seed 003 Table 1, last row: Turing with a per-cell rank-2 tensor along the rays from the "
      "centre (radial), semi-implicit by BiCGSTAB";
  RdConfig& rd = s.rd;
  rd.generalized.field = TensorFieldKind::kRadial;
  rd.scheme = RdScheme::kSemiImplicit;
  rd.dt = 1.6;
  rd.steps_per_frame = 10;
  return s;
}

}  // namespace

void register_texture_scenes(SceneRegistry& registry) {
  for (const TextureSpec& t : kSpecs) {
    const SceneConfig turing = turing_texture(t);
    registry.add({turing.name, turing.description, [t] { return turing_texture(t); }});
  }
  for (const TextureSpec& t : kSpecs) {
    const SceneConfig gs = gray_scott_texture(t);
    registry.add({gs.name, gs.description, [t] { return gray_scott_texture(t); }});
  }
  const SceneConfig map = gray_scott_map();
  registry.add({map.name, map.description, gray_scott_map});
  const SceneConfig vortex = turing_vortex();
  registry.add({vortex.name, vortex.description, turing_vortex});
  const SceneConfig radial = turing_radial();
  registry.add({radial.name, radial.description, turing_radial});
}

}  // namespace ardcell
