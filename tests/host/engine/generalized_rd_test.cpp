// Seed 003's generalized reaction-diffusion on the engine (rd.operator generalized): the fused
// kernel against the double-precision stencil, the schemes of Eqns 27/28, the presets'
// orientations (Fig. 2-5: axes for (d), diagonals for (e), none for (a)), and the checks that
// refuse what the operator cannot run.
#include <fftw3.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <mutex>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "host/engine/engine.h"
#include "host/engine/rd_step.h"
#include "host/scenes/preset.h"
#include "kernels/generalized_rd.h"
#include "kernels/periodic_stencil_solve.h"
#include "tests/support/field_compare.h"
#include "tests/support/preset_params.h"

namespace ardcell {
namespace {

// Diffusion alone (no reaction, no clamp): the fused float kernel with periodic index wrap
// against GeneralizedDiffusion's double sums over a wrapped halo of 2.
TEST(GeneralizedRdKernel, MatchesTheDoubleStencilOnEverySequence) {
  const Int2 size{37, 29};
  for (const NamedTensorSequence& seq : kTable2) {
    const Stencil5x5 k = assemble_generalized_stencil(seq.tensors);
    FieldF a = random_field(size, 2, 7, 0.0f, 1.0f), b = random_field(size, 2, 8, 0.0f, 1.0f);
    FieldF a_out(size, 2), b_out(size, 2), ref(size, 2);
    GeneralizedRdParams p;
    p.scale_a = 0.05f;
    p.scale_b = 0.02f;
    std::vector<float> scratch(generalized_rd_scratch_floats(size.x));
    generalized_rd_rows(GeneralizedTaps(k), a.view(), b.view(), a_out.view(), b_out.view(), size, 0,
                        size.y, p, scratch.data());
    fill_periodic_halo(a);
    GeneralizedDiffusion(k).explicit_step_tile(a.view(), ref.view(), box_of_size(size), 0.05);
    double worst = 0;
    for (int y = 0; y < size.y; ++y)
      for (int x = 0; x < size.x; ++x)
        worst = std::max(worst, double(std::abs(a_out(x, y) - ref(x, y))));
    EXPECT_LT(worst, 2e-6) << "sequence " << seq.name;
  }
}

TEST(GeneralizedRdKernel, BandsOfRowsGiveTheSameBits) {
  const Int2 size{45, 31};
  const GeneralizedTaps k(assemble_generalized_stencil(kTable2C));
  const FieldF a = random_field(size, 1, 3, 0.0f, 1.0f), b = random_field(size, 1, 4, 0.0f, 1.0f);
  GeneralizedRdParams p;
  p.reaction.model = ReactionModel::kGrayScott;
  p.dt = 0.5f;
  p.scale_a = 0.1f;
  p.scale_b = 0.05f;
  std::vector<float> scratch(generalized_rd_scratch_floats(size.x));
  FieldF a1(size, 1), b1(size, 1), a2(size, 1), b2(size, 1);
  generalized_rd_rows(k, a.view(), b.view(), a1.view(), b1.view(), size, 0, size.y, p,
                      scratch.data());
  const int cuts[] = {0, 1, 2, 7, 30, 31};  // bands of 1, 1, 5, 23 and 1 rows
  for (int i = 0; i + 1 < 6; ++i)
    generalized_rd_rows(k, a.view(), b.view(), a2.view(), b2.view(), size, cuts[i], cuts[i + 1], p,
                        scratch.data());
  for (int y = 0; y < size.y; ++y)
    for (int x = 0; x < size.x; ++x) {
      ASSERT_EQ(a1(x, y), a2(x, y)) << x << "," << y;
      ASSERT_EQ(b1(x, y), b2(x, y)) << x << "," << y;
    }
}

// Fused steps (generalized_rd_fused_rows, 1 to 4) give the bits of single steps, over the whole
// grid and in bands (1-row bands, a band at each edge: the first step's rows wrap), for each
// reaction path (Turing, the Gray-Scott map, a model through reaction_rates), with only A
// diffusing, and on grids shorter than the 5-row rings.
TEST(GeneralizedRdKernel, FusedStepsAreSingleSteps) {
  struct Case {
    Int2 size;
    const char* name;
    TensorSequence seq;
    ReactionModel model;
    bool map, b_diffuses;
  };
  const Case cases[] = {
      {{45, 31}, "d", kTable2D, ReactionModel::kTuring, false, true},
      {{70, 23}, "a", kTable2A, ReactionModel::kGrayScott, true, true},
      {{33, 17}, "e", kTable2E, ReactionModel::kFitzHughNagumo, false, false},
      {{130, 3}, "c", kTable2C, ReactionModel::kGrayScott, false, true},
      {{2, 2}, "d", kTable2D, ReactionModel::kTuring, false, true},
  };
  for (const Case& c : cases) {
    const Int2 size = c.size;
    const GeneralizedTaps k(assemble_generalized_stencil(c.seq));
    FieldF a = random_field(size, 1, 3, 0.0f, 1.0f), b = random_field(size, 1, 4, 0.0f, 1.0f);
    GeneralizedRdParams p;
    p.reaction.model = c.model;
    p.dt = 0.25f;
    p.scale_a = 0.1f;
    p.scale_b = c.b_diffuses ? 0.05f : 0.0f;
    p.a_lo = 0.0f, p.a_hi = 0.9f;  // the clamp bites
    if (c.map) p.f_step = 1e-3f, p.k_step = -5e-4f;
    std::vector<float> scratch(generalized_rd_scratch_floats(size.x));
    for (int steps = 1; steps <= kGeneralizedFusedSteps; ++steps) {
      FieldF x = a, y = b, x_next(size, 1), y_next(size, 1), a3(size, 1), b3(size, 1);
      for (int i = 0; i < steps; ++i) {
        generalized_rd_rows(k, x.view(), y.view(), x_next.view(), y_next.view(), size, 0, size.y, p,
                            scratch.data());
        std::swap(x, x_next);
        std::swap(y, y_next);
      }
      std::vector<int> cuts = {0, size.y};
      if (size.y > 4) cuts = {0, 1, 2, size.y / 2, size.y - 1, size.y};
      for (std::size_t i = 0; i + 1 < cuts.size(); ++i)
        generalized_rd_fused_rows(k, a.view(), b.view(), a3.view(), b3.view(), size, cuts[i],
                                  cuts[i + 1], p, steps, scratch.data());
      for (int yy = 0; yy < size.y; ++yy)
        for (int xx = 0; xx < size.x; ++xx) {
          ASSERT_EQ(a3(xx, yy), x(xx, yy))
              << c.name << " " << steps << " steps " << xx << "," << yy;
          ASSERT_EQ(b3(xx, yy), y(xx, yy))
              << c.name << " " << steps << " steps " << xx << "," << yy;
        }
      // The steps moved the fields (a test of equal zeros would prove nothing).
      EXPECT_NE(x(size.x / 2, size.y / 2), a(size.x / 2, size.y / 2)) << c.name;
    }
  }
}

// Fig. 6's parameter map: every cell reacts as the uniform kernel does with that cell's F and k
// (bit for bit: the same float sums), F growing along x and k along y.
TEST(GeneralizedRdKernel, ParameterMapIsTheUniformReactionCellByCell) {
  const Int2 size{37, 21};
  const GeneralizedTaps k(assemble_generalized_stencil(kTable2E));
  const FieldF a = random_field(size, 1, 5, 0.0f, 1.0f), b = random_field(size, 1, 6, 0.0f, 0.5f);
  GeneralizedRdParams p;
  p.reaction.model = ReactionModel::kGrayScott;
  p.reaction.F = 0.01f;
  p.reaction.k = 0.05f;
  p.dt = 1.0f;
  p.scale_a = 0.1f;
  p.scale_b = 0.05f;
  p.f_step = 0.05f / size.x;
  p.k_step = 0.02f / size.y;
  std::vector<float> scratch(generalized_rd_scratch_floats(size.x));
  FieldF am(size, 1), bm(size, 1), au(size, 1), bu(size, 1);
  generalized_rd_rows(k, a.view(), b.view(), am.view(), bm.view(), size, 0, size.y, p,
                      scratch.data());
  for (int x : {0, 17, 36})
    for (int y : {0, 9, 20}) {
      GeneralizedRdParams uniform = p;
      uniform.f_step = uniform.k_step = 0.0f;
      uniform.reaction.F = p.reaction.F + p.f_step * (float(x) + 0.5f);
      uniform.reaction.k = p.reaction.k + p.k_step * (float(y) + 0.5f);
      generalized_rd_rows(k, a.view(), b.view(), au.view(), bu.view(), size, 0, size.y, uniform,
                          scratch.data());
      EXPECT_EQ(am(x, y), au(x, y)) << x << "," << y;
      EXPECT_EQ(bm(x, y), bu(x, y)) << x << "," << y;
      // ...and not the uniform reaction of another cell's parameters.
      if (x > 0) {
        EXPECT_NE(bm(x, y), bu(0, y)) << x << "," << y;
      }
    }
  // The map's corners are the range asked for.
  EXPECT_NEAR(p.reaction.F + p.f_step * size.x, 0.06, 1e-6);
}

// Taps that sum to zero on a periodic grid move mass around and create none.
TEST(GeneralizedRdKernel, PureDiffusionConservesTheTotal) {
  const Int2 size{64, 48};
  const GeneralizedTaps k(assemble_generalized_stencil(kTable2B));
  FieldF a = random_field(size, 1, 11, 0.0f, 1.0f), b = random_field(size, 1, 12, 0.0f, 1.0f);
  FieldF a2(size, 1), b2(size, 1);
  const double before = interior_sum(a);
  GeneralizedRdParams p;
  p.scale_a = p.scale_b = 0.1f;
  std::vector<float> scratch(generalized_rd_scratch_floats(size.x));
  for (int i = 0; i < 100; ++i) {
    generalized_rd_rows(k, a.view(), b.view(), a2.view(), b2.view(), size, 0, size.y, p,
                        scratch.data());
    std::swap(a, a2);
    std::swap(b, b2);
  }
  EXPECT_NEAR(interior_sum(a), before, 1e-5 * before);
}

// Eqn 28 without reaction is exactly one periodic solve of (I - dt D_A K).
TEST(GeneralizedRdEngine, SemiImplicitStepIsTheExactSolve) {
  SceneConfig scene = builtin_preset_scene("mcgraw-turing-a");
  scene.size = {40, 36};
  scene.domain_width = 40 * 1.5;
  scene.rd.react = false;
  scene.rd.steps_per_frame = 1;
  Engine engine(scene, {.backend = EngineOptions::Backend::kSerial});
  FieldF expected = engine.state().A;
  const double delta = scene.rd.dt * scene.rd.diffusion_a;  // K in cells carries 1 / h^2
  const double h = scene.domain_width / scene.size.x;
  PeriodicStencilSolve solve(scene.size, assemble_generalized_stencil(
                                             TensorSequence{.xx = 1 / (h * h), .yy = 1 / (h * h)}));
  solve.solve(expected, delta);
  engine.step();
  const FieldF& a = engine.state().A;
  for (int y = 0; y < scene.size.y; ++y)
    for (int x = 0; x < scene.size.x; ++x) ASSERT_NEAR(a(x, y), expected(x, y), 1e-5);
}

// Every nonzero weight (above the assembly's rounding) of every Table 2 stencil is one tap of one
// group, with its own weight (to the float's rounding: a group shares its first tap's); groups have
// 1, 2, 4 or 8 taps; the symmetric sequences gather their taps (isotropic (a): the centre and the
// four axis neighbours; (d), (e): a quarter turn's orbits of 4 or 8).
TEST(GeneralizedTaps, GroupsHoldEveryTapOnceWithItsWeight) {
  for (const NamedTensorSequence& seq : kTable2) {
    SCOPED_TRACE(seq.name);
    const Stencil5x5 k = assemble_generalized_stencil(seq.tensors);
    const GeneralizedTaps taps(k);
    int seen[5][5] = {}, next = 0, biggest_group = 0;
    for (int g = 0; g < taps.group_count; ++g) {
      const GeneralizedTaps::Group& group = taps.groups[g];
      EXPECT_EQ(group.first, next);
      EXPECT_TRUE(group.count == 1 || group.count == 2 || group.count == 4 || group.count == 8);
      biggest_group = std::max(biggest_group, group.count);
      for (int t = group.first; t < group.first + group.count; ++t) {
        const GeneralizedTaps::Tap& tap = taps.taps[t];
        EXPECT_EQ(tap.weight, group.weight);
        EXPECT_NEAR(tap.weight, k.at(tap.dx, tap.dy), 1e-6 * std::abs(k.at(tap.dx, tap.dy)));
        ++seen[tap.dy + 2][tap.dx + 2];
      }
      next += group.count;
    }
    EXPECT_EQ(next, taps.count);
    double largest = 0;
    for (int dy = -2; dy <= 2; ++dy)
      for (int dx = -2; dx <= 2; ++dx) largest = std::max(largest, std::abs(k.at(dx, dy)));
    for (int dy = -2; dy <= 2; ++dy)
      for (int dx = -2; dx <= 2; ++dx)
        EXPECT_EQ(seen[dy + 2][dx + 2], std::abs(k.at(dx, dy)) > 1e-12 * largest ? 1 : 0)
            << dx << "," << dy;
    if (seq.name == std::string("a")) {
      EXPECT_EQ(taps.group_count, 2);
    }
    if (seq.name == std::string("d") || seq.name == std::string("e")) {
      EXPECT_GE(biggest_group, 4);
    }
  }
}

// seed 003's symmetries: a sequence symmetric under a map of the plane gives a step that commutes
// with it. 64^2, the max difference relative to the field's range.
//   explicit (Eqn 27), reaction on, 1000 steps: each cell adds its taps by symmetry groups
//     (GeneralizedTaps), so a mapped field gets the mapped sums and the error is exactly 0;
//   semi-implicit (Eqn 28), diffusion alone: the FFT rounds a mapped field differently, and that
//     rounding accumulates: 2-4e-5 after 100 steps, ~1e-2 after 1000 (measured), so it takes 100.
double symmetry_error(const char* preset, bool rotate, bool explicit_scheme, int frames) {
  SceneConfig scene = builtin_preset_scene(preset);
  scene.size = {64, 64};
  scene.rd.steps_per_frame = 10;
  if (explicit_scheme) {
    scene.rd.scheme = RdScheme::kExplicit;
    scene.rd.dt = 0.05;  // stable: the explicit update's spectral radius stays <= 1
  } else {
    scene.rd.react = false;
  }
  Engine plain(scene, {.backend = EngineOptions::Backend::kSerial});
  Engine mapped(scene, {.backend = EngineOptions::Backend::kSerial});
  const int n = 64;
  // rotate: (x, y) -> (n - 1 - y, x), a quarter turn; else the transpose (x, y) -> (y, x).
  const auto map = [&](const FieldF& from, FieldF& to) {
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) (rotate ? to(n - 1 - y, x) : to(y, x)) = from(x, y);
  };
  map(plain.state().A, mapped.state().A);
  map(plain.state().B, mapped.state().B);
  for (int i = 0; i < frames; ++i) {
    plain.step();
    mapped.step();
  }
  FieldF expected(scene.size, 1);
  map(plain.state().A, expected);
  const FieldF& a = mapped.state().A;
  double worst = 0, lo = 1e30, hi = -1e30;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      worst = std::max(worst, double(std::abs(a(x, y) - expected(x, y))));
      lo = std::min(lo, double(expected(x, y)));
      hi = std::max(hi, double(expected(x, y)));
    }
  EXPECT_GT(hi - lo, 1e-3) << preset << ": a pattern has grown";
  return worst / std::max(hi - lo, 1e-30);
}

TEST(GeneralizedRdEngine, StepsCommuteExactlyWithTheSequencesSymmetries) {
  constexpr int kFrames = 100;  // x 10 steps: 1000 explicit steps with reaction
  EXPECT_EQ(symmetry_error("mcgraw-turing-c", false, true, kFrames), 0.0) << "(c), transpose";
  EXPECT_EQ(symmetry_error("mcgraw-turing-d", true, true, kFrames), 0.0) << "(d), quarter turn";
  EXPECT_EQ(symmetry_error("mcgraw-turing-e", true, true, kFrames), 0.0) << "(e), quarter turn";
  // A map the sequence lacks breaks it: (c) is not symmetric under a quarter turn.
  EXPECT_GT(symmetry_error("mcgraw-turing-c", true, true, kFrames), 1e-2);
}

TEST(GeneralizedRdEngine, SemiImplicitStepsCommuteWithTheSymmetriesToRounding) {
  EXPECT_LT(symmetry_error("mcgraw-turing-c", false, false, 10), 1e-4) << "(c) and the transpose";
  EXPECT_LT(symmetry_error("mcgraw-turing-d", true, false, 10), 1e-4) << "(d) and a quarter turn";
  EXPECT_LT(symmetry_error("mcgraw-turing-e", true, false, 10), 1e-4) << "(e) and a quarter turn";
  EXPECT_GT(symmetry_error("mcgraw-turing-c", true, false, 10), 1e-2);
}

// A texture tiles: across the wrap-around edges neighbours differ no more than inside.
TEST(GeneralizedRdEngine, TexturesTileWithoutASeam) {
  SceneConfig scene = builtin_preset_scene("mcgraw-gray-scott-e");
  scene.size = {96, 96};
  Engine engine(scene);
  for (int i = 0; i < 150; ++i) engine.step();
  const FieldF& b = engine.state().B;
  double inside = 0, seam = 0;
  for (int i = 0; i < 96; ++i) {
    for (int j = 0; j + 1 < 96; ++j)
      inside = std::max({inside, double(std::abs(b(j + 1, i) - b(j, i))),
                         double(std::abs(b(i, j + 1) - b(i, j)))});
    seam = std::max(
        {seam, double(std::abs(b(0, i) - b(95, i))), double(std::abs(b(i, 0) - b(i, 95)))});
  }
  EXPECT_GT(inside, 0.05) << "a pattern has grown";
  EXPECT_LE(seam, inside);
}

// The share of the power spectrum of A within 22.5 degrees of the axes over that within 22.5
// degrees of the diagonals, for wavenumbers above 2 (the pattern, not the mean's drift).
double axis_over_diagonal_power(const FieldF& f) {
  const int nx = f.nx(), ny = f.ny();
  std::vector<float> in(std::size_t(nx) * ny);
  double mean = 0;
  for (int y = 0; y < ny; ++y)
    for (int x = 0; x < nx; ++x) mean += f(x, y);
  mean /= double(nx) * ny;
  for (int y = 0; y < ny; ++y)
    for (int x = 0; x < nx; ++x) in[std::size_t(y) * nx + x] = float(f(x, y) - mean);
  const int w = nx / 2 + 1;
  std::vector<fftwf_complex> out(std::size_t(w) * ny);
  {
    std::lock_guard<std::mutex> lock(fftw_planner_mutex());
    fftwf_plan plan = fftwf_plan_dft_r2c_2d(ny, nx, in.data(), out.data(), FFTW_ESTIMATE);
    fftwf_execute(plan);
    fftwf_destroy_plan(plan);
  }
  double axis = 0, diagonal = 0;
  for (int my = 0; my < ny; ++my)
    for (int mx = 0; mx < w; ++mx) {
      const double ky = 2 * my <= ny ? my : my - ny, kx = mx;
      if (std::hypot(kx, ky) <= 2) continue;
      const fftwf_complex& c = out[std::size_t(my) * w + mx];
      const double power = double(c[0]) * c[0] + double(c[1]) * c[1];
      const double angle = std::fmod(std::atan2(ky, kx) * 180 / M_PI + 360, 90.0);
      (angle < 22.5 || angle >= 67.5 ? axis : diagonal) += power;
    }
  return axis / diagonal;
}

double developed_orientation(const char* preset) {
  SceneConfig scene = builtin_preset_scene(preset);
  Engine engine(scene);  // threads
  for (int i = 0; i < 200; ++i) engine.step();
  return axis_over_diagonal_power(engine.state().A);
}

TEST(GeneralizedRdEngine, TuringTexturesTakeTheSequencesOrientations) {
  const double a = developed_orientation("mcgraw-turing-a");
  const double d = developed_orientation("mcgraw-turing-d");
  const double e = developed_orientation("mcgraw-turing-e");
  EXPECT_GT(a, 1 / 1.5) << "(a) is isotropic";
  EXPECT_LT(a, 1.5) << "(a) is isotropic";
  EXPECT_GT(d, 1.5) << "(d): the axes";
  EXPECT_LT(e, 1 / 1.5) << "(e): the diagonals";
}

TEST(GeneralizedRdEngine, RefusesWhatTheOperatorCannotRun) {
  SceneConfig scene = builtin_preset_scene("mcgraw-gray-scott-e");
  scene.rd.boundary = BoundaryKind::kNeumann;
  EXPECT_EQ(rd_config_problem(scene),
            "rd.operator generalized needs rd.boundary periodic (its textures tile)");
  scene = builtin_preset_scene("mcgraw-gray-scott-e");
  scene.rd.scheme = RdScheme::kExplicit9;
  EXPECT_NE(rd_config_problem(scene).find("rd.scheme"), std::string::npos);
  scene = builtin_preset_scene("pearson");
  scene.rd.scheme = RdScheme::kSemiImplicit;
  EXPECT_NE(rd_config_problem(scene).find("rd.operator generalized"), std::string::npos);
  // The parameter map: Gray-Scott, generalized operator, explicit or semi-implicit.
  EXPECT_EQ(rd_config_problem(builtin_preset_scene("mcgraw-gray-scott-map")), "");
  scene = builtin_preset_scene("mcgraw-gray-scott-map");
  scene.rd.reaction.model = ReactionModel::kTuring;
  EXPECT_NE(rd_config_problem(scene).find("rd.map"), std::string::npos);
  scene = builtin_preset_scene("mcgraw-gray-scott-map");
  scene.rd.scheme = RdScheme::kImplicit;
  EXPECT_NE(rd_config_problem(scene).find("rd.map"), std::string::npos);
  scene = builtin_preset_scene("pearson");
  scene.rd.map = true;
  EXPECT_NE(rd_config_problem(scene).find("rd.map"), std::string::npos);

  // A new tensor sequence rebuilds the engine; a new rate does not.
  scene = builtin_preset_scene("mcgraw-turing-e");
  scene.size = {32, 32};
  Engine engine(scene);
  SceneConfig next = scene;
  next.rd.generalized.tensors.xxyy = 2;
  const Status s = engine.update_parameters(next);
  ASSERT_FALSE(s);
  EXPECT_NE(s.message().find("rd.generalized"), std::string::npos) << s.message();
  next = scene;
  next.rd.diffusion_b *= 1.1;
  EXPECT_TRUE(engine.update_parameters(next));
}

// The engine runs explicit steps kGeneralizedFusedSteps at a time (4 + 4 + 2 of a 10-step
// frame; the CPU fuses them above 512^2, with bands of 64 rows or more): the same bits as one
// step a frame (fused too, one step per walk; FusedStepsAreSingleSteps compares that with
// generalized_rd_rows), on one worker and on two.
TEST(GeneralizedRdEngine, FusedFramesAreStepByStepFrames) {
  SceneConfig scene = builtin_preset_scene("mcgraw-turing-d");
  scene.size = {520, 520};
  scene.rd.scheme = RdScheme::kExplicit;
  scene.rd.dt = 0.05;
  SceneConfig one_step = scene;
  scene.rd.steps_per_frame = 10;
  one_step.rd.steps_per_frame = 1;
  Engine fused(scene, {.backend = EngineOptions::Backend::kSerial});
  Engine threads(scene, {.backend = EngineOptions::Backend::kThreads, .workers = 2});
  Engine stepwise(one_step, {.backend = EngineOptions::Backend::kSerial});
  const FieldF start = fused.state().A;
  fused.step();
  threads.step();
  for (int i = 0; i < 10; ++i) stepwise.step();
  const Engine& reference = stepwise;
  for (const Engine* e : {&fused, &threads})
    for (int y = 0; y < scene.size.y; ++y)
      for (int x = 0; x < scene.size.x; ++x) {
        ASSERT_EQ(e->state().A(x, y), reference.state().A(x, y)) << x << "," << y;
        ASSERT_EQ(e->state().B(x, y), reference.state().B(x, y)) << x << "," << y;
      }
  EXPECT_GT(max_relative_error(std::as_const(fused).state().A, start), 1e-4);
}

TEST(GeneralizedRdEngine, ExplicitStabilityLineNamesTheSpectralRadius) {
  SceneConfig scene = builtin_preset_scene("mcgraw-turing-d");
  EXPECT_EQ(generalized_stability_line(scene), "");  // semi-implicit: nothing to say
  scene.rd.scheme = RdScheme::kExplicit;
  const std::string line = generalized_stability_line(scene);
  EXPECT_NE(line.find("rho(I + dt D_A K)"), std::string::npos) << line;
  EXPECT_NE(line.find("above 1"), std::string::npos) << line;  // (d) is anti-diffusive
}

}  // namespace
}  // namespace ardcell
