#include "drivers/osc_liblo.h"

#include <gtest/gtest.h>
#include <lo/lo.h>

#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>

#include "host/scenes/preset.h"
#include "tests/support/remote_log_capture.h"

namespace ardcell {
namespace {

struct Osc {
  CommandQueue commands;
  StrokeRing strokes{64};
  RemoteLog log;
  std::unique_ptr<OscServer> server;
  lo_address to = nullptr;
  Osc() {
    Status s = Status::ok();
    server = OscServer::start(0, "127.0.0.1", commands, strokes, log, s);
    EXPECT_TRUE(s.is_ok()) << s.message();
    to = lo_address_new("127.0.0.1", std::to_string(server->port()).c_str());
  }
  ~Osc() { lo_address_free(to); }
  // Waits until the server has seen `n` messages in all.
  void settle(int64_t n) {
    for (int i = 0; i < 1000 && server->handled() + server->rejected() < n; ++i)
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  LiveCommand next() {
    LiveCommand c;
    while (commands.pop(c))
      if (c.kind != LiveCommandKind::kInputActivity) return c;
    ADD_FAILURE() << "no command";
    return c;
  }
};

TEST(Osc, MessagesOverUdpBecomeCommands) {
  Osc osc;
  ASSERT_NE(osc.server->port(), 0);
  lo_send(osc.to, "/ardcell/preset", "s", "cavity");
  lo_send(osc.to, "/ardcell/preset/next", "");
  lo_send(osc.to, "/ardcell/param", "sf", "fluid.viscosity", 0.125f);
  lo_send(osc.to, "/ardcell/param", "ss", "output.colormap", "magma");
  lo_send(osc.to, "/ardcell/mode", "s", "push");
  lo_send(osc.to, "/ardcell/record/start", "");
  lo_send(osc.to, "/ardcell/record/stop", "");
  lo_send(osc.to, "/ardcell/pause", "i", 1);
  osc.settle(8);
  ASSERT_EQ(osc.server->handled(), 8);
  LiveCommand c = osc.next();
  EXPECT_EQ(c.kind, LiveCommandKind::kSelectPreset);
  EXPECT_STREQ(c.text.data(), "cavity");
  EXPECT_EQ(osc.next().kind, LiveCommandKind::kNextPreset);
  c = osc.next();
  EXPECT_EQ(c.kind, LiveCommandKind::kSetParam);
  EXPECT_EQ(&preset_params()[size_t(c.param)], find_param("fluid.viscosity"));
  EXPECT_EQ(c.value, 0.125);
  c = osc.next();
  EXPECT_EQ(&preset_params()[size_t(c.param)], find_param("output.colormap"));
  EXPECT_EQ(c.value, 2);  // magma
  c = osc.next();
  EXPECT_EQ(c.kind, LiveCommandKind::kSetMode);
  EXPECT_EQ(c.value, 2);  // push
  c = osc.next();
  EXPECT_EQ(c.kind, LiveCommandKind::kRecordStart);
  EXPECT_STREQ(c.text.data(), "");  // a generated name in the output folder
  EXPECT_EQ(osc.next().kind, LiveCommandKind::kRecordStop);
  c = osc.next();
  EXPECT_EQ(c.kind, LiveCommandKind::kSetPause);
  EXPECT_EQ(c.value, 1);
}

TEST(Osc, StrokesGoToTheRing) {
  Osc osc;
  lo_send(osc.to, "/ardcell/stroke", "fff", 0.25f, 0.75f, 0.5f);
  lo_send(osc.to, "/ardcell/stroke", "ff", 0.3f, 0.7f);
  lo_send(osc.to, "/ardcell/stroke/end", "");
  osc.settle(3);
  StrokeSample s;
  ASSERT_TRUE(osc.strokes.pop(s));
  EXPECT_EQ(s.x, 0.25f);
  EXPECT_EQ(s.y, 0.75f);
  EXPECT_EQ(s.pressure, 0.5f);
  EXPECT_TRUE(s.touching());
  ASSERT_TRUE(osc.strokes.pop(s));
  EXPECT_EQ(s.pressure, 1.0f);
  ASSERT_TRUE(osc.strokes.pop(s));
  EXPECT_FALSE(s.touching());
  EXPECT_FALSE(osc.strokes.pop(s));
}

TEST(Osc, BadMessagesAreRejectedWithAReason) {
  Osc osc;
  lo_send(osc.to, "/ardcell/param", "sf", "fluid.viscosty", 1.0f);
  lo_send(osc.to, "/ardcell/param", "sf", "fluid.viscosity", -1.0f);
  lo_send(osc.to, "/ardcell/param", "si", "grid.size", 3);
  lo_send(osc.to, "/ardcell/teleport", "");
  lo_send(osc.to, "/ardcell/stroke", "s", "left");
  osc.settle(5);
  EXPECT_EQ(osc.server->rejected(), 5);
  EXPECT_EQ(osc.server->handled(), 0);
  EXPECT_EQ(osc.server->last_error(), "/ardcell/stroke ,s: expected f X f Y [f PRESSURE]");
  LiveCommand c;
  EXPECT_FALSE(osc.commands.pop(c));
  // Garbage bytes through the same handler.
  const char junk[] = "/ardcell/param\0\0,sf\0\0\0\0";
  EXPECT_FALSE(osc.server->dispatch(junk, sizeof junk - 1));
}

TEST(Osc, SendersNameNoFilesOutsideThePresetFolders) {
  namespace fs = std::filesystem;
  const fs::path root = fs::temp_directory_path() / ("ardcell_osc_" + std::to_string(::getpid()));
  fs::remove_all(root);
  fs::create_directories(root / "presets");
  std::ofstream(root / "presets" / "mine.toml") << "name = \"mine\"\n";
  std::ofstream(root / "secret.toml") << "name = \"secret\"\n";
  fs::create_symlink(root / "secret.toml", root / "presets" / "out.toml");
  CommandQueue commands;
  StrokeRing strokes{8};
  RemoteLog log;
  Status st = Status::ok();
  auto server =
      OscServer::start(0, "127.0.0.1", commands, strokes, log, st, {(root / "presets").string()});
  ASSERT_NE(server, nullptr) << st.message();
  auto send = [&](const char* path, const char* types, auto... args) {
    lo_message m = lo_message_new();
    if (types[0] == 's') lo_message_add_string(m, args...);
    char buf[2048];
    size_t n = sizeof buf;
    lo_message_serialise(m, path, buf, &n);
    lo_message_free(m);
    return server->dispatch(buf, n);
  };
  LiveCommand c;
  // A built-in name, and a file of the preset folder (as its real path).
  EXPECT_TRUE(send("/ardcell/preset", "s", "cavity"));
  ASSERT_TRUE(commands.pop(c));
  EXPECT_STREQ(c.text.data(), "cavity");
  while (commands.pop(c)) {
  }
  EXPECT_TRUE(send("/ardcell/preset", "s", "mine.toml"));
  ASSERT_TRUE(commands.pop(c));
  EXPECT_EQ(std::string(c.text.data()), fs::canonical(root / "presets" / "mine.toml").string());
  while (commands.pop(c)) {
  }
  // Paths, "..", a symlink out of the folder, files elsewhere: refused, nothing queued.
  for (const char* bad : {"/etc/shadow", "../secret.toml", "out.toml", "secret", "/dev/zero"}) {
    EXPECT_FALSE(send("/ardcell/preset", "s", bad)) << bad;
    EXPECT_FALSE(commands.pop(c)) << bad;
  }
  EXPECT_FALSE(send("/ardcell/screenshot", "s", "/tmp/overwrite.png"));
  EXPECT_FALSE(send("/ardcell/record/start", "s", "/tmp/overwrite.y4m"));
  EXPECT_FALSE(commands.pop(c));
  // The log shows a short escaped prefix of the sender's text, never all of it.
  const std::string hostile = "\x1b[2J" + std::string(500, 'A');
  EXPECT_FALSE(send("/ardcell/preset", "s", hostile.c_str()));
  const std::string logged = server->last_error();
  EXPECT_EQ(logged.find('\x1b'), std::string::npos) << logged;
  EXPECT_NE(logged.find("\\x1b[2J"), std::string::npos) << logged;
  EXPECT_LT(logged.size(), 250u) << logged;
  server.reset();
  fs::remove_all(root);
}

// A loop to receive the commands: a tiny simulation, no window, screenshots written nowhere.
class TinySimulation final : public LiveSimulation {
 public:
  TinySimulation() {
    state_.size = {8, 8};
    state_.dye = FieldF(state_.size, 1);
  }
  void step() override {}
  void reset() override {}
  const SimState& state() const override { return state_; }
  SimState& state_to_write() override { return state_; }
  void apply(const SceneConfig&) override {}
  void paint(std::span<const StrokeSample>, const InputMapping&, int) override {}
  std::string_view backend() const override { return "tiny"; }

 private:
  SimState state_;
};
class NoDisplay final : public LiveDisplay {
 public:
  void poll(StrokeRing&, CommandQueue&) override {}
  void present(const ImageRgb8&, const HudInfo*) override {}
};
class NowhereWriter final : public FrameWriter {
 public:
  Status write(const ImageRgb8&) override { return Status::ok(); }
  Status finish() override { return Status::ok(); }
};

// Accepted commands print too (a screenshot's path, a preset switch and its outcome): a flood of
// them gives at most kMaxLinesPerSecond lines in the second, then one line counting the rest,
// like rejected ones. Commands from this machine's own keys are not limited.
TEST(Osc, AFloodOfAcceptedCommandsLogsAFewLinesAndASummary) {
  ManualTime time;
  std::FILE* log = std::tmpfile();
  ASSERT_NE(log, nullptr);
  LiveOptions o;
  o.fps = 0;
  o.time = &time;
  o.log = log;
  o.crossfade_frames = 0;
  o.screenshot_dir = "/nonexistent-never-written";
  int screenshots = 0;
  o.screenshotter = [&screenshots](const std::string&, Int2, double, Status&) {
    ++screenshots;
    return std::unique_ptr<FrameWriter>(new NowhereWriter);
  };
  NoDisplay display;
  LiveLoop loop(
      o, [](const Preset&) { return std::make_unique<TinySimulation>(); }, display);
  ASSERT_TRUE(loop.start("cavity"));
  Status s = Status::ok();
  auto server =
      OscServer::start(0, "127.0.0.1", loop.commands(), loop.remote_input(), loop.remote_log(), s);
  ASSERT_NE(server, nullptr) << s.message();
  lo_address to = lo_address_new("127.0.0.1", std::to_string(server->port()).c_str());
  constexpr int kRounds = 100;
  for (int i = 0; i < kRounds; ++i) {
    lo_send(to, "/ardcell/screenshot", "");
    lo_send(to, "/ardcell/preset", "s", "cavity");
    for (int k = 0; k < 1000 && server->handled() < 2 * (i + 1); ++k)
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    loop.run_frame();  // handles them: a screenshot line, a switch or a "queued" line
    time.now += 1'000'000;
  }
  lo_address_free(to);
  EXPECT_EQ(server->handled(), 2 * kRounds);
  EXPECT_EQ(screenshots, 1);  // one a second from remote senders: the disk does not fill
  loop.wait_for_switch();
  loop.run_frame();
  // 0.1 s of fake time went by: one second's lines at most, the rest counted.
  std::vector<std::string> lines = logged_lines(log);
  EXPECT_EQ(lines.size(), size_t(RemoteLog::kMaxLinesPerSecond)) << lines.back();
  for (const std::string& l : lines) EXPECT_EQ(l.rfind("live: ", 0), 0u) << l;
  const int64_t dropped = loop.remote_log().dropped();
  EXPECT_GE(dropped, 2 * kRounds - RemoteLog::kMaxLinesPerSecond);
  // Once the second is over, one line sums up what was dropped.
  time.now += 1'000'000'000;
  loop.run_frame();
  lines = logged_lines(log);
  ASSERT_EQ(lines.size(), size_t(RemoteLog::kMaxLinesPerSecond + 1));
  EXPECT_EQ(lines.back(), "osc: " + std::to_string(dropped) +
                              " more lines caused by remote commands not logged (at most " +
                              std::to_string(RemoteLog::kMaxLinesPerSecond) + " a second)\n");
  // The same commands from the keyboard (not remote) each print their line.
  for (int i = 0; i < 20; ++i)
    loop.commands().push(LiveCommand::make(LiveCommandKind::kScreenshot));
  loop.run_frame();
  EXPECT_EQ(logged_lines(log).size(), size_t(RemoteLog::kMaxLinesPerSecond + 1 + 20));
  EXPECT_EQ(screenshots, 1 + 20);
  server.reset();
  std::fclose(log);
}

TEST(Osc, BindsToLocalhostAndRefusesBadAddresses) {
  CommandQueue q;
  StrokeRing r{8};
  RemoteLog log;
  Status s = Status::ok();
  auto bad = OscServer::start(0, "localhost-ish", q, r, log, s);
  EXPECT_EQ(bad, nullptr);
  EXPECT_EQ(s.message(), "osc: localhost-ish:0: expected an IPv4 address and a port in [0, 65535]");
  auto first = OscServer::start(0, "127.0.0.1", q, r, log, s);
  ASSERT_NE(first, nullptr);
  auto second = OscServer::start(first->port(), "127.0.0.1", q, r, log, s);
  EXPECT_EQ(second, nullptr);
  EXPECT_NE(s.message().find("cannot bind UDP 127.0.0.1:"), std::string::npos) << s.message();
}

}  // namespace
}  // namespace ardcell
