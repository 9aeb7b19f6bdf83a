// The built-in reaction-diffusion scenes (seed 000, Figs. 4-6; Pearson's Gray-Scott; seed 001).
// RD units: rd.cell_size = 1 and rd.dt = 1 unless noted, so diffusion rates are in cells^2 per
// RD step (Pearson's scene keeps his physical units instead). The fluid of Figs. 5 and 6 runs in
// the scene's units and carries the chemicals with Eqn 20.
#include <cstdio>
#include <string>

#include "host/scenes/scene_registry.h"

namespace ardcell {
namespace {

// The field a scene shows, moved in from a std::string: GCC 12 at -O3 warns -Wrestrict (a false
// positive, bug 105329) on a one-character literal assigned straight into the member.
void show_field(SceneConfig& s, const char* field) { s.output.show = std::string(field); }

RdConfig gray_scott_rd() {
  RdConfig rd;
  rd.enabled = true;
  rd.reaction.model = ReactionModel::kGrayScott;
  rd.reaction.F = 0.04f;  // Pearson's growing regime: seeds spread into labyrinths
  rd.reaction.k = 0.06f;
  rd.diffusion_a = 1.0;
  rd.diffusion_b = 0.5;
  rd.dt = 1.0;
  rd.cell_size = 1.0;
  rd.boundary = BoundaryKind::kDirichlet;
  rd.boundary_a = 1.0f;
  rd.boundary_b = 0.0f;
  rd.background_a = 1.0f;
  rd.background_b = 0.0f;
  rd.seed_a = 0.5f;
  rd.seed_b = 0.25f;
  rd.initial = RdInitialPattern::kRandomSpots;
  rd.spots = 24;
  rd.seed_radius = 5;
  return rd;
}

RdConfig fitzhugh_nagumo_rd() {
  RdConfig rd;
  rd.enabled = true;
  rd.reaction.model = ReactionModel::kFitzHughNagumo;
  rd.diffusion_a = 1.0;
  rd.diffusion_b = 3.0;
  rd.dt = 0.5;
  rd.cell_size = 1.0;
  rd.boundary = BoundaryKind::kDirichlet;
  rd.boundary_a = 0.0f;
  rd.boundary_b = 0.0f;
  rd.background_a = 0.0f;
  rd.background_b = 0.0f;
  rd.seed_a = 1.0f;
  rd.seed_b = 0.3f;
  rd.initial = RdInitialPattern::kRandomSpots;
  rd.spots = 30;
  rd.seed_radius = 4;
  rd.noise = 0.0;
  return rd;
}

RdConfig barkley_rd(bool turbulent) {
  RdConfig rd;
  rd.enabled = true;
  rd.reaction.model = turbulent ? ReactionModel::kBarkleyTurbulent : ReactionModel::kBarkley;
  rd.reaction.barkley_a = 0.75f;
  rd.reaction.barkley_b = 0.02f;
  rd.reaction.barkley_epsilon = 0.02f;
  rd.diffusion_a = 1.0;
  rd.diffusion_b = 0.0;  // Barkley: only the fast variable diffuses
  rd.dt = 0.25;
  rd.cell_size = 1.0;
  rd.boundary = BoundaryKind::kDirichlet;
  rd.boundary_a = 0.0f;
  rd.boundary_b = 0.0f;
  rd.background_a = 0.0f;
  rd.background_b = 0.0f;
  rd.seed_a = 1.0f;
  rd.seed_b = 0.8f;
  rd.seed_size = 0.08;
  rd.initial = RdInitialPattern::kStripe;
  rd.noise = 0.0;
  return rd;
}

// Fig. 4: Gray-Scott "space cookies" grown from a central disc with j-lobed anisotropy (Eqn 16).
// F 0.05, k 0.057: the B-rich region spreads as one solid front (no labyrinth inside it), so
// the cookie is the shape the lobes give that front. The disc favours no direction; a square
// seed's corners would start four arms of their own. The grid's 5-point stencil does not treat
// every direction alike (an axis-facing lobe spreads slower than a diagonal one), so the speeds
// are set per lobe to even the cookie out: the 3-lobed one slows its axis lobe, the 5- and
// 8-lobed ones speed theirs up, and the 4 lobes lie on the diagonals. At the last frame each
// cookie is a bounded j-gon whose outline's strongest angular Fourier mode is j
// (tests/host/scenes/space_cookie_test.cpp); left to run on it grows until it meets the walls.
SceneConfig space_cookie(int lobes) {
  SceneConfig s;
  char name[32];
  std::snprintf(name, sizeof name, "space-cookie-%d", lobes);
  s.name = name;
  char desc[160];
  std::snprintf(desc, sizeof desc,
                "Fig. 4 space cookie: Gray-Scott from a central disc, %d-lobed anisotropy "
                "(Eqn 16, one speed per lobe), no fluid",
                lobes);
  s.description = desc;
  s.size = {128, 128};
  s.domain_width = 128.0;
  s.dt = 1.0;
  s.default_steps = 200;  // the cookie then covers 15-30% of the canvas
  s.fluid.kind = FluidSceneKind::kNone;
  s.rd = gray_scott_rd();
  s.rd.reaction.F = 0.05f;
  s.rd.reaction.k = 0.057f;
  s.rd.initial = RdInitialPattern::kCentreDisc;
  s.rd.seed_radius = 8;
  s.rd.steps_per_frame = 2;
  s.rd.diffusion_solver = {SolverKind::kIccg, 40, 1e-5};
  AnisotropyParams& an = s.rd.anisotropy;
  an.kind = AnisotropyKind::kCosineLobes;
  an.lobes = lobes;
  // Lobe n points at 2 pi n / lobes - theta0; lobe 0 along +x unless rotated.
  for (int n = 0; n < lobes; ++n) an.lobe_speed[n] = 2.0f;
  if (lobes == 3) an.lobe_speed[0] = 1.2f;
  if (lobes == 4) an.theta0 = 0.785398163f;  // pi / 4: the lobes on the diagonals
  if (lobes == 5) an.lobe_speed[0] = 3.6f;
  if (lobes == 8)
    for (int n = 0; n < lobes; n += 2) an.lobe_speed[n] = 3.6f;  // the four on the axes
  show_field(s, "B");
  s.output.colormap = "magma";
  return s;
}

SceneConfig with_fluid(SceneConfig s, FluidSceneKind kind) {
  s.fluid.kind = kind;
  if (kind == FluidSceneKind::kCavity) {
    s.size = {256, 256};
    s.domain_width = 1.0;
    s.dt = 0.01;
    s.fluid.lid_speed = 1.0;
    s.fluid.viscosity = 1.0 / 1000.0;  // Re 1000
  } else {
    s.size = {256, 512};
    s.domain_width = 1.0;
    s.dt = 0.005;
    s.fluid.viscosity = 2.0 * 0.08 * 1.0 / 200.0;  // Re 200 on the disc diameter
  }
  s.default_steps = 1500;
  return s;
}

// Fig. 5: lid-driven cavity.
SceneConfig cavity_rd(const char* name, const char* desc, RdConfig rd) {
  SceneConfig s;
  s.name = name;
  s.description = desc;
  s.rd = rd;
  s = with_fluid(s, FluidSceneKind::kCavity);
  show_field(s, "A");
  s.output.colormap = "viridis";
  return s;
}

// Fig. 6: flow past an obstacle; mode 0 advection only, 1 ARD, 2 RD only (same geometry).
SceneConfig obstacle_rd(const char* name, const char* desc, RdConfig rd, int mode) {
  SceneConfig s;
  s.name = name;
  s.description = desc;
  s.rd = rd;
  if (mode == 0) {
    s.rd.react = false;
    s.rd.diffuse = false;
  }
  if (mode == 2) s.rd.advect = false;
  s = with_fluid(s, FluidSceneKind::kObstacle);
  show_field(s, "A");
  return s;
}

RdConfig passive_rd() {
  RdConfig rd = gray_scott_rd();
  rd.react = false;
  rd.diffuse = false;
  rd.initial = RdInitialPattern::kRandomSpots;
  rd.spots = 40;
  rd.seed_radius = 8;
  rd.seed_a = 0.0f;
  rd.seed_b = 1.0f;
  rd.noise = 0.0;
  return rd;
}

SceneConfig pearson() {
  SceneConfig s;
  s.name = "pearson";
  s.description =
      "Pearson's Gray-Scott: periodic 2.5 x 2.5, 256x256, Du 2e-5, Dv 1e-5, central square "
      "u 1/2 v 1/4 with 1% noise, F 0.04 k 0.06 (settable), ETDRK4 at dt 2";
  s.size = {256, 256};
  s.domain_width = 2.5;
  s.dt = 1.0;
  s.default_steps = 1000;
  s.fluid.kind = FluidSceneKind::kNone;
  RdConfig& rd = s.rd;
  rd.enabled = true;
  rd.reaction.model = ReactionModel::kGrayScott;
  rd.reaction.F = 0.04f;
  rd.reaction.k = 0.06f;
  rd.diffusion_a = 2e-5;
  rd.diffusion_b = 1e-5;
  // Fourth-order exponential time differencing: the most unstable mode's growth within 0.5% of
  // linear theory at dt 2 (backward Euler at dt 1: -79%), and cheaper per frame than backward
  // Euler with ICCG (docs/numerics.md, "Reaction-diffusion in time").
  rd.scheme = RdScheme::kEtdrk4;
  rd.dt = 2.0;
  rd.cell_size = 0.0;  // the scene's h = 2.5 / 256
  rd.boundary = BoundaryKind::kPeriodic;
  rd.initial = RdInitialPattern::kCentreSquare;
  rd.seed_size = 20.0 / 256.0;  // Pearson's 20 x 20 cells
  rd.background_a = 1.0f;
  rd.background_b = 0.0f;
  rd.seed_a = 0.5f;
  rd.seed_b = 0.25f;
  rd.noise = 0.01;
  rd.steps_per_frame = 5;                               // 10 time units a frame
  rd.diffusion_solver = {SolverKind::kIccg, 40, 1e-6};  // for the schemes that solve
  show_field(s, "B");
  s.output.colormap = "magma";
  return s;
}

SceneConfig seed001() {
  SceneConfig s;
  s.name = "seed001";
  s.description =
      "seed 001's explicit Gray-Scott: 400x400, DA 1, DB 0.5, F 0.055, k 0.062, 9-point "
      "Laplacian, 10x10 seed, wrap";
  s.size = {400, 400};
  s.domain_width = 400.0;
  s.dt = 1.0;
  s.default_steps = 200;  // x 10 steps per frame = the article's 2000 steps
  s.fluid.kind = FluidSceneKind::kNone;
  RdConfig& rd = s.rd;
  rd.enabled = true;
  rd.scheme = RdScheme::kExplicit9;
  rd.reaction.model = ReactionModel::kGrayScott;
  rd.reaction.F = 0.055f;
  rd.reaction.k = 0.062f;
  rd.diffusion_a = 1.0;
  rd.diffusion_b = 0.5;
  rd.dt = 1.0;
  rd.cell_size = 1.0;
  rd.boundary = BoundaryKind::kPeriodic;
  rd.initial = RdInitialPattern::kSeedSquare;
  rd.seed_cells = 10;
  rd.background_a = 1.0f;
  rd.background_b = 0.0f;
  rd.seed_a = 1.0f;
  rd.seed_b = 1.0f;
  rd.noise = 0.0;
  rd.steps_per_frame = 10;
  show_field(s, "B");
  s.output.colormap = "magma";
  return s;
}

SceneConfig spots(ReactionModel model) {
  SceneConfig s;
  const bool turing = model == ReactionModel::kTuring;
  s.name = turing ? "turing-spots" : "meinhardt-spots";
  s.description = turing ? "Turing's spot formation (Appendix A), implicit, periodic, no fluid"
                         : "Meinhardt's spot formation (Appendix A), implicit, periodic, no fluid";
  s.size = {128, 128};
  s.domain_width = 128.0;
  s.dt = 1.0;
  s.default_steps = 500;
  s.fluid.kind = FluidSceneKind::kNone;
  RdConfig& rd = s.rd;
  rd.enabled = true;
  rd.reaction.model = model;
  rd.dt = turing ? 8.0 : 1.0;
  rd.cell_size = 1.0;
  // Turing: the activator A diffuses 8 times slower than the substrate B. At 4 times the
  // homogeneous state (4, 4) of beta = 12 sits exactly on the Turing threshold (D_B f_A + D_A g_B
  // = 2 sqrt(D_A D_B det J), both 0.25 s) and the noise decays: Turk's spots at that ratio come
  // from a per-cell random beta.
  rd.diffusion_a = turing ? 0.03125 : 0.02;
  rd.diffusion_b = turing ? 0.25 : 1.0;
  rd.boundary = BoundaryKind::kPeriodic;
  rd.initial = RdInitialPattern::kUniform;
  rd.background_a = turing ? 4.0f : 1.6f;
  rd.background_b = turing ? 4.0f : 1.7067f;
  rd.noise = 0.05;
  show_field(s, "A");
  return s;
}

}  // namespace

void register_rd_scenes(SceneRegistry& registry) {
  // The Fig. 4-6 scenes: under load `ardcell live` may take their RD grid down a rung (0.75 of
  // the scene's) after the solver sweeps; at 512^2 on two cores that is what keeps 60 Hz for
  // the space cookies' two anisotropic RD steps a frame (bench/RESULTS_ENGINE.md).
  auto add = [&](SceneConfig (*make)(), double min_rd_scale = 0.75) {
    const SceneConfig s = make();
    SceneEntry e{s.name, s.description, make};
    e.quality.min_rd_scale = min_rd_scale;
    registry.add(std::move(e));
  };
  add([] { return space_cookie(3); });
  add([] { return space_cookie(4); });
  add([] { return space_cookie(5); });
  add([] { return space_cookie(8); });
  add([] {
    return cavity_rd("cavity-advect",
                     "Fig. 5 lid-driven cavity, passive advection of the chemicals only",
                     passive_rd());
  });
  add([] {
    return cavity_rd("cavity-gray-scott", "Fig. 5 lid-driven cavity with Gray-Scott ARD",
                     gray_scott_rd());
  });
  add([] {
    return cavity_rd("cavity-fhn", "Fig. 5 lid-driven cavity with FitzHugh-Nagumo ARD",
                     fitzhugh_nagumo_rd());
  });
  add([] {
    return cavity_rd("cavity-barkley",
                     "Fig. 5 lid-driven cavity with (turbulent, R_B = A^3 - B) Barkley ARD",
                     barkley_rd(true));
  });
  add([] {
    return obstacle_rd("obstacle-advect", "Fig. 6 flow past an obstacle, advection only",
                       passive_rd(), 0);
  });
  add([] {
    return obstacle_rd("obstacle-ard-gray-scott",
                       "Fig. 6 flow past an obstacle, Gray-Scott advection-reaction-diffusion",
                       gray_scott_rd(), 1);
  });
  add([] {
    return obstacle_rd("obstacle-ard-fhn",
                       "Fig. 6 flow past an obstacle, FitzHugh-Nagumo advection-reaction-diffusion",
                       fitzhugh_nagumo_rd(), 1);
  });
  add([] {
    return obstacle_rd(
        "obstacle-ard-barkley",
        "Fig. 6 flow past an obstacle, turbulent Barkley advection-reaction-diffusion",
        barkley_rd(true), 1);
  });
  add([] {
    return obstacle_rd(
        "obstacle-rd-gray-scott",
        "Fig. 6 obstacle geometry, Gray-Scott reaction-diffusion only (no advection)",
        gray_scott_rd(), 2);
  });
  add([] {
    return obstacle_rd("obstacle-rd-fhn",
                       "Fig. 6 obstacle geometry, FitzHugh-Nagumo reaction-diffusion only",
                       fitzhugh_nagumo_rd(), 2);
  });
  add([] {
    return obstacle_rd("obstacle-rd-barkley",
                       "Fig. 6 obstacle geometry, turbulent Barkley reaction-diffusion only",
                       barkley_rd(true), 2);
  });
  // The pattern-formation scenes keep their RD at the scene's grid.
  add(pearson, 1.0);
  add(seed001, 1.0);
  add([] { return spots(ReactionModel::kTuring); }, 1.0);
  add([] { return spots(ReactionModel::kMeinhardt); }, 1.0);
}

}  // namespace ardcell
