// The live loop's commands: the queue every source pushes to, and what each command does
// (LiveLoop::handle); on a video wall, every screen's input handled alike (share_wall_input).
#include "host/live/live_loop.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "host/live/attract_mode.h"
#include "host/live/live_wall.h"

namespace ardcell {

LiveCommand LiveCommand::make(LiveCommandKind k, double value, int param) {
  LiveCommand c;
  c.kind = k;
  c.value = value;
  c.param = param;
  return c;
}

LiveCommand LiveCommand::with_text(LiveCommandKind k, std::string_view text) {
  LiveCommand c;
  c.kind = k;
  const size_t n = std::min(text.size(), c.text.size() - 1);
  std::memcpy(c.text.data(), text.data(), n);
  c.text[n] = '\0';
  return c;
}

void CommandQueue::lock() {
  while (busy_.test_and_set(std::memory_order_acquire)) {
  }
}

bool CommandQueue::push(const LiveCommand& c) {
  lock();
  const bool ok = count_ < kCapacity;
  if (ok) {
    slots_[(head_ + count_) % kCapacity] = c;
    ++count_;
  }
  unlock();
  if (!ok) dropped_.fetch_add(1, std::memory_order_relaxed);
  return ok;
}

bool CommandQueue::pop(LiveCommand& c) {
  lock();
  const bool ok = count_ > 0;
  if (ok) {
    c = slots_[head_];
    head_ = (head_ + 1) % kCapacity;
    --count_;
  }
  unlock();
  return ok;
}

void LiveLoop::handle(const LiveCommand& c) {
  // A split wall keeps the preset its blocks were cut for; no wall records.
  if (options_.wall) {
    switch (c.kind) {
      case LiveCommandKind::kNextPreset:
      case LiveCommandKind::kPrevPreset:
      case LiveCommandKind::kSelectPreset:
        if (options_.wall->mirrored()) break;
        notice("a wall of blocks keeps its preset (start the wall again to change it)");
        return;
      case LiveCommandKind::kRecordStart:
      case LiveCommandKind::kToggleRecord:
        notice("recording: not on a wall (record a screen's output instead)");
        return;
      default:
        break;
    }
  }
  const auto& names = options_.playlist;
  switch (c.kind) {
    case LiveCommandKind::kQuit:
      quit_ = true;
      break;
    case LiveCommandKind::kNextPreset:
    case LiveCommandKind::kPrevPreset:
      if (names.empty()) {
        notice("no preset playlist");
        break;
      }
      playlist_index_ = (playlist_index_ + (c.kind == LiveCommandKind::kNextPreset ? 1 : -1) +
                         int(names.size())) %
                        int(names.size());
      request_preset(names[size_t(playlist_index_)]);
      break;
    case LiveCommandKind::kSelectPreset:
      request_preset(c.text.data());
      break;
    case LiveCommandKind::kReset:
      sim_->reset();
      break;
    case LiveCommandKind::kTogglePause:
      paused_ = !paused_;
      break;
    case LiveCommandKind::kSetPause:
      paused_ = c.value != 0;
      break;
    case LiveCommandKind::kSetParam: {
      const auto params = preset_params();
      if (c.param < 0 || size_t(c.param) >= params.size()) break;
      const ParamSpec& spec = params[size_t(c.param)];
      if (spec.structural) {
        notice("%.*s: changes the grid or models; switch presets instead", int(spec.key.size()),
               spec.key.data());
        break;
      }
      char why[160] = "";
      Preset& target = fading() && !image_fade_ ? fade_to_ : preset_;
      if (!(c.value >= spec.min && c.value <= spec.max) || !spec.set) {
        std::snprintf(why, sizeof why, "%.*s: out of range", int(spec.key.size()), spec.key.data());
        notice("%s", why);
        break;
      }
      (void)set_param(target, spec, c.value);
      if (spec.key.starts_with("quality.")) quality_.set_bounds(bounds_for(preset_));
      applied_ = preset_.scene;
      apply_level();
      break;
    }
    case LiveCommandKind::kSetMode: {
      const ParamSpec* mode = find_param("input.mode");
      if (mode) (void)set_param(preset_, *mode, c.value);
      break;
    }
    case LiveCommandKind::kNextMode: {
      const ParamSpec* mode = find_param("input.mode");
      if (!mode) break;
      const double next = std::fmod(get_param(preset_, *mode) + 1, mode->max + 1);
      (void)set_param(preset_, *mode, next);
      notice("mode %s", preset_.input.mode.c_str());
      break;
    }
    case LiveCommandKind::kScreenshot: {
      // A remote sender gets one screenshot a second: a flood must not fill the disk. A wall's
      // screens count frames (at a nominal 60 Hz, whatever each paces at), so that all of them
      // decide alike and gather the screenshot together.
      const int64_t now = options_.wall ? frame_ * kWallFrameNs : clock_.frame_begin_ns();
      if (c.remote && last_remote_screenshot_ns_ >= 0 &&
          now - last_remote_screenshot_ns_ < kRemoteScreenshotIntervalNs) {
        notice("screenshot refused: remote commands get at most one a second");
        break;
      }
      if (c.remote) last_remote_screenshot_ns_ = now;
      take_screenshot(c.text.data());
      break;
    }
    case LiveCommandKind::kRecordStart:
      start_recording(c.text.data());
      break;
    case LiveCommandKind::kRecordStop:
      stop_recording();
      break;
    case LiveCommandKind::kToggleRecord:
      if (recorder_)
        stop_recording();
      else
        start_recording(options_.record_path);
      break;
    case LiveCommandKind::kToggleHud:
      options_.hud = !options_.hud;
      break;
    case LiveCommandKind::kInputActivity:
      break;
  }
}

void LiveLoop::share_wall_input(bool stop, double now) {
  LiveWall& wall = *options_.wall;
  WallInput& mine = *wall_input_;
  // The attract mode's strokes of the last frame (screen 0) lead this screen's samples.
  mine.samples = wall_attract_samples_;
  mine.commands = 0;
  mine.stop = stop;
  mine.activity = false;
  mine.build_done = build_finished(mine.build_ok, mine.build_digest);
  LiveCommand c;
  while (mine.commands < WallInput::kMaxCommands && commands_.pop(c)) {
    if (c.kind == LiveCommandKind::kInputActivity)
      mine.activity = true;
    else
      mine.command[size_t(mine.commands++)] = c;
  }
  // This screen's pointer strokes, normalised to its view, normalised to the grid (y from the
  // top); a sample off the view (a drag past the window's edge) lifts the pen rather than paint
  // another screen's cells. Remote strokes (OSC) come normalised to the whole canvas already.
  const Box2 view = wall.view();
  const Int2 grid = wall.grid();
  const std::span<StrokeSample> free = std::span(mine.sample).subspan(size_t(mine.samples));
  size_t n = input_.pop_many(free);
  for (size_t i = 0; i < n; ++i) {
    StrokeSample& s = free[i];
    if (!(s.x >= 0.0f && s.x <= 1.0f && s.y >= 0.0f && s.y <= 1.0f)) {
      s.buttons = 0;
      s.pressure = 0.0f;
      s.in_range = false;
    }
    s.x = float((view.min.x + double(s.x) * view.width()) / grid.x);
    s.y = float((grid.y - view.max.y + double(s.y) * view.height()) / grid.y);
  }
  n += remote_input_.pop_many(free.subspan(n));
  mine.samples += int(n);
  mine.activity = mine.activity || n > 0;

  const std::span<const WallInput> all = wall.share(mine);
  // Whether every screen's preset switch is ready (poll_build switches then, on every screen).
  wall_build_done_ = wall_build_ok_ = wall_build_same_ = true;
  for (const WallInput& in : all) {
    wall_build_done_ = wall_build_done_ && in.build_done;
    wall_build_ok_ = wall_build_ok_ && in.build_ok;
    wall_build_same_ = wall_build_same_ && in.build_digest == all[0].build_digest;
  }
  bool activity = false;
  for (const WallInput& in : all) {
    if (in.stop) quit_ = true;
    activity = activity || in.activity;
    for (int k = 0; k < in.commands; ++k) {
      remote_cause_ = in.command[size_t(k)].remote;
      handle(in.command[size_t(k)]);
      remote_cause_ = false;
    }
  }
  for (size_t screen = 0; screen < all.size(); ++screen) {
    const WallInput& in = all[screen];
    if (in.samples <= 0) continue;
    sim_->paint(std::span(in.sample).first(size_t(in.samples)), preset_.input, int(screen));
    painted_samples_ += in.samples;
  }
  // Screen 0's attract mode, idle when no screen was used: its strokes (normalised to the whole
  // canvas, the grid) reach every screen with the next frame's input.
  wall_attract_samples_ = 0;
  if (attract_ && wall.screen() == 0)
    wall_attract_samples_ = int(attract_->update(
        now, activity, std::span(mine.sample).first(size_t(WallInput::kMaxSamples / 2))));
  hud_.attract = attract_ && attract_->active();
}

void LiveLoop::keep_wall_in_step() {
  LiveWall& wall = *options_.wall;
  const int drifted = wall.first_drifted(state_fingerprint(sim_->state()));
  if (drifted < 0) return;
  wall.send_state(sim_->state_to_write());
  // The first drift is said; screens that keep drifting (other CPUs or GPUs) are counted
  // (wall_resyncs(), printed when the wall ends).
  if (wall_resyncs_++ == 0)
    notice(
        "wall: screen %d drifted from screen 0 by frame %lld (rounding on another CPU or GPU); "
        "every screen goes on from screen 0's state",
        drifted, static_cast<long long>(frame_ + 1));
}

}  // namespace ardcell
