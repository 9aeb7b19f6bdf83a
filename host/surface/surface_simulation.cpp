#include "host/surface/surface_simulation.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include "host/paint/paint.h"
#include "host/surface/patch_metric.h"
#include "kernels/reaction.h"

namespace ardcell {
namespace {

// A live surface keeps to what a frame can step: about a million cells.
constexpr long long kMaxLiveCells = 1LL << 20;

// Squared distance from cell c's point to `point`.
double distance2(const std::array<PatchField, 3>& positions, std::size_t c, const double* point) {
  const double dx = positions[0][c] - point[0], dy = positions[1][c] - point[1],
               dz = positions[2][c] - point[2];
  return dx * dx + dy * dy + dz * dz;
}

}  // namespace

Status build_live_surface(PolyMesh mesh, int patch_cells, LimitSurface& out) {
  const int n = patch_cells;
  if (std::string why = patch_cells_problem(n); !why.empty()) return Status::error(why);
  if (Status s = LimitSurface::build(std::move(mesh), {}, out); !s) return s;
  const long long cells = (long long)out.patches() * n * n;
  if (cells > kMaxLiveCells)
    return Status::error(std::to_string(out.patches()) + " patches of " + std::to_string(n) +
                         "^2 cells are " + std::to_string(cells) + " cells (expected at most " +
                         std::to_string(kMaxLiveCells) + " live: a smaller --patch-cells)");
  return sample_limit_metric(out, n).check_nondegenerate();
}

SurfaceSimulation::SurfaceSimulation(const Preset& preset,
                                     std::shared_ptr<const LimitSurface> surface,
                                     const SurfaceLiveOptions& options)
    : surface_(std::move(surface)), fluid_options_(options.fluid) {
  const bool fluid = options.fluid.force != FluidForce::kNone;
  if (Status s = fluid ? preset_fluid(preset) : preset_rd(preset, flat_); !s)
    throw std::invalid_argument(s.message());
  const int n = options.patch_cells;
  if (std::string why = patch_cells_problem(n); !why.empty()) throw std::invalid_argument(why);
  const LimitSurface& surface_ref = *surface_;
  auto metric = std::make_unique<PatchMetric>(sample_limit_metric(surface_ref, n));
  op_ = std::make_unique<SurfaceLaplacian>(surface_ref.topology(), *metric);
  ThreadBackendOptions threads;
  threads.workers = options.workers;
  threads.pin = false;  // beside the display's thread
  backend_ = std::make_unique<ThreadBackend>(threads);
  executor_ = std::make_unique<RowExecutor>(*backend_);
  op_->set_executor(*executor_);
  multigrid_ = std::make_unique<SurfaceMultigrid>(surface_ref, *op_);
  if (fluid) {
    SurfaceFluidParams params;
    params.dt = options.fluid.dt;
    params.force = options.fluid.force;
    params.strength = options.fluid.strength;
    params.source_rate = 0;  // the dye is what the brush paints
    params.projection.tolerance = options.fluid.tolerance;
    apply_preset_fluid(preset.scene, options.fluid.conserve_dye, params);
    // The constructor runs the viscosity's and the dye diffusion's solves when their rates are
    // above 0, which sizes their scratch: a live change from 0 to more must not allocate then.
    SurfaceFluidParams sizing = params;
    sizing.viscosity = std::max(params.viscosity, 1e-6);
    sizing.dye_diffusion = std::max(params.dye_diffusion, 1e-6);
    fluid_ = std::make_unique<SurfaceFluid>(surface_ref, *metric, *op_, *multigrid_, sizing);
    fluid_->set_params(params);
  } else {
    // The pattern's scale: a flat cell is 1/20 of a mean patch's side (as `ardcell surface`).
    length_ = std::sqrt(op_->area() / op_->patches()) / 20;
    rd_ = std::make_unique<SurfaceGrayScott>(*op_, surface_rd_params(flat_, length_),
                                             multigrid_.get());
  }
  metric.reset();  // only the construction reads it
  positions_ = cell_positions(surface_ref, op_->grid());
  renderer_ = std::make_unique<SurfaceRenderer>(surface_ref, op_->grid());
  renderer_->set_executor(*executor_);  // the frame's pixels on the patches' workers
  // The brush's scale: the bounding sphere the view fits (its diameter).
  diameter_ = 2 * renderer_->radius();
  // Each patch's bounding sphere, so that a dab tests the cells of the patches it reaches only.
  const PatchGrid& g = op_->grid();
  patch_spheres_.assign(std::size_t(g.patches()), {});
  for (int p = 0; p < g.patches(); ++p) {
    std::array<double, 4>& sphere = patch_spheres_[std::size_t(p)];
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        for (int k = 0; k < 3; ++k) sphere[std::size_t(k)] += positions_[k][g.index(p, i, j)];
    for (int k = 0; k < 3; ++k) sphere[std::size_t(k)] /= double(n) * n;
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        sphere[3] = std::max(sphere[3], distance2(positions_, g.index(p, i, j), sphere.data()));
    sphere[3] = std::sqrt(sphere[3]);  // the brush compares cell centres only
  }
  view_.width = options.view.x;
  view_.height = options.view.y;
  session_view_ = options.session_view;
  view_.azimuth_deg = session_view_ ? session_view_->azimuth_deg.load() : options.azimuth_deg;
  view_.elevation_deg = session_view_ ? session_view_->elevation_deg.load() : options.elevation_deg;
  view_.fit = SurfaceFit::kSphere;
  set_colours(preset.scene.output);
  state_.size = options.view;
  char name[64];
  std::snprintf(name, sizeof name, "threads x%d, %d patches of %d^2%s", backend_->workers(),
                surface_ref.patches(), n,
                !fluid                                        ? ""
                : options.fluid.force == FluidForce::kGravity ? ", fluid gravity"
                                                              : ", fluid walk");
  backend_name_ = name;
  reset();
}

SurfaceSimulation::~SurfaceSimulation() = default;

void SurfaceSimulation::reset() {
  if (fluid_) {
    fluid_->clear();
    if (fluid_options_.start_dye) fluid_->fill_sources(1.0);
  } else
    rd_->seed_pattern(positions_, surface_start(flat_, length_, op_->area()));
  strokes_.fill({});
}

std::array<double, 3> SurfaceSimulation::screen_down(const SurfaceView& view) {
  const CameraAxes axes = camera_axes(view);
  return {-axes.up[0], -axes.up[1], -axes.up[2]};
}

void SurfaceSimulation::step() {
  if (!fluid_) {
    for (int k = 0; k < flat_.steps_per_frame; ++k) rd_->step();
    return;
  }
  // The seed's viewer-relative gravity: down follows the view as the user turns it.
  if (fluid_options_.force == FluidForce::kGravity &&
      (view_.azimuth_deg != down_azimuth_ || view_.elevation_deg != down_elevation_)) {
    fluid_->set_down(screen_down(view_));
    down_azimuth_ = view_.azimuth_deg;
    down_elevation_ = view_.elevation_deg;
  }
  for (int k = 0; k < fluid_options_.steps_per_frame; ++k) fluid_->step();
}

void SurfaceSimulation::set_colours(const OutputConfig& output) {
  show_a_ = output.show != "B";
  Colormap map;
  if (parse_colormap(output.colormap, map)) colours_.colormap = map;
  if (fluid_) {  // the dye's concentration, 0 to 100%
    colours_.lo = 0, colours_.hi = 1;
    return;
  }
  const ConcentrationBox range = typical_range(flat_.reaction);
  colours_.lo = show_a_ ? range.a_lo : range.b_lo;
  colours_.hi = show_a_ ? range.a_hi : range.b_hi;
}

void SurfaceSimulation::apply(const SceneConfig& config) {
  if (fluid_) {
    SurfaceFluidParams params = fluid_->params();
    apply_preset_fluid(config, fluid_options_.conserve_dye, params);
    fluid_->set_params(params);
    set_colours(config.output);
    return;
  }
  // A value out of range was refused with its line by the loop; keep the running ones then.
  if (!update_preset_rd(config, flat_)) return;
  SurfaceRdParams params = surface_rd_params(flat_, length_);
  params.solve = rd_->params().solve;
  rd_->set_params(params);
  set_colours(config.output);
}

long SurfaceSimulation::cell_at(float x, float y) const {
  if (!(x >= 0 && x < 1 && y >= 0 && y < 1)) return -1;
  return renderer_->cell_at(int(x * float(view_.width)), int(y * float(view_.height)));
}

template <typename Write>
void SurfaceSimulation::for_brush(long cell, double radius, Write&& write) {
  const PatchGrid& g = op_->grid();
  const int n = g.n();
  const double centre[3] = {positions_[0][std::size_t(cell)], positions_[1][std::size_t(cell)],
                            positions_[2][std::size_t(cell)]};
  const double r2 = radius * radius;
  for (int p = 0; p < g.patches(); ++p) {
    const std::array<double, 4>& sphere = patch_spheres_[std::size_t(p)];
    const double dx = sphere[0] - centre[0], dy = sphere[1] - centre[1], dz = sphere[2] - centre[2];
    const double reach = radius + sphere[3];
    if (dx * dx + dy * dy + dz * dz > reach * reach) continue;
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const std::size_t c = g.index(p, i, j);
        const double d2 = distance2(positions_, c, centre);
        if (d2 > r2) continue;
        write(c, brush_falloff(std::sqrt(d2), radius), p, i, j);
      }
  }
}

void SurfaceSimulation::deposit(long cell, float k_base, double radius, double dye) {
  if (fluid_) {
    PatchField& s = fluid_->dye();
    for_brush(cell, radius, [&](std::size_t c, double falloff, int, int, int) {
      s[c] += k_base * falloff * (dye - s[c]);
    });
    return;
  }
  PatchField& a = rd_->a();
  PatchField& b = rd_->b();
  const double da = flat_.start.seed_a, db = flat_.start.seed_b;
  for_brush(cell, radius, [&](std::size_t c, double falloff, int, int, int) {
    const double k = k_base * falloff;
    a[c] += k * (da - a[c]);
    b[c] += k * (db - b[c]);
  });
}

void SurfaceSimulation::push(long cell, float k_base, double radius,
                             const std::array<double, 3>& velocity) {
  SurfaceFluid& f = *fluid_;
  const int n = f.n();
  // Each cell blends the faces on its low sides, so that a face inside a patch is blended once,
  // and a cell on a patch's high edge its high face too: a patch edge's faces are stored by both
  // patches, low or high on either side, and stitching averages the two copies, so each must be
  // blended by its own patch's cell (else a seam gets half the push, or none where two high
  // edges meet).
  const auto blend = [](double& u, double target, double k) { u += k * (target - u); };
  for_brush(cell, radius, [&](std::size_t, double falloff, int p, int i, int j) {
    const double k = k_base * falloff;
    blend(f.u1(p, i, j), f.tangential_u1(p, i, j, velocity), k);
    blend(f.u2(p, i, j), f.tangential_u2(p, i, j, velocity), k);
    if (i == n - 1) blend(f.u1(p, n, j), f.tangential_u1(p, n, j, velocity), k);
    if (j == n - 1) blend(f.u2(p, i, n), f.tangential_u2(p, i, n, velocity), k);
  });
}

void SurfaceSimulation::follow_session_view() {
  if (!session_view_) return;
  view_.azimuth_deg = session_view_->azimuth_deg.load(std::memory_order_relaxed);
  view_.elevation_deg = session_view_->elevation_deg.load(std::memory_order_relaxed);
}

void SurfaceSimulation::paint(std::span<const StrokeSample> samples, const InputMapping& input,
                              int source) {
  follow_session_view();
  if (source < 0 || source >= kMaxInputSources) return;
  const double radius = std::max(1e-12, input.brush_radius * diameter_);
  // Dabs along a stroke half the brush's radius apart on the screen (the sphere fit draws the
  // diameter over 90% of the smaller side, so the brush's radius is 0.9 min(w, h) brush_radius
  // pixels), so a fast stroke paints a line, not dots; at most kMaxDabs a segment. A dab whose
  // picked cell is the last one painted is skipped (but a sample's own dab), so a slow stroke
  // blends each cell about once, as the flat painter does.
  constexpr int kMaxDabs = 64;
  const double brush_px = 0.9 * std::min(view_.width, view_.height) * input.brush_radius;
  const double spacing_px = std::max(1.0, 0.5 * brush_px);
  Stroke& stroke = strokes_[std::size_t(source)];
  // The fluid: push mode blends the velocity under the brush towards the stroke's direction at
  // a quarter of the bounding sphere's diameter per unit time, erase blends the dye towards 0,
  // every other mode paints dye (the RD: every mode deposits).
  const bool pushing = fluid_ && input.mode == "push";
  const bool erasing = fluid_ && input.mode == "erase";
  const double push_speed = 0.25 * diameter_;
  bool pushed = false;
  for (const StrokeSample& s : samples) {
    if (!s.touching() || !s.in_range || !std::isfinite(s.x) || !std::isfinite(s.y) ||
        !std::isfinite(s.pressure)) {
      stroke.mode = Stroke::kNone;
      continue;
    }
    if (s.eraser || (s.buttons & kButtonBarrel) != 0) {
      if (stroke.mode == Stroke::kTurning) {
        view_.azimuth_deg = std::fmod(view_.azimuth_deg - 360.0 * (s.x - stroke.x), 360.0);
        view_.elevation_deg =
            std::clamp(view_.elevation_deg + 180.0 * (s.y - stroke.y), -89.0, 89.0);
        if (session_view_) {
          session_view_->azimuth_deg = view_.azimuth_deg;
          session_view_->elevation_deg = view_.elevation_deg;
        }
      }
      stroke = {Stroke::kTurning, s.x, s.y};
      continue;
    }
    const double pressure = std::pow(std::clamp(double(s.pressure), 0.0, 1.0),
                                     input.pressure_gamma > 0 ? input.pressure_gamma : 1.0);
    const float k = float(std::clamp(input.strength * pressure, 0.0, 1.0));
    // From the previous sample of the stroke (painted already) to this one.
    int dabs = 1;
    long last = -1;
    std::array<double, 3> velocity{};  // push: along the segment, on the screen
    bool moved = false;
    if (stroke.mode == Stroke::kPainting) {
      const double px = (double(s.x) - stroke.x) * view_.width,
                   py = (double(s.y) - stroke.y) * view_.height;
      const double length = std::hypot(px, py);
      const double n = std::ceil(length / spacing_px);  // may be huge (OSC)
      dabs = n >= kMaxDabs ? kMaxDabs : std::max(1, int(n));
      last = stroke.cell;
      if (pushing && length > 0 && std::isfinite(length)) {
        const CameraAxes axes = camera_axes(view_);
        for (std::size_t a = 0; a < 3; ++a)
          velocity[a] = push_speed * (px * axes.right[a] - py * axes.up[a]) / length;
        moved = true;
      }
    }
    for (int d = 1; d <= dabs; ++d) {
      const float t = float(d) / float(dabs);
      const bool end = d == dabs;
      const float x = end ? s.x : stroke.x + t * (s.x - stroke.x);
      const float y = end ? s.y : stroke.y + t * (s.y - stroke.y);
      const long cell = cell_at(x, y);
      if (cell < 0 || (cell == last && !end)) continue;
      if (!pushing) {
        deposit(cell, k, radius, erasing ? 0 : 1);
      } else if (moved) {
        push(cell, k, radius, velocity);  // writes at least the picked cell's faces
        pushed = true;
      }
      last = cell;
    }
    stroke = {Stroke::kPainting, s.x, s.y, last};
  }
  // The two copies of a patch edge's faces back to one flux, only after a push wrote faces (a
  // hover or a turn writes none, and a stitch walks every shared edge).
  if (pushed) fluid_->stitch_velocity();
}

void SurfaceSimulation::render(ImageRgb8& out) {
  follow_session_view();
  renderer_->render(shown(), colours_, view_, out);
}

SimulationFactory surface_simulations(std::shared_ptr<const LimitSurface> surface,
                                      const SurfaceLiveOptions& options) {
  SurfaceLiveOptions session = options;
  if (!session.session_view) {
    session.session_view = std::make_shared<SessionView>();
    session.session_view->azimuth_deg = options.azimuth_deg;
    session.session_view->elevation_deg = options.elevation_deg;
  }
  return [surface, session](const Preset& preset) -> std::unique_ptr<LiveSimulation> {
    return std::make_unique<SurfaceSimulation>(preset, surface, session);
  };
}

Status runs_on_surfaces(const Preset& preset, bool fluid) {
  if (fluid) return preset_fluid(preset);
  PresetRd unused;
  return preset_rd(preset, unused);
}

}  // namespace ardcell
