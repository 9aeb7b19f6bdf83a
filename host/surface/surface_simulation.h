#pragma once
// A flat preset's reaction-diffusion, or stable fluids carrying a dye, on a Catmull-Clark limit
// surface as a LiveSimulation: what `ardcell live PRESET --shape torus` (or --mesh FILE) runs,
// and with --fluid gravity|walk (seed 004; the surface RD of host/surface/surface_gray_scott.h,
// the preset carried over by host/surface/surface_scene.h; the fluid of
// host/surface/surface_fluid.h). One class for both: the surface, the 3D view, picking, the
// brush's geometry and turning the view are the same; what a step advances and what the brush
// writes differ. It draws itself: a 3D view of the surface (host/surface/surface_render.h, the
// field's colours shaded, its scale fixed by the bounding sphere so the view turns without
// zooming). Input, from any stroke source (mouse, pen, touch, OSC, the attract mode's
// recordings):
//   - the tip (left button, a touch) paints: the stroke's point is picked on the 3D view (the
//     cell drawn under it in the last frame) and every cell within the brush of that point
//     (straight-line distance on the surface) is blended towards the preset's seed values (the
//     fluid: the dye towards 1), as the flat painter's deposit mode does (brush_falloff; radius
//     input.brush_radius times the bounding sphere's diameter, strength input.strength times the
//     pressure); between two samples of a stroke, dabs half the brush's radius apart on the
//     screen fill the segment (the fluid: input.mode push blends the velocity under the brush
//     towards the segment's direction instead, erase the dye towards 0);
//   - the eraser (right button) or a barrel switch turns the view: a drag across the whole
//     canvas turns it 360 degrees around the vertical axis, a drag from top to bottom 180
//     degrees in elevation (clamped to +-89).
// A step runs the preset's rd.steps_per_frame surface steps on the threads back end (the
// patches side by side; the same bits for any number of workers). Live changes (apply) take the
// reaction's parameters, the rates, the step, the steps a frame, the start's values (for reset
// and the brush) and the output's field and colormap; the solver is the surface's own (multigrid
// to the tolerance: the loop's adaptive quality does not apply), and a painting mode other than
// deposit paints as deposit.
// The fluid (SurfaceLiveOptions::fluid): a step runs fluid.steps_per_frame fluid steps of
// fluid.dt; the preset gives fluid.viscosity, fluid.dye_diffusion and fluid.conserve_dye
// (apply_preset_fluid, live too) and the colormap (over the dye's [0, 1]); its RD, flat fluid
// scene (lid, obstacle, inflow, emitters), solvers and steps are not used. Gravity's "down" is
// the screen's downward direction in the mesh's coordinates (the seed's viewer-relative
// gravity), taken from the view at each step; reset stops the fluid and brings back the start's
// spots of dye (fluid.start_dye; none when it is off).
// Nothing allocates in step(), paint(), apply() or render() once the first frame is drawn.
#include <array>
#include <atomic>
#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "host/io/surface_ply.h"
#include "host/live/live_loop.h"
#include "host/surface/limit_surface.h"
#include "host/surface/poly_mesh.h"
#include "host/surface/surface_fluid.h"
#include "host/surface/surface_gray_scott.h"
#include "host/surface/surface_laplacian.h"
#include "host/surface/surface_multigrid.h"
#include "host/surface/surface_render.h"
#include "host/surface/surface_scene.h"
#include "runtime/check.h"
#include "runtime/row_executor.h"
#include "runtime/thread/thread_backend.h"

namespace ardcell {

// The view's angles shared by the simulations of one session (surface_simulations), so that a
// preset switched in starts where the user left the view. The live loop builds the next
// simulation on its worker thread while the running one turns the view on the main thread:
// hence atomics.
struct SessionView {
  std::atomic<double> azimuth_deg, elevation_deg;
};

struct SurfaceLiveOptions {
  int patch_cells = 16;                         // N x N cells a patch, a power of two
  int workers = 0;                              // threads the patches run on (0: one per core)
  Int2 view{800, 600};                          // the image drawn, in pixels
  double azimuth_deg = 35, elevation_deg = 25;  // unless session_view holds the session's
  std::shared_ptr<SessionView> session_view;    // null: the view is the simulation's own
  // Stable fluids instead of the preset's RD (`ardcell live --fluid`).
  struct Fluid {
    FluidForce force = FluidForce::kNone;  // kNone: the preset's RD
    double strength = 1;                   // --force
    std::optional<bool> conserve_dye;      // --conserve-dye; unset: the preset's
    double dt = 0.05;                      // `ardcell surface --fluid`'s step
    // One step a frame keeps 60 frames a second at the default 16^2 cells on the torus on two
    // cores (docs/surfaces.md); the projection to 1e-4, not the batch run's 1e-6, for time.
    int steps_per_frame = 1;
    double tolerance = 1e-4;
    // At the start and every reset, a spot of dye on each patch (SurfaceFluid::fill_sources,
    // the seed's Fig. 8 sources, filled once); false: a clean surface for the brush.
    bool start_dye = true;
  } fluid;
};

class SurfaceSimulation final : public LiveSimulation {
 public:
  // `surface`: from build_live_surface, shared by the session's simulations (only read while
  // one is built; a running one no longer evaluates it). Throws std::invalid_argument with one
  // line when the preset's RD cannot run on a surface (preset_rd).
  SurfaceSimulation(const Preset& preset, std::shared_ptr<const LimitSurface> surface,
                    const SurfaceLiveOptions& options);
  ~SurfaceSimulation() override;

  void step() override;
  void reset() override;
  // No flat fields: the size is the view's (walls, which read fields, refuse surfaces).
  const SimState& state() const override { return state_; }
  SimState& state_to_write() override { return state_; }
  void apply(const SceneConfig& config) override;
  void paint(std::span<const StrokeSample> samples, const InputMapping& input, int source) override;
  std::string_view backend() const override { return backend_name_; }
  Int2 view_size() const override { return {view_.width, view_.height}; }
  void render(ImageRgb8& out) override;

  // The RD only: a fluid has none (a check stops there with its line; fluid() instead).
  const SurfaceGrayScott& rd() const {
    ARDCELL_CHECK(rd_ != nullptr, "SurfaceSimulation::rd: a fluid has no reaction-diffusion");
    return *rd_;
  }
  const SurfaceFluid* fluid() const { return fluid_.get(); }  // null for the RD
  // Gravity's direction for `view`: the screen's downward direction in the mesh's coordinates.
  static std::array<double, 3> screen_down(const SurfaceView& view);
  const SurfaceView& view() const { return view_; }
  const PatchGrid& grid() const { return op_->grid(); }
  // The cell drawn at canvas point (x, y) in [0, 1]^2 in the last render, or -1.
  long cell_at(float x, float y) const;

 private:
  const PatchField& shown() const { return fluid_ ? fluid_->dye() : show_a_ ? rd_->a() : rd_->b(); }
  // Every cell within `radius` of `cell`'s point: write(cell index, the brush's falloff there,
  // patch, i, j).
  template <typename Write>
  void for_brush(long cell, double radius, Write&& write);
  // What a dab writes: the RD's seed values, or the dye towards `dye` (1, or 0 to erase).
  void deposit(long cell, float k_base, double radius, double dye = 1);
  // The fluid's velocity towards `velocity`'s tangential part (mesh coordinates).
  void push(long cell, float k_base, double radius, const std::array<double, 3>& velocity);
  // The shown chemical and its colours from the preset's output (show B, else A; its colormap
  // over the model's typical range).
  void set_colours(const OutputConfig& output);

  PresetRd flat_;
  double length_ = 1;  // the surface length of a flat cell
  std::shared_ptr<const LimitSurface> surface_;
  std::unique_ptr<ThreadBackend> backend_;
  std::unique_ptr<RowExecutor> executor_;
  std::unique_ptr<SurfaceLaplacian> op_;
  std::unique_ptr<SurfaceMultigrid> multigrid_;
  std::unique_ptr<SurfaceGrayScott> rd_;
  std::unique_ptr<SurfaceFluid> fluid_;  // instead of rd_ with options.fluid
  SurfaceLiveOptions::Fluid fluid_options_;
  double down_azimuth_ = NAN, down_elevation_ = NAN;  // the view gravity's down was set for
  std::unique_ptr<SurfaceRenderer> renderer_;
  std::array<PatchField, 3> positions_;  // every cell's point on the limit surface
  double diameter_ = 1;                  // of the bounding sphere the view fits
  // Each patch's cells' centroid and the distance to its farthest cell.
  std::vector<std::array<double, 4>> patch_spheres_;
  SurfaceView view_;
  std::shared_ptr<SessionView> session_view_;  // the session's angles (null: none)
  // view_ takes the session's angles: a simulation built on the loop's worker thread read them
  // once, and the running one may have turned the view since (paint and render run on the
  // main thread, which alone writes them).
  void follow_session_view();
  SurfaceColours colours_;
  bool show_a_ = true;
  SimState state_;
  std::string backend_name_;
  // Per source: what its pointer is doing and where it was at the previous sample.
  struct Stroke {
    enum Mode : uint8_t { kNone, kTurning, kPainting } mode = kNone;
    float x = 0, y = 0;
    long cell = -1;  // painting: the cell of the last dab
  };
  std::array<Stroke, kMaxInputSources> strokes_{};
};

// The limit surface of `mesh`, checked once for a live session: one line when it cannot be
// built (check_manifold), N is not a power of two, N x N cells a patch exceed about a million,
// or the limit surface is degenerate.
Status build_live_surface(PolyMesh mesh, int patch_cells, LimitSurface& out);
// The live loop's factory of surface simulations: every preset on the same surface.
SimulationFactory surface_simulations(std::shared_ptr<const LimitSurface> surface,
                                      const SurfaceLiveOptions& options);
// Whether `preset`'s reaction-diffusion can run on a surface: preset_rd's line when it cannot
// (the CLI's checks of the first preset and the playlist, and the default playlist's filter).
// With `fluid`: whether it can run as a surface fluid instead (preset_fluid).
Status runs_on_surfaces(const Preset& preset, bool fluid = false);

}  // namespace ardcell
