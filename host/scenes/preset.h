#pragma once
// Presets: a scene as a TOML file (presets/*.toml, also embedded in the binary). One table of
// parameter specs (key, type, range, accessor) drives everything: parsing with validation
// (unknown keys, wrong types and out-of-range values give "file:line: key: what was expected"),
// writing a preset back to TOML, live parameter changes (OSC, crossfades) and the tests.
//
//   name = "cavity"                    # defaults to the file name
//   description = "lid-driven cavity"
//   [grid]     size = [256, 256]  domain_width = 1.0  dt = 0.01  steps = 500
//   [fluid]    scene = "cavity"  viscosity = 0.01  lid_speed = 1.0  dye_diffusion = 0.0
//   [fluid.pressure_solver]  kind = "mg"  iterations = 20  tolerance = 1e-8
//   [rd]       enabled = true  scheme = "implicit"  boundary = "periodic"  diffusion_a = 2e-5
//   [rd.reaction]    model = "gray-scott"  f = 0.04  k = 0.06
//   [rd.anisotropy]  kind = "lobes"  lobes = 4  lobe_speed = [2.0, 1.2, 2.0, 1.2]
//   [rd.initial]     pattern = "centre-square"  seed_size = 0.08  noise = 0.01
//   [output]   show = "dye"  colormap = "viridis"
//   [quality]  adaptive = true  min_sweeps = 4  max_sweeps = 20  min_rd_scale = 0.5
//   [input]    mode = "deposit"  brush_radius = 0.03  strength = 1.0
// Every key is optional; a missing key keeps the SceneConfig default. Every SceneConfig member
// has a key (tests/host/scenes/preset_keys_test.cpp); docs/presets.md lists them all
// (generated: scripts/preset_keys.sh, `ardcell live --keys --markdown`).
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "host/config/scene_config.h"
#include "host/config/status.h"
#include "host/scenes/adaptive_quality.h"

namespace ardcell {

// How pointer input paints (the painting modes of DESIGN.md "Painting").
struct InputMapping {
  std::string mode = "deposit";  // deposit | orient | push | obstacle | erase
  double brush_radius = 0.03;    // fraction of the grid width
  double strength = 1.0;         // deposit amount / push force at full pressure
  double pressure_gamma = 1.0;   // effective pressure = pressure^gamma
};

struct Preset {
  SceneConfig scene;
  QualityBounds quality;
  InputMapping input;
  std::string source;  // where it came from: a file path, "embedded:NAME" or "builtin:NAME"
};

// kFloats: a fixed float array (rd.anisotropy.lobe_speed[16], .sample[64]) written as a TOML
// array without its trailing entries equal to `fill` (read back: missing entries are `fill`).
// kEmitters: the ink scene's emitters, a TOML array of tables ([[fluid.emitters]]).
enum class ParamKind : uint8_t {
  kNumber,
  kInteger,
  kBool,
  kChoice,
  kString,
  kSize,
  kFloats,
  kEmitters
};

// One key of the preset format. Numeric kinds (number, integer, bool, choice index) go through
// get/set as double, so a live change never allocates; strings and sizes have their own.
struct ParamSpec {
  std::string_view key;  // dotted path: "fluid.viscosity"
  ParamKind kind;
  double min = 0, max = 0;                    // inclusive range (number, integer, size)
  std::span<const std::string_view> choices;  // kChoice: names by index
  bool structural = false;                    // changing it rebuilds the simulation (grid, models)
  std::string_view help;
  double (*get)(const Preset&) = nullptr;
  void (*set)(Preset&, double) = nullptr;
  std::string& (*text)(Preset&) = nullptr;        // kString (and kChoice stored as a string)
  Int2& (*size)(Preset&) = nullptr;               // kSize
  std::span<float> (*floats)(Preset&) = nullptr;  // kFloats
  std::vector<FluidEmitter>& (*emitters)(Preset&) = nullptr;  // kEmitters
  double fill = 0;      // kFloats: the value of entries not written
  bool single = false;  // the field is a float: written with float precision
};

// Every key, in file order.
std::span<const ParamSpec> preset_params();
const ParamSpec* find_param(std::string_view key);
// "a number in [0, 10]", "one of gray|viridis", ... for messages and --keys.
std::string param_expectation(const ParamSpec& spec);

// docs/presets.md: every key with its type, range (as enforced), live or rebuild and meaning,
// as Markdown (`ardcell live --keys --markdown`, scripts/preset_keys.sh).
std::string preset_keys_markdown();

// Parses TOML text. `source_name` is used in messages ("presets/x.toml:12: ..."). On failure
// returns every problem, one per line, and leaves `out` unspecified.
Status parse_preset(std::string_view text, std::string_view source_name, Preset& out);
Status load_preset_file(const std::string& path, Preset& out);
// A path (contains '/' or ends in .toml), else a built-in preset by name (load_builtin_preset).
Status load_preset(std::string_view name_or_path, Preset& out);
// An embedded preset by name, else a built-in scene (host/scenes/scene_registry.h) with default
// quality and input; never a file (a saved state's meta.json names its scene, not a path to
// read).
Status load_builtin_preset(std::string_view name, Preset& out);

// The preset as TOML that parse_preset reads back to the same values.
std::string preset_to_toml(const Preset& preset);
// A preset for a built-in scene's SceneConfig (default quality and input).
Preset preset_from_scene(const SceneConfig& scene);
// The same for a registered scene, with the entry's live quality bounds.
struct SceneEntry;
Preset preset_from_entry(const SceneEntry& entry);
// Empty when every parameter is equal (exact), else "key: a vs b" for the first difference.
std::string preset_difference(const Preset& a, const Preset& b);
// True when b differs from a only in parameters that can change on a running simulation.
bool presets_share_structure(const Preset& a, const Preset& b);

// Applies one "key=value" assignment (`ardcell run --set fluid.viscosity=0.02`) to `scene`
// through the key table: the value is a TOML value (numbers, true/false, "strings" or bare
// words for choices and strings, [a, b] arrays). Keys outside the scene (quality.*, input.*)
// are refused. On failure `scene` is unchanged and the message is one line naming the key and
// what was expected: "--set rd.reaction.f: expected a number in [0, 1], got 2".
Status apply_param_override(SceneConfig& scene, std::string_view assignment);

// The checks of one key against the others (parse_preset makes them with file:line): polar
// anisotropy needs 2 or more samples, the explicit schemes are isotropic, a manual table range
// is a non-empty box. One line per problem ("rd.scheme: expected implicit with ..."); for a
// scene changed after parsing (--set, saved states).
Status check_scene_keys(const SceneConfig& scene);

// Validates and sets one numeric parameter (OSC, GPIO, crossfades); never allocates on success.
// Choices may be given by index. Returns false with a one-line reason in `why` when invalid.
bool set_param(Preset& preset, const ParamSpec& spec, double value, std::string* why = nullptr);
double get_param(const Preset& preset, const ParamSpec& spec);
// A command-line flag that stands for a preset key (`--dt` for grid.dt): the same range check
// as the key, the message naming the flag: "--dt 1e+308: expected a number in [1e-09, 100]
// (preset key grid.dt)". set_flag_param also sets it; check_flag_param only validates (a
// kSize key checks one side).
Status check_flag_param(std::string_view key, double value, std::string_view flag);
Status set_flag_param(Preset& preset, std::string_view key, double value, std::string_view flag);
// Numeric parameters of `to` blended into `out` at weight t in [0, 1]: numbers interpolate,
// integers round, the rest switch at t >= 0.5. Never allocates for numeric kinds.
void blend_params(const Preset& from, const Preset& to, double t, Preset& out);

// The solver iterations of the scene scaled for a quality level (sweeps out of max_sweeps).
void apply_quality(const Preset& preset, const QualityLevel& level, SceneConfig& out);

// The real-time settings (`ardcell live --realtime-solvers`): every implicit solve (viscosity,
// pressure, RD diffusion) a fixed quality.max_sweeps Jacobi sweeps with tolerance 0, and the
// implicit reaction from its table - what keeps every Fig. 4-6 preset at 60 FPS at 512^2 on two
// cores (bench/RESULTS_ENGINE.md), where multigrid and ICCG solve to a tolerance.
void use_realtime_solvers(Preset& preset);

// Presets compiled into the binary from presets/*.toml (cmake/embed_presets.cmake).
struct EmbeddedPreset {
  const char* file;  // "cavity.toml"
  const char* text;
};
std::span<const EmbeddedPreset> embedded_presets();
// Names (file stems) of the embedded presets, then built-in scenes that have no TOML file.
std::vector<std::string> preset_names();

}  // namespace ardcell
