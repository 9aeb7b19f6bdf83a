#include "host/live/live_loop.h"

#include <algorithm>
#include <cmath>
#include <condition_variable>
#include <cstdarg>
#include <cstring>
#include <ctime>
#include <semaphore>
#include <utility>

#include "host/live/attract_mode.h"
#include "host/live/live_wall.h"
#include "host/run/offline_run.h"

namespace ardcell {

// The preset switch in flight: loaded and built on a worker thread.
// Shared by the loop and the builder thread, so that a build let go of at quit (detached) is
// freed by its thread when it ends.
struct LiveLoop::Build {
  std::thread thread;
  std::atomic<bool> done{false};
  std::atomic<bool> cancelled{false};  // quit: skip the build if it has not begun
  std::string name;
  bool remote = false;  // asked for by a remote sender: its outcome is logged as remote
  Preset preset;
  std::uint64_t digest = 0;  // text_fingerprint of the preset as TOML (a wall's screens compare)
  std::unique_ptr<LiveSimulation> sim;
  Status status = Status::ok();
  ~Build() {
    if (thread.joinable()) thread.join();
  }
};

// Frames go to the writer thread through preallocated slots; when every slot is full the loop
// waits (and counts a stall) rather than leave a frame out of the recording.
struct LiveLoop::Recorder {
  std::unique_ptr<FrameWriter> writer;
  std::vector<ImageRgb8> slots;
  std::mutex mutex;
  std::condition_variable cv;
  size_t head = 0, count = 0;
  bool closing = false;
  Status status = Status::ok();
  std::string path;
  std::thread thread;
  std::atomic<int64_t>* written = nullptr;

  void run() {
    for (;;) {
      std::unique_lock lock(mutex);
      cv.wait(lock, [&] { return count > 0 || closing; });
      if (count == 0) break;
      ImageRgb8& img = slots[head];
      lock.unlock();
      if (status) {
        Status s = writer->write(img);
        if (!s) status = std::move(s);
      }
      written->fetch_add(1);
      lock.lock();
      head = (head + 1) % slots.size();
      --count;
      cv.notify_all();
    }
    if (status) status = writer->finish();
  }
  // Copies the frame into a free slot; returns true when it had to wait.
  bool push(const ImageRgb8& frame) {
    std::unique_lock lock(mutex);
    bool stalled = false;
    while (count == slots.size()) {
      stalled = true;
      cv.wait(lock);
    }
    ImageRgb8& dst = slots[(head + count) % slots.size()];
    if (dst.rgb.size() == frame.rgb.size()) {
      dst.width = frame.width;
      dst.height = frame.height;
      std::memcpy(dst.rgb.data(), frame.rgb.data(), frame.rgb.size());
    } else {
      dst = frame;  // only when the size changed (a preset switch), not in steady state
    }
    ++count;
    cv.notify_all();
    return stalled;
  }
  Status close() {
    {
      std::lock_guard lock(mutex);
      closing = true;
    }
    cv.notify_all();
    if (thread.joinable()) thread.join();
    return status;
  }
};

LiveLoop::LiveLoop(LiveOptions options, SimulationFactory factory, LiveDisplay& display)
    : options_(std::move(options)),
      factory_(std::move(factory)),
      display_(display),
      clock_(options_.fps, options_.time ? *options_.time : MonotonicTime::instance()),
      remote_log_(options_.log, options_.time),
      quality_(QualityBounds{}) {
  message_.reserve(256);
  if (options_.wall) {
    ARDCELL_CHECK(!options_.pipeline, "LiveLoop: a wall does not pipeline");
    ARDCELL_CHECK(options_.wall->screens() <= LiveSimulation::kMaxInputSources,
                  "LiveLoop: a wall of more screens than input sources");
    options_.adaptive = false;
    wall_input_ = std::make_unique<WallInput>();
  }
}

// The pipeline's stepping thread: step() on `go`, `done` after. Semaphores: no allocation.
struct LiveLoop::Stepper {
  std::binary_semaphore go{0}, done{0};
  LiveSimulation* sim = nullptr;
  bool quit = false;
  std::thread thread{[this] {
    for (;;) {
      go.acquire();
      if (quit) return;
      sim->step();
      done.release();
    }
  }};
  ~Stepper() {
    quit = true;
    go.release();
    thread.join();
  }
  void start(LiveSimulation& s) {
    sim = &s;
    go.release();
  }
  void wait() { done.acquire(); }
};

LiveLoop::~LiveLoop() {
  stepper_.reset();
  if (recorder_) (void)recorder_->close();
  if (build_ && build_->thread.joinable()) build_->thread.join();
  build_.reset();
}

std::string LiveLoop::last_message() const {
  std::lock_guard lock(message_mutex_);
  return message_;
}

void LiveLoop::notice(const char* fmt, ...) {
  char buf[512];
  va_list args;
  va_start(args, fmt);
  std::vsnprintf(buf, sizeof buf, fmt, args);
  va_end(args);
  // One log line per problem: a preset's message lists each on its own line.
  const char* first_end = std::strchr(buf, '\n');
  if (options_.log) {
    const char* prefix_end = first_end ? std::strstr(buf, ": ") : nullptr;
    const int prefix = prefix_end && prefix_end < first_end ? int(prefix_end - buf + 2) : 0;
    for (const char* line = buf; *line;) {
      const char* end = std::strchr(line, '\n');
      const int n = end ? int(end - line) : int(std::strlen(line));
      // Lines after the first repeat the notice's lead ("keeping cavity: ").
      const int lead = line == buf ? 0 : prefix;
      if (line == buf || n > 0) {
        if (remote_cause_) {
          char joined[sizeof buf * 2];
          std::snprintf(joined, sizeof joined, "%.*s%.*s", lead, buf, n, line);
          remote_log_.line("live", joined);
        } else {
          std::fprintf(options_.log, "live: %.*s%.*s\n", lead, buf, n, line);
        }
      }
      line = end ? end + 1 : line + n;
    }
  }
  {
    std::lock_guard lock(message_mutex_);
    message_.assign(buf, first_end ? size_t(first_end - buf) : std::strlen(buf));
  }
  std::snprintf(hud_.message.data(), hud_.message.size(), "%.*s",
                first_end ? int(first_end - buf) : int(std::strlen(buf)), buf);
  hud_.message_until_frame = frame_ + 180;
}

Status load_live_preset(std::string_view name, Preset& p, bool realtime_solvers) {
  if (Status s = load_preset(name, p); !s) return s;
  if (realtime_solvers) use_realtime_solvers(p);
  if (Status s = check_memory_for_grid(p.scene); !s)
    return Status::error("preset " + std::string(name) + ": " + s.message());
  return Status::ok();
}

Status LiveLoop::start(std::string_view name) {
  Preset p;
  Status s = load_live_preset(name, p, options_.realtime_solvers);
  if (!s) return s;
  try {
    sim_ = factory_(p);
  } catch (const std::exception& e) {
    return Status::error(std::string(name) + ": cannot build the scene: " + e.what());
  }
  if (!sim_) return Status::error(std::string(name) + ": cannot build the scene");
  preset_ = p;
  applied_ = p.scene;
  quality_.set_bounds(bounds_for(p));
  quality_.restore_full();
  apply_level();
  for (size_t i = 0; i < options_.playlist.size(); ++i)
    if (options_.playlist[i] == name) playlist_index_ = int(i);
  size_image();
  hud_.preset.fill(0);
  std::snprintf(hud_.preset.data(), hud_.preset.size(), "%s", preset_.scene.name.c_str());
  std::snprintf(hud_.backend.data(), hud_.backend.size(), "%.*s", int(sim_->backend().size()),
                sim_->backend().data());
  hud_.frame = 0;
  if (!options_.record_path.empty()) start_recording(options_.record_path);
  return Status::ok();
}

void LiveLoop::size_image() {
  // The cells drawn: the grid, or on a wall this screen's view.
  if (const Int2 view = sim_->view_size(); view.x > 0 && view.y > 0) {
    image_.resize(view.x, view.y);
    return;
  }
  const Box2 shown = options_.wall ? options_.wall->view() : box_of_size(sim_->state({}).size);
  image_.resize(shown.width(), shown.height());
}

QualityBounds LiveLoop::bounds_for(const Preset& preset) const {
  QualityBounds b = preset.quality;
  b.adaptive = b.adaptive && options_.adaptive;
  b.min_rd_scale = std::max(b.min_rd_scale, sim_ ? sim_->lowest_rd_scale() : 1.0);
  return b;
}

void LiveLoop::apply_level() {
  apply_quality(preset_, quality_.level(), applied_);
  sim_->apply(applied_);
  sim_->set_rd_scale(quality_.level().rd_scale);
}

void LiveLoop::request_preset(std::string name) {
  if (builder_busy_) {
    // The latest request runs once the one loading now is done.
    notice("preset %s: queued after the switch in progress",
           remote_cause_ ? escaped_prefix(name, RemoteLog::kMaxEchoedChars).c_str() : name.c_str());
    pending_preset_ = std::move(name);
    pending_remote_ = remote_cause_;
    return;
  }
  build_ = std::make_shared<Build>();
  build_->name = std::move(name);
  build_->remote = remote_cause_;
  builder_busy_ = true;
  std::shared_ptr<Build> b = build_;
  SimulationFactory factory = factory_;
  const bool realtime_solvers = options_.realtime_solvers;
  build_->thread = std::thread([b, factory, realtime_solvers] {
    b->status = load_live_preset(b->name, b->preset, realtime_solvers);
    if (b->status && b->cancelled.load()) b->status = Status::error(b->name + ": cancelled");
    if (b->status) b->digest = text_fingerprint(preset_to_toml(b->preset));
    if (b->status) {
      try {
        b->sim = factory(b->preset);
        if (!b->sim) b->status = Status::error(b->name + ": cannot build the scene");
      } catch (const std::exception& e) {
        b->status = Status::error(b->name + ": cannot build the scene: " + e.what());
      }
    }
    b->done.store(true, std::memory_order_release);
  });
}

bool LiveLoop::build_finished(bool& ok, std::uint64_t& digest) const {
  const bool done = builder_busy_ && build_->done.load(std::memory_order_acquire);
  ok = done && build_->status.is_ok();
  digest = ok ? build_->digest : 0;
  return done;
}

void LiveLoop::wait_for_switch() {
  ARDCELL_CHECK(!options_.wall,
                "LiveLoop::wait_for_switch: a wall switches in step, frame by frame");
  while (builder_busy_) {
    if (build_ && build_->thread.joinable()) build_->thread.join();
    poll_build();
  }
}

void LiveLoop::poll_build() {
  // A wall's screens switch together: in the frame where every screen's build is done.
  if (!builder_busy_) return;
  if (options_.wall ? !wall_build_done_ : !build_->done.load(std::memory_order_acquire)) return;
  wall_build_done_ = false;
  if (build_->thread.joinable()) build_->thread.join();
  builder_busy_ = false;
  std::shared_ptr<Build> b = std::move(build_);
  // What the switch's outcome prints counts as caused by whoever asked for it.
  const bool outer_cause = std::exchange(remote_cause_, b->remote);
  Status status = b->status;
  if (status && options_.wall && !wall_build_ok_)
    status = Status::error(b->name + ": another screen of the wall could not load it");
  if (status && options_.wall && !wall_build_same_)
    status = Status::error(b->name +
                           ": the screens of the wall loaded different presets by that name "
                           "(expected the same preset files on every screen)");
  if (status && options_.wall && pending_preset_.empty() &&
      !options_.wall->regrid(b->preset.scene.size))
    status = Status::error(b->name + ": its " + std::to_string(b->preset.scene.size.x) + "x" +
                           std::to_string(b->preset.scene.size.y) +
                           " grid leaves a screen of the wall no cell");
  if (!status) {
    // A bad preset never takes the running one down: keep it, say why.
    ++preset_errors_;
    notice("keeping %s: %s", preset_.scene.name.c_str(), status.message().c_str());
  } else if (pending_preset_.empty()) {
    begin_switch(std::move(b->sim), std::move(b->preset));
  }
  if (!pending_preset_.empty()) {
    remote_cause_ = pending_remote_;
    request_preset(std::exchange(pending_preset_, std::string()));
  }
  remote_cause_ = outer_cause;
}

void LiveLoop::begin_switch(std::unique_ptr<LiveSimulation> sim, Preset next) {
  fade_frames_ = std::max(0, options_.crossfade_frames);
  fade_frame_ = 0;
  fade_from_ = preset_;
  fade_to_ = next;
  if (presets_share_structure(preset_, next) && fade_frames_ > 0) {
    // Same grid and models: keep the running simulation and glide its parameters across.
    image_fade_ = false;
  } else {
    image_fade_ = fade_frames_ > 0;
    if (!presented_) present_and_record();  // the pipeline's last frame of the old preset
    fade_image_ = image_;                   // frozen last image of the old preset
    sim_ = std::move(sim);
    preset_ = next;
    size_image();
  }
  quality_.set_bounds(bounds_for(next));
  quality_.restore_full();
  if (fade_frames_ == 0) preset_ = next;
  applied_ = preset_.scene;
  apply_level();
  hud_.preset.fill(0);
  std::snprintf(hud_.preset.data(), hud_.preset.size(), "%s", next.scene.name.c_str());
  std::snprintf(hud_.backend.data(), hud_.backend.size(), "%.*s", int(sim_->backend().size()),
                sim_->backend().data());
  notice("preset %s", next.scene.name.c_str());
}

void LiveLoop::start_recording(std::string path) {
  if (recorder_) return;
  if (!options_.recorder) {
    notice("recording is not available in this build");
    return;
  }
  if (path.empty()) {
    char buf[64];
    const std::time_t t = std::time(nullptr);
    std::tm tm{};
    localtime_r(&t, &tm);
    std::strftime(buf, sizeof buf, "ardcell-%Y%m%d-%H%M%S.y4m", &tm);
    path = options_.screenshot_dir + "/" + buf;
  }
  Status s = Status::ok();
  const double fps = options_.fps > 0 ? options_.fps : 60.0;
  auto writer = options_.recorder(path, Int2{image_.width, image_.height}, fps, s);
  if (!writer) {
    notice("record %s: %s", path.c_str(), s.message().c_str());
    return;
  }
  auto r = std::make_unique<Recorder>();
  r->writer = std::move(writer);
  r->path = path;
  r->written = &recorded_frames_;
  r->slots.resize(size_t(std::max(2, options_.record_slots)));
  for (ImageRgb8& slot : r->slots) slot.resize(image_.width, image_.height);
  Recorder* raw = r.get();
  r->thread = std::thread([raw] { raw->run(); });
  recorder_ = std::move(r);
  hud_.recording = true;
  notice("recording to %s", path.c_str());
}

void LiveLoop::stop_recording() {
  if (!recorder_) return;
  const Status s = recorder_->close();
  const std::string path = recorder_->path;
  recorder_.reset();
  hud_.recording = false;
  if (s)
    notice("recorded %s", path.c_str());
  else
    notice("record %s: %s", path.c_str(), s.message().c_str());
}

void LiveLoop::take_screenshot(std::string path) {
  if (!options_.screenshotter) {
    notice("screenshots are not available in this build");
    return;
  }
  if (path.empty()) {
    char buf[64];
    const std::time_t t = std::time(nullptr);
    std::tm tm{};
    localtime_r(&t, &tm);
    std::strftime(buf, sizeof buf, "ardcell-%Y%m%d-%H%M%S", &tm);
    path =
        options_.screenshot_dir + "/" + buf + "-" + std::to_string(screenshot_counter_++) + ".png";
  }
  const ImageRgb8* shot = &image_;
  if (options_.wall) {  // every screen's view, written by screen 0
    if (!options_.wall->gather_image(image_, wall_shot_)) return;
    shot = &wall_shot_;
  }
  Status s = Status::ok();
  auto writer = options_.screenshotter(path, Int2{shot->width, shot->height}, 0, s);
  if (writer) s = writer->write(*shot);
  if (writer && s) s = writer->finish();
  if (s)
    notice("screenshot %s", path.c_str());
  else
    notice("screenshot %s: %s", path.c_str(), s.message().c_str());
}

bool LiveLoop::run_frame() {
  const bool stop = options_.stop && options_.stop->load(std::memory_order_relaxed);
  // On a wall a stop reaches every screen with the frame's input (share_wall_input).
  if (stop && !options_.wall) quit_ = true;
  if (quit_) return false;
  clock_.begin_frame();
  if (take_report_request()) clock_.print_report(options_.log ? options_.log : stderr);

  // Input: window events, commands from every source, strokes.
  display_.poll(input_, commands_);
  const double now = double(clock_.frame_begin_ns()) * 1e-9;
  if (options_.wall) {
    share_wall_input(stop, now);
    remote_log_.tick();
  } else {
    bool activity = false;
    LiveCommand c;
    while (commands_.pop(c)) {
      if (c.kind == LiveCommandKind::kInputActivity) activity = true;
      remote_cause_ = c.remote;
      handle(c);
      remote_cause_ = false;
    }
    remote_log_.tick();
    size_t n = input_.pop_many(samples_);
    n += remote_input_.pop_many(std::span(samples_).subspan(n));
    activity = activity || n > 0;
    if (attract_) n += attract_->update(now, activity, std::span(samples_).subspan(n));
    hud_.attract = attract_ && attract_->active();
    if (n > 0) {
      sim_->paint(std::span<const StrokeSample>(samples_.data(), n), preset_.input, 0);
      painted_samples_ += int64_t(n);
    }
  }
  clock_.mark(FrameStage::kInput);

  // Simulate (a parameter fade advances first, so the step uses the blended values).
  poll_build();
  if (fading() && !image_fade_) {
    ++fade_frame_;
    blend_params(fade_from_, fade_to_, double(fade_frame_) / fade_frames_, preset_);
    if (!fading()) preset_ = fade_to_;
    applied_ = preset_.scene;
    apply_level();
  }
  if (options_.pipeline) {
    // The step on its thread; meanwhile the frame rendered before goes to the display.
    if (!paused_) {
      if (!stepper_) stepper_ = std::make_unique<Stepper>();
      stepper_->start(*sim_);
    }
    if (!presented_) present_and_record();
    if (!paused_) stepper_->wait();
  } else if (!paused_) {
    sim_->step();
  }
  if (options_.wall && options_.wall->mirrored() && frame_ % LiveWall::kCheckFrames == 0)
    keep_wall_in_step();
  clock_.mark(FrameStage::kSimulate);

  render();
  if (fading() && image_fade_) {
    ++fade_frame_;
    crossfade_images(fade_image_, double(fade_frame_) / fade_frames_, image_);
  }
  clock_.mark(FrameStage::kRender);
  presented_ = false;
  if (!options_.pipeline) present_and_record();

  ++frame_;
  const int64_t work = clock_.elapsed_in_frame_ns();
  if (quality_.update(work, clock_.period_ns())) apply_level();
  clock_.end_frame_and_wait();
  heartbeat_.fetch_add(1, std::memory_order_relaxed);
  if (options_.max_frames > 0 && frame_ >= options_.max_frames) quit_ = true;
  return !quit_;
}

void LiveLoop::present_and_record() {
  hud_.fps = clock_.recent_fps();
  hud_.p50_ms = double(clock_.recent_percentile_ns(0.5)) * 1e-6;
  hud_.p99_ms = double(clock_.recent_percentile_ns(0.99)) * 1e-6;
  hud_.misses = clock_.misses();
  hud_.frame = frame_;
  hud_.sweeps = quality_.level().sweeps;
  hud_.rd_scale = quality_.level().rd_scale;
  hud_.paused = paused_;
  if (frame_ > hud_.message_until_frame) hud_.message[0] = '\0';
  if (options_.wall) options_.wall->before_present();
  display_.present(image_, options_.hud ? &hud_ : nullptr);
  clock_.mark(FrameStage::kPresent);
  if (recorder_) {
    if (recorder_->push(image_)) ++record_stalls_;
  }
  clock_.mark(FrameStage::kRecord);
  presented_ = true;
}

Status LiveLoop::run() {
  if (!sim_) return Status::error("live: no preset started");
  while (run_frame()) {
  }
  if (!presented_) present_and_record();  // the pipeline's last frame
  abandon_switch();                       // quitting never waits for a preset still loading
  // --screenshot: the window's pixels; a wall's, every screen's frame (not its window, whose
  // size and letterbox are its own) placed as the views lie, written by screen 0. Every screen
  // takes part in the gather, also one not given --screenshot (a wall started with other flags
  // on some screens must not leave them waiting).
  ImageRgb8 shot;
  bool write = !options_.exit_screenshot.empty();
  if (options_.wall)
    write = options_.wall->gather_image(image_, shot) && write;
  else if (write && !display_.read_back(shot))
    shot = image_;
  if (write) {
    Status s = Status::ok();
    auto writer =
        options_.screenshotter
            ? options_.screenshotter(options_.exit_screenshot, Int2{shot.width, shot.height}, 0, s)
            : nullptr;
    if (writer) s = writer->write(shot);
    if (writer && s) s = writer->finish();
    if (!writer && s) s = Status::error("screenshots are not available in this build");
    if (!s) return Status::error(options_.exit_screenshot + ": " + s.message());
  }
  stop_recording();
  remote_log_.finish();
  if (options_.log) clock_.print_report(options_.log);
  return Status::ok();
}

void LiveLoop::abandon_switch() {
  if (!builder_busy_) return;
  pending_preset_.clear();
  builder_busy_ = false;
  std::shared_ptr<Build> b = std::move(build_);
  if (b->done.load(std::memory_order_acquire)) {
    if (b->thread.joinable()) b->thread.join();
    return;
  }
  // Quitting never waits for a load: the thread runs on, detached, and frees the build.
  b->cancelled.store(true);
  b->thread.detach();
  switch_abandoned_ = true;
  const bool outer_cause = std::exchange(remote_cause_, b->remote);
  notice("quit without waiting for preset %s (still loading)", b->name.c_str());
  remote_cause_ = outer_cause;
}

}  // namespace ardcell
