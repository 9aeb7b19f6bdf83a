// The live loop as one screen of a video wall (host/live/live_wall.h), against an in-process wall
// whose other screen's input the test writes: every screen's strokes and commands act on this
// one in the same frame (strokes mapped from a screen's view to the grid, each screen painting
// with a stroke of its own), a stop on any screen ends every screen after that frame, a
// screenshot is the whole wall's, a wall keeps its preset and does not record; the views hide the
// bezel's cells at inner edges only. Over Open MPI: tests/drivers/live_wall_cli_test.cpp.
#include "host/live/live_wall.h"

#include <gtest/gtest.h>

#include "tests/support/fake_time.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include <unistd.h>

namespace ardcell {
namespace {

struct Painted {
  StrokeSample sample;
  int source;
};

// Dye over the whole grid; remembers what it was asked to paint, and from which screen.
class RecordingSimulation final : public LiveSimulation {
 public:
  explicit RecordingSimulation(const Preset& p) {
    state_.size = p.scene.size;
    state_.dye = FieldF(p.scene.size, 1);
    for (int y = 0; y < state_.size.y; ++y)
      for (int x = 0; x < state_.size.x; ++x) state_.dye(x, y) = float(x + y) / 32.0f;
  }
  void step() override { ++steps; }
  void reset() override {}
  const SimState& state() const override { return state_; }
  SimState& state_to_write() override { return state_; }
  void apply(const SceneConfig&) override {}
  void paint(std::span<const StrokeSample> samples, const InputMapping&, int source) override {
    for (const StrokeSample& s : samples) painted.push_back({s, source});
  }
  std::string_view backend() const override { return "fake"; }
  int64_t steps = 0;
  std::vector<Painted> painted;

 private:
  SimState state_;
};

class NullDisplay final : public LiveDisplay {
 public:
  void poll(StrokeRing&, CommandQueue&) override {}
  void present(const ImageRgb8& frame, const HudInfo*) override {
    ++presents;
    size = {frame.width, frame.height};
  }
  int64_t presents = 0;
  Int2 size{};
};

// Two screens side by side on a 16 x 16 grid, 2 bezel cells between them; this process is
// screen `me`, the other screen's input of frame f is other[f] (none past the end). Mirrored,
// screen 0's state is `screen0` (this screen's is compared with it; a drift copies it here).
class TwoScreenWall final : public LiveWall {
 public:
  explicit TwoScreenWall(int me, bool mirrored = false)
      : layout_(BlockLayout::split({16, 16}, {2, 1})), me_(me), mirrored_(mirrored) {}
  int screens() const override { return 2; }
  int screen() const override { return me_; }
  Int2 grid() const override { return layout_.domain(); }
  Box2 block() const override { return mirrored_ ? box_of_size(grid()) : layout_.block(me_); }
  bool mirrored() const override { return mirrored_; }
  Box2 view() const override { return wall_view(layout_, me_, bezel); }
  std::span<const WallInput> share(const WallInput& mine) override {
    sent.push_back(mine);
    all_[std::size_t(me_)] = mine;
    all_[std::size_t(1 - me_)] = frame_ < other.size() ? other[frame_] : WallInput{};
    ++frame_;
    return all_;
  }
  void agree_range(float&, float&) override {}
  void before_present() override { ++barriers; }
  bool gather_image(const ImageRgb8& mine, ImageRgb8& wall) override {
    if (me_ != 0) return false;
    wall.resize(16, 16);
    place_on_wall(mine, view(), grid(), 1, wall);
    return true;
  }
  int first_drifted(std::uint64_t fingerprint) override {
    ++checks;
    // Screen 0 is the reference (the other screen's state is not modelled).
    return me_ == 0 || fingerprint == state_fingerprint(screen0) ? -1 : me_;
  }
  void send_state(SimState& state) override {
    ++sends;
    state.dye = screen0.dye;
  }
  // As RankWall: a grid whose views would hide a screen's every cell is refused.
  bool regrid(Int2 grid) override {
    if (!mirrored_) return grid == layout_.domain();
    const BlockLayout next = BlockLayout::split(grid, {2, 1});
    if (wall_view(next, 0, bezel).empty() || wall_view(next, 1, bezel).empty()) return false;
    layout_ = next;
    return true;
  }
  std::vector<WallInput> other, sent;
  int barriers = 0, checks = 0, sends = 0;
  int bezel = 2;  // cells
  SimState screen0;

 private:
  BlockLayout layout_;
  int me_;
  bool mirrored_;
  std::size_t frame_ = 0;
  std::array<WallInput, 2> all_{};
};

struct WallFixture {
  std::filesystem::path dir;
  FakeTime time;
  NullDisplay display;
  RecordingSimulation* sim = nullptr;
  int builds = 0;
  std::vector<ImageRgb8> shots;

  WallFixture() {
    dir = std::filesystem::temp_directory_path() /
          ("ardcell_live_wall_test_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    std::ofstream(dir / "wall.toml") << "[grid]\nsize = [16, 16]\n[output]\nshow = \"dye\"\n";
  }
  ~WallFixture() { std::filesystem::remove_all(dir); }
  std::string preset() const { return (dir / "wall.toml").string(); }
  LiveOptions options(TwoScreenWall& wall) {
    LiveOptions o;
    o.fps = 60;
    o.time = &time;
    o.log = nullptr;
    o.wall = &wall;
    o.playlist = {preset(), "cavity"};
    o.screenshotter = [this](const std::string&, Int2, double,
                             Status&) -> std::unique_ptr<FrameWriter> {
      struct Keep final : FrameWriter {
        std::vector<ImageRgb8>* to;
        Status write(const ImageRgb8& f) override {
          to->push_back(f);
          return Status::ok();
        }
        Status finish() override { return Status::ok(); }
      };
      auto w = std::make_unique<Keep>();
      w->to = &shots;
      return w;
    };
    return o;
  }
  SimulationFactory factory() {
    return [this](const Preset& p) {
      ++builds;
      auto s = std::make_unique<RecordingSimulation>(p);
      sim = s.get();
      return s;
    };
  }
};

StrokeSample touch(float x, float y) {
  StrokeSample s;
  s.x = x;
  s.y = y;
  s.pressure = 1.0f;
  s.buttons = kButtonTip;
  s.in_range = true;
  return s;
}

TEST(WallView, HidesTheBezelAtInnerEdgesOnly) {
  const BlockLayout layout = BlockLayout::split({20, 12}, {2, 2});
  // 5 bezel cells: the left / lower screen hides 2, the other 3.
  EXPECT_EQ(wall_view(layout, 0, 5), (Box2{{0, 0}, {8, 4}}));
  EXPECT_EQ(wall_view(layout, 1, 5), (Box2{{13, 0}, {20, 4}}));
  EXPECT_EQ(wall_view(layout, 2, 5), (Box2{{0, 9}, {8, 12}}));
  EXPECT_EQ(wall_view(layout, 3, 5), (Box2{{13, 9}, {20, 12}}));
  EXPECT_EQ(wall_view(layout, 3, 0), layout.block(3));
}

TEST(LiveWall, EveryScreensStrokesAndCommandsActOnEveryScreen) {
  WallFixture fx;
  TwoScreenWall wall(1);
  WallInput other;
  other.samples = 1;
  other.sample[0] = touch(0.25f, 0.75f);  // screen 0's strokes come normalised to the grid
  other.commands = 1;
  other.command[0] = LiveCommand::make(LiveCommandKind::kSetPause, 1);
  other.activity = true;
  wall.other = {other};
  LiveLoop loop(fx.options(wall), fx.factory(), fx.display);
  ASSERT_TRUE(loop.start(fx.preset()).is_ok());
  // This screen shows cells x 9..15 of the grid: the middle of its window is x = 12.5 cells.
  loop.input().push(touch(0.5f, 0.25f));
  ASSERT_TRUE(loop.run_frame());
  ASSERT_EQ(wall.sent.size(), 1u);
  ASSERT_EQ(wall.sent[0].samples, 1);
  EXPECT_FLOAT_EQ(wall.sent[0].sample[0].x, 12.5f / 16.0f);
  EXPECT_FLOAT_EQ(wall.sent[0].sample[0].y, 0.25f);
  EXPECT_TRUE(wall.sent[0].activity);
  // Both screens' strokes, in screen order, each screen its own input source.
  ASSERT_EQ(fx.sim->painted.size(), 2u);
  EXPECT_EQ(fx.sim->painted[0].source, 0);
  EXPECT_FLOAT_EQ(fx.sim->painted[0].sample.x, 0.25f);
  EXPECT_EQ(fx.sim->painted[1].source, 1);
  EXPECT_FLOAT_EQ(fx.sim->painted[1].sample.x, 12.5f / 16.0f);
  // Screen 0's pause reached this screen; its frame showed the view, after the barrier.
  EXPECT_TRUE(loop.paused());
  EXPECT_EQ(fx.display.size, (Int2{7, 16}));
  EXPECT_EQ(wall.barriers, 1);
}

TEST(WallFingerprint, DiffersWhenAnyCellOrTheStepDiffers) {
  SimState a;
  a.size = {37, 7};  // two runs of sixteen cells a row and five more
  a.A = FieldF(a.size, 1);
  a.B = FieldF(a.size, 1);
  for (int y = 0; y < 7; ++y)
    for (int x = 0; x < 37; ++x) a.A(x, y) = float(x * 7 + y) * 0.1f;
  SimState b = a;
  EXPECT_EQ(state_fingerprint(a), state_fingerprint(b));
  // A halo cell is not the state's: it does not count.
  b.A(-1, 3) = 5.0f;
  EXPECT_EQ(state_fingerprint(a), state_fingerprint(b));
  for (Int2 cell : {Int2{0, 0}, Int2{12, 6}, Int2{21, 3}, Int2{31, 0}, Int2{36, 6}}) {
    SimState c = a;
    c.A(cell.x, cell.y) = std::nextafter(c.A(cell.x, cell.y), 2.0f);  // one ulp
    EXPECT_NE(state_fingerprint(a), state_fingerprint(c)) << cell.x << "," << cell.y;
    SimState d = a;
    d.B(cell.x, cell.y) = -0.0f;  // the bits, not the value
    EXPECT_NE(state_fingerprint(a), state_fingerprint(d)) << cell.x << "," << cell.y;
  }
  // The same cells in the other field.
  SimState swapped = a;
  std::swap(swapped.A, swapped.B);
  EXPECT_NE(state_fingerprint(a), state_fingerprint(swapped));
  b = a;
  ++b.step;
  EXPECT_NE(state_fingerprint(a), state_fingerprint(b));
}

// A mirrored wall (every screen steps the whole grid) compares the screens' states after the
// first frame and then every kCheckFrames frames; a screen that drifted goes on from screen 0's
// state, in the frame of the check, and says so. A split wall never compares.
TEST(LiveWall, AMirroredScreenThatDriftedGoesOnFromScreen0sState) {
  WallFixture fx;
  TwoScreenWall wall(1, /*mirrored=*/true);
  wall.screen0.size = {16, 16};
  wall.screen0.dye = FieldF({16, 16}, 1);
  wall.screen0.dye.fill(0.75f);
  LiveOptions o = fx.options(wall);
  char log[512] = {};
  std::FILE* log_file = fmemopen(log, sizeof log - 1, "w");
  ASSERT_NE(log_file, nullptr);
  o.log = log_file;
  LiveLoop loop(o, fx.factory(), fx.display);
  ASSERT_TRUE(loop.start(fx.preset()).is_ok());
  ASSERT_TRUE(loop.run_frame());
  EXPECT_EQ(wall.checks, 1);
  EXPECT_EQ(wall.sends, 1);
  EXPECT_EQ(loop.wall_resyncs(), 1);
  EXPECT_EQ(fx.sim->state().dye(3, 5), 0.75f);
  EXPECT_EQ(fx.sim->state().dye(15, 15), 0.75f);
  // The whole grid is this screen's block: it shows its view of it.
  EXPECT_EQ(fx.display.size, (Int2{7, 16}));
  // In step now: the next check (after kCheckFrames frames) sends nothing.
  for (int f = 1; f <= LiveWall::kCheckFrames; ++f) ASSERT_TRUE(loop.run_frame());
  EXPECT_EQ(wall.checks, 2);
  EXPECT_EQ(wall.sends, 1);
  std::fclose(log_file);
  EXPECT_NE(std::string(log).find("wall: screen 1 drifted from screen 0 by frame 1"),
            std::string::npos)
      << log;

  WallFixture split_fx;
  TwoScreenWall split(1);
  LiveLoop split_loop(split_fx.options(split), split_fx.factory(), split_fx.display);
  ASSERT_TRUE(split_loop.start(split_fx.preset()).is_ok());
  for (int f = 0; f <= LiveWall::kCheckFrames; ++f) ASSERT_TRUE(split_loop.run_frame());
  EXPECT_EQ(split.checks, 0);
}

TEST(LiveWall, AStopOnAnyScreenEndsEveryScreenAfterThatFrame) {
  WallFixture fx;
  TwoScreenWall wall(0);
  wall.other.resize(3);
  wall.other[2].stop = true;  // a signal on the other screen in the third frame
  LiveOptions o = fx.options(wall);
  std::atomic<bool> stop{false};
  o.stop = &stop;
  LiveLoop loop(o, fx.factory(), fx.display);
  ASSERT_TRUE(loop.start(fx.preset()).is_ok());
  ASSERT_TRUE(loop.run().is_ok());
  EXPECT_EQ(loop.frames(), 3);
  EXPECT_EQ(fx.display.presents, 3);
  EXPECT_EQ(wall.barriers, 3);
  // This screen's own signal goes to the others with the frame's input instead of quitting.
  TwoScreenWall second(1);
  LiveOptions o2 = fx.options(second);
  o2.stop = &stop;
  LiveLoop loop2(o2, fx.factory(), fx.display);
  ASSERT_TRUE(loop2.start(fx.preset()).is_ok());
  stop = true;
  EXPECT_FALSE(loop2.run_frame());  // the frame runs to its end on every screen, the last
  ASSERT_EQ(second.sent.size(), 1u);
  EXPECT_TRUE(second.sent[0].stop);
  EXPECT_EQ(loop2.frames(), 1);
  EXPECT_EQ(second.barriers, 1);
}

// A mirrored wall switches presets in step: the frame the command reaches every screen starts
// each screen's build, and the switch happens in the first frame where every screen's build is
// done (this one's alone is not enough), over the new preset's grid; a build that failed on any
// screen keeps the preset on every screen.
TEST(LiveWall, AMirroredWallSwitchesPresetsWhenEveryScreenHasBuiltTheNext) {
  WallFixture fx;
  TwoScreenWall wall(0, /*mirrored=*/true);
  wall.bezel = 4;
  const std::string next = (fx.dir / "wide.toml").string();
  std::ofstream(next) << "[grid]\nsize = [24, 20]\n[output]\nshow = \"dye\"\n";
  LiveOptions o = fx.options(wall);
  o.playlist = {fx.preset(), next};
  LiveLoop loop(o, fx.factory(), fx.display);
  ASSERT_TRUE(loop.start(fx.preset()).is_ok());
  const std::string tiny = (fx.dir / "tiny.toml").string();
  std::ofstream(tiny) << "[grid]\nsize = [4, 4]\n[output]\nshow = \"dye\"\n";
  // The other screen's input of the next frame: its build done, ok, of the same preset as this
  // screen's or not.
  const auto other_next_frame = [&](bool done, bool ok, bool same = true) {
    wall.other.resize(wall.sent.size() + 1);
    wall.other.back().build_done = done;
    wall.other.back().build_ok = ok;
    wall.other.back().build_digest = wall.sent.back().build_digest + (same ? 0 : 1);
  };
  // Until this screen's build is done (it says so in its input), the other screen's is not.
  const auto build_here = [&](const std::string& name) {
    loop.commands().push(LiveCommand::with_text(LiveCommandKind::kSelectPreset, name));
    const std::size_t before = wall.sent.size();
    for (int f = 0; f < 1000 && (wall.sent.size() == before || !wall.sent.back().build_done); ++f) {
      ASSERT_TRUE(loop.run_frame());
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    ASSERT_TRUE(wall.sent.back().build_done);
    EXPECT_TRUE(wall.sent.back().build_ok);
    ASSERT_TRUE(loop.run_frame());
    EXPECT_TRUE(loop.switch_pending());
  };
  build_here(next);
  EXPECT_EQ(wall.grid(), (Int2{16, 16}));
  other_next_frame(true, false);  // the other screen could not load it
  ASSERT_TRUE(loop.run_frame());
  EXPECT_FALSE(loop.switch_pending());
  EXPECT_NE(loop.last_message().find("another screen of the wall could not load it"),
            std::string::npos)
      << loop.last_message();
  EXPECT_EQ(wall.grid(), (Int2{16, 16}));
  build_here(next);
  other_next_frame(true, true, /*same=*/false);  // another file of that name over there
  ASSERT_TRUE(loop.run_frame());
  EXPECT_FALSE(loop.switch_pending());
  EXPECT_NE(loop.last_message().find("loaded different presets by that name"), std::string::npos)
      << loop.last_message();
  build_here(tiny);  // 4 x 4 cells: the 4 bezel cells leave each screen none
  other_next_frame(true, true);
  ASSERT_TRUE(loop.run_frame());
  EXPECT_NE(loop.last_message().find("its 4x4 grid leaves a screen of the wall no cell"),
            std::string::npos)
      << loop.last_message();
  EXPECT_EQ(wall.grid(), (Int2{16, 16}));

  build_here(next);
  other_next_frame(true, true);
  ASSERT_TRUE(loop.run_frame());
  EXPECT_FALSE(loop.switch_pending());
  EXPECT_NE(loop.last_message().find("preset wide"), std::string::npos) << loop.last_message();
  EXPECT_EQ(wall.grid(), (Int2{24, 20}));
  EXPECT_EQ(fx.sim->state().size, (Int2{24, 20}));
  // The new view: cells 0..9 of the left half (the bezel's cells 10 and 11 hidden).
  EXPECT_EQ(fx.display.size, (Int2{10, 20}));
  EXPECT_EQ(fx.builds, 5);
}

TEST(LiveWall, KeepsItsPresetRecordsNothingAndShootsTheWholeWall) {
  WallFixture fx;
  TwoScreenWall wall(0);
  LiveLoop loop(fx.options(wall), fx.factory(), fx.display);
  ASSERT_TRUE(loop.start(fx.preset()).is_ok());
  loop.commands().push(LiveCommand::make(LiveCommandKind::kNextPreset));
  loop.run_frame();
  EXPECT_NE(loop.last_message().find("a wall of blocks keeps its preset"), std::string::npos);
  EXPECT_FALSE(loop.switch_pending());
  EXPECT_EQ(fx.builds, 1);
  loop.commands().push(LiveCommand::make(LiveCommandKind::kToggleRecord));
  loop.run_frame();
  EXPECT_NE(loop.last_message().find("recording: not on a wall"), std::string::npos);
  EXPECT_FALSE(loop.recording());
  loop.commands().push(LiveCommand::with_text(LiveCommandKind::kScreenshot, "wall.png"));
  loop.run_frame();
  ASSERT_EQ(fx.shots.size(), 1u);
  const ImageRgb8& shot = fx.shots[0];
  ASSERT_EQ(shot.width, 16);
  ASSERT_EQ(shot.height, 16);
  // This screen's view (x 0..6) drawn; the bezel cell x = 7 and the other screen left black.
  const auto black = [&](int x, int y) {
    const uint8_t* p = shot.row(y) + 3 * x;
    return p[0] == 0 && p[1] == 0 && p[2] == 0;
  };
  for (int y = 0; y < 16; ++y) {
    EXPECT_FALSE(black(3, y)) << y;
    EXPECT_TRUE(black(7, y)) << y;
    EXPECT_TRUE(black(12, y)) << y;
  }
  EXPECT_EQ(std::memcmp(shot.row(0), loop.image().row(0), 7 * 3), 0);
}

}  // namespace
}  // namespace ardcell
