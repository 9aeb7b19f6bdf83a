// The preset key table covers every SceneConfig field, and `--set key=value` overrides.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <tuple>
#include <type_traits>
#include <utility>
#include <vector>

#include "host/scenes/preset.h"
#include "host/scenes/scene_registry.h"

namespace ardcell {
namespace {

// Every member of the scene structs, by structured binding: adding a member to one of them
// stops this test from compiling until the comparison (and so the key table, which the
// round-trip tests below check against it) covers it.
auto members(const SceneConfig& s) {
  const auto& [name, description, size, domain_width, dt, default_steps, fluid, rd, output] = s;
  return std::tie(name, description, size.x, size.y, domain_width, dt, default_steps, fluid, rd,
                  output);
}
auto members(const FluidConfig& f) {
  const auto& [kind, viscosity, lid_speed, viscosity_solver, pressure_solver, dye_diffusion,
               conserve_dye, advection, inflow_speed, inflow_side, inflow_profile, wall_low,
               wall_high, obstacle_x, obstacle_y, obstacle_radius, obstacle_boundary,
               inflow_dye_stripes, probes, walls, emitters] = f;
  return std::tie(kind, viscosity, lid_speed, viscosity_solver, pressure_solver, dye_diffusion,
                  conserve_dye, advection, inflow_speed, inflow_side, inflow_profile, wall_low,
                  wall_high, obstacle_x, obstacle_y, obstacle_radius, obstacle_boundary,
                  inflow_dye_stripes, probes, walls, emitters);
}
auto members(const FluidEmitter& e) {
  const auto& [x, y, radius, dye_rate, force_x, force_y, swirl] = e;
  return std::tie(x, y, radius, dye_rate, force_x, force_y, swirl);
}
auto members(const SolverSettings& s) {
  const auto& [kind, max_iterations, tolerance] = s;
  return std::tie(kind, max_iterations, tolerance);
}
auto members(const OutputConfig& o) {
  const auto& [show, colormap] = o;
  return std::tie(show, colormap);
}
auto members(const ConcentrationBox& b) {
  const auto& [a_lo, a_hi, b_lo, b_hi] = b;
  return std::tie(a_lo, a_hi, b_lo, b_hi);
}
auto members(const ReactionParams& r) {
  const auto& [model, F, k, turing_s, turing_beta, turing_supply, meinhardt_s, meinhardt_alpha,
               meinhardt_p1, meinhardt_p2, meinhardt_p3, fhn_epsilon, fhn_a0, fhn_a1,
               barkley_epsilon, barkley_a, barkley_b] = r;
  return std::tie(model, F, k, turing_s, turing_beta, turing_supply, meinhardt_s, meinhardt_alpha,
                  meinhardt_p1, meinhardt_p2, meinhardt_p3, fhn_epsilon, fhn_a0, fhn_a1,
                  barkley_epsilon, barkley_a, barkley_b);
}
auto members(const AnisotropyParams& a) {
  const auto& [kind, isotropic_value, a1, a2, lobes, lobe_speed, samples, sample, theta0,
               gradient_epsilon] = a;
  return std::tie(kind, isotropic_value, a1, a2, lobes, lobe_speed, samples, sample, theta0,
                  gradient_epsilon);
}
auto members(const TensorSequence& t) {
  const auto& [xx, xy, yy, xxx, xxy, xyy, yyy, xxxx, xxxy, xxyy, xyyy, yyyy] = t;
  return std::tie(xx, xy, yy, xxx, xxy, xyy, yyy, xxxx, xxxy, xxyy, xyyy, yyyy);
}
auto members(const GeneralizedRdConfig& g) {
  const auto& [tensors, savitzky_golay_degree, second_derivatives, field, d_along, d_across] = g;
  return std::tie(tensors, savitzky_golay_degree, second_derivatives, field, d_along, d_across);
}
auto members(const RdConfig& r) {
  const auto& [enabled, reaction, map, map_f, map_k, react, use_table, table_resolution,
               table_range_auto, table_range, diffuse, diffusion_operator, generalized, diffusion_a,
               diffusion_b, anisotropy, anisotropy_on_b, diffusion_solver, boundary, boundary_a,
               boundary_b, crank_nicolson, advect, scheme, dt, cell_size, steps_per_frame, initial,
               background_a, background_b, seed_a, seed_b, seed_size, seed_cells, spots,
               seed_radius, noise, seed] = r;
  return std::tie(enabled, reaction, map, map_f, map_k, react, use_table, table_resolution,
                  table_range_auto, table_range, diffuse, diffusion_operator, generalized,
                  diffusion_a, diffusion_b, anisotropy, anisotropy_on_b, diffusion_solver, boundary,
                  boundary_a, boundary_b, crank_nicolson, advect, scheme, dt, cell_size,
                  steps_per_frame, initial, background_a, background_b, seed_a, seed_b, seed_size,
                  seed_cells, spots, seed_radius, noise, seed);
}

// Empty when a and b are equal member by member (exactly), else the path of the first difference.
template <class T>
std::string difference(const T& a, const T& b, const std::string& path) {
  if constexpr (requires { members(a); }) {
    const auto ma = members(a), mb = members(b);
    std::string d;
    [&]<size_t... I>(std::index_sequence<I...>) {
      ((d.empty() ? (void)(d = difference(std::get<I>(ma), std::get<I>(mb),
                                          path + "." + std::to_string(I)))
                  : (void)0),
       ...);
    }
    (std::make_index_sequence<std::tuple_size_v<decltype(ma)>>{});
    return d;
  } else if constexpr (std::is_array_v<T>) {
    for (size_t i = 0; i < std::size(a); ++i)
      if (!(a[i] == b[i])) return path + "[" + std::to_string(i) + "]";
    return {};
  } else if constexpr (requires {
                         a.size();
                         a[0].x;
                       }) {
    if (a.size() != b.size()) return path + ".size()";
    for (size_t i = 0; i < a.size(); ++i)
      if (auto d = difference(a[i], b[i], path + "[" + std::to_string(i) + "]"); !d.empty())
        return d;
    return {};
  } else {
    return a == b ? std::string() : path;
  }
}

// A scene with every member away from its default, values picked within the key ranges.
SceneConfig everything_changed() {
  SceneConfig s;
  s.name = "odd \"name\"";
  s.description = "every key set";
  s.size = {37, 21};
  s.domain_width = 3.25;
  s.dt = 0.0123;
  s.default_steps = 77;
  FluidConfig& f = s.fluid;
  f.kind = FluidSceneKind::kInk;
  f.viscosity = 0.3;
  f.lid_speed = -2.5;
  f.viscosity_solver = {SolverKind::kRedBlackGaussSeidel, 13, 0.125};
  f.pressure_solver = {SolverKind::kIccg, 17, 1e-9};
  f.dye_diffusion = 0.001;
  f.conserve_dye = false;
  f.inflow_speed = 0.7;
  f.inflow_side = BoundarySide::kRight;
  f.inflow_profile = InflowProfile::kParabolic;
  f.wall_low = FluidWalls::kNoSlip;
  f.wall_high = FluidWalls::kPeriodic;
  f.obstacle_x = 0.1;
  f.obstacle_y = 0.2;
  f.obstacle_radius = 0.3;
  f.obstacle_boundary = ObstacleBoundary::kCutCell;
  f.inflow_dye_stripes = 3;
  f.probes = {0.5f, 0.25f, 1.5f, 0.125f, 2.0f, 0.0f, -1, -1};
  f.walls = FluidWalls::kPeriodic;
  f.emitters = {{0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7}, {-1, -2, 3, -4, -5, -6, -7}};
  RdConfig& r = s.rd;
  r.enabled = true;
  r.reaction = {ReactionModel::kMeinhardt,
                0.031f,
                0.059f,
                0.1f,
                11.0f,
                14.0f,
                0.02f,
                90.0f,
                -0.5f,
                -1.25f,
                0.2f,
                0.04f,
                -0.2f,
                1.5f,
                0.03f,
                0.8f,
                0.01f};
  r.map = true;
  r.map_f = 0.07f;
  r.map_k = 0.0625f;
  r.react = false;
  r.use_table = true;
  r.table_resolution = 129;
  r.table_range_auto = false;
  r.table_range = {-1.5, 2.5, -0.25, 3.75};
  r.diffuse = false;
  r.diffusion_operator = RdOperator::kGeneralized;
  r.generalized.tensors = {0.5, 0.25, 1.5, 0.1, -0.2, 0.3, -0.4, -0.5, 0.6, -0.7, 0.8, -0.9};
  r.generalized.savitzky_golay_degree = 5;
  r.generalized.second_derivatives = SecondDerivatives::kSavitzkyGolay;
  r.generalized.field = TensorFieldKind::kRadial;
  r.generalized.d_along = 0.7;
  r.generalized.d_across = 0.15;
  r.diffusion_a = 0.33;
  r.diffusion_b = 0.77;
  r.anisotropy.kind = AnisotropyKind::kPolarSamples;
  r.anisotropy.isotropic_value = 0.9f;
  r.anisotropy.a1 = 1.1f;
  r.anisotropy.a2 = 0.3f;
  r.anisotropy.lobes = 5;
  for (int i = 0; i < kMaxLobes; ++i) r.anisotropy.lobe_speed[i] = 0.5f + 0.1f * float(i);
  r.anisotropy.samples = 7;
  for (int i = 0; i < 7; ++i) r.anisotropy.sample[i] = 0.25f * float(i + 1);
  r.anisotropy.theta0 = 0.7853982f;
  r.anisotropy.gradient_epsilon = 1e-5f;
  r.anisotropy_on_b = false;
  r.diffusion_solver = {SolverKind::kMultigrid, 9, 1e-4};
  r.boundary = BoundaryKind::kNeumann;
  r.boundary_a = 0.4f;
  r.boundary_b = 0.6f;
  r.crank_nicolson = true;
  r.advect = false;
  r.scheme = RdScheme::kExplicit5;
  r.dt = 0.2;
  r.cell_size = 0.5;
  r.steps_per_frame = 3;
  r.initial = RdInitialPattern::kStripe;
  r.background_a = 0.9f;
  r.background_b = 0.1f;
  r.seed_a = 0.3f;
  r.seed_b = 0.7f;
  r.seed_size = 0.15;
  r.seed_cells = 6;
  r.spots = 5;
  r.seed_radius = 2.5;
  r.noise = 0.02;
  r.seed = 123456789012345ull;
  s.output = {"vorticity", "rdbu"};
  return s;
}

SceneConfig through_toml(const SceneConfig& scene, std::string* text = nullptr) {
  const std::string toml = preset_to_toml(preset_from_scene(scene));
  if (text) *text = toml;
  Preset back;
  const Status st = parse_preset(toml, "roundtrip.toml", back);
  EXPECT_TRUE(st.is_ok()) << st.message() << "\n" << toml;
  return back.scene;
}

TEST(PresetKeys, EveryMemberAwayFromItsDefaultSurvivesToml) {
  const SceneConfig s = everything_changed();
  // Check the test's premise: every member differs from the default (so each one is exercised).
  const SceneConfig d;
  const auto ms = members(s), md = members(d);
  std::vector<std::string> unchanged;
  [&]<size_t... I>(std::index_sequence<I...>) {
    ((difference(std::get<I>(ms), std::get<I>(md), "m").empty()
          ? unchanged.push_back("member " + std::to_string(I))
          : void()),
     ...);
  }
  (std::make_index_sequence<std::tuple_size_v<decltype(ms)>>{});
  for (auto [a, b] : {std::pair{members(s.rd), members(d.rd)}}) {
    [&]<size_t... I>(std::index_sequence<I...>) {
      ((difference(std::get<I>(a), std::get<I>(b), "m").empty()
            ? unchanged.push_back("rd member " + std::to_string(I))
            : void()),
       ...);
    }
    (std::make_index_sequence<std::tuple_size_v<decltype(a)>>{});
  }
  const auto mr = members(s.rd.reaction), mdr = members(d.rd.reaction);
  [&]<size_t... I>(std::index_sequence<I...>) {
    ((difference(std::get<I>(mr), std::get<I>(mdr), "m").empty()
          ? unchanged.push_back("reaction member " + std::to_string(I))
          : void()),
     ...);
  }
  (std::make_index_sequence<std::tuple_size_v<decltype(mr)>>{});
  EXPECT_EQ(unchanged, std::vector<std::string>{});
  // The explicit schemes are isotropic (check_scene_keys refuses both at once): the scheme and
  // the anisotropy go through TOML in two scenes.
  // The generalized operator needs a periodic, isotropic scene and its own schemes: a third.
  SceneConfig explicit_scheme = s, anisotropic = s, generalized = s;
  explicit_scheme.rd.anisotropy.kind = AnisotropyKind::kIsotropic;
  anisotropic.rd.scheme = RdScheme::kImplicit;
  for (SceneConfig* v : {&explicit_scheme, &anisotropic})
    v->rd.diffusion_operator = RdOperator::kLaplacian;
  generalized.rd.anisotropy.kind = AnisotropyKind::kIsotropic;
  generalized.rd.scheme = RdScheme::kSemiImplicit;
  generalized.rd.boundary = BoundaryKind::kPeriodic;
  for (const SceneConfig& v : {explicit_scheme, anisotropic, generalized}) {
    std::string text;
    const SceneConfig back = through_toml(v, &text);
    EXPECT_EQ(difference(v, back, "scene"), "") << text;
  }
  Preset refused;
  EXPECT_FALSE(parse_preset(preset_to_toml(preset_from_scene(s)), "both.toml", refused).is_ok());
}

TEST(PresetKeys, EveryBuiltinSceneSurvivesTomlMemberByMember) {
  ASSERT_GE(builtin_scenes().entries().size(), 20u);
  for (const SceneEntry& e : builtin_scenes().entries()) {
    const SceneConfig s = e.make();
    std::string text;
    const SceneConfig back = through_toml(s, &text);
    EXPECT_EQ(difference(s, back, e.name), "") << text;
    // And writing it again gives the same text.
    EXPECT_EQ(preset_to_toml(preset_from_scene(back)), text) << e.name;
  }
}

TEST(PresetKeys, ArraysAreLengthCheckedAndPadded) {
  Preset p;
  ASSERT_TRUE(parse_preset("[rd.anisotropy]\nlobe_speed = [2, 1.5]\n", "a.toml", p).is_ok());
  EXPECT_EQ(p.scene.rd.anisotropy.lobe_speed[0], 2.0f);
  EXPECT_EQ(p.scene.rd.anisotropy.lobe_speed[1], 1.5f);
  EXPECT_EQ(p.scene.rd.anisotropy.lobe_speed[2], 1.0f);
  std::string seventeen = "[rd.anisotropy]\nlobe_speed = [";
  for (int i = 0; i < 17; ++i) seventeen += i ? ", 1" : "1";
  seventeen += "]\n";
  Status st = parse_preset(seventeen, "a.toml", p);
  ASSERT_FALSE(st.is_ok());
  EXPECT_EQ(st.message(),
            "a.toml:2: rd.anisotropy.lobe_speed: expected an array of at most 16 numbers in [0, "
            "1000], got 17 numbers");
  st = parse_preset("[rd.anisotropy]\nsample = [1, \"x\"]\n", "a.toml", p);
  ASSERT_FALSE(st.is_ok());
  EXPECT_EQ(st.message(),
            "a.toml:2: rd.anisotropy.sample: expected an array of at most 64 numbers in [0, "
            "1000], got the string \"x\" at [1]");
  st = parse_preset("[rd.reaction]\nmodel = \"brusselator\"\n", "a.toml", p);
  ASSERT_FALSE(st.is_ok());
  EXPECT_EQ(st.message(),
            "a.toml:2: rd.reaction.model: expected one of gray-scott | turing | meinhardt | "
            "fitzhugh-nagumo | barkley | barkley-turbulent, got \"brusselator\"");
  st = parse_preset("[fluid]\nemitters = [{x = 0.5, speed = 2}]\n", "a.toml", p);
  ASSERT_FALSE(st.is_ok());
  EXPECT_EQ(st.message(),
            "a.toml:2: fluid.emitters[0].speed: unknown key; expected one of: x | y | radius | "
            "dye_rate | force_x | force_y | swirl");
  ASSERT_TRUE(parse_preset("[[fluid.emitters]]\nx = 0.25\nswirl = 1\n[[fluid.emitters]]\ny = 0.1\n",
                           "a.toml", p)
                  .is_ok());
  ASSERT_EQ(p.scene.fluid.emitters.size(), 2u);
  EXPECT_EQ(p.scene.fluid.emitters[0].x, 0.25);
  EXPECT_EQ(p.scene.fluid.emitters[0].swirl, 1.0);
  EXPECT_EQ(p.scene.fluid.emitters[1].y, 0.1);
}

TEST(ParamOverride, PearsonFeedAndKill) {
  SceneConfig s = builtin_scenes().find("pearson")->make();
  ASSERT_TRUE(apply_param_override(s, "rd.reaction.f=0.035").is_ok());
  ASSERT_TRUE(apply_param_override(s, "rd.reaction.k=0.065").is_ok());
  EXPECT_EQ(s.rd.reaction.F, 0.035f);
  EXPECT_EQ(s.rd.reaction.k, 0.065f);
  const Status st = apply_param_override(s, "rd.reaction.f=2");
  ASSERT_FALSE(st.is_ok());
  EXPECT_EQ(st.message(), "--set rd.reaction.f: expected a number in [0, 1], got 2");
}

TEST(ParamOverride, SetsNumbersChoicesSizesAndStrings) {
  SceneConfig s;
  ASSERT_TRUE(apply_param_override(s, "fluid.viscosity=0.02").is_ok());
  EXPECT_EQ(s.fluid.viscosity, 0.02);
  ASSERT_TRUE(apply_param_override(s, " fluid.pressure_solver.kind = rbgs ").is_ok());
  EXPECT_EQ(s.fluid.pressure_solver.kind, SolverKind::kRedBlackGaussSeidel);
  ASSERT_TRUE(apply_param_override(s, "fluid.pressure_solver.kind=\"iccg\"").is_ok());
  EXPECT_EQ(s.fluid.pressure_solver.kind, SolverKind::kIccg);
  ASSERT_TRUE(apply_param_override(s, "grid.size=64x32").is_ok());
  EXPECT_EQ(s.size, (Int2{64, 32}));
  ASSERT_TRUE(apply_param_override(s, "grid.size=[16, 8]").is_ok());
  EXPECT_EQ(s.size, (Int2{16, 8}));
  ASSERT_TRUE(apply_param_override(s, "description=a quick look").is_ok());
  EXPECT_EQ(s.description, "a quick look");
}

TEST(ParamOverride, BadAssignmentsNameTheKeyAndLeaveTheSceneAlone) {
  SceneConfig s;
  const SceneConfig before = s;
  auto fails = [&](std::string_view a, std::string_view expected) {
    const Status st = apply_param_override(s, a);
    ASSERT_FALSE(st.is_ok()) << a;
    EXPECT_EQ(st.message(), expected) << a;
    EXPECT_EQ(st.message().find('\n'), std::string::npos);
  };
  fails("fluid.viscosity=-1", "--set fluid.viscosity: expected a number in [0, 1000], got -1");
  fails("fluid.viscosity=abc", "--set fluid.viscosity: expected a number in [0, 1000], got 'abc'");
  fails("fluid.viscosity", "--set fluid.viscosity: expected key=value, e.g. rd.reaction.f=0.04");
  fails("fluid.viscosity=",
        "--set fluid.viscosity: expected a number in [0, 1000], got nothing after '='");
  fails("fluid.pressure_solver.kind=sor",
        "--set fluid.pressure_solver.kind: expected one of jacobi | rbgs | iccg | mg, got \"sor\"");
  const Status unknown = apply_param_override(s, "fluid.viscosty=1");
  ASSERT_FALSE(unknown.is_ok());
  EXPECT_TRUE(
      unknown.message().starts_with("--set fluid.viscosty: unknown scene key; expected one of: "))
      << unknown.message();
  EXPECT_FALSE(apply_param_override(s, "quality.max_sweeps=3").is_ok());
  EXPECT_EQ(s.fluid.viscosity, before.fluid.viscosity);
  EXPECT_EQ(s.fluid.pressure_solver.kind, before.fluid.pressure_solver.kind);
}

}  // namespace
}  // namespace ardcell
