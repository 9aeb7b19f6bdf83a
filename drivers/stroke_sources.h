#pragma once
// Stroke sources from files and devices, and the painting options of `ardcell run`:
//   --strokes FILE   a stroke recording (host/paint/stroke_io.h, JSON lines), replayed in real time
//   --replay FILE    a hid-recorder capture of a pen tablet, decoded through its descriptor
//   --paint-mode M   deposit | orient | push | obstacle | erase (default: the preset's mode)
//   --paint-radius R brush radius in cells at full pressure
// A run loop with a per-step hook calls RunPaintOptions::make() once and
// StrokePlayback::before_step(state, step * dt) before each step.
#include <memory>
#include <string>

#include <CLI/CLI.hpp>

#include "host/config/scene_config.h"
#include "host/paint/paint.h"
#include "host/paint/stroke.h"
#include "host/paint/stroke_playback.h"

namespace ardcell {

// A ReplayStrokeSource over a stroke file; nullptr and `error` (one line) on bad input.
std::unique_ptr<StrokeSource> open_stroke_file_source(const std::string& path, bool loop,
                                                      std::string& error);
// A ReplayStrokeSource over the pen reports of a hid-recorder file (times from its E: lines).
std::unique_ptr<StrokeSource> open_hid_replay_source(const std::string& path, bool loop,
                                                     std::string& error);
// The live tablet (hidapi) when built with it, else nullptr and `error`.
std::unique_ptr<StrokeSource> open_tablet_source(std::string& error);

struct RunPaintOptions {
  std::string strokes, replay, mode;
  double radius = 0;
  bool loop = false;
  bool any() const { return !strokes.empty() || !replay.empty(); }
  // The playback for a scene, or nullptr when no stroke option was given. False with a
  // one-line `error` on a bad file or mode.
  bool make(const SceneConfig& scene, std::unique_ptr<StrokePlayback>& out,
            std::string& error) const;
};

// Adds --strokes, --replay, --paint-mode, --paint-radius, --loop-strokes to a subcommand.
void add_run_paint_options(CLI::App& command, RunPaintOptions& options);

// The Painter defaults for a scene (host/paint/paint.h paint_config_for).
PaintConfig paint_config_for_scene(const SceneConfig& scene);

}  // namespace ardcell
