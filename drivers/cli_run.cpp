// `ardcell run`: the headless run (host/offline_run.h) with frame, video and state output.
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <ctime>
#include <filesystem>
#include <memory>
#include <vector>

#include "drivers/cli.h"
#include "drivers/ffmpeg_pipe.h"
#include "drivers/png_writer.h"
#include "host/atomic_file.h"
#include "host/offline_run.h"
#include "host/preset.h"
#include "host/state_io.h"

namespace ardcell {
namespace {

namespace fs = std::filesystem;

std::atomic<bool> g_stop{false};
extern "C" void on_interrupt(int) { g_stop.store(true); }

struct RunArgs {
  std::string scene, scene_positional, size, solver, out, save_state, load_state;
  std::string colormap, show, video;
  bool list = false, no_png = false, quiet = false;
  int64_t steps = 0, every = 0;
  double dt = 0, re = 0;
  int sweeps = 0, fps = 30;
  CLI::Option *steps_opt, *every_opt, *dt_opt, *re_opt, *sweeps_opt, *solver_opt, *size_opt;
  CLI::Option *colormap_opt, *show_opt;
};

std::string timestamp() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  ::localtime_r(&now, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y%m%d-%H%M%S", &tm);
  return buf;
}

// Creates dir and its missing parents; `created` lists what was made (deepest last), so that
// a failure can remove exactly that.
Status make_output_folder(const fs::path& dir, std::vector<fs::path>& created) {
  std::vector<fs::path> missing;
  std::error_code ec;
  for (fs::path p = dir; !p.empty() && !fs::exists(p, ec); p = p.parent_path()) {
    missing.push_back(p);
    if (p == p.parent_path()) break;
  }
  for (auto it = missing.rbegin(); it != missing.rend(); ++it) {
    if (::mkdir(it->c_str(), 0755) != 0 && errno != EEXIST)
      return Status::error("--out " + dir.string() + ": cannot create folder " + it->string() +
                           " (" + errno_text(errno) + ")");
    created.push_back(*it);
  }
  if (!fs::is_directory(dir, ec))
    return Status::error("--out " + dir.string() +
                         ": not a folder (expected a folder to write "
                         "frames into)");
  // Probe: can we create files here?
  AtomicFile probe;
  if (Status s = probe.open(dir / "probe"); !s)
    return Status::error("--out " + dir.string() + ": folder is not writable (" +
                         errno_text(errno) + ")");
  probe.abandon();
  return Status::ok();
}

void remove_created(const std::vector<fs::path>& created) {
  for (auto it = created.rbegin(); it != created.rend(); ++it) ::rmdir(it->c_str());
}

std::string scene_list() {
  std::string names;
  for (const std::string& n : preset_names()) names += (names.empty() ? "" : ", ") + n;
  return names;
}

int list_scenes(CliContext& ctx) {
  for (const std::string& name : preset_names()) {
    Preset p;
    std::string description;
    if (load_preset(name, p)) description = p.scene.description;
    std::fprintf(ctx.out, "%-24s %s\n", name.c_str(), description.c_str());
  }
  return kExitOk;
}

int do_run(RunArgs& a, CliContext& ctx) {
  auto usage = [&](const std::string& m) { return cli_usage_error(ctx, "run", m); };
  if (a.list) return list_scenes(ctx);

  if (!a.scene.empty() && !a.scene_positional.empty() && a.scene != a.scene_positional)
    return usage("scene given twice ('" + a.scene_positional + "' and --scene " + a.scene +
                 "); expected one");
  std::string scene_name = !a.scene.empty() ? a.scene : a.scene_positional;

  // The scene: a saved state's, or a built-in scene / preset by name or path.
  Preset preset;
  SavedStateMeta meta;
  const bool resume = !a.load_state.empty();
  if (resume) {
    if (Status s = read_state_meta(a.load_state, meta); !s)
      return usage("--load-state " + s.message());
    if (!scene_name.empty() && scene_name != meta.scene)
      return usage("--load-state " + a.load_state + " holds scene '" + meta.scene +
                   "' but the scene given is '" + scene_name + "' (expected the same or none)");
    scene_name = meta.scene;
    if (!load_preset(scene_name, preset)) {
      preset = preset_from_scene(SceneConfig{});
      preset.scene.name = scene_name;
    }
    const std::string what = (fs::path(a.load_state) / "meta.json").string();
    if (Status s = apply_preset_parameters(meta.parameters, what, preset); !s)
      return usage("--load-state " + s.message());
    preset.scene.size = meta.size;
  } else {
    if (scene_name.empty()) scene_name = "cavity";
    if (Status s = load_preset(scene_name, preset); !s) {
      const bool is_path =
          scene_name.find('/') != std::string::npos || scene_name.ends_with(".toml");
      return usage(is_path ? s.message()
                           : "unknown scene '" + scene_name +
                                 "' (expected one of: " + scene_list() + ")");
    }
  }
  SceneConfig scene = preset.scene;
  if (scene.name.empty()) scene.name = scene_name;

  // Overrides.
  SceneOverrides o;
  if (a.size_opt->count()) {
    Int2 size;
    if (Status s = parse_grid_size(a.size, size); !s) return usage(s.message());
    if (resume && size != meta.size)
      return usage("--size " + a.size + " does not match the saved state's " +
                   std::to_string(meta.size.x) + "x" + std::to_string(meta.size.y) +
                   " (expected the same size or no --size)");
    o.size = size;
  }
  if (a.dt_opt->count()) o.dt = a.dt;
  if (a.re_opt->count()) o.reynolds = a.re;
  if (a.sweeps_opt->count()) o.sweeps = a.sweeps;
  if (a.solver_opt->count()) {
    SolverKind kind;
    if (!parse_solver_kind(a.solver, kind))
      return usage("--solver '" + a.solver + "': expected jacobi, rbgs, iccg or mg");
    o.solver = kind;
  }
  if (Status s = apply_overrides(o, scene); !s) return usage(s.message());
  const int64_t steps = a.steps_opt->count() ? a.steps : scene.default_steps;
  if (steps < 0) return usage("--steps " + std::to_string(a.steps) + ": expected 0 or more");
  const int64_t every = a.every_opt->count() ? a.every : std::max<int64_t>(1, steps / 50);
  if (every < 0) return usage("--every " + std::to_string(a.every) + ": expected 0 or more");
  if (a.fps < 1 || a.fps > 1000) return usage("--fps: expected 1..1000");

  // What frames show.
  const std::string show = a.show_opt->count() ? a.show : scene.output.show;
  FrameField field;
  if (!parse_frame_field(show, field))
    return usage("--show '" + show + "': expected one of " + std::string(frame_field_names()));
  RenderSettings render = default_render_settings(field);
  std::string colormap = a.colormap_opt->count() ? a.colormap : "";
  if (colormap.empty() &&
      (field == FrameField::kDye || field == FrameField::kA || field == FrameField::kB))
    colormap = scene.output.colormap;
  if (!colormap.empty() && !parse_colormap(colormap, render.colormap))
    return usage("--colormap '" + colormap + "': expected one of " + std::string(colormap_names()));

  if (Status s = check_memory_for_grid(scene); !s) return usage(s.message());

  // The engine, and the saved state it resumes from.
  Engine engine(scene);
  if (!frame_field_available(engine.state(), field))
    return usage("--show " + show + ": scene '" + scene.name + "' has no " + show +
                 " field (expected one of the fields it simulates)");
  if (resume)
    if (Status s = load_state_fields(a.load_state, meta, engine.state()); !s)
      return usage("--load-state " + s.message());

  // Outputs: checked and created before the first step, removed again on a usage error.
  const bool png = every > 0 && !a.no_png;
  const std::string out = !a.out.empty() ? a.out : "out/" + scene.name + "-" + timestamp();
  std::vector<fs::path> created;
  std::vector<std::unique_ptr<FrameSink>> sinks;
  if (png) {
    if (Status s = make_output_folder(out, created); !s) {
      remove_created(created);
      return usage(s.message());
    }
    sinks.push_back(std::make_unique<PngSequenceSink>(out, show));
  }
  if (!a.video.empty()) {
    const fs::path video(a.video);
    std::error_code ec;
    const fs::path parent = video.parent_path().empty() ? fs::path(".") : video.parent_path();
    if (!fs::is_directory(parent, ec) || ::access(parent.c_str(), W_OK) != 0) {
      remove_created(created);
      return usage("--video " + a.video + ": folder " + parent.string() +
                   " does not exist or is not writable");
    }
    std::unique_ptr<FrameSink> sink;
    std::string note;
    std::signal(SIGPIPE, SIG_IGN);  // a dying ffmpeg gives EPIPE, not a silent exit
    if (Status s = make_video_sink(video, scene.size.x, scene.size.y, a.fps, sink, note); !s) {
      remove_created(created);
      return usage(s.message());
    }
    if (!note.empty()) std::fprintf(ctx.err, "ardcell run: %s\n", note.c_str());
    sinks.push_back(std::move(sink));
  }
  if (every == 0 && !sinks.empty()) sinks.clear();

  OfflineRunOptions options;
  options.steps = steps;
  options.every = every;
  options.render = render;
  options.progress = (!a.quiet && ::isatty(STDERR_FILENO)) ? ctx.err : nullptr;
  options.stop = &g_stop;
  std::signal(SIGINT, on_interrupt);
  std::signal(SIGTERM, on_interrupt);
  std::vector<FrameSink*> sink_ptrs;
  for (auto& s : sinks) sink_ptrs.push_back(s.get());
  OfflineRunSummary summary;
  Status run = run_offline(engine, options, sink_ptrs, summary);
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);
  if (!run) {
    std::fprintf(ctx.err, "ardcell run: %s\n", run.message().c_str());
    return kExitFailure;
  }
  for (auto& s : sinks)
    if (Status f = s->finish(); !f) {
      std::fprintf(ctx.err, "ardcell run: %s\n", f.message().c_str());
      return kExitFailure;
    }
  if (summary.non_finite_cells > 0)
    std::fprintf(ctx.err,
                 "ardcell run: warning: %lld cells of the last frame were not finite (drawn "
                 "magenta)\n",
                 static_cast<long long>(summary.non_finite_cells));
  if (summary.stopped_early)
    std::fprintf(ctx.err, "ardcell run: interrupted after %lld frames\n",
                 static_cast<long long>(summary.steps));
  if (!a.save_state.empty()) {
    if (Status s = save_state(a.save_state, engine.state(), scene); !s) {
      std::fprintf(ctx.err, "ardcell run: --save-state %s\n", s.message().c_str());
      return kExitFailure;
    }
  }
  std::string where = png ? out : (!a.video.empty() ? a.video : "-");
  std::fprintf(ctx.out, "%s\n", format_summary(summary, where).c_str());
  if (!a.save_state.empty()) std::fprintf(ctx.out, "state=%s\n", a.save_state.c_str());
  std::fflush(ctx.out);
  return summary.stopped_early ? 130 : kExitOk;
}

}  // namespace

void add_run_command(CLI::App& app, CliContext& ctx) {
  auto args = std::make_shared<RunArgs>();
  RunArgs& a = *args;
  CLI::App* run = app.add_subcommand(
      "run", "Simulate a scene headless: PNG frames, video, saved state and a summary line");
  run->add_option("scene_name", a.scene_positional, "scene or preset (same as --scene)");
  run->add_option("--scene", a.scene, "scene or preset name, or a .toml path (default cavity)");
  run->add_flag("--list", a.list, "list the scenes with a one-line description and exit");
  a.size_opt = run->add_option("--size", a.size, "grid: N (N x N) or WxH cells");
  a.steps_opt = run->add_option("--steps", a.steps, "frames to simulate (default: the scene's)");
  a.dt_opt = run->add_option("--dt", a.dt, "time step per frame");
  a.re_opt = run->add_option("--re", a.re, "Reynolds number (sets the viscosity)");
  a.solver_opt =
      run->add_option("--solver", a.solver, "implicit solver: jacobi | rbgs | iccg | mg");
  a.sweeps_opt = run->add_option("--sweeps", a.sweeps,
                                 "sweeps (jacobi, rbgs), iterations (iccg) or V-cycles (mg)");
  run->add_option("--out", a.out, "folder for PNG frames (default out/<scene>-<time>)");
  a.every_opt = run->add_option("--every", a.every,
                                "write a frame every N steps; 0: none (default steps/50)");
  a.show_opt = run->add_option("--show", a.show,
                               "field drawn: dye | speed | vorticity | "
                               "pressure | A | B (default: the scene's)");
  a.colormap_opt = run->add_option("--colormap", a.colormap, "gray | viridis | magma | rdbu");
  run->add_option("--video", a.video,
                  "also write a video: .y4m built in, other extensions through ffmpeg");
  run->add_option("--fps", a.fps, "video frame rate (default 30)");
  run->add_flag("--no-png", a.no_png, "write no PNG frames (e.g. video only)");
  run->add_option("--save-state", a.save_state, "save the final state to this folder");
  run->add_option("--load-state", a.load_state, "resume from a state saved by --save-state");
  run->add_flag("--quiet", a.quiet, "no progress bar");
  run->callback([args, &ctx] {
    try {
      ctx.exit_code = do_run(*args, ctx);
    } catch (const std::bad_alloc&) {
      ctx.exit_code = cli_usage_error(ctx, "run", "out of memory (expected a smaller --size)");
    }
  });
}

}  // namespace ardcell
