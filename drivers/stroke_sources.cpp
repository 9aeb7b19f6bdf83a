#include "drivers/stroke_sources.h"

#include "drivers/hid_descriptor.h"
#include "drivers/hid_recorder.h"
#include "drivers/hid_report.h"
#include "host/paint/stroke_io.h"
#include "host/scenes/preset.h"
#if defined(ARDCELL_WITH_HIDAPI)
#include "drivers/tablet_hidapi.h"
#endif

namespace ardcell {

std::unique_ptr<StrokeSource> open_stroke_file_source(const std::string& path, bool loop,
                                                      std::string& error) {
  std::vector<StrokeSample> samples;
  if (!read_stroke_file(path, samples, error)) return nullptr;
  if (samples.empty()) {
    error = path + ": no samples (expected one JSON object per line)";
    return nullptr;
  }
  return std::make_unique<ReplayStrokeSource>(std::move(samples), "strokes " + path, loop);
}

std::unique_ptr<StrokeSource> open_hid_replay_source(const std::string& path, bool loop,
                                                     std::string& error) {
  HidRecording rec;
  if (!read_hid_recording(path, rec, error)) return nullptr;
  HidDescriptor desc;
  std::string why;
  if (!parse_hid_descriptor(rec.descriptor, desc, why)) {
    error = path + ": report descriptor: " + why;
    return nullptr;
  }
  const std::vector<HidPenLayout> pens = find_pens(desc);
  if (pens.empty()) {
    error = path + ": the report descriptor has no pen (usage page 0x0D with X and Y)";
    return nullptr;
  }
  std::vector<StrokeSample> samples;
  for (const HidEvent& e : rec.events)
    for (const HidPenLayout& pen : pens) {
      HidPenState st;
      if (decode_pen(pen, desc.uses_report_ids, e.data, st, why))
        samples.push_back(pen_state_to_sample(pen, st, e.time));
    }
  if (samples.empty()) {
    error = path + ": no pen reports among its " + std::to_string(rec.events.size()) + " events";
    return nullptr;
  }
  return std::make_unique<ReplayStrokeSource>(std::move(samples), "replay " + path, loop);
}

std::unique_ptr<StrokeSource> open_tablet_source(std::string& error) {
#if defined(ARDCELL_WITH_HIDAPI)
  (void)error;
  return std::make_unique<HidTabletSource>(stderr);
#else
  error = "built without hidapi (ARDCELL_WITH_HIDAPI=OFF): no live tablet";
  return nullptr;
#endif
}

PaintConfig paint_config_for_scene(const SceneConfig& scene) { return paint_config_for(scene); }

bool RunPaintOptions::make(const SceneConfig& scene, std::unique_ptr<StrokePlayback>& out,
                           std::string& error) const {
  out.reset();
  if (!any()) {
    // The painting flags shape a recording's strokes: alone they would do nothing.
    const char* alone = !mode.empty() ? "--paint-mode"
                        : radius != 0 ? "--paint-radius"
                        : loop        ? "--loop-strokes"
                                      : nullptr;
    if (!alone) return true;
    error = std::string(alone) + ": paints a recording; expected --strokes FILE or --replay FILE";
    return false;
  }
  if (!strokes.empty() && !replay.empty()) {
    error = "--strokes and --replay: give one of them";
    return false;
  }
  PaintConfig c = paint_config_for_scene(scene);
  if (!mode.empty() && !parse_paint_mode(mode, c.mode)) {
    error = "--paint-mode " + mode + ": expected deposit, orient, push, obstacle or erase";
    return false;
  }
  if (radius != 0) {
    // In cells here; the preset key input.brush_radius holds the same as a fraction of nx.
    const std::string flag = "--paint-radius " + std::to_string(radius) + " cells is a brush of";
    if (Status s = check_flag_param("input.brush_radius", radius / scene.size.x, flag); !s) {
      error = s.message();
      return false;
    }
    c.radius = float(radius);
  }
  std::unique_ptr<StrokeSource> source = strokes.empty()
                                             ? open_hid_replay_source(replay, loop, error)
                                             : open_stroke_file_source(strokes, loop, error);
  if (!source) return false;
  out = std::make_unique<StrokePlayback>(std::move(source), scene.size, c);
  return true;
}

void add_run_paint_options(CLI::App& command, RunPaintOptions& o) {
  command.add_option("--strokes", o.strokes, "paint a stroke recording (JSON lines) while running");
  command.add_option("--replay", o.replay,
                     "paint a hid-recorder tablet capture while running (decoded generically)");
  command.add_option("--paint-mode", o.mode, "deposit|orient|push|obstacle|erase");
  command.add_option("--paint-radius", o.radius, "brush radius in cells at full pressure");
  command.add_flag("--loop-strokes", o.loop, "repeat the recording (attract mode)");
}

}  // namespace ardcell
