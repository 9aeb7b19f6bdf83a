#pragma once
// The Engine (host/engine/engine.h) as a LiveSimulation: what `ardcell live` runs.
//  - Live parameter changes reach the engine through Engine::update_parameters.
//  - Stroke samples are painted by a Painter (host/paint/paint.h), the one painting path that
//    `ardcell run --strokes` uses too: its PaintConfig is the scene's defaults (paint_config_for)
//    with the preset's [input] table on top (live_paint_config); pressure^pressure_gamma is the
//    pressure.
//  - Adaptive RD resolution: one RD grid per rung of rd_scale_ladder(quality.min_rd_scale) is
//    preallocated. Below full resolution the fluid still runs on the scene's grid
//    (Engine::step_without_rd) while A and B are reacted, diffused and advected on the coarse
//    grid (its own RdStepper, with the velocity and obstacle restricted to it); the shown A and B
//    are the coarse ones prolongated (bilinear) every frame. Going down a rung restricts A and B
//    (area average), going up prolongates them. Painting stays on the scene's grid; coarse cells
//    under a stroke take the restriction of the painted cells. Nothing allocates per frame.
//  - On OpenCL (EngineOptions::Backend::kOpenCl) the fields stay on the device between frames;
//    state() downloads them for the display, painting uploads what it wrote. The simulations
//    of one factory share the device: the loop builds the next preset's on its worker thread
//    while the current one runs, so every use of a simulation's engine takes the factory's
//    device mutex (kernel arguments are set on kernels the engines share).
#include <array>
#include <memory>
#include <mutex>
#include <vector>

#include "host/engine/engine.h"
#include "host/live/live_loop.h"
#include "host/paint/paint.h"

namespace ardcell {

// The Painter configuration for live input: `base` (the scene's defaults, paint_config_for)
// with the preset's input mapping applied: mode (when it names one),
// radius = brush_radius * grid width in cells (min_radius stays base's), strength.
PaintConfig live_paint_config(const PaintConfig& base, const InputMapping& input, Int2 grid);

// Paints `samples` on `state` through `painter` (set to live_paint_config(base, input, grid)
// when it differs), pressure^input.pressure_gamma being the pressure; `scratch` holds the
// adjusted samples, a chunk at a time. Allocates nothing. The one live painting path of the CPU
// and OpenCL simulations.
void paint_live_samples(Painter& painter, const PaintConfig& base,
                        std::span<const StrokeSample> samples, const InputMapping& input,
                        std::array<StrokeSample, 512>& scratch, SimState& state);

class EngineSimulation final : public LiveSimulation {
 public:
  EngineSimulation(const Preset& preset, const PaintConfig& paint_base,
                   const EngineOptions& options = {});
  ~EngineSimulation() override;

  // device_mutex: held around every use of the engine (null: none needed, the CPU back ends).
  EngineSimulation(const Preset& preset, const PaintConfig& paint_base,
                   const EngineOptions& options, std::shared_ptr<std::mutex> device_mutex);
  void step() override;
  void reset() override;
  const SimState& state() const override;
  const SimState& state(std::span<const std::string_view> fields) const override;
  SimState& state_to_write() override;
  // Refused changes (structural ones) keep the current parameters: the live loop switches
  // presets for those.
  void apply(const SceneConfig& config) override;
  void paint(std::span<const StrokeSample> samples, const InputMapping& input, int source) override;
  std::string_view backend() const override { return engine_->backend_name(); }
  double lowest_rd_scale() const override;
  void set_rd_scale(double scale) override;

  const Engine& engine() const { return *engine_; }
  const Painter& painter() const { return painter_; }
  double rd_scale() const;
  // The grid the RD runs on now (the scene's grid at scale 1).
  Int2 rd_grid() const;

 private:
  struct RdLevel;
  void to_level(int level);
  void sync_coarse_from_fine(RdLevel& l, bool chemicals);

  std::unique_lock<std::mutex> lock_device() const;

  std::shared_ptr<std::mutex> device_mutex_;
  std::unique_ptr<Engine> engine_;
  PaintConfig paint_base_;
  Painter painter_;
  int source_ = 0;  // whose stroke painter_ holds; the others' wait in strokes_
  std::array<Painter::Stroke, kMaxInputSources> strokes_{};
  std::vector<std::unique_ptr<RdLevel>> levels_;  // coarser RD grids, finest first
  int level_ = -1;                                // -1: the engine's own RD grid
  bool fine_written_ = false;  // state_to_write() below full RD resolution: re-restrict A, B
  FieldF snap_a_, snap_b_;     // A, B before this frame's strokes
  std::array<StrokeSample, 512> pressured_{};  // samples with pressure^gamma
};

// What `ardcell live` runs: an EngineSimulation whose painter starts from the scene's defaults
// (paint_config_for, as `ardcell run --strokes` does).
std::unique_ptr<LiveSimulation> make_engine_simulation(const Preset& preset);
// The same on a chosen back end (`ardcell live --backend serial|threads|opencl --workers N`);
// for OpenCL, options.opencl must outlive every simulation made.
SimulationFactory engine_simulations(const EngineOptions& options);

}  // namespace ardcell
