#include "host/scenes/preset.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "host/scenes/scene_registry.h"

namespace ardcell {
namespace {

Status parse(std::string_view text, Preset& p) { return parse_preset(text, "bad.toml", p); }

TEST(Preset, EmptyFileGivesDefaultsAndTheFileName) {
  Preset p;
  ASSERT_TRUE(parse_preset("", "presets/quiet.toml", p).is_ok());
  EXPECT_EQ(p.scene.name, "quiet");
  EXPECT_EQ(preset_difference(p,
                              [] {
                                Preset d;
                                d.scene.name = "quiet";
                                return d;
                              }()),
            "");
}

TEST(Preset, ReadsEveryKindOfKey) {
  Preset p;
  const Status s = parse(R"(
name = "demo"
description = "a demo"
[grid]
size = [64, 48]
dt = 0.02
steps = 100
[fluid]
scene = "ink"
viscosity = 1e-3
lid_speed = 2        # an integer is a fine number
[fluid.pressure_solver]
kind = "rbgs"
iterations = 30
[rd]
enabled = true
[output]
colormap = "magma"
show = "B"
[quality]
min_sweeps = 3
max_sweeps = 30
min_rd_scale = 0.5
adaptive = false
[input]
mode = "orient"
brush_radius = 0.05
)",
                         p);
  ASSERT_TRUE(s.is_ok()) << s.message();
  EXPECT_EQ(p.scene.name, "demo");
  EXPECT_EQ(p.scene.size, (Int2{64, 48}));
  EXPECT_EQ(p.scene.dt, 0.02);
  EXPECT_EQ(p.scene.default_steps, 100);
  EXPECT_EQ(p.scene.fluid.kind, FluidSceneKind::kInk);
  EXPECT_EQ(p.scene.fluid.viscosity, 1e-3);
  EXPECT_EQ(p.scene.fluid.lid_speed, 2.0);
  EXPECT_EQ(p.scene.fluid.pressure_solver.kind, SolverKind::kRedBlackGaussSeidel);
  EXPECT_EQ(p.scene.fluid.pressure_solver.max_iterations, 30);
  EXPECT_TRUE(p.scene.rd.enabled);
  EXPECT_EQ(p.scene.output.colormap, "magma");
  EXPECT_EQ(p.scene.output.show, "B");
  EXPECT_EQ(p.quality.min_sweeps, 3);
  EXPECT_EQ(p.quality.max_sweeps, 30);
  EXPECT_EQ(p.quality.min_rd_scale, 0.5);
  EXPECT_FALSE(p.quality.adaptive);
  EXPECT_EQ(p.input.mode, "orient");
  EXPECT_EQ(p.input.brush_radius, 0.05);
}

struct Broken {
  const char* text;
  const char* message;  // the whole expected message
};

TEST(Preset, BrokenPresetsGiveFileLineKeyAndExpectation) {
  const Broken cases[] = {
      {"[fluid]\nviscosty = 0.1\n",
       "bad.toml:2: fluid.viscosty: unknown key; expected one of: scene, viscosity, lid_speed, "
       "dye_diffusion, conserve_dye, advection, inflow_speed, inflow_side, inflow_profile, "
       "wall_low, wall_high, obstacle_x, obstacle_y, obstacle_radius, obstacle_boundary, probes, "
       "inflow_dye_stripes, walls, emitters, viscosity_solver, pressure_solver"},
      {"\n[grid]\nsize = [64, 64]\ndt = \"fast\"\n",
       "bad.toml:4: grid.dt: expected a number in [1e-09, 100], got the string \"fast\""},
      {"[fluid]\nviscosity = -1.0\n",
       "bad.toml:2: fluid.viscosity: expected a number in [0, 1000], got -1"},
      {"[grid]\nsize = [64]\n",
       "bad.toml:2: grid.size: expected [nx, ny], two integers in [4, 8192], got an array"},
      {"[grid]\nsize = [2, 64]\n",
       "bad.toml:2: grid.size: expected [nx, ny], two integers in [4, 8192], got [2, 64]"},
      {"[output]\ncolormap = \"rainbow\"\n",
       "bad.toml:2: output.colormap: expected one of gray | viridis | magma | rdbu, got "
       "\"rainbow\""},
      {"[fluid.pressure_solver]\niterations = 2.5\n",
       "bad.toml:2: fluid.pressure_solver.iterations: expected an integer in [1, 10000], got the "
       "number 2.5"},
      {"[rd]\nenabled = 1\n", "bad.toml:2: rd.enabled: expected true or false, got the integer 1"},
      {"[quality]\nmin_sweeps = 30\nmax_sweeps = 10\n",
       "bad.toml:2: quality.min_sweeps: expected at most quality.max_sweeps (10), got 30"},
      {"[colour]\nx = 1\n",
       "bad.toml:1: colour: unknown table; expected one of: name, description, grid, fluid, rd, "
       "output, quality, input"},
      {"name = \"a\"\nname = \"b\"\n",
       "bad.toml:2: Error while parsing key-value pair: cannot redefine existing string 'name'"},
      {"[grid\n", "bad.toml:1: Error while parsing table header: expected ']', saw '\\n'"},
      // The ranges are the engine's (rd_config_problem), so nothing in range is refused later.
      {"[rd]\nsteps_per_frame = 5000\n",
       "bad.toml:2: rd.steps_per_frame: expected an integer in [1, 1000], got 5000"},
      {"[rd.table]\nresolution = 8192\n",
       "bad.toml:2: rd.table.resolution: expected an integer in [2, 4096], got 8192"},
      {"[rd.initial]\nnoise = 5.0\n",
       "bad.toml:2: rd.initial.noise: expected a number in [0, 1], got 5"},
      {"[rd.reaction]\nfhn_a1 = 0.0\n",
       "bad.toml:2: rd.reaction.fhn_a1: expected a number in [1e-09, 1000], got 0"},
      // Keys checked against others, at the key's line (else the line of what it depends on).
      {"[rd]\nenabled = true\n[rd.anisotropy]\nkind = \"polar\"\n",
       "bad.toml:4: rd.anisotropy.samples: expected an integer in [2, 64] with "
       "rd.anisotropy.kind polar, got 0"},
      {"[rd]\nenabled = true\nscheme = \"explicit5\"\n[rd.anisotropy]\nkind = \"lobes\"\n",
       "bad.toml:3: rd.scheme: expected implicit, crank-nicolson-am2 or sbdf2 with "
       "rd.anisotropy.kind lobes (the explicit schemes and etdrk4 are isotropic), got explicit5"},
      {"[rd]\nenabled = true\n[rd.table]\nenabled = true\nrange_auto = false\na_min = 2.0\n"
       "a_max = 1.0\n",
       "bad.toml:7: rd.table.a_max: expected more than rd.table.a_min (2), got 1"},
  };
  for (const Broken& c : cases) {
    Preset p;
    const Status s = parse(c.text, p);
    ASSERT_FALSE(s.is_ok()) << c.text;
    EXPECT_EQ(s.message(), c.message) << c.text;
  }
}

TEST(Preset, SceneKeysAreCheckedAgainstEachOtherAfterOverrides) {
  SceneConfig scene;
  scene.rd.enabled = true;
  ASSERT_TRUE(apply_param_override(scene, "rd.anisotropy.kind=polar").is_ok());
  ASSERT_TRUE(apply_param_override(scene, "rd.scheme=explicit9").is_ok());
  const Status s = check_scene_keys(scene);
  ASSERT_FALSE(s.is_ok());
  EXPECT_EQ(s.message(),
            "rd.anisotropy.samples: expected an integer in [2, 64] with rd.anisotropy.kind polar, "
            "got 0\nrd.scheme: expected implicit, crank-nicolson-am2 or sbdf2 with "
            "rd.anisotropy.kind polar (the explicit schemes and etdrk4 are isotropic), got "
            "explicit9");
  scene.rd.enabled = false;  // the engine checks RD parameters only when RD runs
  EXPECT_TRUE(check_scene_keys(scene).is_ok());
}

TEST(Preset, ReportsEveryProblemOnItsOwnLine) {
  Preset p;
  const Status s = parse("[fluid]\nviscosity = \"x\"\nlid = 1\n", p);
  ASSERT_FALSE(s.is_ok());
  EXPECT_EQ(std::count(s.message().begin(), s.message().end(), '\n'), 1) << s.message();
  EXPECT_NE(s.message().find("bad.toml:2: fluid.viscosity"), std::string::npos);
  EXPECT_NE(s.message().find("bad.toml:3: fluid.lid"), std::string::npos);
}

TEST(Preset, EveryBuiltinSceneRoundTripsThroughToml) {
  int n = 0;
  for (const SceneEntry& e : builtin_scenes().entries()) {
    const Preset original = preset_from_entry(e);
    Preset back;
    const Status s = parse_preset(preset_to_toml(original), e.name + ".toml", back);
    ASSERT_TRUE(s.is_ok()) << e.name << ": " << s.message();
    EXPECT_EQ(preset_difference(original, back), "") << e.name;
    ++n;
  }
  // A preset with unusual values round-trips exactly too.
  Preset odd;
  odd.scene.name = "odd \"quoted\"";
  odd.scene.dt = 1.0 / 3.0;
  odd.scene.fluid.viscosity = 1e-7;
  odd.scene.size = {17, 5};
  odd.input.mode = "erase";
  Preset back;
  ASSERT_TRUE(parse_preset(preset_to_toml(odd), "odd.toml", back).is_ok());
  EXPECT_EQ(preset_difference(odd, back), "");
  EXPECT_EQ(back.scene.dt, 1.0 / 3.0);
}

TEST(Preset, EveryPresetFileLoadsAndIsEmbedded) {
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(ARDCELL_SOURCE_DIR "/presets")) {
    if (entry.path().extension() != ".toml") continue;
    ++files;
    Preset from_file;
    const Status s = load_preset_file(entry.path().string(), from_file);
    ASSERT_TRUE(s.is_ok()) << s.message();
    // The same preset is in the binary, under its file name.
    Preset embedded;
    const Status e = load_preset(entry.path().stem().string(), embedded);
    ASSERT_TRUE(e.is_ok()) << e.message();
    EXPECT_EQ(preset_difference(from_file, embedded), "") << entry.path();
    EXPECT_EQ(embedded.source, "embedded:" + entry.path().stem().string());
  }
  EXPECT_EQ(size_t(files), embedded_presets().size());
  // Every built-in scene is reachable as a preset name.
  const auto names = preset_names();
  for (const SceneEntry& e : builtin_scenes().entries())
    EXPECT_NE(std::find(names.begin(), names.end(), e.name), names.end()) << e.name;
}

TEST(Preset, UnknownNameListsWhatExists) {
  Preset p;
  const Status s = load_preset("no-such-preset", p);
  ASSERT_FALSE(s.is_ok());
  EXPECT_EQ(s.message().rfind("preset 'no-such-preset': no such file or preset; expected", 0), 0u)
      << s.message();
  const Status f = load_preset("/nonexistent/x.toml", p);
  EXPECT_EQ(f.message(), "/nonexistent/x.toml: not found (expected a preset TOML file)");
}

TEST(Preset, SetParamValidatesAndBlendInterpolates) {
  Preset a, b;
  const ParamSpec* visc = find_param("fluid.viscosity");
  ASSERT_NE(visc, nullptr);
  std::string why;
  EXPECT_FALSE(set_param(a, *visc, -2.0, &why));
  EXPECT_EQ(why, "fluid.viscosity: expected a number in [0, 1000], got -2");
  ASSERT_TRUE(set_param(a, *visc, 0.0));
  ASSERT_TRUE(set_param(b, *visc, 1.0));
  const ParamSpec* cmap = find_param("output.colormap");
  ASSERT_TRUE(set_param(b, *cmap, 2));  // magma by index
  EXPECT_EQ(b.scene.output.colormap, "magma");
  Preset mid = a;
  blend_params(a, b, 0.25, mid);
  EXPECT_DOUBLE_EQ(mid.scene.fluid.viscosity, 0.25);
  EXPECT_EQ(mid.scene.output.colormap, a.scene.output.colormap);
  blend_params(a, b, 0.75, mid);
  EXPECT_EQ(mid.scene.output.colormap, "magma");
  EXPECT_TRUE(presets_share_structure(a, b));
  b.scene.size = {32, 32};
  EXPECT_FALSE(presets_share_structure(a, b));
  EXPECT_EQ(find_param("no.such"), nullptr);
}

TEST(Preset, QualityScalesSolverIterations) {
  Preset p;
  p.scene.fluid.pressure_solver.max_iterations = 40;
  p.quality.max_sweeps = 20;
  SceneConfig out = p.scene;
  apply_quality(p, {.sweeps = 5, .rd_scale = 1.0}, out);
  EXPECT_EQ(out.fluid.pressure_solver.max_iterations, 10);
  apply_quality(p, {.sweeps = 20, .rd_scale = 1.0}, out);
  EXPECT_EQ(out.fluid.pressure_solver.max_iterations, 40);
}

}  // namespace
}  // namespace ardcell
