#pragma once
// LiveLoop: the real-time loop of `ardcell live`. Each frame: input (display events, pen/touch
// strokes, OSC and GPIO commands, the attract mode) -> simulate -> render through the colormap
// -> present -> record, paced by a FrameClock with absolute deadlines. Pipelined (`ardcell live
// --pipeline`), the step runs on a thread of its own while the main thread presents and records
// the frame rendered before: a frame's work is input + max(simulate, present + record) + render,
// and the window shows each frame one period later. Adaptive quality lowers
// the solver sweeps, then the RD resolution, when a frame would miss and raises them with
// slack; a parameter change
// applies on the next frame; a preset switch loads and builds the new simulation on a worker
// thread while the current one keeps running, then crossfades (parameters when the two presets
// share a grid and models, the displayed image otherwise). After the first frames a
// steady-state frame allocates nothing: input, display, HUD and recording included.
#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "host/config/sim_state.h"
#include "host/config/status.h"
#include "host/live/frame_clock.h"
#include "host/live/remote_log.h"
#include "host/paint/stroke.h"
#include "host/render/image.h"
#include "host/scenes/adaptive_quality.h"
#include "host/scenes/preset.h"

namespace ardcell {

class AttractMode;
class LiveWall;
struct WallInput;

// What the loop runs: the engine (host/live/live_engine.h) or, in tests, something simpler.
class LiveSimulation {
 public:
  virtual ~LiveSimulation() = default;
  virtual void step() = 0;
  virtual void reset() = 0;
  virtual const SimState& state() const = 0;
  // The state with at least the named fields current (SimState::for_each_field names): what the
  // display draws from. The others, and every field when `fields` is empty, may be stale on a
  // device that keeps its own copies; sizes are always right.
  virtual const SimState& state(std::span<const std::string_view> fields) const {
    (void)fields;
    return state();
  }
  // The state for the caller to overwrite (a mirrored video wall bringing this screen back in
  // step with screen 0, host/live/live_wall.h): every field current on the host; the next
  // step() starts from what the caller wrote.
  virtual SimState& state_to_write() = 0;
  // Non-structural parameters (viscosity, dt, solver iterations, ...) for the next step().
  // Must not allocate.
  virtual void apply(const SceneConfig& config) = 0;
  // Stroke samples of this frame from input `source` (0 .. kMaxInputSources - 1: the screens of
  // a video wall, each with strokes of its own), painted before the next step(). Must not
  // allocate.
  static constexpr int kMaxInputSources = 16;
  virtual void paint(std::span<const StrokeSample> samples, const InputMapping& mapping,
                     int source) = 0;
  // "threads x2", "opencl NVIDIA ...": for the HUD.
  virtual std::string_view backend() const = 0;
  // The lowest RD resolution (a rung of rd_scale_ladder) this simulation has a grid for; the
  // loop never asks for less. 1: the RD always runs on the scene's grid.
  virtual double lowest_rd_scale() const { return 1.0; }
  // Runs the RD at `scale` (a rung >= lowest_rd_scale()) from the next step(), carrying the
  // chemicals across. Must not allocate.
  virtual void set_rd_scale(double /*scale*/) {}
  // A simulation that draws itself (a surface's 3D view, host/surface/surface_simulation.h)
  // returns its image's size here and draws into render(); {0, 0}: the loop draws state()'s
  // shown field through the colormap, one pixel a cell. render() must not allocate once `out`
  // has that size.
  virtual Int2 view_size() const { return {0, 0}; }
  virtual void render(ImageRgb8& /*out*/) {}
};
using SimulationFactory = std::function<std::unique_ptr<LiveSimulation>(const Preset&)>;

// Commands from keyboard, GPIO, OSC and tests. Plain data, so queueing never allocates.
enum class LiveCommandKind : uint8_t {
  kQuit,
  kNextPreset,
  kPrevPreset,
  kSelectPreset,  // text: a preset name or path
  kReset,
  kTogglePause,
  kSetPause,  // value: 1 pause, 0 run
  kSetParam,  // param: index into preset_params(), value
  kSetMode,   // value: index of the painting mode (input.mode)
  kNextMode,
  kScreenshot,   // text: path, or empty for a generated name
  kRecordStart,  // text: path, or empty for the --record path / a generated name
  kRecordStop,
  kToggleRecord,
  kToggleHud,
  kInputActivity,  // a pointer moved without painting: counts as presence for the attract mode
};

struct LiveCommand {
  LiveCommandKind kind = LiveCommandKind::kQuit;
  int param = -1;
  double value = 0;
  // From a remote sender (OSC): every line it causes, now or when its preset switch completes,
  // goes through the rate-limited remote_log().
  bool remote = false;
  std::array<char, 240> text{};  // NUL-terminated
  static LiveCommand make(LiveCommandKind k, double value = 0, int param = -1);
  static LiveCommand with_text(LiveCommandKind k, std::string_view text);
};

// A fixed-capacity queue for commands from any thread (GPIO, OSC, the loop itself); a short
// spin lock is enough at the rate commands arrive, and nothing allocates.
class CommandQueue {
 public:
  static constexpr size_t kCapacity = 256;
  bool push(const LiveCommand& c);  // false when full (the command is dropped and counted)
  bool pop(LiveCommand& c);
  uint64_t dropped() const { return dropped_.load(std::memory_order_relaxed); }

 private:
  void lock();
  void unlock() { busy_.clear(std::memory_order_release); }
  std::atomic_flag busy_ = ATOMIC_FLAG_INIT;
  std::array<LiveCommand, kCapacity> slots_{};
  size_t head_ = 0, count_ = 0;
  std::atomic<uint64_t> dropped_{0};
};

// What the HUD shows; filled by the loop each frame with no allocation.
struct HudInfo {
  double fps = 0;
  double p50_ms = 0, p99_ms = 0;
  int64_t misses = 0;
  int64_t frame = 0;
  int sweeps = 0;
  double rd_scale = 1;
  bool paused = false, recording = false, attract = false;
  std::array<char, 64> preset{};
  std::array<char, 64> backend{};
  std::array<char, 96> message{};  // last notice (preset error, screenshot path), fades
  int64_t message_until_frame = 0;
};

// The window (drivers/display_sdl.h) or a headless stand-in.
class LiveDisplay {
 public:
  virtual ~LiveDisplay() = default;
  // Turns pending window events into stroke samples (input) and commands. Never blocks.
  virtual void poll(StrokeRing& input, CommandQueue& commands) = 0;
  // Shows the frame (and the HUD when given). Must not allocate in steady state.
  virtual void present(const ImageRgb8& frame, const HudInfo* hud) = 0;
  // The pixels now shown, as the window's renderer holds them; false when unsupported.
  virtual bool read_back(ImageRgb8&) { return false; }
};

// A destination for frames (PNG for screenshots, Y4M or ffmpeg for recordings).
class FrameWriter {
 public:
  virtual ~FrameWriter() = default;
  virtual Status write(const ImageRgb8& frame) = 0;
  virtual Status finish() = 0;  // completes the file (rename into place)
};
// path, frame size, frame rate -> writer, or nullptr with `error` set.
using FrameWriterFactory = std::function<std::unique_ptr<FrameWriter>(
    const std::string& path, Int2 size, double fps, Status& error)>;

struct LiveOptions {
  double fps = 60;                    // <= 0: unpaced
  int64_t max_frames = 0;             // 0: run until quit
  std::vector<std::string> playlist;  // presets for next/previous (names or paths)
  int crossfade_frames = 30;
  bool hud = false;
  bool adaptive = true;           // and the preset's quality.adaptive
  bool realtime_solvers = false;  // every preset on its real-time settings (use_realtime_solvers)
  bool pipeline = false;          // present the previous frame while the next one steps
  std::string record_path;        // --record: start recording at once
  std::string screenshot_dir = ".";
  std::string exit_screenshot;       // --screenshot PATH: the window's pixels after the last frame
  FrameWriterFactory recorder;       // makes the --record writer (by extension)
  FrameWriterFactory screenshotter;  // makes PNG writers
  int record_slots = 8;              // frames buffered between the loop and the writer thread
  TimeSource* time = nullptr;        // default: the monotonic clock
  const std::atomic<bool>* stop = nullptr;  // set asynchronously (a signal): quit as Esc does
  std::FILE* log = stderr;
  // One screen of a video wall (host/live/live_wall.h; outlives the loop): input is shared with
  // the other screens every frame, the view of its block drawn in the range they agree on, and
  // a frame presented when every screen has it. A wall keeps its preset, does not record, does
  // not adapt its quality (the screens would step different solvers) nor pipeline; a
  // screenshot (S, OSC, --screenshot) is the whole wall's frame, one pixel a cell, the bezels'
  // cells black, written by screen 0.
  LiveWall* wall = nullptr;
};

class LiveLoop {
 public:
  LiveLoop(LiveOptions options, SimulationFactory factory, LiveDisplay& display);
  ~LiveLoop();
  LiveLoop(const LiveLoop&) = delete;
  LiveLoop& operator=(const LiveLoop&) = delete;

  // Loads and builds the first preset synchronously (a bad first preset is fatal).
  Status start(std::string_view preset);
  // Runs until quit or max_frames; returns the exit status (non-ok when a fatal error stopped it).
  Status run();
  // One frame (run() calls this); false once quit was requested.
  bool run_frame();

  void set_attract_mode(AttractMode* attract) { attract_ = attract; }

  CommandQueue& commands() { return commands_; }
  StrokeRing& input() { return input_; }
  // A second input ring for a remote producer thread (OSC), each ring having one producer.
  StrokeRing& remote_input() { return remote_input_; }
  FrameClock& clock() { return clock_; }
  // Where every line a remote sender causes is logged, rate-limited: the OSC server's
  // rejections and what the loop says about remote commands (on options.log, with its clock).
  RemoteLog& remote_log() { return remote_log_; }
  AdaptiveQuality& quality() { return quality_; }
  const Preset& preset() const { return preset_; }  // current (blended during a fade)
  const LiveSimulation& simulation() const { return *sim_; }
  const ImageRgb8& image() const { return image_; }
  const HudInfo& hud() const { return hud_; }
  bool paused() const { return paused_; }
  bool recording() const { return recorder_ != nullptr; }
  bool fading() const { return fade_frame_ < fade_frames_; }
  bool switch_pending() const { return builder_busy_; }
  int64_t frames() const { return frame_; }
  // A mirrored wall: how often a screen drifted and screen 0's state was sent to all.
  int64_t wall_resyncs() const { return wall_resyncs_; }
  int64_t preset_errors() const { return preset_errors_; }
  int64_t painted_samples() const { return painted_samples_; }
  int64_t recorded_frames() const { return recorded_frames_.load(); }
  int64_t record_stalls() const { return record_stalls_; }
  // Increases once per finished frame: the watchdog's heartbeat.
  const std::atomic<int64_t>& heartbeat() const { return heartbeat_; }
  // The last notice shown on the HUD / logged ("preset x.toml:3: ...", "screenshot a.png").
  std::string last_message() const;

  // Blocks until a pending preset switch has been built (tests).
  void wait_for_switch();
  // True once run() quit while a preset switch was still loading: its builder thread was
  // detached (and skips the build if it had not begun) instead of waited for. It may still be
  // running the SimulationFactory, so whatever that uses must outlive it: `ardcell live` ends
  // the process at once (_Exit, after the recording and report are finished).
  bool switch_abandoned() const { return switch_abandoned_; }

 private:
  struct Recorder;
  struct Build;
  struct Stepper;
  // The HUD's figures, then the display and the recorder take image_.
  void present_and_record();
  void handle(const LiveCommand& c);
  void request_preset(std::string name);
  void poll_build();
  void abandon_switch();
  void begin_switch(std::unique_ptr<LiveSimulation> sim, Preset preset);
  // The frame's image of the shown field (on a wall, this screen's view), and its size.
  void render();
  void size_image();
  // A wall's input: this screen's to every screen, and every screen's handled and painted.
  void share_wall_input(bool stop, double now);
  // Whether the preset being loaded has finished building (ok: without error; digest: its
  // text_fingerprint, 0 unless ok).
  bool build_finished(bool& ok, std::uint64_t& digest) const;
  // A mirrored wall, every LiveWall::kCheckFrames frames: the screens compare their states and
  // continue from screen 0's when one drifted.
  void keep_wall_in_step();
  void notice(const char* fmt, ...);
  void start_recording(std::string path);
  void stop_recording();
  void take_screenshot(std::string path);
  void apply_level();
  // The preset's quality bounds, limited to what the running simulation can do.
  QualityBounds bounds_for(const Preset& preset) const;

  LiveOptions options_;
  SimulationFactory factory_;
  LiveDisplay& display_;
  FrameClock clock_;
  RemoteLog remote_log_;
  bool remote_cause_ = false;  // the command or switch being handled came from a remote sender
  static constexpr int64_t kRemoteScreenshotIntervalNs = 1'000'000'000;
  static constexpr int64_t kWallFrameNs = 16'666'667;
  int64_t last_remote_screenshot_ns_ = -1;  // frame clock time of the last remote screenshot
  AdaptiveQuality quality_;
  CommandQueue commands_;
  StrokeRing input_{4096};
  StrokeRing remote_input_{4096};
  std::array<StrokeSample, 512> samples_{};
  AttractMode* attract_ = nullptr;
  std::unique_ptr<WallInput> wall_input_;  // a wall: this screen's input of the frame
  int wall_attract_samples_ = 0;           // ... led by the attract mode's strokes (screen 0)
  int64_t wall_resyncs_ = 0;               // a mirrored wall: times screen 0's state was sent
  // Every screen's switch, this frame: built, without error, the same preset.
  bool wall_build_done_ = false, wall_build_ok_ = false, wall_build_same_ = false;

  Preset preset_;     // as running now (blended during a parameter fade)
  Preset fade_from_;  // parameter fade endpoints
  Preset fade_to_;
  SceneConfig applied_;  // preset_.scene with the quality level applied
  std::unique_ptr<LiveSimulation> sim_;
  int playlist_index_ = 0;
  bool paused_ = false;
  bool quit_ = false;
  bool image_fade_ = false;
  int fade_frame_ = 0, fade_frames_ = 0;
  ImageRgb8 image_, fade_image_;
  ImageRgb8 wall_shot_;  // a wall's screenshot (screen 0)
  HudInfo hud_;
  int64_t frame_ = 0;
  int64_t preset_errors_ = 0;
  int64_t painted_samples_ = 0;
  int64_t record_stalls_ = 0;
  std::atomic<int64_t> recorded_frames_{0};
  std::atomic<int64_t> heartbeat_{0};
  int screenshot_counter_ = 0;

  std::shared_ptr<Build> build_;
  bool builder_busy_ = false;
  bool switch_abandoned_ = false;
  std::string pending_preset_;   // the latest switch asked for while one was loading
  bool pending_remote_ = false;  // ... by a remote sender
  std::unique_ptr<Recorder> recorder_;
  std::unique_ptr<Stepper> stepper_;  // pipeline: the thread that steps
  bool presented_ = true;             // pipeline: image_ is on the display
  mutable std::mutex message_mutex_;
  std::string message_;
};

// A preset by name or path (load_preset) whose grid fits in memory (the check `ardcell run`
// makes): what every preset of `ardcell live` goes through, the first, the playlist, switches;
// with `realtime_solvers`, on its real-time settings (use_realtime_solvers).
Status load_live_preset(std::string_view name, Preset& p, bool realtime_solvers = false);

// The field a preset shows, as RGB through its colormap (host/render/frame_render.h, the same image
// `ardcell run` writes). `out` must already have the state's size.
void render_state(const SimState& state, const OutputConfig& output, ImageRgb8& out);
// Blends `from` (any size, sampled nearest) into `to` at weight 1 - t (t = 1: `to` unchanged).
void crossfade_images(const ImageRgb8& from, double t, ImageRgb8& to);

}  // namespace ardcell
