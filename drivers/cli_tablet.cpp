// `ardcell tablet`: list pen tablets, record one in hid-recorder format, decode a recording
// (JSON lines), and play strokes into a scene to a PNG.
#include <nlohmann/json.hpp>

#include "drivers/cli.h"
#include "drivers/hid_descriptor.h"
#include "drivers/hid_recorder.h"
#include "drivers/hid_report.h"
#include "drivers/png_writer.h"
#include "drivers/stroke_sources.h"
#include "host/engine/engine.h"
#include "host/io/atomic_file.h"
#include "host/render/frame_render.h"
#include "host/run/offline_run.h"
#include "host/scenes/preset.h"
#if defined(ARDCELL_WITH_HIDAPI)
#include "drivers/tablet_hidapi.h"
#endif

namespace ardcell {
namespace {

int list_command(CliContext& ctx) {
#if defined(ARDCELL_WITH_HIDAPI)
  const std::vector<TabletInfo> tablets = list_tablets();
  if (tablets.empty()) {
    std::fprintf(ctx.out, "no pen tablet found (HID usage page 0x0D); everything else runs\n");
    return kExitOk;
  }
  for (const TabletInfo& t : tablets) {
    std::fprintf(ctx.out, "%s  %04x:%04x  interface %d  usage 0x%04x/0x%04x  %s%s\n",
                 t.path.c_str(), t.vendor, t.product, t.interface_number, t.usage_page, t.usage,
                 t.name.c_str(), t.readable ? "" : "  (no permission)");
    if (!t.readable) {
      std::fprintf(ctx.out, "  %s\n", tablet_permission_hint(t.path).c_str());
      continue;
    }
    std::vector<uint8_t> bytes;
    std::string error;
    HidDescriptor d;
    if (!read_report_descriptor(t.path, bytes, error) || !parse_hid_descriptor(bytes, d, error)) {
      std::fprintf(ctx.out, "  descriptor: %s\n", error.c_str());
      continue;
    }
    for (const HidPenLayout& pen : find_pens(d))
      std::fprintf(ctx.out, "  pen: report %d, X 0..%lld, Y 0..%lld, pressure %s, tilt %s\n",
                   pen.report_id, (long long)(pen.x ? pen.x->logical_max : 0),
                   (long long)(pen.y ? pen.y->logical_max : 0),
                   pen.pressure ? std::to_string(pen.pressure->logical_max).c_str() : "none",
                   pen.x_tilt ? "yes" : "no");
  }
  return kExitOk;
#else
  std::fprintf(ctx.out, "built without hidapi (ARDCELL_WITH_HIDAPI=OFF): no tablets\n");
  return kExitOk;
#endif
}

int record_command(CliContext& ctx, const std::string& file, const std::string& device,
                   double seconds) {
  // The destination is checked before any device is opened.
  if (file.empty()) return cli_usage_error(ctx, "tablet record", "FILE: expected a path");
  if (Status st = check_output_path(file, false); !st)
    return cli_usage_error(ctx, "tablet record", st.message());
#if defined(ARDCELL_WITH_HIDAPI)
  // SIGINT, SIGTERM and SIGHUP end the recording as --seconds does: what was recorded is
  // written and renamed into place; a second signal meanwhile cannot cut that short.
  const StopSignals stop_signals;
  std::string error;
  if (!record_tablet(device, file, StopSignals::requested(), seconds > 0 ? seconds : 1e12, ctx.err,
                     error))
    return cli_usage_error(ctx, "tablet record", error);
  std::fprintf(ctx.out, "wrote %s\n", file.c_str());
  return StopSignals::exit_code(kExitOk);
#else
  (void)file;
  (void)device;
  (void)seconds;
  return cli_usage_error(ctx, "tablet record", "built without hidapi (ARDCELL_WITH_HIDAPI=OFF)");
#endif
}

int decode_command(CliContext& ctx, const std::string& file) {
  HidRecording rec;
  std::string error;
  if (!read_hid_recording(file, rec, error)) return cli_usage_error(ctx, "tablet decode", error);
  HidDescriptor desc;
  if (!parse_hid_descriptor(rec.descriptor, desc, error))
    return cli_usage_error(ctx, "tablet decode", file + ": report descriptor: " + error);
  const std::vector<HidPenLayout> pens = find_pens(desc);
  HidReportDecoder decoder(desc);
  HidDecodedReport report;
  for (const HidEvent& e : rec.events) {
    nlohmann::ordered_json j;
    j["t"] = e.time;
    if (!decoder.decode(e.data, report, error)) {
      j["error"] = error;
      std::fprintf(ctx.out, "%s\n", j.dump().c_str());
      continue;
    }
    j["report_id"] = report.report_id;
    nlohmann::ordered_json fields = nlohmann::ordered_json::object();
    for (const HidDecodedValue& v : report.values) {
      if (v.field->is_array()) {
        if (v.usage && (v.usage & 0xffff)) fields["pressed"].push_back(hid_usage_name(v.usage));
        continue;
      }
      const std::string name = hid_usage_name(v.usage);
      if (!fields.contains(name)) fields[name] = v.value;  // a repeated usage: the first one
    }
    j["fields"] = fields;
    for (const HidPenLayout& pen : pens) {
      HidPenState st;
      if (!decode_pen(pen, desc.uses_report_ids, e.data, st, error)) continue;
      const StrokeSample s = pen_state_to_sample(pen, st, e.time);
      j["pen"] = {{"tip", st.tip},
                  {"in_range", st.in_range},
                  {"barrel", st.barrel},
                  {"secondary", st.secondary},
                  {"invert", st.invert},
                  {"eraser", st.eraser},
                  {"x", st.x},
                  {"y", st.y},
                  {"pressure", st.pressure},
                  {"tilt_x", st.x_tilt},
                  {"tilt_y", st.y_tilt}};
      j["sample"] = {{"x", s.x},
                     {"y", s.y},
                     {"pressure", s.pressure},
                     {"tilt_x", s.tilt_x},
                     {"tilt_y", s.tilt_y},
                     {"buttons", s.buttons},
                     {"in_range", s.in_range},
                     {"eraser", s.eraser}};
    }
    if (!e.comment.empty()) j["comment"] = e.comment;
    std::fprintf(ctx.out, "%s\n", j.dump().c_str());
  }
  return kExitOk;
}

struct PlayArgs {
  std::string scene, png, show;
  int64_t steps = 0;
  RunPaintOptions paint;
};

int play_command(CliContext& ctx, const PlayArgs& a) {
  Preset preset;
  if (Status st = load_preset(a.scene, preset); !st)
    return cli_usage_error(ctx, "tablet play", st.message());
  if (!a.paint.any())
    return cli_usage_error(ctx, "tablet play", "give --strokes FILE or --replay FILE");
  std::unique_ptr<StrokePlayback> playback;
  std::string error;
  if (!a.paint.make(preset.scene, playback, error))
    return cli_usage_error(ctx, "tablet play", error);
  FrameField field = FrameField::kB;
  if (!a.show.empty() && !parse_frame_field(a.show, field))
    return cli_usage_error(ctx, "tablet play",
                           "--show " + a.show + ": expected " + std::string(frame_field_names()));
  if (a.png.empty())
    return cli_usage_error(ctx, "tablet play", "--png: expected a path, got an empty string");
  if (Status st = check_output_path(a.png, false); !st)
    return cli_usage_error(ctx, "tablet play", "--png " + st.message());
  if (Status st = check_memory_for_grid(preset.scene); !st)
    return cli_usage_error(ctx, "tablet play", st.message());
  std::unique_ptr<Engine> made;
  if (Status st = make_engine(preset.scene, EngineOptions{}, made); !st)
    return cli_usage_error(ctx, "tablet play", st.message());
  Engine& engine = *made;
  if (!frame_field_available(engine.state(), field))
    return cli_usage_error(ctx, "tablet play", "--show: the scene has no such field");
  const int64_t steps = a.steps > 0 ? a.steps : preset.scene.default_steps;
  int64_t painted = 0;
  for (int64_t i = 0; i < steps; ++i) {
    painted += int64_t(playback->before_step(engine.state(), double(i) * preset.scene.dt));
    engine.step();
  }
  ImageRgb8 image;
  image.resize(engine.state().size.x, engine.state().size.y);
  render_frame(engine.state(), default_render_settings(field), image);
  if (Status st = write_png(a.png, image); !st) {
    std::fprintf(ctx.err, "ardcell tablet play: %s\n", st.message().c_str());
    return kExitFailure;
  }
  std::fprintf(ctx.out, "steps=%lld samples=%lld mode=%s png=%s\n", (long long)steps,
               (long long)painted, std::string(paint_mode_name(playback->painter().mode())).c_str(),
               a.png.c_str());
  return kExitOk;
}

}  // namespace

void add_tablet_command(CLI::App& app, CliContext& ctx) {
  CLI::App* tablet = app.add_subcommand("tablet", "pen tablets: list, record, decode, play");
  tablet->require_subcommand(1);

  CLI::App* list = tablet->add_subcommand("list", "list pen digitizers (HID usage page 0x0D)");
  list->callback([&ctx] { ctx.exit_code = list_command(ctx); });

  auto file = std::make_shared<std::string>();
  auto device = std::make_shared<std::string>();
  auto seconds = std::make_shared<double>(0);
  CLI::App* record = tablet->add_subcommand(
      "record",
      "record the first tablet's reports in hid-recorder format until Ctrl-C (or SIGTERM, "
      "SIGHUP, --seconds)");
  record->add_option("FILE", *file, "output file (written atomically)")->required();
  record->add_option("--device", *device, "a /dev/hidrawN path (default: the first tablet)");
  record->add_option("--seconds", *seconds, "stop after this many seconds");
  record->callback([&ctx, file, device, seconds] {
    ctx.exit_code = record_command(ctx, *file, *device, *seconds);
  });

  auto in = std::make_shared<std::string>();
  CLI::App* decode = tablet->add_subcommand(
      "decode", "print each event of a hid-recorder file as a JSON line of decoded fields");
  decode->add_option("FILE", *in, "hid-recorder file (R:, N:, I:, E: lines)")->required();
  decode->callback([&ctx, in] { ctx.exit_code = decode_command(ctx, *in); });

  auto play = std::make_shared<PlayArgs>();
  CLI::App* p = tablet->add_subcommand(
      "play", "run a scene while painting --strokes/--replay into it; write the last frame");
  p->add_option("SCENE", play->scene, "built-in scene, embedded preset or .toml")->required();
  p->add_option("--png", play->png, "output PNG")->required();
  p->add_option("--steps", play->steps, "frames (default: the scene's)");
  p->add_option("--show", play->show, "field to draw (default B)");
  add_run_paint_options(*p, play->paint);
  p->callback([&ctx, play] { ctx.exit_code = play_command(ctx, *play); });
}

}  // namespace ardcell
