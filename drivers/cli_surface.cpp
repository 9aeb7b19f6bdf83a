// `ardcell surface`: Gray-Scott reaction-diffusion on the Catmull-Clark limit surface of a
// control mesh (seed 004, docs/surfaces.md), or with --fluid stable fluids carrying a dye
// (host/surface/surface_fluid.h), written as a PLY of the limit surface with the field as vertex
// colours (--out), as a texture atlas with a UV-mapped OBJ (--atlas) and/or as a PNG render
// (--render).
//
// A subcommand of its own, not a scene of `ardcell run`: the patches do not run on the engine
// yet (no Device ops, back ends, frames or state files, which run's flags are about); once
// patches are blocks of the frame plan it becomes `ardcell run surface-gray-scott`.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "drivers/cli.h"
#include "drivers/surface_fluid_flags.h"

#if ARDCELL_WITH_OPENSUBDIV
#include "drivers/png_writer.h"
#include "host/io/atomic_file.h"
#include "host/io/surface_atlas.h"
#include "host/io/surface_ply.h"
#include "host/scenes/preset.h"
#include "host/surface/limit_surface.h"
#include "host/surface/patch_metric.h"
#include "host/surface/procedural_mesh.h"
#include "host/surface/surface_fluid.h"
#include "host/surface/surface_gray_scott.h"
#include "host/surface/surface_multigrid.h"
#include "host/surface/surface_render.h"
#include "host/surface/surface_scene.h"
#include "runtime/row_executor.h"
#include "runtime/thread/thread_backend.h"
#endif

namespace ardcell {
namespace {

#if ARDCELL_WITH_OPENSUBDIV

// About 350 bytes a cell while the metric is sampled (7 doubles at 4 samples a cell), 130
// after: at most about 1.5 GB.
constexpr long long kMaxCells = 1LL << 22;

struct SurfaceArgs {
  std::string mesh, shape = "torus", out, atlas, render, view = "35,25", reaction = "euler",
                    field = "b", colormap = "magma";
  int patch_cells = 16, steps = 3000, workers = 0;
  unsigned seed = 1;
  double F = 0.055, k = 0.062, dt = 1.0, scale = 0, tolerance = 1e-6;
  std::string solver = "jacobi";
  std::string preset;
  // --fluid: stable fluids with a dye instead of reaction-diffusion.
  SurfaceFluidFlags fluid;  // --fluid, --force, --conserve-dye (shared with `ardcell live`)
  std::string down = "0,0,-1";
  double viscosity = 0, dye_diffusion = 0, source_rate = 1;
  CLI::Option *mesh_opt, *shape_opt, *scale_opt, *reaction_opt, *field_opt, *f_opt, *k_opt, *dt_opt,
      *seed_opt, *steps_opt, *solver_opt, *preset_opt, *down_opt;
  std::vector<CLI::Option*> fluid_only;  // --viscosity, --dye-diffusion, --force, ...
  // What messages about the control mesh start with: the --mesh file, "--shape eight" for a
  // packaged mesh, nothing for one built in code (set by control_mesh).
  std::string mesh_label;
};

std::string mesh_prefix(const SurfaceArgs& a) {
  return a.mesh_label.empty() ? std::string() : a.mesh_label + ": ";
}

// --preset NAME: its reaction-diffusion as the surface takes it (host/surface/surface_scene.h).
Status preset_rd(const std::string& name, PresetRd& out) {
  Preset p;
  if (Status s = load_preset(name, p); !s) return Status::error("--preset " + s.message());
  if (Status s = preset_rd(p, out); !s)
    return Status::error("--preset " + name + ": " + s.message());
  return Status::ok();
}

Status control_mesh(SurfaceArgs& a, PolyMesh& mesh) {
  return surface_control_mesh(a.shape, a.mesh_opt->count() ? a.mesh : std::string(), mesh,
                              a.mesh_label);
}

// --out, --atlas and --render of `field` (cells of `grid`), in that order; the first failure.
Status write_outputs(const SurfaceArgs& a, const LimitSurface& surface, const PatchGrid& grid,
                     const PatchField& field, const SurfaceColours& colours,
                     const SurfaceView& view) {
  const auto atlas_file = [&](const char* extension) {
    return std::filesystem::path(a.atlas + extension);
  };
  Status written = Status::ok();
  if (!a.out.empty()) written = write_surface_ply(a.out, surface, grid, field, colours);
  if (written && !a.atlas.empty()) {
    const AtlasLayout layout = atlas_layout(surface.patches(), grid.n());
    written = write_png(atlas_file(".png"), surface_atlas_image(grid, field, layout, colours));
    if (written)
      written = write_surface_obj(atlas_file(".obj"), atlas_file(".mtl"),
                                  atlas_file(".png").filename().string(), surface, layout);
  }
  if (written && !a.render.empty())
    written = write_png(a.render, render_surface(surface, grid, field, colours, view));
  return written;
}

// The cells' range of a field.
std::pair<double, double> cell_range(const PatchGrid& g, const PatchField& f) {
  double lo = INFINITY, hi = -INFINITY;
  for (int p = 0; p < g.patches(); ++p)
    for (int j = 0; j < g.n(); ++j)
      for (int i = 0; i < g.n(); ++i) {
        lo = std::min(lo, f[g.index(p, i, j)]);
        hi = std::max(hi, f[g.index(p, i, j)]);
      }
  return {lo, hi};
}

// The threads back end the patches run on side by side (the same bits for any --workers),
// unpinned: a short command beside whatever else runs.
ThreadBackendOptions surface_threads(int workers) {
  ThreadBackendOptions threads;
  threads.workers = workers;
  threads.pin = false;
  return threads;
}

// --fluid: stable fluids on the surface (seed 004, Sec. 5), the dye from sources at the patches'
// centres (the seed's Fig. 8) written as the field.
int run_fluid(SurfaceArgs& a, CliContext& ctx, const LimitSurface& surface,
              const std::array<double, 3>& down, SurfaceColours colours, const SurfaceView& view) {
  auto usage = [&](const std::string& m) { return cli_usage_error(ctx, "surface", m); };
  const int n = a.patch_cells;
  const auto start = std::chrono::steady_clock::now();
  auto metric = std::make_unique<PatchMetric>(sample_limit_metric(surface, n));
  if (Status s = metric->check_nondegenerate(); !s) return usage(mesh_prefix(a) + s.message());
  SurfaceLaplacian op(surface.topology(), *metric);
  ThreadBackend backend(surface_threads(a.workers));
  RowExecutor executor(backend);
  op.set_executor(executor);
  const SurfaceMultigrid multigrid(surface, op);
  SurfaceFluidParams params;
  params.dt = a.dt_opt->count() ? a.dt : 0.05;
  if (Status s = parse_fluid_force(a.fluid.fluid, params.force); !s) return usage(s.message());
  params.strength = a.fluid.force;
  params.down = down;
  params.viscosity = a.viscosity;
  params.dye_diffusion = a.dye_diffusion;
  params.source_rate = a.source_rate;
  params.conserve_dye = a.fluid.conserve_dye;
  params.projection.tolerance = a.tolerance;
  SurfaceFluid fluid(surface, *metric, op, multigrid, params);
  metric.reset();  // only the construction reads it
  const int steps = a.steps_opt->count() ? a.steps : 200;
  std::fprintf(ctx.out,
               "patches=%d%s cells=%lld area=%.4g fluid=%s dt=%g force=%g viscosity=%g "
               "dye_diffusion=%g workers=%d\n",
               surface.patches(), surface.refined() ? " (refined once)" : "",
               (long long)surface.patches() * n * n, op.area(), a.fluid.fluid.c_str(), params.dt,
               params.strength, params.viscosity, params.dye_diffusion, backend.workers());
  std::fflush(ctx.out);
  StopSignals signals;
  int done = 0;
  long long cycles = 0;
  bool warned = false;          // a projection that stopped short of the tolerance is said once
  bool warned_viscous = false;  // and a viscosity solve at its sweep limit
  for (; done < steps && !StopSignals::requested(); ++done) {
    const FluidReport r = fluid.step();
    cycles += r.cycles;
    if (!warned_viscous && r.viscosity_sweeps >= params.viscous.max_sweeps) {
      warned_viscous = true;
      std::fprintf(ctx.err,
                   "ardcell surface: step %d: the viscosity's Jacobi sweeps stopped at their limit "
                   "(%d) above a relative residual of %g (a smaller --viscosity or --dt)\n",
                   done + 1, params.viscous.max_sweeps, params.viscous.tolerance);
    }
    if (!warned && !(r.residual <= params.projection.tolerance)) {
      warned = true;
      std::fprintf(ctx.err,
                   "ardcell surface: step %d: the projection stopped at relative residual %.3g, "
                   "above --tolerance %g (%d V-cycles)\n",
                   done + 1, r.residual, params.projection.tolerance, params.projection.max_sweeps);
    }
  }
  if (done < steps) {
    std::fprintf(ctx.err, "ardcell surface: interrupted after %d of %d steps; nothing written\n",
                 done, steps);
    return StopSignals::exit_code(kExitOk);
  }
  colours.lo = 0, colours.hi = 1;  // the dye's concentration, 0 to 100%
  if (Status written = write_outputs(a, surface, op.grid(), fluid.dye(), colours, view); !written) {
    std::fprintf(ctx.err, "ardcell surface: %s\n", written.message().c_str());
    return kExitFailure;
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const auto [lo, hi] = cell_range(op.grid(), fluid.dye());
  std::fprintf(ctx.out,
               "steps=%d mean_cycles=%.1f seconds=%.2f s=[%.4g, %.4g] total=%.4g max_div=%.3g "
               "out=%s%s%s%s%s\n",
               done, done ? double(cycles) / done : 0.0, seconds, lo, hi, fluid.dye_total(),
               fluid.max_divergence(), a.out.empty() ? "-" : a.out.c_str(),
               a.atlas.empty() ? "" : " atlas=", a.atlas.empty() ? "" : (a.atlas + ".obj").c_str(),
               a.render.empty() ? "" : " render=", a.render.c_str());
  std::fflush(ctx.out);
  return StopSignals::exit_code(kExitOk);
}

int do_surface(SurfaceArgs& a, CliContext& ctx) {
  auto usage = [&](const std::string& m) { return cli_usage_error(ctx, "surface", m); };
  const int n = a.patch_cells;
  if (std::string why = patch_cells_problem(n); !why.empty()) return usage(why);
  if (a.steps < 0) return usage("--steps " + std::to_string(a.steps) + ": expected 0 or more");
  if (a.workers < 0 || a.workers > 256)
    return usage("--workers " + std::to_string(a.workers) + ": expected 1..256 (0: one per core)");
  const bool fluid = a.fluid.fluid_opt->count() > 0;
  std::array<double, 3> down{0, 0, -1};
  if (fluid) {
    FluidForce force;
    if (Status s = parse_fluid_force(a.fluid.fluid, force); !s) return usage(s.message());
    for (CLI::Option* o : {a.preset_opt, a.f_opt, a.k_opt, a.reaction_opt, a.field_opt, a.scale_opt,
                           a.solver_opt, a.seed_opt})
      if (o->count())
        return usage(o->get_name() + ": a reaction-diffusion setting (expected no " +
                     o->get_name() + " with --fluid)");
    if (force == FluidForce::kWalk && a.down_opt->count())
      return usage("--down: a gravity setting (expected no --down with --fluid walk)");
    char tail = 0;
    // A direction: finite, not all 0 (its length is taken after scaling, never squared here).
    if (std::sscanf(a.down.c_str(), "%lf,%lf,%lf%c", &down[0], &down[1], &down[2], &tail) != 3 ||
        !std::isfinite(down[0]) || !std::isfinite(down[1]) || !std::isfinite(down[2]) ||
        (down[0] == 0 && down[1] == 0 && down[2] == 0))
      return usage("--down '" + a.down + "': expected X,Y,Z, a finite direction (not 0,0,0)");
  } else {
    for (CLI::Option* o : a.fluid_only)
      if (o->count()) return usage(fluid_setting_without_fluid(*o));
  }
  SurfaceRdParams params;
  PresetRd flat;
  const bool from_preset = !a.preset.empty();
  if (from_preset) {
    for (CLI::Option* o : {a.f_opt, a.k_opt})
      if (o->count())
        return usage(o->get_name() + ": the preset sets the reaction (expected no " +
                     o->get_name() + " with --preset)");
    if (Status s = preset_rd(a.preset, flat); !s) return usage(s.message());
    params.reaction = flat.reaction;
    if (!a.dt_opt->count()) a.dt = flat.dt;
    if (!a.field_opt->count()) a.field = "a";
  } else {
    params.reaction.F = float(a.F);
    params.reaction.k = float(a.k);
  }
  if (const char* problem = reaction_params_problem(params.reaction)) return usage(problem);
  if (a.reaction != "euler" && a.reaction != "implicit")
    return usage("--reaction '" + a.reaction + "': expected euler (the seed's) or implicit");
  if (a.solver != "jacobi" && a.solver != "mg")
    return usage("--solver '" + a.solver + "': expected jacobi (the seed's sweeps) or mg");
  // The seed's forward Euler by default; with a preset, Kim & Lin's implicit reaction (any model
  // at the preset's step).
  const bool implicit = a.reaction_opt->count() ? a.reaction == "implicit" : from_preset;
  params.scheme = implicit ? SurfaceReaction::kImplicit : SurfaceReaction::kForwardEuler;
  if (a.field != "a" && a.field != "b") return usage("--field '" + a.field + "': expected a or b");
  SurfaceColours colours;
  if (!parse_colormap(a.colormap, colours.colormap))
    return usage("--colormap '" + a.colormap + "': expected " + std::string(colormap_names()));
  if (a.out.empty() && a.atlas.empty() && a.render.empty())
    return usage("nothing to write: expected --out FILE.ply, --atlas PREFIX or --render FILE.png");
  SurfaceView view;
  {
    char tail = 0;
    if (std::sscanf(a.view.c_str(), "%lf,%lf%c", &view.azimuth_deg, &view.elevation_deg, &tail) !=
            2 ||
        !std::isfinite(view.azimuth_deg) || !(std::abs(view.elevation_deg) <= 90))
      return usage("--view '" + a.view +
                   "': expected AZIMUTH,ELEVATION in degrees, elevation in -90..90");
  }
  if (!a.render.empty())
    if (Status s = check_output_path(a.render, false); !s) return usage("--render " + s.message());
  if (!a.out.empty())
    if (Status s = check_output_path(a.out, false); !s) return usage("--out " + s.message());
  // --atlas PREFIX: PREFIX.obj, PREFIX.mtl and PREFIX.png side by side.
  const auto atlas_file = [&](const char* extension) {
    return std::filesystem::path(a.atlas + extension);
  };
  if (!a.atlas.empty())
    for (const char* extension : {".obj", ".mtl", ".png"})
      if (Status s = check_output_path(atlas_file(extension), false); !s)
        return usage("--atlas " + s.message());

  PolyMesh mesh;
  if (Status s = control_mesh(a, mesh); !s) return usage(s.message());
  LimitSurface surface;
  if (Status s = LimitSurface::build(std::move(mesh), {}, surface); !s)
    return usage(mesh_prefix(a) + s.message());
  const long long cells = (long long)surface.patches() * n * n;
  if (cells > kMaxCells)
    return usage(std::to_string(surface.patches()) + " patches of " + std::to_string(n) + "^2 " +
                 "cells are " + std::to_string(cells) + " cells (expected at most " +
                 std::to_string(kMaxCells) + ": a smaller --patch-cells)");
  if (fluid) return run_fluid(a, ctx, surface, down, colours, view);

  const auto start = std::chrono::steady_clock::now();
  Status geometry = Status::ok();
  SurfaceLaplacian op = [&] {  // the metric is needed only to build the operator
    const PatchMetric metric = sample_limit_metric(surface, n);
    geometry = metric.check_nondegenerate();
    return SurfaceLaplacian(surface.topology(), metric);
  }();
  if (!geometry) return usage(mesh_prefix(a) + geometry.message());
  // The patches run side by side on the threads back end (the same bits for any --workers).
  ThreadBackend backend(surface_threads(a.workers));
  RowExecutor executor(backend);
  op.set_executor(executor);
  // Pattern scale: the classic flat model's cell, 1/20 of a mean patch's side by default.
  const double side = std::sqrt(op.area() / op.patches());
  const double length = a.scale_opt->count() ? a.scale : side / 20;
  // A flat cell is `length` on the surface: rates in cells^2 per unit time scale by length^2.
  if (from_preset) {
    const SurfaceRdParams scaled = surface_rd_params(flat, length);
    params.diffusion_a = scaled.diffusion_a;
    params.diffusion_b = scaled.diffusion_b;
  } else {
    const SurfaceRdParams rates = gray_scott_for_length(length);
    params.diffusion_a = rates.diffusion_a;
    params.diffusion_b = rates.diffusion_b;
  }
  params.dt = a.dt;
  params.solve.tolerance = a.tolerance;
  std::fprintf(ctx.out,
               "patches=%d%s cells=%lld area=%.4g scale=%.4g r_a=%.4g r_b=%.4g model=%s%s%s dt=%g "
               "reaction=%s workers=%d\n",
               surface.patches(), surface.refined() ? " (refined once)" : "", cells, op.area(),
               length, params.diffusion_a, params.diffusion_b,
               std::string(reaction_model_name(params.reaction.model)).c_str(),
               from_preset ? " preset=" : "", from_preset ? flat.name.c_str() : "", a.dt,
               params.scheme == SurfaceReaction::kImplicit ? "implicit" : "euler",
               backend.workers());
  std::fflush(ctx.out);
  std::unique_ptr<SurfaceMultigrid> multigrid;
  if (a.solver == "mg") multigrid = std::make_unique<SurfaceMultigrid>(surface, op);
  SurfaceGrayScott rd(op, params, multigrid.get());
  if (from_preset) {
    SurfaceGrayScott::Start start = surface_start(flat, length, op.area());
    if (a.seed_opt->count()) start.seed = a.seed;
    rd.seed_pattern(cell_positions(surface, op.grid()), start);
  } else {
    rd.seed_spots(cell_positions(surface, op.grid()), a.seed, 3 * op.patches(), 0.2 * side);
  }

  StopSignals signals;
  int done = 0;
  int sweeps = 0, cycles = 0;
  bool warned = false;  // a solve that stopped short of the tolerance is said once
  for (; done < a.steps && !StopSignals::requested(); ++done) {
    const DiffusionReport r = rd.step();
    sweeps += r.sweeps;
    cycles += r.cycles;
    if (!warned && !(r.residual <= params.solve.tolerance)) {
      warned = true;
      std::fprintf(ctx.err,
                   "ardcell surface: step %d: the implicit diffusion stopped at relative residual "
                   "%.3g, above --tolerance %g%s\n",
                   done + 1, r.residual, params.solve.tolerance,
                   multigrid ? ""
                   : r.residual <= 1
                       ? " (Jacobi's sweep limit: a looser --tolerance or --solver mg)"
                       : " (Jacobi diverges when a step spreads over hundreds of "
                         "cells: --solver mg)");
    }
  }
  if (done < a.steps) {
    std::fprintf(ctx.err, "ardcell surface: interrupted after %d of %d steps; nothing written\n",
                 done, a.steps);
    return StopSignals::exit_code(kExitOk);
  }
  const PatchField& field = a.field == "a" ? rd.a() : rd.b();
  if (from_preset) {
    // The model's working range (kernels/reaction.h typical_range).
    const ConcentrationBox range = typical_range(params.reaction);
    colours.lo = a.field == "a" ? range.a_lo : range.b_lo;
    colours.hi = a.field == "a" ? range.a_hi : range.b_hi;
  } else {
    // b lives in [0, ~0.45] in Gray-Scott's patterns, a in [~0.2, 1].
    colours.lo = a.field == "a" ? 0.2 : 0.0;
    colours.hi = a.field == "a" ? 1.0 : 0.45;
  }
  const Status written = write_outputs(a, surface, op.grid(), field, colours, view);
  if (!written) {
    std::fprintf(ctx.err, "ardcell surface: %s\n", written.message().c_str());
    return kExitFailure;
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  // The cells' range of each chemical: whether a pattern grew (and what the colours span).
  const auto [a_lo, a_hi] = cell_range(op.grid(), rd.a());
  const auto [b_lo, b_hi] = cell_range(op.grid(), rd.b());
  char mean_cycles[48] = "";  // multigrid's V-cycles a solve
  if (multigrid)
    std::snprintf(mean_cycles, sizeof mean_cycles, " mean_cycles=%.1f",
                  done ? double(cycles) / done : 0.0);
  std::fprintf(ctx.out,
               "steps=%d mean_sweeps=%.1f%s seconds=%.2f a=[%.4g, %.4g] b=[%.4g, %.4g] "
               "out=%s%s%s%s%s\n",
               done, done ? double(sweeps) / done : 0.0, mean_cycles, seconds, a_lo, a_hi, b_lo,
               b_hi, a.out.empty() ? "-" : a.out.c_str(),
               a.atlas.empty() ? "" : " atlas=", a.atlas.empty() ? "" : (a.atlas + ".obj").c_str(),
               a.render.empty() ? "" : " render=", a.render.c_str());
  std::fflush(ctx.out);
  return StopSignals::exit_code(kExitOk);
}

#endif  // ARDCELL_WITH_OPENSUBDIV

}  // namespace

void add_surface_command(CLI::App& app, CliContext& ctx) {
  CLI::App* cmd = app.add_subcommand(
      "surface",
      "Gray-Scott on the Catmull-Clark limit surface of a mesh (OBJ, OFF or built in), written as "
      "a "
      "PLY with the field as vertex colours or as a texture atlas with a UV-mapped OBJ");
#if ARDCELL_WITH_OPENSUBDIV
  auto args = std::make_shared<SurfaceArgs>();
  SurfaceArgs& a = *args;
  a.mesh_opt =
      cmd->add_option("--mesh", a.mesh,
                      "control mesh, a Wavefront OBJ or OFF file (quads, or mixed: refined once)");
  a.shape_opt = cmd->add_option(
      "--shape", a.shape,
      "built-in mesh when no --mesh: torus (32 patches, default), cube-sphere (24), genus2 (a "
      "double torus, 50), or from Debian's libcgal-demo eight (a genus-2 figure eight, 1902) or "
      "elephant (genus 3, 16674: --patch-cells 8 at most; ARDCELL_MESH_DIR overrides the folder "
      "they are read from)");
  a.mesh_opt->excludes(a.shape_opt);
  cmd->add_option("--patch-cells", a.patch_cells, "N: N x N cells a patch, a power of two (16)");
  a.steps_opt = cmd->add_option("--steps", a.steps, "steps of dt (3000; with --fluid 200)");
  cmd->add_option("--workers", a.workers,
                  "threads that run the patches side by side, 0: one per core (0; the same "
                  "result for any number)");
  cmd->add_option("--out", a.out, "the PLY to write (vertex colours)");
  cmd->add_option("--atlas", a.atlas,
                  "also (or instead) PREFIX.obj, .mtl and .png: the limit surface UV-mapped onto "
                  "a texture atlas of the field (Blender, MeshLab)");
  cmd->add_option("--render", a.render,
                  "also a PNG of the surface from a fixed camera (800 x 600)");
  cmd->add_option("--view", a.view,
                  "the render's camera direction AZIMUTH,ELEVATION in degrees (35,25)");
  a.reaction_opt =
      cmd->add_option("--reaction", a.reaction,
                      "euler (the seed's forward Euler) or implicit (ardcell's backward Euler; "
                      "the default with --preset)");
  a.preset_opt = cmd->add_option(
      "--preset", a.preset,
      "a scene or preset's reaction-diffusion on the surface (its model, parameters, "
      "rates, step and start; e.g. turing-spots, meinhardt-spots)");
  a.f_opt = cmd->add_option("--F", a.F, "Gray-Scott feed (0.055)")->check(finite_range(0, 1));
  a.k_opt = cmd->add_option("--k", a.k, "Gray-Scott kill (0.062)")->check(finite_range(0, 1));
  a.dt_opt =
      cmd->add_option("--dt", a.dt, "time step (1; with --preset the preset's; with --fluid 0.05)")
          ->check(finite_range(1e-6, 100));
  a.scale_opt = cmd->add_option("--scale", a.scale,
                                "the flat model's cell in surface units: sets the wavelength "
                                "(default: a patch's side / 20)")
                    ->check(finite_range(1e-9, 1e9));
  cmd->add_option("--tolerance", a.tolerance,
                  "implicit diffusion's (with --fluid the projection's) relative residual (1e-6)")
      ->check(finite_range(1e-14, 1));
  a.solver_opt =
      cmd->add_option("--solver", a.solver,
                      "implicit diffusion: jacobi (the seed's sweeps) or mg (multigrid V-cycles)");
  a.seed_opt = cmd->add_option("--seed", a.seed, "random start (1; with --preset the preset's)");
  a.field_opt = cmd->add_option("--field", a.field, "a or b (b; with --preset a)");
  cmd->add_option("--colormap", a.colormap, std::string(colormap_names()) + " (magma)");
  add_surface_fluid_flags(
      *cmd, a.fluid,
      "stable fluids instead of reaction-diffusion: gravity (dye sinks along --down) or walk "
      "(a point circling each patch pushes the fluid); the field drawn is the dye, from sources "
      "at the patches' centres");
  a.fluid_only = {
      cmd->add_option("--viscosity", a.viscosity,
                      "--fluid: kinematic viscosity, surface area per unit time (0)")
          ->check(finite_range(0, 1e6)),
      cmd->add_option("--dye-diffusion", a.dye_diffusion,
                      "--fluid: the dye's diffusion, surface area per unit time (0)")
          ->check(finite_range(0, 1e6)),
      a.fluid.force_opt,
      a.down_opt = cmd->add_option(
          "--down", a.down,
          "--fluid gravity: the downward direction X,Y,Z in the mesh's coordinates (0,0,-1)"),
      cmd->add_option("--source-rate", a.source_rate,
                      "--fluid: dye added per unit time at the sources, up to 1 (1)")
          ->check(finite_range(0, 1e6)),
      a.fluid.conserve_dye_opt};
  cmd->callback([args, &ctx] {
    try {
      ctx.exit_code = do_surface(*args, ctx);
    } catch (const std::bad_alloc&) {
      ctx.exit_code =
          cli_usage_error(ctx, "surface", "out of memory (expected a smaller --patch-cells)");
    }
  });
#else
  cmd->allow_extras();
  cmd->callback([&ctx] {
    ctx.exit_code = cli_usage_error(
        ctx, "surface", "this ardcell was built without OpenSubdiv (-DARDCELL_WITH_OPENSUBDIV=ON)");
  });
#endif
}

}  // namespace ardcell
