#include "host/live/live_loop.h"

#include <gtest/gtest.h>

#include "tests/support/fake_time.h"

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <new>

#include <malloc.h>
#include <unistd.h>

#include "tests/support/sanitizers.h"
#if ARDCELL_TEST_ASAN
// From the sanitizer runtime (sanitizer/allocator_interface.h, which GCC does not install).
extern "C" {
size_t __sanitizer_get_current_allocated_bytes();
int __sanitizer_install_malloc_and_free_hooks(void (*malloc_hook)(const volatile void*, size_t),
                                              void (*free_hook)(const volatile void*));
}
#endif

#include "host/engine/rd_step.h"
#include "host/live/attract_mode.h"
#include "host/live/live_engine.h"
#include "host/paint/stroke_playback.h"
#include "kernels/reaction.h"

// Counts heap allocations made by this process, so the steady-state frame can be checked.
#include "tests/support/alloc_counter.h"

namespace ardcell {
namespace {

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
  SimState& state_to_write() override { return state_; }
  void apply(const SceneConfig& c) override { config_ = c; }
  void paint(std::span<const StrokeSample> samples, const InputMapping&, int) override {
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

// --realtime-solvers: the first preset and every switch run fixed Jacobi sweeps (the preset's
// quality.max_sweeps, tolerance 0) in every solve and the tabulated reaction.
TEST(LiveLoop, RealtimeSolversApplyToEveryPreset) {
  Fixture fx;
  LiveOptions o = fx.options();
  o.realtime_solvers = true;
  o.crossfade_frames = 0;
  LiveLoop loop(o, fx.factory(), fx.display);
  const auto expect_realtime = [](const SceneConfig& s, int sweeps, const char* what) {
    for (const SolverSettings* solver :
         {&s.fluid.viscosity_solver, &s.fluid.pressure_solver, &s.rd.diffusion_solver}) {
      EXPECT_EQ(solver->kind, SolverKind::kJacobi) << what;
      EXPECT_EQ(solver->max_iterations, sweeps) << what;
      EXPECT_EQ(solver->tolerance, 0.0) << what;
    }
    EXPECT_TRUE(s.rd.use_table) << what;
  };
  ASSERT_TRUE(loop.start("cavity-gray-scott").is_ok());  // multigrid and ICCG in the preset
  expect_realtime(fx.sim->config_, 20, "first");
  loop.commands().push(LiveCommand::with_text(LiveCommandKind::kSelectPreset, "space-cookie-5"));
  loop.run_frame();
  loop.wait_for_switch();
  loop.run_frame();
  expect_realtime(fx.sim->config_, 20, "switched");
  // Without the option the preset's own solvers run.
  Fixture plain;
  LiveLoop own(plain.options(), plain.factory(), plain.display);
  ASSERT_TRUE(own.start("cavity-gray-scott").is_ok());
  EXPECT_EQ(plain.sim->config_.fluid.pressure_solver.kind, SolverKind::kMultigrid);
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

// Pipelined (`ardcell live`'s default), the step overlaps the present of the frame before: the
// same frames reach the display and the recording, in the same order, the last one at exit.
TEST(LiveLoop, PipelineShowsAndRecordsTheSameFrames) {
  std::vector<ImageRgb8> recorded[2];
  for (int pipelined = 0; pipelined < 2; ++pipelined) {
    Fixture fx;
    std::vector<ImageRgb8>& frames = recorded[pipelined];
    frames.reserve(64);
    LiveOptions o = fx.options();
    o.time = nullptr;  // the step runs on the pipeline's thread: no shared fake clock
    o.fps = 0;
    o.pipeline = pipelined == 1;
    o.max_frames = 30;
    o.record_path = "mem";
    o.record_slots = 4;
    o.recorder = [&](const std::string&, Int2, double, Status&) {
      return std::make_unique<MemoryWriter>(&frames);
    };
    FakeSimulation* sim = nullptr;
    LiveLoop loop(
        o,
        [&](const Preset& p) {
          auto s = std::make_unique<FakeSimulation>(p, nullptr);
          sim = s.get();
          return s;
        },
        fx.display);
    ASSERT_TRUE(loop.start(fx.path("small.toml")).is_ok());
    StrokeSample dab{};
    dab.x = 0.5f;
    dab.y = 0.25f;
    for (int i = 0; i < 30 && loop.run_frame(); ++i) {
      if (i % 7 == 3) {
        ASSERT_TRUE(loop.input().push(dab));  // painted between steps
      }
    }
    ASSERT_TRUE(loop.run().is_ok());
    EXPECT_EQ(sim->steps, 30);
    EXPECT_EQ(fx.display.presents, 30) << "pipelined " << pipelined;
    ASSERT_EQ(frames.size(), 30u) << "pipelined " << pipelined;
    EXPECT_EQ(frames.back().rgb, loop.image().rgb);
  }
  for (std::size_t i = 0; i < recorded[0].size(); ++i)
    EXPECT_EQ(recorded[0][i].rgb, recorded[1][i].rgb) << "frame " << i;
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

// ---- The real engine (host/live/live_engine.h) ----

// A built-in preset with fluid and RD, shrunk to `n` x `n` cells, as a TOML file; `edit`
// changes it further.
std::string small_engine_preset(Fixture& fx, const std::string& builtin, int n, double min_rd_scale,
                                const std::function<void(Preset&)>& edit = {}) {
  Preset p;
  EXPECT_TRUE(load_preset(builtin, p).is_ok());
  p.scene.size = {n, n};
  p.quality.min_rd_scale = min_rd_scale;
  if (edit) edit(p);
  const std::string name = builtin + "-" + std::to_string(n) + ".toml";
  fx.write(name, preset_to_toml(p));
  return fx.path(name);
}

// One stroke of `count` samples across the middle, pen down all the way, then lifted.
std::vector<StrokeSample> wave_stroke(int count, double seconds) {
  std::vector<StrokeSample> stroke;
  for (int i = 0; i <= count; ++i) {
    StrokeSample s;
    s.time = seconds * i / count;
    s.x = float(0.1 + 0.8 * i / count);
    s.y = float(0.5 + 0.3 * std::sin(i / 10.0));
    s.pressure = float(0.4 + 0.6 * (i % 7) / 6.0);
    s.buttons = i < count ? uint32_t(kButtonTip) : 0u;
    s.in_range = true;
    stroke.push_back(s);
  }
  return stroke;
}

bool all_finite(const SimState& s) {
  bool ok = true;
  s.for_each_field([&](std::string_view, const FieldF& f) {
    for (int y = 0; y < f.ny(); ++y)
      for (int x = 0; x < f.nx(); ++x) ok = ok && std::isfinite(f(x, y));
  });
  return ok;
}

// A and B inside the model's invariant box (kernels/reaction.h), up to float rounding.
bool in_invariant_box(const SimState& s, const ReactionParams& r) {
  const ConcentrationBox box = invariant_box(r);
  const double tol = 1e-5;
  for (int y = 0; y < s.size.y; ++y)
    for (int x = 0; x < s.size.x; ++x) {
      const double a = s.A(x, y), b = s.B(x, y);
      if (!(a >= box.a_lo - tol && a <= box.a_hi + tol && b >= box.b_lo - tol &&
            b <= box.b_hi + tol))
        return false;
    }
  return true;
}

// Every heap block, not only operator new's (Field storage comes from aligned_alloc): under
// AddressSanitizer its malloc hook counts every allocation and it reports the bytes in use;
// elsewhere glibc's mallinfo2 reports the bytes in use.
std::atomic<long> g_mallocs{0};
#if ARDCELL_TEST_ASAN
void count_malloc(const volatile void*, size_t) { g_mallocs.fetch_add(1); }
void ignore_free(const volatile void*) {}
#endif

struct HeapProbe {
  long mallocs = 0;  // under ASan only
  int64_t bytes_in_use = 0;
  static HeapProbe now() {
    HeapProbe h;
#if ARDCELL_TEST_ASAN
    static const bool hooked = __sanitizer_install_malloc_and_free_hooks(count_malloc, ignore_free);
    (void)hooked;
    h.mallocs = g_mallocs.load();
    h.bytes_in_use = int64_t(__sanitizer_get_current_allocated_bytes());
#else
    const struct mallinfo2 m = mallinfo2();
    h.bytes_in_use = int64_t(m.uordblks + m.hblkhd);
#endif
    return h;
  }
};

int64_t resident_bytes() {
  std::ifstream statm("/proc/self/statm");
  int64_t size = 0, resident = 0;
  statm >> size >> resident;
  return resident * int64_t(sysconf(_SC_PAGESIZE));
}

// A clock whose every reading costs `cost_ns`: the frame's measured work grows with what the
// loop does, and the test sets the load (the engine's real time is not looked at).
class LoadedTime final : public TimeSource {
 public:
  int64_t now_ns() override { return now += cost_ns; }
  void sleep_until_ns(int64_t d) override {
    if (d > now) now = d;
  }
  int64_t now = 1'000'000'000;
  int64_t cost_ns = 0;
};

// Kiosk soak: 100 000 frames of the real engine (cavity + Gray-Scott at 16 x 16, the preset
// `ardcell live cavity-gray-scott` runs, shrunk, with fewer solver iterations) with the attract
// mode replaying a recorded stroke in every painting mode in turn, resets, load swings that make
// adaptive quality lower and raise the sweeps and the RD resolution, and preset switches
// between the five 20 000-frame segments. Inside a segment no frame allocates (operator new and,
// under ASan, every malloc), heap bytes in use and the resident set do not grow; every frame,
// every field is finite and A, B stay in the model's invariant box.
TEST(LiveEngine, SoakWithAttractModeIsFlatAndFinite) {
  Fixture fx;
  LoadedTime time;
  LiveOptions o = fx.options();
  o.time = &time;
  o.hud = true;
  o.crossfade_frames = 10;
  // The soak's budget under sanitizers: fewer iterations per solve than the full presets (at
  // 16 x 16 one multigrid V-cycle, whose coarsest grid is solved to convergence, does most of
  // the projection; the viscous solve, diagonally dominant at this viscosity, takes two
  // red-black Gauss-Seidel sweeps instead of V-cycles; three CG iterations for the RD).
  const auto cheaper = [](Preset& p) {
    p.scene.fluid.pressure_solver.max_iterations = 1;
    p.scene.fluid.viscosity_solver.kind = SolverKind::kRedBlackGaussSeidel;
    p.scene.fluid.viscosity_solver.max_iterations = 2;
    p.scene.rd.diffusion_solver.max_iterations = 3;
  };
  o.playlist = {small_engine_preset(fx, "cavity-gray-scott", 16, 0.5, cheaper),
                small_engine_preset(fx, "cavity-fhn", 16, 0.5, cheaper)};
  LiveLoop loop(o, make_engine_simulation, fx.display);
  ASSERT_TRUE(loop.start(o.playlist[0]).is_ok());
  AttractMode attract(2.0, 0.5);
  attract.add_recording(wave_stroke(90, 1.5), "wave");
  loop.set_attract_mode(&attract);

  int64_t frames = 0, bad_frames = 0, coarse_frames = 0, low_sweep_frames = 0;
  int64_t rd_switches = 0;
  double last_scale = 1;
  auto frame = [&] {
    loop.run_frame();
    ++frames;
    const auto& sim = dynamic_cast<const EngineSimulation&>(loop.simulation());
    const SimState& s = sim.state();
    if (!all_finite(s) || !in_invariant_box(s, sim.engine().config().rd.reaction)) ++bad_frames;
    if (sim.rd_scale() < 1) ++coarse_frames;
    if (sim.rd_scale() != last_scale) ++rd_switches;
    last_scale = sim.rd_scale();
    if (loop.quality().level().sweeps < loop.preset().quality.max_sweeps) ++low_sweep_frames;
  };
  auto next_mode = [&] { loop.commands().push(LiveCommand::make(LiveCommandKind::kNextMode)); };
  constexpr int kSegments = 5, kSegmentFrames = 20'000;
  int64_t allocations = 0, mallocs = 0, heap_growth = 0, rss_growth = 0;
  const int64_t rss_begin = resident_bytes();
  const HeapProbe heap_begin = HeapProbe::now();
  const int64_t painted_begin = loop.painted_samples();
  for (int segment = 0; segment < kSegments; ++segment) {
    if (segment > 0) {  // a preset switch: builds an engine (allocates), outside the segment
      loop.commands().push(LiveCommand::make(LiveCommandKind::kNextPreset));
      loop.run_frame();
      loop.wait_for_switch();
    }
    // The crossfade, then one stroke in each painting mode: first uses (an obstacle mask on a
    // scene that had none) happen here, before the segment.
    for (int i = 0; i < 200; ++i) frame();
    for (int m = 0; m < kPaintModeCount; ++m) {
      next_mode();
      for (int i = 0; i < 150; ++i) frame();
    }
    const int64_t rss0 = resident_bytes();
    const int64_t allocs0 = g_allocations.load();
    const HeapProbe heap0 = HeapProbe::now();
    for (int i = 0; i < kSegmentFrames; ++i) {
      // Load swings: 1 200 frames at 3x the period (lowers sweeps, then resolution), then
      // 2 800 light frames (raises them back); a reset now and then; the next painting mode
      // every 2 000 frames (two rounds of the five per segment).
      time.cost_ns = i % 4000 < 1200 ? 6'000'000 : 0;
      if (i % 5000 == 4999) loop.commands().push(LiveCommand::make(LiveCommandKind::kReset));
      if (i % 2000 == 1999) next_mode();
      frame();
    }
    const HeapProbe heap1 = HeapProbe::now();
    allocations += g_allocations.load() - allocs0;
    mallocs += heap1.mallocs - heap0.mallocs;
    heap_growth = std::max(heap_growth, heap1.bytes_in_use - heap0.bytes_in_use);
    rss_growth = std::max(rss_growth, resident_bytes() - rss0);
  }
  const int64_t rss_end = resident_bytes();
  std::printf(
      "soak: %lld frames, steady state: %lld operator-new allocations, %lld mallocs (ASan "
      "hook%s), heap in use grew by at most %lld bytes; RSS %.2f MiB -> %.2f MiB (max growth in "
      "a segment %lld KiB); %lld coarse-RD frames, %lld RD resolution switches, %lld low-sweep "
      "frames, %lld samples painted, %lld attract starts\n",
      (long long)frames, (long long)allocations, (long long)mallocs,
      ARDCELL_TEST_ASAN ? "" : " not available: 0", (long long)heap_growth, rss_begin / 1048576.0,
      rss_end / 1048576.0, (long long)(rss_growth / 1024), (long long)coarse_frames,
      (long long)rd_switches, (long long)low_sweep_frames,
      (long long)(loop.painted_samples() - painted_begin), (long long)attract.activations());
  EXPECT_GE(frames, 100'000);
  EXPECT_EQ(bad_frames, 0);
  EXPECT_EQ(allocations, 0);
  EXPECT_EQ(mallocs, 0);
  EXPECT_LE(heap_growth, 0);
  if (ARDCELL_TEST_ASAN) {  // the probe sees Field storage: the preset switches made some
    EXPECT_GT(HeapProbe::now().mallocs - heap_begin.mallocs, 0);
  }
  // No allocation inside a segment, so the only pages it may add are first touches of memory
  // already allocated (stack, lazily committed heap pages): a few dozen at most.
  EXPECT_LE(rss_growth, 256 * 1024);
  // Across the whole soak: four preset switches, each building and dropping a 16 x 16 engine
  // (well under 1 MiB, kept a while in the sanitizer's quarantine).
  EXPECT_LE(rss_end - rss_begin, 16 * 1024 * 1024);
  EXPECT_GT(attract.activations(), 0);
  EXPECT_GT(loop.painted_samples() - painted_begin, 10'000);  // the replay kept painting
  EXPECT_GT(coarse_frames, 1000);
  EXPECT_GT(rd_switches, 10);
  EXPECT_GT(low_sweep_frames, 1000);
}

// Hands the test's samples for this frame to a StrokePlayback, as a file replay would.
class ChunkSource final : public StrokeSource {
 public:
  std::size_t poll(double, std::span<StrokeSample> out) override {
    const size_t n = std::min(out.size(), chunk.size() - taken);
    std::copy_n(chunk.begin() + std::ptrdiff_t(taken), n, out.begin());
    taken += n;
    return n;
  }
  std::string describe() const override { return "chunks"; }
  std::vector<StrokeSample> chunk;
  size_t taken = 0;
};

template <class T>
bool same_field(const Field<T>& a, const Field<T>& b) {
  if (a.empty() != b.empty() || a.size() != b.size()) return false;
  for (int y = 0; y < a.ny(); ++y)
    for (int x = 0; x < a.nx(); ++x)
      if (std::memcmp(&a(x, y), &b(x, y), sizeof(T)) != 0) return false;
  return true;
}

// The one painting path: the live engine paints exactly what `ardcell run --strokes` paints
// (StrokePlayback: the same Painter from the scene's paint_config_for, with the preset's input
// mapping by live_paint_config), in every mode, with the mode switched between strokes and
// pressure varying along them.
TEST(LiveEngine, PaintsExactlyLikeTheStrokePlayback) {
  Fixture fx;
  Preset p;
  ASSERT_TRUE(load_preset(small_engine_preset(fx, "cavity-gray-scott", 24, 1.0), p).is_ok());
  p.input.brush_radius = 0.12;
  p.input.strength = 0.8;
  const PaintConfig base = paint_config_for(p.scene);  // what `ardcell run --strokes` starts from
  EngineSimulation live(p, base);
  Engine offline(p.scene);
  auto source = std::make_unique<ChunkSource>();
  ChunkSource& chunks = *source;
  StrokePlayback playback(std::move(source), p.scene.size,
                          live_paint_config(base, p.input, p.scene.size));
  const std::vector<StrokeSample> stroke = wave_stroke(40, 0.4);
  const SimState& a = live.state();
  const SimState& b = offline.state();
  float theta_before = 0;
  long live_allocations = 0;
  for (std::string_view mode : {"deposit", "orient", "push", "obstacle", "erase"}) {
    p.input.mode = std::string(mode);
    playback.painter().set_config(live_paint_config(base, p.input, p.scene.size));
    if (mode == "orient") theta_before = a.theta0(3, 12);
    for (size_t i = 0; i < stroke.size(); i += 4) {  // 4 samples a frame
      chunks.chunk.assign(stroke.begin() + std::ptrdiff_t(i),
                          stroke.begin() + std::ptrdiff_t(std::min(stroke.size(), i + 4)));
      chunks.taken = 0;
      const long before = g_allocations.load();
      live.paint(chunks.chunk, p.input, 0);
      live.step();
      live_allocations += g_allocations.load() - before;
      playback.before_step(offline.state(), b.time);
      offline.step();
    }
    // Live painting allocates nothing, but for an obstacle mask on a scene that had none.
    EXPECT_LE(live_allocations, mode == "obstacle" ? 1 : 0) << mode;
    live_allocations = 0;
    EXPECT_TRUE(same_field(a.A, b.A) && same_field(a.B, b.B) && same_field(a.dye, b.dye) &&
                same_field(a.u, b.u) && same_field(a.v, b.v) && same_field(a.theta0, b.theta0) &&
                same_field(a.obstacle, b.obstacle))
        << "after the " << mode << " stroke";
    // (3, 12): under the stroke's first samples.
    if (mode == "deposit") {
      EXPECT_GT(a.B(3, 12), 0.1f);
    }
    if (mode == "orient") {
      EXPECT_NE(a.theta0(3, 12), theta_before);
    }
    if (mode == "obstacle") {
      ASSERT_FALSE(a.obstacle.empty());
      EXPECT_EQ(a.obstacle(3, 12), 1);
    }
    if (mode == "erase") {
      EXPECT_EQ(a.obstacle(3, 12), 0);
    }
  }
}

// pressure_gamma bends the pressure before the Painter sees it: gamma 2 at pressure 0.5 paints
// as pressure 0.25 does.
TEST(LiveEngine, PressureGammaShapesThePressure) {
  Fixture fx;
  Preset p;
  ASSERT_TRUE(load_preset(small_engine_preset(fx, "cavity-gray-scott", 24, 1.0), p).is_ok());
  std::vector<StrokeSample> stroke = wave_stroke(20, 0.2);
  EngineSimulation curved(p, PaintConfig{});
  for (StrokeSample& s : stroke) s.pressure = 0.5f;
  p.input.pressure_gamma = 2.0;
  curved.paint(stroke, p.input, 0);
  EngineSimulation linear(p, PaintConfig{});
  for (StrokeSample& s : stroke) s.pressure = 0.25f;
  p.input.pressure_gamma = 1.0;
  linear.paint(stroke, p.input, 0);
  EXPECT_TRUE(same_field(curved.state().B, linear.state().B));
  EXPECT_GT(curved.state().B(12, 12), 0.0f);
}

// Adaptive quality's sweeps reach the engine: under an artificial load the RD diffusion solve
// really runs fewer iterations (tolerance 0, so it always runs its limit), and after the load
// the full count again.
TEST(LiveEngine, AdaptiveQualityRunsFewerSolverSweepsUnderLoad) {
  Fixture fx;
  LoadedTime time;
  LiveOptions o = fx.options();
  o.time = &time;
  const std::string path = small_engine_preset(fx, "cavity-gray-scott", 16, 1.0, [](Preset& p) {
    p.scene.rd.diffusion_solver.max_iterations = 20;
    p.scene.rd.diffusion_solver.tolerance = 0;
    p.quality.min_sweeps = 4;
    p.quality.max_sweeps = 20;
  });
  LiveLoop loop(o, make_engine_simulation, fx.display);
  ASSERT_TRUE(loop.start(path).is_ok());
  const auto& sim = dynamic_cast<const EngineSimulation&>(loop.simulation());
  ASSERT_NE(sim.engine().rd_stats(), nullptr);
  const RdStepStats& stats = *sim.engine().rd_stats();
  for (int i = 0; i < 5; ++i) loop.run_frame();
  EXPECT_EQ(stats.diffusion_iterations_a, 20);
  time.cost_ns = 6'000'000;  // every frame misses
  for (int i = 0; i < 60; ++i) loop.run_frame();
  EXPECT_EQ(loop.quality().level().sweeps, 4);
  EXPECT_EQ(stats.diffusion_iterations_a, 4);
  EXPECT_EQ(stats.diffusion_iterations_b, 4);
  EXPECT_EQ(sim.rd_scale(), 1.0);  // min_rd_scale 1: the resolution stays
  time.cost_ns = 0;
  for (int i = 0; i < 600; ++i) loop.run_frame();
  EXPECT_EQ(loop.quality().level().sweeps, 20);
  EXPECT_EQ(stats.diffusion_iterations_a, 20);
}

double relative_l2(const FieldF& a, const FieldF& b) {
  double num = 0, den = 0;
  for (int y = 0; y < a.ny(); ++y)
    for (int x = 0; x < a.nx(); ++x) {
      num += (double(a(x, y)) - b(x, y)) * (double(a(x, y)) - b(x, y));
      den += double(b(x, y)) * b(x, y);
    }
  return std::sqrt(num / std::max(den, 1e-30));
}

// The RD resolution knob is applied: at a lower rung the chemicals run on a coarser grid, and a
// stretch at 18 x 18 (strokes painted meanwhile) then back at 32 x 32 leaves a pattern close to
// the one a run at full resolution all along makes, finite and inside the invariant box.
TEST(LiveEngine, LoweringThenRaisingRdResolutionKeepsThePattern) {
  Fixture fx;
  Preset p;
  ASSERT_TRUE(load_preset(small_engine_preset(fx, "cavity-gray-scott", 32, 0.5), p).is_ok());
  EngineSimulation coarse(p, PaintConfig{}), full(p, PaintConfig{});
  EXPECT_DOUBLE_EQ(coarse.lowest_rd_scale(), 0.5625);  // rungs 1, 0.75, 0.5625 >= 0.5
  const std::vector<StrokeSample> stroke = wave_stroke(30, 0.3);
  coarse.paint(stroke, p.input, 0);
  full.paint(stroke, p.input, 0);
  for (int i = 0; i < 100; ++i) {
    coarse.step();
    full.step();
  }
  coarse.set_rd_scale(0.5625);
  EXPECT_EQ(coarse.rd_grid(), (Int2{18, 18}));
  EXPECT_DOUBLE_EQ(coarse.rd_scale(), 0.5625);
  coarse.set_rd_scale(0.6);  // between rungs: the coarser grid at or above it
  EXPECT_DOUBLE_EQ(coarse.rd_scale(), 0.75);
  EXPECT_EQ(coarse.rd_grid(), (Int2{24, 24}));
  coarse.set_rd_scale(0.5625);
  const ReactionParams& r = p.scene.rd.reaction;
  for (int i = 0; i < 40; ++i) {
    if (i == 20) {
      coarse.paint(stroke, p.input, 0);
      full.paint(stroke, p.input, 0);
    }
    coarse.step();
    full.step();
    ASSERT_TRUE(all_finite(coarse.state()) && in_invariant_box(coarse.state(), r)) << i;
  }
  const double while_coarse = relative_l2(coarse.state().B, full.state().B);
  coarse.set_rd_scale(1.0);
  EXPECT_EQ(coarse.rd_grid(), (Int2{32, 32}));
  for (int i = 0; i < 40; ++i) {
    coarse.step();
    full.step();
    ASSERT_TRUE(all_finite(coarse.state()) && in_invariant_box(coarse.state(), r)) << i;
  }
  const double after = relative_l2(coarse.state().B, full.state().B);
  double b_max = 0, b_sum = 0;
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 32; ++x) {
      b_max = std::max(b_max, double(full.state().B(x, y)));
      b_sum += full.state().B(x, y);
    }
  std::printf(
      "RD at 18x18 for 40 frames: B differs from full resolution by %.3f (L2, relative); "
      "40 frames after coming back: %.3f (B max %.3f mean %.4f)\n",
      while_coarse, after, b_max, b_sum / 1024);
  EXPECT_GT(while_coarse, 0.0);  // it really ran elsewhere
  EXPECT_LT(while_coarse, 0.3);
  EXPECT_LT(after, 0.3);
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
