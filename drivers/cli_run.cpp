// `ardcell run`: the headless run (host/run/offline_run.h) with frame, video and state output.
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <ctime>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "drivers/cli.h"
#include "drivers/cli_backend.h"
#include "drivers/cli_ranks.h"
#include "drivers/ffmpeg_pipe.h"
#include "drivers/png_writer.h"
#include "drivers/stroke_sources.h"
#include "host/engine/rd_step.h"
#include "host/engine/table1_plan.h"
#include "host/io/atomic_file.h"
#include "host/io/state_io.h"
#include "host/run/offline_run.h"
#include "host/run/probe_recorder.h"
#if defined(ARDCELL_WITH_MPI)
#include "host/run/rank_stepper.h"
#endif
#include "host/scenes/preset.h"
#include "runtime/opencl/backend_choice.h"

namespace ardcell {
namespace {

namespace fs = std::filesystem;

struct RunArgs {
  std::string scene, scene_positional, size, solver, out, save_state, load_state;
  std::string colormap, show, video, schedule, backend, store_kib, probe_csv, ranks;
  std::vector<std::string> sets;
  bool list = false, no_png = false, quiet = false, stats = false, realtime_solvers = false;
  int64_t steps = 0, every = 0;
  double dt = 0, re = 0;
  int sweeps = 0, fps = 30, cl_device = -1, workers = 0;
  CLI::Option *steps_opt, *every_opt, *dt_opt, *re_opt, *sweeps_opt, *solver_opt, *size_opt;
  CLI::Option *colormap_opt, *show_opt, *schedule_opt, *backend_opt, *cl_device_opt, *workers_opt;
  CLI::Option *store_kib_opt, *out_opt, *video_opt, *save_state_opt, *ranks_opt;
  RunPaintOptions paint;  // --strokes, --replay, --paint-mode, --paint-radius, --loop-strokes
};

// --stats keeps at most this many per-frame times (8 MiB), allocated before the run.
constexpr int64_t kMaxTimedFrames = int64_t(1) << 20;

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

// --colormap when given, else the scene's colormap for the fields it colours (dye, A, B);
// returns the usage error ("" when fine).
std::string choose_colormap(const RunArgs& a, FrameField field, const SceneConfig& scene,
                            RenderSettings& render) {
  std::string colormap = a.colormap_opt->count() ? a.colormap : "";
  if (colormap.empty() &&
      (field == FrameField::kDye || field == FrameField::kA || field == FrameField::kB))
    colormap = scene.output.colormap;
  if (!colormap.empty() && !parse_colormap(colormap, render.colormap))
    return "--colormap '" + colormap + "': expected one of " + std::string(colormap_names());
  return "";
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

// What a run writes (PNG frames, video), opened before the first step.
struct RunOutputs {
  std::vector<fs::path> created;
  std::vector<std::unique_ptr<FrameSink>> sinks;
  std::string out;
  bool png = false;
  std::unique_ptr<ProbeRecorder> probes;  // --probe-csv
};

// Whether a run writes frames (PNG or video): open_outputs opens their sinks, and every rank of
// a ranked run gathers the blocks at them.
bool writes_frames(const RunArgs& a, int64_t every) {
  return every > 0 && (!a.no_png || !a.video.empty());
}

// Checks and creates the outputs; on a usage error removes what it made and returns the exit
// code, else kExitOk.
int open_outputs(RunArgs& a, CliContext& ctx, const std::string& scene_name, Int2 size,
                 const std::string& show, int64_t every, RunOutputs& o) {
  auto usage = [&](const std::string& m) {
    remove_created(o.created);
    return cli_usage_error(ctx, "run", m);
  };
  // Every destination is checked before anything is written.
  for (CLI::Option* opt : {a.out_opt, a.video_opt, a.save_state_opt})
    if (opt->count() && opt->as<std::string>().empty())
      return usage(opt->get_name() + ": expected a path, got an empty string");
  if (!a.save_state.empty())
    if (Status s = check_state_destination(a.save_state); !s)
      return usage("--save-state " + s.message());
  if (!a.video.empty())
    if (Status s = check_output_path(a.video, false); !s) return usage("--video " + s.message());
  o.png = every > 0 && !a.no_png;
  o.out = !a.out.empty() ? a.out : "out/" + scene_name + "-" + timestamp();
  if (o.png) {
    if (Status s = make_output_folder(o.out, o.created); !s) return usage(s.message());
    o.sinks.push_back(std::make_unique<PngSequenceSink>(o.out, show));
  }
  if (!a.video.empty()) {
    const fs::path video(a.video);
    std::unique_ptr<FrameSink> sink;
    std::string note;
    std::signal(SIGPIPE, SIG_IGN);  // a dying ffmpeg gives EPIPE, not a silent exit
    if (Status s = make_video_sink(video, size.x, size.y, a.fps, sink, note); !s)
      return usage(s.message());
    if (!note.empty()) std::fprintf(ctx.err, "ardcell run: %s\n", note.c_str());
    o.sinks.push_back(std::move(sink));
  }
  if (!writes_frames(a, every)) o.sinks.clear();
  return kExitOk;
}

// Steps the run, finishes the sinks, saves the state and prints the summary line (and, with
// --stats, the per-frame times; `after_run` prints what else the run can tell).
// Across ranks every rank steps, the blocks are gathered for the saved state, and only rank 0
// writes and reports.
struct RankRun {
  const std::atomic<bool>* stop = nullptr;  // agreed by every rank
  std::function<void()> gather;             // every rank calls it before the state is saved
  bool root = true;
};

int run_and_report(RunArgs& a, CliContext& ctx, OfflineStepper& stepper, const SceneConfig& scene,
                   int64_t steps, int64_t every, const RenderSettings& render, RunOutputs& outputs,
                   const std::function<void()>& after_run = {}, const RankRun& ranks = {}) {
  OfflineRunOptions options;
  options.steps = steps;
  options.every = every;
  options.render = render;
  options.progress = (!a.quiet && ranks.root && ::isatty(STDERR_FILENO)) ? ctx.err : nullptr;
  // From here to the summary, SIGINT/SIGTERM/SIGHUP end the run early and the frames, video
  // and state are still finished; a second signal cannot cut the saving short.
  StopSignals signals;
  options.stop = ranks.stop ? ranks.stop : &StopSignals::requested();
  std::vector<double> frame_seconds;
  if (a.stats) {
    frame_seconds.assign(std::size_t(std::min(steps, kMaxTimedFrames)), 0.0);
    options.frame_seconds = frame_seconds;
  }
  std::vector<FrameSink*> sink_ptrs;
  for (auto& s : outputs.sinks) sink_ptrs.push_back(s.get());
  options.observer = outputs.probes.get();
  OfflineRunSummary summary;
  // Start-up: from exec to the first frame, i.e. the CPU time before main() (the process does
  // not wait then) and the wall time since.
  const double main_to_first_frame_ms =
      1e3 *
      std::chrono::duration<double>(std::chrono::steady_clock::now() - ctx.main_started).count();
  Status run = run_offline(stepper, options, sink_ptrs, summary);
  if (!run) {
    std::fprintf(ctx.err, "ardcell run: %s\n", run.message().c_str());
    return kExitFailure;
  }
  for (auto& s : outputs.sinks)
    if (Status f = s->finish(); !f) {
      std::fprintf(ctx.err, "ardcell run: %s\n", f.message().c_str());
      return kExitFailure;
    }
  if (outputs.probes)
    if (Status f = outputs.probes->commit(); !f) {
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
  if (!a.save_state.empty() && ranks.gather) ranks.gather();
  if (!a.save_state.empty() && ranks.root) {
    if (Status s = save_state(a.save_state, stepper.frame_state(), scene); !s) {
      std::fprintf(ctx.err, "ardcell run: --save-state %s\n", s.message().c_str());
      return kExitFailure;
    }
  }
  const std::string where = outputs.png ? outputs.out : (!a.video.empty() ? a.video : "-");
  std::fprintf(ctx.out, "%s\n", format_summary(summary, where).c_str());
  if (!a.save_state.empty()) std::fprintf(ctx.out, "state=%s\n", a.save_state.c_str());
  if (outputs.probes)
    std::fprintf(ctx.out, "%s csv=%s\n", outputs.probes->summary().c_str(), a.probe_csv.c_str());
  if (a.stats) {
    const std::size_t timed = std::min(frame_seconds.size(), std::size_t(summary.steps));
    const FrameTimeStats st = frame_time_stats(std::span<double>(frame_seconds).first(timed));
    std::fprintf(ctx.out, "%s\n", format_frame_time_stats(st).c_str());
    std::fprintf(ctx.out,
                 "start ms: to_first_frame=%.1f (before main %.1f cpu, main to first frame %.1f)\n",
                 1e3 * ctx.cpu_before_main_s + main_to_first_frame_ms, 1e3 * ctx.cpu_before_main_s,
                 main_to_first_frame_ms);
    if (after_run) after_run();
  }
  std::fflush(ctx.out);
  return StopSignals::exit_code(kExitOk);
}

int do_run(RunArgs& a, CliContext& ctx) {
  auto usage = [&](const std::string& m) { return cli_usage_error(ctx, "run", m); };
  if (a.list) return list_scenes(ctx);

  if (!a.scene.empty() && !a.scene_positional.empty() && a.scene != a.scene_positional)
    return usage("scene given twice ('" + a.scene_positional + "' and --scene " + a.scene +
                 "); expected one");
  std::string scene_name = !a.scene.empty() ? a.scene : a.scene_positional;

  // Back end and schedule: checked for every scene, used by the table1 scenes.
  BackendKind backend = BackendKind::kAuto;
  if (a.backend_opt->count() && !parse_backend_kind(a.backend, backend))
    return usage("--backend '" + a.backend + "': expected auto, threads, serial or opencl");
  PlanOptions plan;
  if (a.schedule_opt->count() && !parse_plan_schedule(a.schedule, plan.schedule))
    return usage("--schedule '" + a.schedule + "': expected serial, stream or blocked");
  if (a.store_kib_opt->count()) {
    if (a.store_kib == "spe") {
      plan.local_store_bytes = kSpeLocalStoreBytes;
    } else {
      char* end = nullptr;
      const long kib = std::strtol(a.store_kib.c_str(), &end, 10);
      if (end == a.store_kib.c_str() || *end != '\0' || kib < 16 || kib > 65536 || kib % 16)
        return usage("--store-kib " + a.store_kib +
                     ": expected a multiple of 16 in 16..65536, or spe (the Cell's 256)");
      plan.local_store_bytes = std::size_t(kib) * 1024;
    }
  }
  if (a.cl_device_opt->count() && a.cl_device < 0)
    return usage("--cl-device " + std::to_string(a.cl_device) +
                 ": expected a device index (0 or more, see ardcell devices)");
  // OpenCL: asked for by --backend opencl, or auto (the default: a GPU when there is one).
  const bool opencl_asked = backend == BackendKind::kOpenCl || backend == BackendKind::kAuto;
  {
    if (a.workers_opt->count() && (a.workers < 1 || a.workers > 256))
      return usage("--workers " + std::to_string(a.workers) + ": expected 1..256");
    if (a.workers_opt->count() && backend == BackendKind::kSerial)
      return usage(
          "--workers applies to the threads back end (expected no --workers with "
          "--backend serial)");
    if (a.cl_device_opt->count() && !opencl_asked)
      return usage("--cl-device " + std::to_string(a.cl_device) + " needs --backend opencl or " +
                   "auto (expected no --cl-device with --backend " + a.backend + ")");
  }

  // --ranks: this process is one rank of an mpirun, running one block of the grid. Only rank 0
  // speaks: every rank makes the same checks.
  const bool ranked = a.ranks_opt->count() > 0;
#if defined(ARDCELL_WITH_MPI)
  RankJob job;
#endif
  if (ranked) {
#if defined(ARDCELL_WITH_MPI)
    if (backend == BackendKind::kOpenCl)
      return usage(
          "--ranks runs each rank on the threads or serial back end (expected no "
          "--backend opencl)");
    if (backend == BackendKind::kAuto) backend = BackendKind::kThreads;
    if (std::string why = start_rank_job("--ranks", a.ranks, ctx, job); !why.empty())
      return usage(why);
#else
    return usage(
        "--ranks: this ardcell was built without MPI (expected a build with "
        "-DARDCELL_WITH_MPI=ON and libopenmpi-dev)");
#endif
  }

  // The scene: a saved state's, or a built-in scene / preset by name or path.
  Preset preset;
  SavedStateMeta meta;
  const bool resume = !a.load_state.empty();
  if (resume) {
    if (Status s = read_state_meta(a.load_state, meta); !s)
      return usage("--load-state " + s.message());
    if (!scene_name.empty() && scene_name != meta.scene)
      return usage("--load-state " + a.load_state + " holds scene '" +
                   escaped_prefix(meta.scene, 60) + "' but the scene given is '" + scene_name +
                   "' (expected the same or none)");
    scene_name = meta.scene;
    std::string notice;
    if (Status s = saved_state_preset(a.load_state, meta, preset, notice); !s)
      return usage("--load-state " + s.message());
    if (!notice.empty()) std::fprintf(ctx.err, "ardcell: %s\n", notice.c_str());
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
  if (a.realtime_solvers) use_realtime_solvers(preset);
  SceneConfig scene = preset.scene;
  if (scene.name.empty()) scene.name = scene_name;

  // Overrides (after --realtime-solvers, so that --solver, --sweeps and --set refine it).
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
  for (const std::string& assignment : a.sets)
    if (Status s = apply_param_override(scene, assignment); !s) return usage(s.message());
  if (Status s = check_scene_keys(scene); !s) return usage(s.message());
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
  if (std::string error = choose_colormap(a, field, scene, render); !error.empty())
    return usage(error);

  if (Status s = check_memory_for_grid(scene); !s) return usage(s.message());

  // A scene of tile passes (the table1 scenes) takes a schedule and a local store size.
  const bool planned = scene.fluid.kind == FluidSceneKind::kTable1;
  if (!planned) {
    const std::string general =
        " applies to the scenes built of tile passes (table1, table1-ard); scene '" + scene.name +
        "' runs its steps as stages (expected no ";
    if (a.schedule_opt->count()) return usage("--schedule" + general + "--schedule)");
    if (a.store_kib_opt->count()) return usage("--store-kib" + general + "--store-kib)");
  } else if (a.schedule_opt->count()) {
    if (backend == BackendKind::kSerial && plan.schedule != PlanSchedule::kSerial)
      return usage("--schedule " + a.schedule +
                   " needs a tiling back end (threads or opencl); --backend serial runs the "
                   "whole-grid reference (expected --schedule serial or no --schedule)");
    if (backend == BackendKind::kOpenCl && plan.schedule == PlanSchedule::kSerial)
      return usage(
          "--schedule serial is the whole-grid CPU reference; expected stream or blocked with "
          "--backend opencl");
  }

  // The engine, on an OpenCL device when asked for and possible (else the threads back end,
  // with one line saying why), and the saved state it resumes from.
  EngineOptions options;
  options.plan = plan;
  if (a.workers_opt->count()) options.workers = a.workers;
  options.pin_workers = !ranked;  // nothing else of ours runs beside the engine (one rank)
  const BackendChoice choice = choose_engine_backend(backend, a.cl_device, options, ctx);
#if defined(ARDCELL_WITH_MPI)
  // One block of the grid per rank, its halos exchanged with the other ranks.
  if (ranked)
    if (std::string why = split_rank_job("--ranks", a.ranks, scene, job, options); !why.empty())
      return usage(why);
#endif
  std::unique_ptr<Engine> engine;
  if (Status s = make_engine(scene, options, engine); !s) return usage(s.message());
  if (std::string line = generalized_stability_line(scene); !line.empty())
    std::fprintf(ctx.err, "ardcell run: %s\n", line.c_str());
  SimState* state = &engine->state();
  const std::string no_field = "--show " + show + ": scene '" + scene.name + "' has no " + show +
                               " field (expected one of the fields it simulates)";
  // A rank's fields are its block's: its run checks the gathered state (below).
  if (!ranked && !frame_field_available(*state, field)) return usage(no_field);
  if (resume) {
#if defined(ARDCELL_WITH_MPI)
    if (ranked) {
      if (Status s = load_state_into_block(a.load_state, meta, *engine); !s)
        return usage("--load-state " + s.message());
    } else
#endif
        if (Status s = load_state_fields(a.load_state, meta, *state); !s)
      return usage("--load-state " + s.message());
  }

  // Stroke playback (--strokes / --replay): files are read before any output is created.
  std::unique_ptr<StrokePlayback> playback;
  if (std::string error; !a.paint.make(scene, playback, error)) return usage(error);
  // Every rank reads the same strokes: it paints its block's cells of the chemicals, dye and
  // velocity, and the whole grid's orientation sources and obstacle mask (host/paint/paint.h).
  if (ranked && !a.probe_csv.empty())
    return usage("--probe-csv records one process's grid (expected no --ranks)");

  // Outputs: checked and created before the first step, removed again on a usage error.
  RunOutputs outputs;
#if defined(ARDCELL_WITH_MPI)
  if (ranked) {
    // Rank 0 writes; every rank leaves together when it cannot.
    const int rc = job.world->rank() == 0
                       ? open_outputs(a, ctx, scene.name, scene.size, show, every, outputs)
                       : kExitOk;
    if (job.world->any(rc != kExitOk)) return kExitUsage;
  } else
#endif
      if (int rc = open_outputs(a, ctx, scene.name, scene.size, show, every, outputs);
          rc != kExitOk)
    return rc;
  if (!a.probe_csv.empty())
    if (Status s = ProbeRecorder::open(*engine, a.probe_csv, steps, outputs.probes); !s) {
      remove_created(outputs.created);
      return usage(s.message());
    }
  if (a.stats) {
    std::fprintf(ctx.out, "scene=%s size=%dx%d backend=%s workers=%d", scene.name.c_str(),
                 scene.size.x, scene.size.y, engine->backend_name(), engine->workers());
    if (Table1Plan* t = engine->table1_plan()) {
      std::fprintf(ctx.out, " schedule=%s", std::string(plan_schedule_name(t->schedule())).c_str());
      if (engine->device().fields_on_host())
        std::fprintf(ctx.out, " local_store=%zuKiB", t->local_store_bytes() / 1024);
    }
#if defined(ARDCELL_WITH_OPENCL)
    if (choice.opencl)
      std::fprintf(ctx.out, " device=%s", choice.opencl->device().device_name.c_str());
#endif
    std::fputc('\n', ctx.out);
  }
  const auto print_passes = [&] {
    engine->plan().print_stats(ctx.out);
    if (!engine->device().fields_on_host())
      std::fprintf(ctx.out, "(%s queues its work: a step's time is the host's time to queue it)\n",
                   engine->backend_name());
  };
#if defined(ARDCELL_WITH_MPI)
  if (ranked) {
    RankStepper stepper(*engine, *job.layout, *job.world, writes_frames(a, every) ? every : 0,
                        &StopSignals::requested(), playback.get());
    if (job.world->any(job.world->rank() == 0 &&
                       !frame_field_available(stepper.frame_state(), field))) {
      remove_created(outputs.created);
      return usage(no_field);
    }
    RankRun run{stepper.stop(), [&] { stepper.gather(); }, job.world->rank() == 0};
    const auto print_ranks = [&] {
      print_passes();
      // Every rank takes part in the sum; rank 0 prints.
      const double frames = double(std::max<std::int64_t>(1, engine->plan().runs()));
      const double sent = job.world->sum(job.channel->bytes_sent());
      std::fprintf(ctx.out,
                   "ranks=%s halo: sent=%.1fKiB/frame (all ranks) exchange=%.3fms/frame (rank 0, "
                   "waiting included)\n",
                   a.ranks.c_str(), sent / frames / 1024.0, 1e3 * job.channel->seconds() / frames);
    };
    return run_and_report(a, ctx, stepper, scene, steps, every, render, outputs, print_ranks, run);
  }
#endif
  EngineStepper stepper(*engine, playback.get());
  return run_and_report(a, ctx, stepper, scene, steps, every, render, outputs, print_passes);
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
  run->add_flag("--realtime-solvers", a.realtime_solvers,
                "every solve quality.max_sweeps fixed Jacobi sweeps, the reaction tabulated "
                "(ardcell live's real-time settings)");
  a.out_opt = run->add_option("--out", a.out, "folder for PNG frames (default out/<scene>-<time>)");
  a.every_opt = run->add_option("--every", a.every,
                                "write a frame every N steps; 0: none (default steps/50)");
  a.show_opt = run->add_option("--show", a.show,
                               "field drawn: dye | speed | vorticity | "
                               "pressure | A | B (default: the scene's)");
  a.colormap_opt = run->add_option("--colormap", a.colormap, "gray | viridis | magma | rdbu");
  a.video_opt = run->add_option(
      "--video", a.video, "also write a video: .y4m built in, other extensions through ffmpeg");
  run->add_option("--fps", a.fps, "video frame rate (default 30)");
  run->add_flag("--no-png", a.no_png, "write no PNG frames (e.g. video only)");
  a.save_state_opt =
      run->add_option("--save-state", a.save_state, "save the final state to this folder");
  run->add_option("--load-state", a.load_state, "resume from a state saved by --save-state");
  run->add_flag("--quiet", a.quiet, "no progress bar");
  run->add_option("--probe-csv", a.probe_csv,
                  "obstacle scenes: write drag, lift and the probes (fluid.probes) each frame "
                  "to this CSV file");
  run->add_option("--set", a.sets,
                  "set a scene parameter, key=value (repeatable; e.g. fluid.viscosity=0.02)");
  add_run_paint_options(*run, a.paint);
  a.schedule_opt = run->add_option("--schedule", a.schedule,
                                   "table1 scenes: serial | stream | blocked (default blocked)");
  a.backend_opt = run->add_option("--backend", a.backend,
                                  "auto | threads | serial | opencl (default auto: an OpenCL GPU, "
                                  "else threads)");
  a.cl_device_opt =
      run->add_option("--cl-device", a.cl_device, "OpenCL device index (see ardcell devices)");
  a.workers_opt =
      run->add_option("--workers", a.workers, "threads back end workers (default: one per core)");
  a.ranks_opt = run->add_option(
      "--ranks", a.ranks,
      "under mpirun: the grid cut into WxH blocks, one per process (mpirun -np W*H); a fluid, "
      "the RD's solves and advection run on the grid gathered from every block");
  a.store_kib_opt = run->add_option(
      "--store-kib", a.store_kib,
      "table1 scenes: local store per worker in KiB, or spe (the Cell's 256; default: one L2 "
      "per double-buffer slot)");
  run->add_flag(
      "--stats", a.stats,
      "print per-frame times (mean, p50, p99) and the time of each step of the frame plan");
  run->callback([args, &ctx] {
    try {
      ctx.exit_code = do_run(*args, ctx);
    } catch (const std::bad_alloc&) {
      ctx.exit_code = cli_usage_error(ctx, "run", "out of memory (expected a smaller --size)");
    }
  });
}

}  // namespace ardcell
