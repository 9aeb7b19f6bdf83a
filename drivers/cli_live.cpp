// `ardcell live [PRESET]`: the real-time window (drivers/display_sdl.h) running the live loop
// (host/live/live_loop.h) with presets, adaptive quality, attract mode, GPIO buttons, OSC and
// recording. See docs/live-and-kiosk.md.
#include <sched.h>
#include <sys/mman.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>

#include "drivers/cli.h"
#include "drivers/cli_backend.h"
#include "drivers/cli_ranks.h"
#include "drivers/live_services.h"
#include "drivers/surface_fluid_flags.h"
#include "host/io/atomic_file.h"
#include "host/live/live_engine.h"
#include "host/live/live_wall.h"
#if defined(ARDCELL_WITH_MPI)
#include "host/live/rank_wall.h"
#endif
#include "host/scenes/preset.h"
#if ARDCELL_WITH_OPENSUBDIV
#include "host/surface/surface_scene.h"
#include "host/surface/surface_simulation.h"
#endif
#include "runtime/opencl/backend_choice.h"
#ifdef ARDCELL_WITH_SDL2
#include "drivers/display_sdl.h"
#endif

namespace ardcell {

namespace {

struct LiveArgs {
  std::string preset;
  double fps = -1;  // -1: not given
  bool rt = false;
  int osc_port = -1;
  std::string osc_bind = "127.0.0.1";
  bool osc_remote = false;
  std::vector<std::string> preset_dirs;
  double attract_seconds = 0;
  std::string attract_dir;
  std::string gpio_config;
  int64_t frames = 0;
  int display = 0;
  bool fullscreen = false;
  bool no_vsync = false;
  int scale = 0;
  bool hud = false;
  bool no_adaptive = false;
  bool pipeline = false;
  bool realtime_solvers = false;
  std::string record;
  std::string screenshot;
  std::string screenshot_dir = ".";
  std::vector<std::string> playlist;
  int crossfade = 30;
  bool keys = false;
  bool markdown = false;
  bool list = false;
  std::string backend = "auto";
  int cl_device = -1;
  int workers = 0;
  std::string wall;
  int bezel = 0;
  std::string shape, mesh;
  int patch_cells = 16;
  SurfaceFluidFlags fluid;  // --fluid, --force, --conserve-dye (as `ardcell surface`)
  CLI::Option* shape_opt = nullptr;
  CLI::Option* mesh_opt = nullptr;
  CLI::Option* patch_cells_opt = nullptr;
  CLI::Option* cl_device_opt = nullptr;
  CLI::Option* workers_opt = nullptr;
  CLI::Option* wall_opt = nullptr;
  CLI::Option* playlist_opt = nullptr;
};

// --wall: the flags a wall's screens cannot honour. "" when none, else the usage line.
std::string check_wall_args(const LiveArgs& a) {
  if (a.wall_opt->count() == 0) return a.bezel > 0 ? "--bezel applies to a --wall" : "";
  const auto refuse = [](const char* flag, const char* why) {
    return std::string(flag) + " does not run on a --wall (" + why + ")";
  };
  if (a.pipeline) return refuse("--pipeline", "the screens step in lockstep");
  if (!a.record.empty()) return refuse("--record", "record one screen's output instead");
  if (a.bezel > 0 && a.scale == 0)
    return "--bezel " + std::to_string(a.bezel) +
           " needs --scale (the window pixels per cell that turn the bezel into cells)";
  return "";
}

// --backend / --cl-device: what to run the presets on. "" when valid, else the usage line.
std::string check_backend_args(const LiveArgs& a, BackendKind& kind, bool& opencl_asked) {
  if (!parse_backend_kind(a.backend, kind))
    return "--backend '" + a.backend + "': expected auto, threads, serial or opencl";
  if (a.workers_opt && a.workers_opt->count()) {
    if (a.workers < 1 || a.workers > 256)
      return "--workers " + std::to_string(a.workers) + ": expected 1..256";
    if (kind == BackendKind::kSerial)
      return "--workers applies to the threads back end (expected no --workers with --backend "
             "serial)";
  }
  const bool device_given = a.cl_device_opt && a.cl_device_opt->count() > 0;
  if (device_given && a.cl_device < 0)
    return "--cl-device " + std::to_string(a.cl_device) +
           ": expected a device index (0 or more, see ardcell devices)";
  // As `ardcell run`: OpenCL when asked for by --backend opencl, or auto (a GPU if there is one).
  opencl_asked = kind == BackendKind::kOpenCl || kind == BackendKind::kAuto;
  if (device_given && !opencl_asked)
    return "--cl-device " + std::to_string(a.cl_device) +
           " needs --backend opencl or auto (expected no --cl-device with --backend " + a.backend +
           ")";
  return "";
}

// --shape / --mesh: "" when the flags can show a surface, else the usage line.
std::string check_surface_args(const LiveArgs& a, BackendKind backend) {
  const bool on_surface = a.shape_opt->count() > 0 || a.mesh_opt->count() > 0;
  const bool fluid = a.fluid.fluid_opt->count() > 0;
  if (!fluid)
    if (const CLI::Option* o = a.fluid.setting_given()) return fluid_setting_without_fluid(*o);
  if (!on_surface) {
    if (fluid) return "--fluid runs on a surface (expected --shape or --mesh with --fluid)";
    return a.patch_cells_opt->count() ? "--patch-cells applies to --shape or --mesh" : "";
  }
#if !ARDCELL_WITH_OPENSUBDIV
  (void)backend;
  return "--shape/--mesh: this ardcell was built without OpenSubdiv (expected a build with "
         "-DARDCELL_WITH_OPENSUBDIV=ON and libosd-dev)";
#else
  if (a.wall_opt->count())
    return "--wall shows a flat grid (expected no --shape or --mesh with --wall)";
  if (backend == BackendKind::kOpenCl || backend == BackendKind::kSerial)
    return "--backend " + a.backend +
           ": a surface's patches run on the threads back end (expected auto or threads with "
           "--shape or --mesh)";
  if (a.cl_device_opt->count())
    return "--cl-device: a surface's patches run on the threads back end (expected no "
           "--cl-device with --shape or --mesh)";
  if (a.realtime_solvers)
    return "--realtime-solvers: a surface solves by its own multigrid (expected no "
           "--realtime-solvers with --shape or --mesh)";
  if (FluidForce force; fluid)
    if (Status s = parse_fluid_force(a.fluid.fluid, force); !s) return s.message();
  return patch_cells_problem(a.patch_cells);
#endif
}

void request_realtime(std::FILE* err) {
  sched_param sp{};
  sp.sched_priority = 10;
  if (sched_setscheduler(0, SCHED_FIFO, &sp) != 0)
    std::fprintf(err, "ardcell live: --rt: SCHED_FIFO refused (%s); running at normal priority\n",
                 std::strerror(errno));
  if (mlockall(MCL_CURRENT | MCL_FUTURE) != 0)
    std::fprintf(err, "ardcell live: --rt: mlockall refused (%s); memory may be paged\n",
                 std::strerror(errno));
}

int run_live(const LiveArgs& a, CliContext& ctx) {
  if (a.keys && a.markdown) {
    std::fputs(preset_keys_markdown().c_str(), ctx.out);
    return kExitOk;
  }
  if (a.keys) {
    for (const ParamSpec& s : preset_params())
      std::fprintf(ctx.out, "%-36.*s %s; %.*s\n", int(s.key.size()), s.key.data(),
                   param_expectation(s).c_str(), int(s.help.size()), s.help.data());
    return kExitOk;
  }
  if (a.list) {
    for (const std::string& n : preset_names()) std::fprintf(ctx.out, "%s\n", n.c_str());
    return kExitOk;
  }
  BackendKind backend = BackendKind::kAuto;
  bool opencl_asked = false;
  if (std::string why = check_backend_args(a, backend, opencl_asked); !why.empty())
    return cli_usage_error(ctx, "live", why);
  if (std::string why = check_wall_args(a); !why.empty()) return cli_usage_error(ctx, "live", why);
  const bool walled = a.wall_opt->count() > 0;
  // --shape / --mesh: the presets' reaction-diffusion on a surface, drawn in 3D.
  [[maybe_unused]] const bool on_surface = a.shape_opt->count() > 0 || a.mesh_opt->count() > 0;
  if (std::string why = check_surface_args(a, backend); !why.empty())
    return cli_usage_error(ctx, "live", why);
#if ARDCELL_WITH_OPENSUBDIV
  // The limit surface once for every preset of the session, its problems named by the mesh.
  std::shared_ptr<LimitSurface> surface;
  if (on_surface) {
    PolyMesh mesh;
    std::string label;
    if (Status s = surface_control_mesh(a.shape_opt->count() ? a.shape : std::string(), a.mesh,
                                        mesh, label);
        !s)
      return cli_usage_error(ctx, "live", s.message());
    surface = std::make_shared<LimitSurface>();
    if (Status s = build_live_surface(std::move(mesh), a.patch_cells, *surface); !s)
      return cli_usage_error(ctx, "live", (label.empty() ? "" : label + ": ") + s.message());
  }
#endif
  [[maybe_unused]] int screen = 0;  // on a wall, this process's screen (its rank)
  [[maybe_unused]] std::FILE* const own_err = ctx.err;  // before a wall quiets screens but 0
  // Once MPI runs, every screen of a wall agrees once whether all of them could start (an
  // all-reduce): one that cannot (a preset file, a display, a GPIO chip or an OSC port missing on
  // its host) must not leave the others waiting for it in their first frame. What every screen
  // checks alike, screen 0 says; what failed on one host, that screen says on its own stderr.
  [[maybe_unused]] bool agreed = false;
#if defined(ARDCELL_WITH_MPI)
  RankJob job;
  // The agreement is one all-gather of every screen's vote: whether it failed, and a digest of
  // what it runs (the preset as TOML, --realtime-solvers in it, --crossfade and --frames).
  struct StartVote {
    std::uint32_t failed = 0, unused = 0;
    std::uint64_t digest = 0;
  };
  std::vector<StartVote> votes;
  const auto vote = [&](bool failed, std::uint64_t digest) {
    const StartVote mine{failed ? 1u : 0u, 0, digest};
    votes.resize(std::size_t(job.world->size()));
    job.world->all_gather(&mine, sizeof mine, votes.data());
  };
#endif
  const auto fail = [&](int code, const std::string& line, bool local) {
#if defined(ARDCELL_WITH_MPI)
    if (walled && !agreed) {
      if (local && screen != 0)
        std::fprintf(own_err, "ardcell live: screen %d: %s\n", screen, line.c_str());
      else
        std::fprintf(ctx.err, "ardcell live: %s\n", line.c_str());
      agreed = true;
      vote(true, 0);
      return code;
    }
#endif
    (void)local;
    if (code == kExitUsage) return cli_usage_error(ctx, "live", line);
    std::fprintf(ctx.err, "ardcell live: %s\n", line.c_str());
    return code;
  };
#if defined(ARDCELL_WITH_MPI)
  // --wall: this process is one screen of an mpirun, showing the block of the grid it runs.
  if (walled) {
    // Mirrored screens step alike on one kind of back end: auto is the CPU's threads (OpenCL
    // when --cl-device names a device).
    if (backend == BackendKind::kAuto)
      backend = a.cl_device_opt->count() ? BackendKind::kOpenCl : BackendKind::kThreads;
    // A wrong layout or process count is every screen's: they leave together at once.
    if (std::string why = start_rank_job("--wall", a.wall, ctx, job); !why.empty())
      return cli_usage_error(ctx, "live", why);
    screen = job.world->rank();
    if (job.world->size() > LiveSimulation::kMaxInputSources)
      return fail(kExitUsage,
                  "--wall " + a.wall + ": at most " +
                      std::to_string(LiveSimulation::kMaxInputSources) + " screens",
                  false);
  }
#else
  if (walled)
    return cli_usage_error(ctx, "live",
                           "--wall: this ardcell was built without MPI (expected a build with "
                           "-DARDCELL_WITH_MPI=ON and libopenmpi-dev)");
#endif
  if (a.osc_port >= 0 && !a.osc_remote && is_remote_address(a.osc_bind))
    return fail(kExitUsage,
                "--osc-bind " + a.osc_bind +
                    ": listening beyond 127.0.0.0/8 lets anyone on the network "
                    "control the display (expected a loopback address, or "
                    "--osc-remote to allow it)",
                false);
  for (const std::string& dir : a.preset_dirs)
    if (std::error_code ec; !std::filesystem::is_directory(dir, ec))
      return fail(kExitUsage,
                  "--preset-dir " + dir + ": not a folder (expected a folder of .toml presets)",
                  true);
#ifndef ARDCELL_WITH_SDL2
  return fail(kExitUsage, "this build has no SDL2 display (ARDCELL_WITH_SDL2=OFF)", false);
#else
  LiveOptions o;
  o.playlist = a.playlist.empty() ? preset_names() : a.playlist;
  // --fluid: the presets' fluids on the surface instead of their RD.
  [[maybe_unused]] const bool fluid = on_surface && a.fluid.fluid_opt->count() > 0;
#if ARDCELL_WITH_OPENSUBDIV
  // On a surface the default playlist is the presets whose RD a surface can run (with --fluid,
  // the presets with a fluid).
  if (on_surface && a.playlist.empty())
    std::erase_if(o.playlist, [fluid](const std::string& name) {
      Preset p;
      return !load_preset(name, p) || !runs_on_surfaces(p, fluid);
    });
#endif
  const std::string first = !a.preset.empty() ? a.preset
                            : on_surface && a.playlist.empty()
                                ? std::string(fluid ? "cavity" : "turing-spots")
                            : o.playlist.empty() ? std::string("cavity")
                                                 : o.playlist.front();
  Preset preset;
  if (Status s = load_live_preset(first, preset, a.realtime_solvers); !s)
    return fail(kExitUsage, s.message(), true);
#if ARDCELL_WITH_OPENSUBDIV
  if (on_surface)
    if (Status s = runs_on_surfaces(preset, fluid); !s)
      return fail(kExitUsage, first + ": " + s.message(), true);
#endif
  for (const std::string& name : a.playlist) {
    Preset p;
    if (Status s = load_live_preset(name, p); !s)
      return fail(kExitUsage, "--playlist " + name + ": " + s.message(), true);
#if ARDCELL_WITH_OPENSUBDIV
    if (on_surface)
      if (Status s = runs_on_surfaces(p, fluid); !s)
        return fail(kExitUsage, "--playlist " + name + ": " + s.message(), true);
#endif
  }
  // Every destination is checked before the window opens (on a wall, screen 0 writes them).
  if (!a.record.empty())
    if (Status s = check_output_path(a.record, false); !s)
      return fail(kExitUsage, "--record " + s.message(), true);
  if (!a.screenshot.empty() && screen == 0)
    if (Status s = check_output_path(a.screenshot, false); !s)
      return fail(kExitUsage, "--screenshot " + s.message(), true);
  if (std::error_code ec; screen == 0 && !std::filesystem::is_directory(a.screenshot_dir, ec))
    return fail(
        kExitUsage,
        "--screenshot-dir " + a.screenshot_dir + ": not a folder (expected an existing folder)",
        true);
  if (Status s = check_output_path(a.screenshot_dir, true); screen == 0 && !s)
    return fail(kExitUsage, "--screenshot-dir " + s.message(), true);
  if (a.rt) request_realtime(ctx.err);

  // Declared before the loop: the simulations it makes must outlive it.
  EngineOptions engine_options;
  if (a.workers_opt->count()) engine_options.workers = a.workers;
  Int2 window_cells = preset.scene.size;
#if ARDCELL_WITH_OPENSUBDIV
  // A surface draws its 3D view at SurfaceLiveOptions' size, one window pixel a pixel.
  if (on_surface) window_cells = SurfaceLiveOptions{}.view;
#endif
#if defined(ARDCELL_WITH_MPI)
  std::unique_ptr<RankWall> wall;
  if (walled) {
    // A scene whose blocks compute only their cells (block_support, not gathering) splits its
    // grid between the screens, unless the wall switches presets (--playlist) or steps on
    // OpenCL; every other scene, and those, run whole on every screen (host/live/live_wall.h): a
    // block that gathers the grid would compute it whole anyway, and mirrored walls switch
    // presets.
    const BlockSupport support = block_support(preset.scene);
    const bool split = support.problem.empty() && !support.gathers &&
                       backend != BackendKind::kOpenCl && a.playlist_opt->count() == 0;
    if (split) {
      if (std::string why = split_rank_job("--wall", a.wall, preset.scene, job, engine_options);
          !why.empty())
        return fail(kExitUsage, why, false);
    } else {
      try {
        job.layout = BlockLayout::split(preset.scene.size, job.parts);
      } catch (const std::invalid_argument& e) {
        return fail(kExitUsage, "--wall " + a.wall + ": " + e.what(), false);
      }
    }
    const int bezel_cells = a.bezel > 0 ? (a.bezel + a.scale - 1) / a.scale : 0;
    for (int b = 0; b < job.layout->count(); ++b)
      if (wall_view(*job.layout, b, bezel_cells).empty())
        return fail(kExitUsage,
                    "--bezel " + std::to_string(a.bezel) + ": hides every cell of a " +
                        std::to_string(job.layout->block(b).width()) + "x" +
                        std::to_string(job.layout->block(b).height()) +
                        " screen (expected a smaller bezel or a larger grid)",
                    false);
    wall = std::make_unique<RankWall>(*job.layout, bezel_cells, *job.world, !split);
    window_cells = wall->view().size();
  }
#endif

  Status error = Status::ok();
  const std::string title =
      walled ? "ardcell " + a.wall + " screen " + std::to_string(screen) : "ardcell";
  auto display = SdlDisplay::open({.display = a.display,
                                   .fullscreen = a.fullscreen,
                                   .vsync = !a.no_vsync,
                                   .scale = a.scale,
                                   .title = title},
                                  window_cells, error);
  if (!display) return fail(kExitFailure, error.message(), true);
  if (!display->hud_notice().empty())
    std::fprintf(ctx.err, "ardcell live: %s\n", display->hud_notice().c_str());
  // A wall's screens pace alike (a barrier joins their frames anyway): 60 Hz unless told.
  o.fps = a.fps >= 0                               ? a.fps
          : !walled && display->refresh_rate() > 0 ? display->refresh_rate()
                                                   : 60.0;
  o.max_frames = a.frames;
  o.hud = a.hud;
  // A surface's solves are its own multigrid, which the quality levels do not reach.
  o.adaptive = !a.no_adaptive && !on_surface;
  o.pipeline = a.pipeline;
  o.realtime_solvers = a.realtime_solvers;
  o.crossfade_frames = a.crossfade;
  o.record_path = a.record;
  o.screenshot_dir = a.screenshot_dir;
  o.exit_screenshot = a.screenshot;
  o.log = ctx.err;
  use_file_writers(o);
#if defined(ARDCELL_WITH_MPI)
  o.wall = wall.get();
  if (walled) o.adaptive = false;
#endif
  // Its OpenCL context outlives the loop's simulations.
  SimulationFactory factory;
  [[maybe_unused]] BackendChoice choice;
#if ARDCELL_WITH_OPENSUBDIV
  if (on_surface) {
    SurfaceLiveOptions options;
    options.patch_cells = a.patch_cells;
    if (a.workers_opt->count()) options.workers = a.workers;
    if (fluid) {
      if (Status s = parse_fluid_force(a.fluid.fluid, options.fluid.force); !s)  // checked above
        return fail(kExitUsage, s.message(), false);
      options.fluid.strength = a.fluid.force;
      if (a.fluid.conserve_dye_opt->count()) options.fluid.conserve_dye = a.fluid.conserve_dye;
    }
    factory = surface_simulations(std::move(surface), options);
  }
#endif
  if (!factory) {
    choice = choose_engine_backend(backend, a.cl_device, engine_options, ctx);
    factory = engine_simulations(engine_options);
  }
  // SIGINT/SIGTERM/SIGHUP quit as Esc does (recording finished, stats printed), also when an
  // ignored SIGINT was inherited; kept until the recording is renamed into place.
  StopSignals signals;
  o.stop = &StopSignals::requested();
  LiveLoop loop(o, factory, *display);
  if (Status s = loop.start(first); !s) return fail(kExitUsage, s.message(), true);
  install_report_signal();

  // Kiosk services: the attract mode, GPIO buttons, OSC (on a wall, screen 0 listens for all).
  LiveServices services;
  const LiveServiceProblem problem = services.start({.attract_seconds = a.attract_seconds,
                                                     .attract_dir = a.attract_dir,
                                                     .gpio_config = a.gpio_config,
                                                     .osc_port = a.osc_port,
                                                     .osc_bind = a.osc_bind,
                                                     .preset_dirs = a.preset_dirs},
                                                    !walled || screen == 0, loop, ctx.err);
  if (!problem.line.empty()) return fail(kExitUsage, problem.line, problem.local);
#if defined(ARDCELL_WITH_MPI)
  // Every screen started, or every screen leaves (the one that could not said why); and every
  // screen runs the same, or a mirrored wall's screens would step different simulations.
  if (walled) {
    vote(false,
         text_fingerprint(preset_to_toml(preset) + "crossfade=" + std::to_string(a.crossfade) +
                          " frames=" + std::to_string(a.frames)));
    int other = -1;
    for (std::size_t r = 0; r < votes.size(); ++r) {
      if (votes[r].failed) {
        std::fprintf(ctx.err,
                     "ardcell live: another screen of the wall could not start (its line above)\n");
        return kExitFailure;
      }
      if (other < 0 && votes[r].digest != votes[0].digest) other = int(r);
    }
    if (other >= 0) {
      std::fprintf(ctx.err,
                   "ardcell live: --wall: screen %d runs another preset or other settings than "
                   "screen 0 (expected the same preset, --realtime-solvers, --crossfade and "
                   "--frames on every screen)\n",
                   other);
      return kExitUsage;
    }
  }
#endif
  std::string wall_line;  // on a wall, how it runs
#if defined(ARDCELL_WITH_MPI)
  if (wall)
    wall_line = "; wall " + a.wall + ": " +
                (wall->mirrored() ? "every screen steps the whole grid (mirrored)"
                                  : "each screen steps its block of the grid (split)");
#endif
  std::fprintf(ctx.err, "ardcell live: backend %.*s%s\n", int(loop.simulation().backend().size()),
               loop.simulation().backend().data(), wall_line.c_str());

  const Status s = services.run(loop);
  if (loop.wall_resyncs() > 0)
    std::fprintf(ctx.err,
                 "ardcell live: wall: the screens drifted apart %lld times; each time they went "
                 "on from screen 0's state\n",
                 static_cast<long long>(loop.wall_resyncs()));
  const int code = s ? StopSignals::exit_code(kExitOk) : kExitFailure;
  if (!s) std::fprintf(ctx.err, "ardcell live: %s\n", s.message().c_str());
  if (loop.switch_abandoned()) {
    // Quit while a preset was loading: its detached builder may still use the engine options
    // and OpenCL context of this function, so end here; the recording, screenshot and report
    // are finished (LiveLoop::run), nothing else holds the user's data.
    std::fflush(nullptr);
    std::_Exit(code);
  }
  return code;
#endif
}

}  // namespace

void add_live_command(CLI::App& app, CliContext& ctx) {
  auto args = std::make_shared<LiveArgs>();
  CLI::App* live = app.add_subcommand(
      "live", "Real-time window: paint with mouse, touch or pen; presets, kiosk, OSC");
  live->add_option("preset", args->preset, "Preset name or .toml path (`--list`)");
  live->add_option("--fps", args->fps,
                   "Target frame rate, 0 unpaced (default: the display's refresh; a wall's 60)")
      ->check(finite_range(0.0, 1000.0));
  live->add_flag("--rt", args->rt, "Ask for SCHED_FIFO and mlockall (goes on when refused)");
  live->add_option("--osc", args->osc_port, "Listen for OSC on this UDP port")
      ->check(CLI::Range(0, 65535));
  live->add_option("--osc-bind", args->osc_bind, "Address OSC binds to (default 127.0.0.1)");
  live->add_flag("--osc-remote", args->osc_remote,
                 "Allow --osc-bind beyond 127.0.0.0/8 (no authentication: trusted networks only)");
  live->add_option("--preset-dir", args->preset_dirs,
                   "Folder OSC /ardcell/preset may load .toml presets from (repeatable)");
  live->add_option("--attract", args->attract_seconds,
                   "Replay recorded strokes after this many idle seconds")
      ->check(finite_range(0.0, 1e6));
  live->add_option("--attract-dir", args->attract_dir, "Folder of .jsonl stroke recordings");
  live->add_option("--gpio", args->gpio_config, "GPIO buttons config (TOML)");
  live->add_option("--frames", args->frames, "Exit after N frames (tests)")
      ->check(CLI::Range(int64_t(0), int64_t(1) << 40));
  live->add_option("--display", args->display, "Display index for the window");
  live->add_flag("--fullscreen", args->fullscreen, "Fullscreen on the display");
  live->add_flag("--no-vsync", args->no_vsync, "Do not wait for vertical sync");
  live->add_option("--scale", args->scale, "Window pixels per cell (default: fit the screen)")
      ->check(CLI::Range(0, 64));
  live->add_flag("--hud", args->hud, "Start with the HUD shown (H toggles)");
  live->add_flag("--no-adaptive", args->no_adaptive, "Keep full quality even when frames miss");
  live->add_flag("--pipeline", args->pipeline,
                 "Step the next frame while presenting the last (one period more latency; for a "
                 "simulation that leaves a core free: a GPU, or --workers below the cores)");
  live->add_flag("--realtime-solvers", args->realtime_solvers,
                 "Every solve quality.max_sweeps fixed Jacobi sweeps, the reaction tabulated "
                 "(60 FPS at 512^2 on two cores)");
  live->add_option("--record", args->record, "Record from the start (.mp4 via ffmpeg, .y4m)");
  live->add_option("--screenshot", args->screenshot, "PNG of the window after the last frame");
  live->add_option("--screenshot-dir", args->screenshot_dir, "Folder for S-key screenshots");
  args->playlist_opt =
      live->add_option("--playlist", args->playlist, "Presets for next/previous (default: all)")
          ->delimiter(',');
  live->add_option("--crossfade", args->crossfade, "Frames of crossfade on preset switch")
      ->check(CLI::Range(0, 10000));
  live->add_flag("--keys", args->keys, "List every preset key and exit");
  live->add_flag("--markdown", args->markdown,
                 "With --keys: print docs/presets.md (the key table as Markdown)")
      ->needs("--keys");
  live->add_flag("--list", args->list, "List preset names and exit");
  live->add_option("--backend", args->backend,
                   "auto | threads | serial | opencl: threads runs every preset on every core, "
                   "serial on one, opencl on an OpenCL device; auto (the default) an OpenCL GPU "
                   "when there is one, else threads");
  args->workers_opt = live->add_option("--workers", args->workers,
                                       "threads back end workers (default: one per core)");
  args->cl_device_opt =
      live->add_option("--cl-device", args->cl_device, "OpenCL device index (see ardcell devices)");
  args->wall_opt = live->add_option(
      "--wall", args->wall,
      "WxH: one screen of a video wall under mpirun -np W*H, showing its part of one "
      "simulation");
  live->add_option("--bezel", args->bezel,
                   "--wall: window pixels hidden between screens (needs --scale)")
      ->check(CLI::Range(0, 100000));
  args->shape_opt = live->add_option(
      "--shape", args->shape,
      "show the preset's reaction-diffusion on a surface's 3D view: torus, cube-sphere, genus2, "
      "eight or elephant (the left button paints, the right one turns the view)");
  args->mesh_opt =
      live->add_option("--mesh", args->mesh, "as --shape, on this control mesh (OBJ or OFF)")
          ->excludes(args->shape_opt);
  args->patch_cells_opt =
      live->add_option("--patch-cells", args->patch_cells,
                       "--shape/--mesh: N x N cells a patch, a power of two (16)");
  add_surface_fluid_flags(
      *live, args->fluid,
      "--shape/--mesh: stable fluids carrying a dye instead of the preset's reaction-diffusion: "
      "gravity (the dye falls towards the bottom of the screen as the view turns) or walk (a "
      "point circling each patch pushes the fluid); the left button paints dye",
      "; default: the preset's fluid.conserve_dye");
  live->callback([args, &ctx] { ctx.exit_code = run_live(*args, ctx); });
}

}  // namespace ardcell
