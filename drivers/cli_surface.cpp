// `ardcell surface`: Gray-Scott reaction-diffusion on the Catmull-Clark limit surface of a
// control mesh (seed 004, docs/surfaces.md), written as a PLY of the limit surface with the
// field as vertex colours (--out), as a texture atlas with a UV-mapped OBJ (--atlas) and/or as a
// PNG render (--render).
//
// A subcommand of its own, not a scene of `ardcell run`: the patches do not run on the engine
// yet (no Device ops, back ends, frames or state files, which run's flags are about); once
// patches are blocks of the frame plan it becomes `ardcell run surface-gray-scott`.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include "drivers/cli.h"

#if ARDCELL_WITH_OPENSUBDIV
#include "drivers/png_writer.h"
#include "host/io/atomic_file.h"
#include "host/io/surface_atlas.h"
#include "host/io/surface_ply.h"
#include "host/surface/limit_surface.h"
#include "host/surface/patch_metric.h"
#include "host/surface/procedural_mesh.h"
#include "host/surface/surface_gray_scott.h"
#include "host/surface/surface_render.h"
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
  CLI::Option *mesh_opt, *shape_opt, *scale_opt;
};

Status control_mesh(const SurfaceArgs& a, PolyMesh& mesh) {
  if (a.mesh_opt->count()) return read_obj(a.mesh, {}, mesh);
  if (a.shape == "torus")
    mesh = torus_mesh(8, 4, 2.0, 0.8);
  else if (a.shape == "cube-sphere")
    mesh = cube_mesh(2);
  else if (a.shape == "genus2")
    mesh = genus2_mesh(1.0);
  else
    return Status::error("--shape '" + a.shape + "': expected torus, cube-sphere or genus2");
  return Status::ok();
}

int do_surface(SurfaceArgs& a, CliContext& ctx) {
  auto usage = [&](const std::string& m) { return cli_usage_error(ctx, "surface", m); };
  const int n = a.patch_cells;
  if (n < 2 || n > 1024 || (n & (n - 1)) != 0)
    return usage("--patch-cells " + std::to_string(n) + ": expected a power of two in 2..1024");
  if (a.steps < 0) return usage("--steps " + std::to_string(a.steps) + ": expected 0 or more");
  if (a.workers < 0 || a.workers > 256)
    return usage("--workers " + std::to_string(a.workers) + ": expected 1..256 (0: one per core)");
  SurfaceRdParams params;
  params.reaction.F = float(a.F);
  params.reaction.k = float(a.k);
  if (const char* problem = reaction_params_problem(params.reaction)) return usage(problem);
  if (a.reaction == "implicit")
    params.scheme = SurfaceReaction::kImplicit;
  else if (a.reaction != "euler")
    return usage("--reaction '" + a.reaction + "': expected euler (the seed's) or implicit");
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
    return usage((a.mesh_opt->count() ? a.mesh + ": " : std::string()) + s.message());
  const long long cells = (long long)surface.patches() * n * n;
  if (cells > kMaxCells)
    return usage(std::to_string(surface.patches()) + " patches of " + std::to_string(n) + "^2 " +
                 "cells are " + std::to_string(cells) + " cells (expected at most " +
                 std::to_string(kMaxCells) + ": a smaller --patch-cells)");

  const auto start = std::chrono::steady_clock::now();
  Status geometry = Status::ok();
  SurfaceLaplacian op = [&] {  // the metric is needed only to build the operator
    const PatchMetric metric = sample_limit_metric(surface, n);
    geometry = metric.check_nondegenerate();
    return SurfaceLaplacian(surface.topology(), metric);
  }();
  if (!geometry)
    return usage((a.mesh_opt->count() ? a.mesh + ": " : std::string()) + geometry.message());
  // The patches run side by side on the threads back end (the same bits for any --workers).
  ThreadBackendOptions threads;
  threads.workers = a.workers;
  threads.pin = false;  // a short command beside whatever else runs
  ThreadBackend backend(threads);
  RowExecutor executor(backend);
  op.set_executor(executor);
  // Pattern scale: the classic flat model's cell, 1/20 of a mean patch's side by default.
  const double side = std::sqrt(op.area() / op.patches());
  const double length = a.scale_opt->count() ? a.scale : side / 20;
  const SurfaceRdParams rates = gray_scott_for_length(length);
  params.diffusion_a = rates.diffusion_a;
  params.diffusion_b = rates.diffusion_b;
  params.dt = a.dt;
  params.solve.tolerance = a.tolerance;
  std::fprintf(ctx.out,
               "patches=%d%s cells=%lld area=%.4g scale=%.4g r_a=%.4g r_b=%.4g F=%g k=%g dt=%g "
               "reaction=%s workers=%d\n",
               surface.patches(), surface.refined() ? " (refined once)" : "", cells, op.area(),
               length, params.diffusion_a, params.diffusion_b, a.F, a.k, a.dt, a.reaction.c_str(),
               backend.workers());
  std::fflush(ctx.out);
  SurfaceGrayScott rd(op, params);
  rd.seed_spots(cell_positions(surface, op.grid()), a.seed, 3 * op.patches(), 0.2 * side);

  StopSignals signals;
  int done = 0;
  int sweeps = 0;
  for (; done < a.steps && !StopSignals::requested(); ++done) sweeps += rd.step().sweeps;
  if (done < a.steps) {
    std::fprintf(ctx.err, "ardcell surface: interrupted after %d of %d steps; nothing written\n",
                 done, a.steps);
    return StopSignals::exit_code(kExitOk);
  }
  const PatchField& field = a.field == "a" ? rd.a() : rd.b();
  // b lives in [0, ~0.45] in Gray-Scott's patterns, a in [~0.2, 1].
  colours.lo = a.field == "a" ? 0.2 : 0.0;
  colours.hi = a.field == "a" ? 1.0 : 0.45;
  Status written = Status::ok();
  if (!a.out.empty()) written = write_surface_ply(a.out, surface, op.grid(), field, colours);
  if (written && !a.atlas.empty()) {
    const AtlasLayout layout = atlas_layout(surface.patches(), n);
    written = write_png(atlas_file(".png"), surface_atlas_image(op.grid(), field, layout, colours));
    if (written)
      written = write_surface_obj(atlas_file(".obj"), atlas_file(".mtl"),
                                  atlas_file(".png").filename().string(), surface, layout);
  }
  if (written && !a.render.empty())
    written = write_png(a.render, render_surface(surface, op.grid(), field, colours, view));
  if (!written) {
    std::fprintf(ctx.err, "ardcell surface: %s\n", written.message().c_str());
    return kExitFailure;
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::fprintf(ctx.out, "steps=%d mean_sweeps=%.1f seconds=%.2f out=%s%s%s%s%s\n", done,
               done ? double(sweeps) / done : 0.0, seconds, a.out.empty() ? "-" : a.out.c_str(),
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
      "Gray-Scott on the Catmull-Clark limit surface of a mesh (OBJ or built in), written as a "
      "PLY with the field as vertex colours or as a texture atlas with a UV-mapped OBJ");
#if ARDCELL_WITH_OPENSUBDIV
  auto args = std::make_shared<SurfaceArgs>();
  SurfaceArgs& a = *args;
  a.mesh_opt = cmd->add_option("--mesh", a.mesh,
                               "control mesh, a Wavefront OBJ (quads, or mixed: refined once)");
  a.shape_opt = cmd->add_option("--shape", a.shape,
                                "built-in mesh when no --mesh: torus (32 patches, default), "
                                "cube-sphere (24) or genus2 (a double torus, 50)");
  a.mesh_opt->excludes(a.shape_opt);
  cmd->add_option("--patch-cells", a.patch_cells, "N: N x N cells a patch, a power of two (16)");
  cmd->add_option("--steps", a.steps, "steps of dt (3000)");
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
  cmd->add_option("--reaction", a.reaction,
                  "euler (the seed's forward Euler) or implicit (ardcell's backward Euler)");
  cmd->add_option("--F", a.F, "Gray-Scott feed (0.055)")->check(finite_range(0, 1));
  cmd->add_option("--k", a.k, "Gray-Scott kill (0.062)")->check(finite_range(0, 1));
  cmd->add_option("--dt", a.dt, "time step (1)")->check(finite_range(1e-6, 100));
  a.scale_opt = cmd->add_option("--scale", a.scale,
                                "the flat model's cell in surface units: sets the wavelength "
                                "(default: a patch's side / 20)")
                    ->check(finite_range(1e-9, 1e9));
  cmd->add_option("--tolerance", a.tolerance, "implicit diffusion's relative residual (1e-6)")
      ->check(finite_range(1e-14, 1));
  cmd->add_option("--seed", a.seed, "random start (1)");
  cmd->add_option("--field", a.field, "a or b (b)");
  cmd->add_option("--colormap", a.colormap, std::string(colormap_names()) + " (magma)");
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
