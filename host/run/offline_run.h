#pragma once
// The headless run loop behind `ardcell run`: step an Engine N frames, every `every` frames
// render the chosen field and hand the image to the frame sinks, show a progress bar on a
// terminal, and measure ms per frame and cells per second (the simulation steps only, not
// rendering or file output).
#include <atomic>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <span>
#include <string>
#include <utility>

#include "host/config/scene_config.h"
#include "host/config/status.h"
#include "host/engine/engine.h"
#include "host/paint/stroke_playback.h"
#include "host/render/frame_render.h"
#include "host/render/frame_sink.h"

namespace ardcell {

// Command-line overrides of a scene; unset members keep the scene's value.
struct SceneOverrides {
  std::optional<Int2> size;
  std::optional<double> dt;
  std::optional<double> reynolds;
  std::optional<SolverKind> solver;
  std::optional<int> sweeps;
};

// Applies the overrides, each validated by the range of the preset key it stands for (size:
// grid.size, dt: grid.dt, Re: the fluid.viscosity it gives, sweeps: the solver iterations).
Status apply_overrides(const SceneOverrides& overrides, SceneConfig& scene);

// Parses "N" or "WxH" (positive integers, at most kMaxGridSide each).
inline constexpr int kMaxGridSide = 1 << 16;
Status parse_grid_size(const std::string& text, Int2& out);

// An estimate of the memory the engine needs for a grid (fields, solver scratch, frames).
uint64_t estimated_bytes_for_grid(const SceneConfig& scene);
// Memory this process may still use: MemAvailable, capped by a cgroup limit and RLIMIT_AS.
uint64_t available_memory_bytes();
// Error when the grid needs more memory than is available.
Status check_memory_for_grid(const SceneConfig& scene);
// The Engine for a scene given by the user (`run`, `tablet play`; check_memory_for_grid first):
// a parameter the engine refuses (std::invalid_argument, one line naming it) or a
// failed allocation is an error, never an exception.
Status make_engine(const SceneConfig& scene, const EngineOptions& options,
                   std::unique_ptr<Engine>& out);

// What the run loop steps: an Engine (the general scenes), or another workload (the Table 1
// scenes) that shows its fields as a SimState for rendering.
class OfflineStepper {
 public:
  virtual ~OfflineStepper() = default;
  // One frame; returns when its results are complete (timed by the loop).
  virtual void step() = 0;
  // The state to render; called only after steps whose frame is written (may copy fields).
  virtual const SimState& frame_state() = 0;
};

// The general scenes' stepper: the Engine, with an optional stroke playback (--strokes /
// --replay) that paints the samples due at the frame's time before each step.
class EngineStepper final : public OfflineStepper {
 public:
  explicit EngineStepper(Engine& engine, StrokePlayback* playback = nullptr)
      : engine_(engine), playback_(playback) {}
  void step() override {
    if (playback_) playback_->before_step(engine_.state(), engine_.state().time);
    engine_.step();
    engine_.finish();  // a frame counts when it is done
  }
  const SimState& frame_state() override { return std::as_const(engine_).state(); }

 private:
  Engine& engine_;
  StrokePlayback* playback_;
};

// Called after every step, outside the timed part (probes written as a time series); an error
// ends the run.
class StepObserver {
 public:
  virtual ~StepObserver() = default;
  virtual Status after_step(int64_t frame) = 0;
};

struct OfflineRunOptions {
  int64_t steps = 0;                        // frames to simulate
  int64_t every = 0;                        // write a frame after every `every` steps; 0: none
  RenderSettings render;                    // what frames show
  std::FILE* progress = nullptr;            // progress bar stream (a terminal), or none
  const std::atomic<bool>* stop = nullptr;  // set asynchronously (Ctrl-C) to end early
  // When non-empty, frame i's step time in seconds goes to frame_seconds[i - 1] (for as many
  // frames as it holds): the caller allocates it before the run (`--stats`).
  std::span<double> frame_seconds;
  StepObserver* observer = nullptr;
};

struct OfflineRunSummary {
  int64_t steps = 0;  // frames simulated
  int64_t frames_written = 0;
  double step_seconds = 0;       // wall time inside Engine::step
  int64_t cells = 0;             // cells per frame
  int64_t non_finite_cells = 0;  // in the last rendered frame
  bool stopped_early = false;

  double ms_per_frame() const { return steps ? 1e3 * step_seconds / double(steps) : 0.0; }
  double cells_per_second() const {
    return step_seconds > 0 ? double(cells) * double(steps) / step_seconds : 0.0;
  }
};

// Runs the loop; fails on the first sink error (the sinks are not finished here).
Status run_offline(Engine& engine, const OfflineRunOptions& options,
                   std::span<FrameSink* const> sinks, OfflineRunSummary& summary);
Status run_offline(OfflineStepper& stepper, const OfflineRunOptions& options,
                   std::span<FrameSink* const> sinks, OfflineRunSummary& summary);

// Per-frame step times: mean, median and 99th percentile in ms (sorts `seconds` in place).
struct FrameTimeStats {
  int64_t frames = 0;
  double mean_ms = 0, p50_ms = 0, p99_ms = 0, max_ms = 0;
};
FrameTimeStats frame_time_stats(std::span<double> seconds);
// "frame ms: mean=3.210 p50=3.100 p99=4.020 max=4.500 (500 frames)"
std::string format_frame_time_stats(const FrameTimeStats& stats);

// "frames=500 ms/frame=3.21 cells/s=2.04e+07 images=50 out=out/cavity"
std::string format_summary(const OfflineRunSummary& summary, const std::string& out);

}  // namespace ardcell
