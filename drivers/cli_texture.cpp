// `ardcell texture`: a tileable texture for artists from a periodic reaction-diffusion preset,
// grown coarse to fine (host/run/texture_synthesis.h, seed 003's Results), written as an 8-bit
// height PNG and optionally a 16-bit height PNG, a tangent-space normal map (Fig. 7's bump
// maps) and the raw field as .npy.
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "drivers/cli.h"
#include "drivers/cli_backend.h"
#include "drivers/png_writer.h"
#include "host/io/atomic_file.h"
#include "host/io/npy.h"
#include "host/render/texture_maps.h"
#include "host/run/offline_run.h"
#include "host/run/texture_synthesis.h"
#include "host/scenes/preset.h"
#include "runtime/opencl/backend_choice.h"

namespace ardcell {
namespace {

constexpr int kDefaultStart = 64;  // seed 003: 64, 128, 256

struct TextureArgs {
  std::string preset, size, levels, out, normal_map, height16, npy, field, backend = "auto";
  std::vector<std::string> sets;
  int start = 0, cl_device = -1, workers = 0;
  int64_t frames_per_level = 0;
  double normal_strength = 4.0;
  bool quiet = false;
  CLI::Option *size_opt, *levels_opt, *start_opt, *frames_opt, *field_opt, *cl_device_opt,
      *workers_opt;
};

std::string scene_list() {
  std::string names;
  for (const std::string& n : preset_names()) names += (names.empty() ? "" : ", ") + n;
  return names;
}

// The levels from --levels / --start / --size and the preset; "" when fine, else the reason.
std::string choose_levels(const TextureArgs& a, const SceneConfig& scene, std::vector<int>& out) {
  int final_side = 0;
  if (a.size_opt->count()) {
    Int2 size;
    if (Status s = parse_grid_size(a.size, size); !s) return s.message();
    if (size.x != size.y)
      return "--size " + a.size + ": textures are square (expected N, e.g. --size 512)";
    final_side = size.x;
  }
  if (a.levels_opt->count()) {
    if (Status s = parse_texture_levels(a.levels, out); !s) return s.message();
    if (final_side && out.back() != final_side)
      return "--levels " + a.levels + " ends at " + std::to_string(out.back()) + " but --size is " +
             std::to_string(final_side) + " (expected the last level to be the size)";
    return "";
  }
  if (!final_side) {
    if (scene.size.x != scene.size.y)
      return "preset '" + scene.name + "' is " + std::to_string(scene.size.x) + "x" +
             std::to_string(scene.size.y) + " (expected --size N for a square texture)";
    final_side = scene.size.x;
  }
  if (final_side < kMinTextureSide)
    return "--size " + std::to_string(final_side) + ": expected at least " +
           std::to_string(kMinTextureSide);
  int start = std::min(kDefaultStart, final_side);
  if (a.start_opt->count()) {
    if (a.start < kMinTextureSide || a.start > final_side)
      return "--start " + std::to_string(a.start) + ": expected " +
             std::to_string(kMinTextureSide) + ".." + std::to_string(final_side) +
             " (the first level's side, at most --size)";
    start = a.start;
  }
  out = doubling_levels(start, final_side);
  return "";
}

// Every destination checked before anything runs: one line naming the flag.
std::string check_destinations(const TextureArgs& a) {
  std::set<std::string> seen;
  const std::pair<const char*, const std::string*> outputs[] = {{"--out", &a.out},
                                                                {"--normal-map", &a.normal_map},
                                                                {"--height16", &a.height16},
                                                                {"--npy", &a.npy}};
  for (const auto& [flag, path] : outputs) {
    if (path->empty()) {
      if (std::string(flag) == "--out") return "--out: expected a path, got an empty string";
      continue;
    }
    if (Status s = check_output_path(*path, false); !s)
      return std::string(flag) + " " + s.message();
    const std::string key = std::filesystem::absolute(*path).lexically_normal().string();
    if (!seen.insert(key).second)
      return std::string(flag) + " " + *path + ": written twice (expected a different file)";
  }
  return "";
}

Status write_outputs(const TextureArgs& a, const FieldF& field, bool periodic,
                     int64_t& non_finite) {
  ImageGray8 height;
  non_finite = height_map_8(field, height).non_finite;
  if (!a.npy.empty())
    if (Status s = write_npy(a.npy, field.view(field.interior())); !s) return s;
  if (!a.height16.empty()) {
    ImageGray16 h16;
    height_map_16(field, h16);
    if (Status s = write_png_gray16(a.height16, h16); !s) return s;
  }
  if (!a.normal_map.empty()) {
    ImageRgb8 normals;
    normal_map(field, {a.normal_strength, periodic}, normals);
    if (Status s = write_png(a.normal_map, normals); !s) return s;
  }
  return write_png_gray8(a.out, height);
}

int do_texture(TextureArgs& a, CliContext& ctx) {
  auto usage = [&](const std::string& m) { return cli_usage_error(ctx, "texture", m); };
  Preset preset;
  if (Status s = load_preset(a.preset, preset); !s) {
    const bool is_path = a.preset.find('/') != std::string::npos || a.preset.ends_with(".toml");
    return usage(is_path
                     ? s.message()
                     : "unknown preset '" + a.preset + "' (expected one of: " + scene_list() + ")");
  }
  SceneConfig scene = preset.scene;
  if (scene.name.empty()) scene.name = a.preset;
  for (const std::string& assignment : a.sets)
    if (Status s = apply_param_override(scene, assignment); !s) return usage(s.message());
  if (Status s = check_scene_keys(scene); !s) return usage(s.message());
  if (Status s = check_texture_scene(scene); !s) return usage(s.message());

  std::vector<int> levels;
  if (std::string error = choose_levels(a, scene, levels); !error.empty()) return usage(error);
  for (int side : levels) {
    SceneConfig level;
    if (Status s = texture_level_scene(scene, side, level); !s) return usage(s.message());
    if (side == levels.back())
      if (Status s = check_memory_for_grid(level); !s) return usage(s.message());
  }
  int64_t frames = a.frames_per_level;
  if (a.frames_opt->count()) {
    if (frames < 1)
      return usage("--frames-per-level " + std::to_string(frames) + ": expected 1 or more");
  } else {
    // The preset's grid.steps, split over the levels.
    const int64_t n = int64_t(levels.size());
    frames = std::max<int64_t>(1, (scene.default_steps + n - 1) / n);
  }

  const std::string field_name = a.field_opt->count() ? a.field
                                 : (scene.output.show == "A" || scene.output.show == "B")
                                     ? scene.output.show
                                     : "B";
  if (field_name != "A" && field_name != "B")
    return usage("--field '" + field_name + "': expected A or B (the chemicals of the preset)");
  if (std::string error = check_destinations(a); !error.empty()) return usage(error);

  BackendKind backend = BackendKind::kAuto;
  if (!parse_backend_kind(a.backend, backend))
    return usage("--backend '" + a.backend + "': expected auto, threads, serial or opencl");
  if (a.workers_opt->count() && (a.workers < 1 || a.workers > 256))
    return usage("--workers " + std::to_string(a.workers) + ": expected 1..256");
  if (a.cl_device_opt->count() && a.cl_device < 0)
    return usage("--cl-device " + std::to_string(a.cl_device) +
                 ": expected a device index (0 or more, see ardcell devices)");
  TextureOptions options;
  if (a.workers_opt->count()) options.engine.workers = a.workers;
  const BackendChoice choice = choose_engine_backend(backend, a.cl_device, options.engine, ctx);
  options.levels = levels;
  options.frames_per_level = frames;
  options.progress = (!a.quiet && ::isatty(STDERR_FILENO)) ? ctx.err : nullptr;
  std::fprintf(ctx.out, "levels=%s frames_per_level=%lld rd_steps_per_frame=%d scene=%s field=%s\n",
               format_levels(levels).c_str(), static_cast<long long>(frames),
               scene.rd.steps_per_frame, scene.name.c_str(), field_name.c_str());
  std::fflush(ctx.out);

  // From here SIGINT/SIGTERM/SIGHUP end the synthesis between frames; an unfinished texture is
  // not written.
  StopSignals signals;
  options.stop = &StopSignals::requested();
  TextureResult result;
  if (Status s = synthesize_texture(scene, options, result); !s) {
    std::fprintf(ctx.err, "ardcell texture: %s\n", s.message().c_str());
    return StopSignals::exit_code(kExitFailure);
  }
  if (result.stopped_early) {
    std::fprintf(ctx.err,
                 "ardcell texture: interrupted at level %d of %zu after %lld frames; nothing "
                 "written\n",
                 result.levels_done + 1, levels.size(), static_cast<long long>(result.frames));
    return StopSignals::exit_code(kExitOk);
  }
  const FieldF& field = field_name == "A" ? result.state.A : result.state.B;
  int64_t non_finite = 0;
  if (Status s = write_outputs(a, field, true, non_finite); !s) {
    std::fprintf(ctx.err, "ardcell texture: %s\n", s.message().c_str());
    return kExitFailure;
  }
  if (non_finite > 0)
    std::fprintf(ctx.err,
                 "ardcell texture: warning: %lld cells were not finite (drawn at height 0.5 for "
                 "NaN, 1 for +inf, 0 for -inf)\n",
                 static_cast<long long>(non_finite));
  std::fprintf(ctx.out, "size=%dx%d frames=%lld seconds=%.2f out=%s", field.nx(), field.ny(),
               static_cast<long long>(result.frames), result.step_seconds, a.out.c_str());
  if (!a.normal_map.empty()) std::fprintf(ctx.out, " normal_map=%s", a.normal_map.c_str());
  if (!a.height16.empty()) std::fprintf(ctx.out, " height16=%s", a.height16.c_str());
  if (!a.npy.empty()) std::fprintf(ctx.out, " npy=%s", a.npy.c_str());
  std::fputc('\n', ctx.out);
  std::fflush(ctx.out);
  return StopSignals::exit_code(kExitOk);
}

}  // namespace

void add_texture_command(CLI::App& app, CliContext& ctx) {
  auto args = std::make_shared<TextureArgs>();
  TextureArgs& a = *args;
  CLI::App* cmd = app.add_subcommand(
      "texture",
      "Grow a tileable texture coarse to fine from a periodic RD preset: height PNG (8/16-bit), "
      "normal map, .npy");
  cmd->add_option("preset", a.preset, "a periodic reaction-diffusion preset, or a .toml path")
      ->required();
  a.size_opt = cmd->add_option("--size", a.size, "texture side N (default: the preset's)");
  a.levels_opt = cmd->add_option("--levels", a.levels,
                                 "the sides of the levels, increasing, e.g. 64,128,256,512");
  a.start_opt = cmd->add_option("--start", a.start,
                                "the first level's side; each next one doubles up to --size "
                                "(default 64)");
  a.levels_opt->excludes(a.start_opt);
  a.frames_opt = cmd->add_option("--frames-per-level", a.frames_per_level,
                                 "engine frames at each level (default: the preset's grid.steps "
                                 "split over the levels)");
  cmd->add_option("--out", a.out, "8-bit grayscale height PNG of the field")->required();
  cmd->add_option("--normal-map", a.normal_map, "also write a tangent-space normal map PNG");
  cmd->add_option("--normal-strength", a.normal_strength,
                  "the normal map's relief: cells of height for the field's full range "
                  "(default 4)")
      ->check(finite_range(-1000, 1000));
  cmd->add_option("--height16", a.height16, "also write a 16-bit grayscale height PNG");
  cmd->add_option("--npy", a.npy, "also write the field as a float32 .npy");
  a.field_opt =
      cmd->add_option("--field", a.field, "A or B (default: the preset's output.show, else B)");
  cmd->add_option("--set", a.sets, "set a preset parameter, key=value (repeatable, as in run)");
  cmd->add_option("--backend", a.backend, "auto | threads | serial | opencl (default auto)");
  a.cl_device_opt =
      cmd->add_option("--cl-device", a.cl_device, "OpenCL device index (see ardcell devices)");
  a.workers_opt =
      cmd->add_option("--workers", a.workers, "threads back end workers (default: one per core)");
  cmd->add_flag("--quiet", a.quiet, "no progress bar");
  cmd->callback([args, &ctx] {
    try {
      ctx.exit_code = do_texture(*args, ctx);
    } catch (const std::bad_alloc&) {
      ctx.exit_code = cli_usage_error(ctx, "texture", "out of memory (expected a smaller --size)");
    }
  });
}

}  // namespace ardcell
