#include "host/live_loop.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <new>

#include "host/attract_mode.h"

// Counts heap allocations made by this process, so the steady-state frame can be checked.

#include "tests/support/alloc_counter.h"

namespace ardcell {
namespace {

class FakeTime final : public TimeSource {
 public:
  int64_t now_ns() override { return now; }
  void sleep_until_ns(int64_t d) override {
    if (d > now) now = d;
  }
  int64_t now = 1'000'000'000;
};

// A small "simulation": dye decays and paint deposits. Each step costs fake time in
// proportion to the solver iterations it was told to run, plus an artificial load.
class FakeSimulation final : public LiveSimulation {
 public:
  FakeSimulation(const Preset& p, FakeTime* time) : time_(time) {
    state_.size = p.scene.size;
    state_.dye = FieldF(p.scene.size, 1);
    config_ = p.scene;
    reset();
  }
  void step() override {
    ++steps;
    for (int y = 0; y < state_.size.y; ++y)
      for (int x = 0; x < state_.size.x; ++x) state_.dye(x, y) *= float(1.0 - config_.dt);
    if (time_)
      time_->now +=
          int64_t(config_.fluid.pressure_solver.max_iterations) * per_iteration_ns + *extra_load_ns;
  }
  void reset() override {
    ++resets;
    for (int y = 0; y < state_.size.y; ++y)
      for (int x = 0; x < state_.size.x; ++x) state_.dye(x, y) = float(x) / float(state_.size.x);
  }
  const SimState& state() const override { return state_; }
  void apply(const SceneConfig& c) override { config_ = c; }
  void paint(std::span<const StrokeSample> samples, const InputMapping&) override {
    for (const StrokeSample& s : samples) {
      ++painted;
      const int x = int(s.x * float(state_.size.x)), y = int(s.y * float(state_.size.y));
      if (x >= 0 && y >= 0 && x < state_.size.x && y < state_.size.y) state_.dye(x, y) = 1.0f;
    }
  }
  std::string_view backend() const override { return "fake"; }

  SceneConfig config_;
  int64_t steps = 0, resets = 0, painted = 0;
  int64_t per_iteration_ns = 500'000;
  const int64_t* extra_load_ns = &zero_;

 private:
  static constexpr int64_t zero_ = 0;
  FakeTime* time_;
  SimState state_;
};

class MemoryDisplay final : public LiveDisplay {
 public:
  void poll(StrokeRing&, CommandQueue&) override { ++polls; }
  void present(const ImageRgb8& frame, const HudInfo* hud) override {
    ++presents;
    last_size = {frame.width, frame.height};
    hud_shown = hud != nullptr;
  }
  int64_t polls = 0, presents = 0;
  Int2 last_size{};
  bool hud_shown = false;
};

class MemoryWriter final : public FrameWriter {
 public:
  explicit MemoryWriter(std::vector<ImageRgb8>* frames) : frames_(frames) {}
  Status write(const ImageRgb8& f) override {
    frames_->push_back(f);
    return Status::ok();
  }
  Status finish() override { return Status::ok(); }
  std::vector<ImageRgb8>* frames_;
};

struct Fixture {
  std::filesystem::path dir;
  FakeTime time;
  MemoryDisplay display;
  FakeSimulation* sim = nullptr;  // the latest one built
  int64_t extra_load = 0;

  Fixture() {
    dir = std::filesystem::temp_directory_path() /
          ("ardcell_live_loop_test_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    write("small.toml",
          "[grid]\nsize = [16, 16]\ndt = 0.01\n[fluid.pressure_solver]\n"
          "iterations = 20\n[quality]\nmin_sweeps = 2\nmax_sweeps = 20\n");
    write("small_thick.toml",
          "[grid]\nsize = [16, 16]\ndt = 0.05\n[fluid]\nviscosity = 1.0\n"
          "[fluid.pressure_solver]\niterations = 20\n");
    write("large.toml", "[grid]\nsize = [32, 24]\n[output]\ncolormap = \"magma\"\n");
    write("broken.toml", "[grid]\nsize = [16, 16]\ndt = \"soon\"\n");
  }
  ~Fixture() { std::filesystem::remove_all(dir); }
  void write(const std::string& name, const std::string& text) {
    std::ofstream(dir / name) << text;
  }
  std::string path(const std::string& name) const { return (dir / name).string(); }

  LiveOptions options(double fps = 60) {
    LiveOptions o;
    o.fps = fps;
    o.time = &time;
    o.log = nullptr;
    o.crossfade_frames = 10;
    return o;
  }
  SimulationFactory factory() {
    return [this](const Preset& p) {
      auto s = std::make_unique<FakeSimulation>(p, &time);
      s->extra_load_ns = &extra_load;
      sim = s.get();
      return s;
    };
  }
};

TEST(LiveLoop, RendersFramesAndCountsThem) {
  Fixture fx;
  LiveOptions o = fx.options();
  o.max_frames = 25;
  LiveLoop loop(o, fx.factory(), fx.display);
  ASSERT_TRUE(loop.start(fx.path("small.toml")).is_ok());
  ASSERT_TRUE(loop.run().is_ok());
  EXPECT_EQ(loop.frames(), 25);
  EXPECT_EQ(fx.sim->steps, 25);
  EXPECT_EQ(fx.display.presents, 25);
  EXPECT_EQ(fx.display.last_size, (Int2{16, 16}));
  EXPECT_EQ(loop.clock().misses(), 0);  // 10 ms of fake work in a 16.7 ms frame
  EXPECT_EQ(loop.heartbeat().load(), 25);
}

TEST(LiveLoop, ParameterChangeAppliesOnTheNextFrame) {
  Fixture fx;
  LiveLoop loop(fx.options(), fx.factory(), fx.display);
  ASSERT_TRUE(loop.start(fx.path("small.toml")).is_ok());
  loop.run_frame();
  const ParamSpec* visc = find_param("fluid.viscosity");
  const int index = int(visc - preset_params().data());
  loop.commands().push(LiveCommand::make(LiveCommandKind::kSetParam, 0.25, index));
  const int64_t steps = fx.sim->steps;
  loop.run_frame();
  EXPECT_EQ(fx.sim->config_.fluid.viscosity, 0.25);
  EXPECT_EQ(fx.sim->steps, steps + 1);  // no stall, the frame still stepped
  // Out of range: refused with a message, value kept.
  loop.commands().push(LiveCommand::make(LiveCommandKind::kSetParam, -5, index));
  loop.run_frame();
  EXPECT_EQ(fx.sim->config_.fluid.viscosity, 0.25);
  EXPECT_NE(loop.last_message().find("fluid.viscosity"), std::string::npos);
}

TEST(LiveLoop, HotSwitchUnderARunningLoopCrossfadesTheImage) {
  Fixture fx;
  LiveOptions o = fx.options();
  o.playlist = {fx.path("small.toml"), fx.path("large.toml"), fx.path("broken.toml")};
  LiveLoop loop(o, fx.factory(), fx.display);
  ASSERT_TRUE(loop.start(fx.path("small.toml")).is_ok());
  for (int i = 0; i < 5; ++i) loop.run_frame();
  FakeSimulation* old_sim = fx.sim;
  loop.commands().push(LiveCommand::make(LiveCommandKind::kNextPreset));
  loop.run_frame();  // the request is taken; the old preset keeps running meanwhile
  loop.wait_for_switch();
  EXPECT_NE(fx.sim, old_sim);
  loop.run_frame();
  ASSERT_TRUE(loop.fading());
  EXPECT_EQ(fx.display.last_size, (Int2{32, 24}));
  // Mid-fade the image is neither the old frame nor the new one alone.
  ImageRgb8 pure(loop.image());
  render_state(loop.simulation().state(), loop.preset().scene.output, pure);
  EXPECT_NE(pure.rgb, loop.image().rgb);
  for (int i = 0; i < 12; ++i) loop.run_frame();
  EXPECT_FALSE(loop.fading());
  render_state(loop.simulation().state(), loop.preset().scene.output, pure);
  EXPECT_EQ(pure.rgb, loop.image().rgb);
  EXPECT_EQ(std::string(loop.hud().preset.data()), "large");

  // A broken preset is refused; the current one keeps running.
  loop.commands().push(LiveCommand::make(LiveCommandKind::kNextPreset));
  loop.run_frame();
  loop.wait_for_switch();
  const int64_t steps = fx.sim->steps;
  loop.run_frame();
  EXPECT_EQ(loop.preset_errors(), 1);
  EXPECT_EQ(loop.preset().scene.name, "large");
  EXPECT_EQ(fx.sim->steps, steps + 1);
  EXPECT_NE(loop.last_message().find("broken.toml:3: grid.dt: expected a number"),
            std::string::npos)
      << loop.last_message();
}

TEST(LiveLoop, SameGridSwitchGlidesParameters) {
  Fixture fx;
  LiveLoop loop(fx.options(), fx.factory(), fx.display);
  ASSERT_TRUE(loop.start(fx.path("small.toml")).is_ok());
  loop.run_frame();
  FakeSimulation* sim = fx.sim;
  loop.commands().push(
      LiveCommand::with_text(LiveCommandKind::kSelectPreset, fx.path("small_thick.toml")));
  loop.run_frame();
  loop.wait_for_switch();
  std::vector<double> dts;
  for (int i = 0; i < 12; ++i) {
    loop.run_frame();
    dts.push_back(sim->config_.dt);
  }
  // The same simulation object, its dt rising monotonically from 0.01 to 0.05.
  EXPECT_EQ(&loop.simulation(), sim);
  EXPECT_GT(dts.front(), 0.01);
  EXPECT_LT(dts.front(), 0.05);
  for (size_t i = 1; i < dts.size(); ++i) EXPECT_GE(dts[i], dts[i - 1]);
  EXPECT_DOUBLE_EQ(dts.back(), 0.05);
  EXPECT_EQ(loop.preset().scene.fluid.viscosity, 1.0);
}

TEST(LiveLoop, AdaptiveQualityLowersSweepsUnderLoadAndRestoresThem) {
  Fixture fx;
  LiveLoop loop(fx.options(), fx.factory(), fx.display);
  ASSERT_TRUE(loop.start(fx.path("small.toml")).is_ok());
  for (int i = 0; i < 10; ++i) loop.run_frame();
  EXPECT_EQ(fx.sim->config_.fluid.pressure_solver.max_iterations, 20);
  fx.extra_load = 12'000'000;  // an artificial 12 ms on top of 10 ms
  for (int i = 0; i < 100; ++i) loop.run_frame();
  const int lowered = fx.sim->config_.fluid.pressure_solver.max_iterations;
  EXPECT_LT(lowered, 20);
  EXPECT_LT(loop.quality().level().sweeps, 20);
  const int64_t misses = loop.clock().misses();
  for (int i = 0; i < 20; ++i) loop.run_frame();
  EXPECT_EQ(loop.clock().misses(), misses);  // settled inside the deadline
  fx.extra_load = 0;
  for (int i = 0; i < 600; ++i) loop.run_frame();
  EXPECT_EQ(fx.sim->config_.fluid.pressure_solver.max_iterations, 20);
}

TEST(LiveLoop, InjectedSlowFrameIsAMiss) {
  Fixture fx;
  LiveOptions o = fx.options();
  o.adaptive = false;
  LiveLoop loop(o, fx.factory(), fx.display);
  ASSERT_TRUE(loop.start(fx.path("small.toml")).is_ok());
  for (int i = 0; i < 5; ++i) loop.run_frame();
  fx.extra_load = 40'000'000;
  loop.run_frame();
  fx.extra_load = 0;
  for (int i = 0; i < 5; ++i) loop.run_frame();
  EXPECT_EQ(loop.clock().misses(), 1);
}

TEST(LiveLoop, RecordingKeepsEveryFrame) {
  Fixture fx;
  std::vector<ImageRgb8> frames;
  frames.reserve(100);
  LiveOptions o = fx.options();
  o.max_frames = 40;
  o.record_path = "mem";
  o.record_slots = 2;
  o.recorder = [&](const std::string&, Int2, double, Status&) {
    return std::make_unique<MemoryWriter>(&frames);
  };
  LiveLoop loop(o, fx.factory(), fx.display);
  ASSERT_TRUE(loop.start(fx.path("small.toml")).is_ok());
  ASSERT_TRUE(loop.run().is_ok());
  ASSERT_EQ(frames.size(), 40u);
  EXPECT_EQ(fx.sim->steps, 40);
  // The last recorded frame is the last frame shown.
  EXPECT_EQ(frames.back().rgb, loop.image().rgb);
  EXPECT_NE(frames.front().rgb, frames.back().rgb);
}

TEST(LiveLoop, PauseResetAndStrokes) {
  Fixture fx;
  LiveLoop loop(fx.options(), fx.factory(), fx.display);
  ASSERT_TRUE(loop.start(fx.path("small.toml")).is_ok());
  loop.commands().push(LiveCommand::make(LiveCommandKind::kTogglePause));
  loop.run_frame();
  EXPECT_EQ(fx.sim->steps, 0);
  StrokeSample s;
  s.x = 0.5f;
  s.y = 0.5f;
  s.pressure = 1;
  s.buttons = kButtonTip;
  loop.input().push(s);
  loop.run_frame();  // painting works while paused
  EXPECT_EQ(fx.sim->painted, 1);
  loop.commands().push(LiveCommand::make(LiveCommandKind::kTogglePause));
  loop.commands().push(LiveCommand::make(LiveCommandKind::kReset));
  loop.run_frame();
  EXPECT_EQ(fx.sim->resets, 2);
  EXPECT_EQ(fx.sim->steps, 1);
  loop.commands().push(LiveCommand::make(LiveCommandKind::kNextMode));
  loop.run_frame();
  EXPECT_EQ(loop.preset().input.mode, "orient");
}

// Kiosk soak: 100 000 frames at 16 x 16 with the attract mode replaying strokes. After the
// warm-up no frame allocates, and no value goes NaN.
TEST(LiveLoop, SoakWithAttractModeAllocatesNothingAndStaysFinite) {
  Fixture fx;
  LiveOptions o = fx.options();
  o.hud = true;
  LiveLoop loop(o, fx.factory(), fx.display);
  ASSERT_TRUE(loop.start(fx.path("small.toml")).is_ok());
  AttractMode attract(2.0, 0.5);
  std::vector<StrokeSample> stroke;
  for (int i = 0; i < 60; ++i) {
    StrokeSample s;
    s.time = i / 60.0;
    s.x = float(0.1 + 0.8 * i / 60.0);
    s.y = float(0.5 + 0.3 * std::sin(i / 10.0));
    s.pressure = 1;
    s.buttons = kButtonTip;
    s.in_range = true;
    stroke.push_back(s);
  }
  attract.add_recording(stroke, "wave");
  loop.set_attract_mode(&attract);
  for (int i = 0; i < 1000; ++i) loop.run_frame();
  const int64_t before = g_allocations.load();
  const int64_t painted_before = fx.sim->painted;
  bool finite = true;
  for (int i = 0; i < 100'000; ++i) {
    loop.run_frame();
    if (i % 997 == 0) {
      const FieldF& d = loop.simulation().state().dye;
      for (int y = 0; y < d.ny(); ++y)
        for (int x = 0; x < d.nx(); ++x) finite = finite && std::isfinite(d(x, y));
    }
  }
  EXPECT_EQ(g_allocations.load() - before, 0);
  EXPECT_TRUE(finite);
  EXPECT_GT(attract.activations(), 0);
  EXPECT_GT(fx.sim->painted - painted_before, 10'000);  // the replay kept painting
  EXPECT_EQ(loop.clock().misses(), 0);
}

TEST(AttractMode, StartsAfterIdleAndStopsAtOnceOnInput) {
  AttractMode attract(5.0, 1.0);
  std::vector<StrokeSample> rec(3);
  for (int i = 0; i < 3; ++i) {
    rec[size_t(i)].time = 10.0 + i * 0.5;
    rec[size_t(i)].x = 0.1f * float(i);
    rec[size_t(i)].buttons = kButtonTip;
  }
  attract.add_recording(rec, "r");
  std::array<StrokeSample, 8> out;
  EXPECT_EQ(attract.update(0.0, false, out), 0u);
  EXPECT_EQ(attract.update(4.9, false, out), 0u);
  EXPECT_FALSE(attract.active());
  EXPECT_EQ(attract.update(5.0, false, out), 1u);  // first sample due at once
  EXPECT_TRUE(attract.active());
  EXPECT_EQ(out[0].x, 0.0f);
  EXPECT_EQ(out[0].time, 5.0);
  EXPECT_EQ(attract.update(5.5, false, out), 1u);
  EXPECT_EQ(out[0].x, 0.1f);
  // A touch: replay ends in this frame, the pen is lifted.
  EXPECT_EQ(attract.update(5.6, true, out), 1u);
  EXPECT_FALSE(out[0].touching());
  EXPECT_FALSE(attract.active());
  EXPECT_EQ(attract.update(10.0, false, out), 0u);  // idle counts from the touch
  EXPECT_EQ(attract.update(10.6, false, out), 1u);
  EXPECT_EQ(attract.activations(), 2);
}

TEST(AttractMode, LoadsAFolderAndNamesBadFiles) {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("ardcell_attract_test_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "a.jsonl") << "{\"t\":0,\"x\":0.5,\"y\":0.5,\"buttons\":1}\n"
                                    "{\"t\":0.1,\"x\":0.6,\"y\":0.5,\"buttons\":1}\n";
  std::ofstream(dir / "b.jsonl") << "{\"t\":0,\"x\":\"left\"}\n";
  AttractMode attract(1.0);
  const Status s = attract.load_folder(dir.string());
  EXPECT_FALSE(s.is_ok());
  EXPECT_NE(s.message().find("b.jsonl"), std::string::npos) << s.message();
  EXPECT_EQ(attract.recordings(), 1u);
  std::filesystem::remove_all(dir);
  EXPECT_FALSE(attract.load_folder(dir.string()).is_ok());
}

}  // namespace
}  // namespace ardcell
