// `ardcell live` left running as a kiosk (issue 18), under a display (xvfb-run in CI): a random
// OSC client, valid and invalid messages, against the attract mode for a bounded time must not
// make its resident memory grow after warm-up, and SIGTERM ends it with exit 143 and the
// recording whole; quitting while a preset switch is loading does not wait for the load.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "tests/drivers/process_run_fixture.h"

#if defined(ARDCELL_WITH_LIBLO)
#include <lo/lo.h>

namespace ardcell {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

class LiveSoakCli : public ProcessRunTest {
 protected:
  void SetUp() override {
    ProcessRunTest::SetUp();
    if (!std::getenv("DISPLAY") && !std::getenv("WAYLAND_DISPLAY"))
      GTEST_SKIP() << "no X or Wayland display";
    fs::create_directories(dir() / "presets");
    fs::create_directories(dir() / "attract");
    fs::create_directories(dir() / "shots");
    // Two small presets of one size (a switch between them changes no buffer size).
    write("presets/small-a.toml",
          "name = \"small-a\"\n[grid]\nsize = [96, 96]\n[fluid]\n"
          "scene = \"cavity\"\n");
    write("presets/small-b.toml",
          "name = \"small-b\"\n[grid]\nsize = [96, 96]\n[fluid]\nscene = \"cavity\"\n[rd]\n"
          "enabled = true\nadvect = true\n");
    std::string circle;
    for (int i = 0; i < 60; ++i)
      circle += "{\"t\": " + std::to_string(i * 0.03) +
                ", \"x\": " + std::to_string(0.5 + 0.3 * std::cos(i * 0.2)) +
                ", \"y\": " + std::to_string(0.5 + 0.3 * std::sin(i * 0.2)) + "}\n";
    write("attract/circle.jsonl", circle);
  }
  void write(const std::string& name, const std::string& text) {
    std::ofstream(dir() / name, std::ios::binary) << text;
  }
  // `ardcell live` on small-a with OSC on a free port, recording to rec.y4m.
  pid_t start_live(const std::vector<std::string>& more = {}) {
    std::vector<std::string> args = {"live",
                                     "presets/small-a.toml",
                                     "--osc",
                                     "0",
                                     "--preset-dir",
                                     "presets",
                                     "--record",
                                     "rec.y4m",
                                     "--fps",
                                     "30",
                                     "--no-vsync",
                                     "--backend",
                                     "serial",
                                     "--scale",
                                     "1",
                                     "--screenshot-dir",
                                     "shots"};
    args.insert(args.end(), more.begin(), more.end());
    // ASan's quarantine of freed memory (256 MiB by default) would read as growth.
    const char* asan = std::getenv("ASAN_OPTIONS");
    return start(args, false,
                 {std::string("ASAN_OPTIONS=") + (asan ? asan : "") + ":quarantine_size_mb=4"});
  }
  // The UDP port it prints ("OSC on udp://127.0.0.1:PORT"); 0 when it never does.
  int osc_port() {
    const std::string key = "OSC on udp://127.0.0.1:";
    if (!wait_for_text("stderr", key)) return 0;
    const std::string err = read("stderr");
    return std::atoi(err.c_str() + err.find(key) + key.size());
  }
  // rec.y4m is a whole YUV4MPEG2 stream: its header, then only whole frames (at least one).
  void expect_whole_recording() {
    const std::string y4m = read("rec.y4m");
    ASSERT_EQ(y4m.rfind("YUV4MPEG2 W96 H96 ", 0), 0u) << y4m.substr(0, 64);
    const size_t header = y4m.find('\n') + 1;
    const bool c420 = y4m.substr(0, header).find("C420") != std::string::npos;
    const size_t frame = 6 + (c420 ? 96 * 96 * 3 / 2 : 96 * 96 * 3);
    EXPECT_EQ((y4m.size() - header) % frame, 0u) << y4m.size();
    EXPECT_GT((y4m.size() - header) / frame, 10u);
    EXPECT_EQ(y4m.compare(header, 6, "FRAME\n"), 0);
    EXPECT_TRUE(temporaries().empty()) << temporaries().front();
  }
};

// One random message: most are valid, many are not (unknown keys and addresses, values out of
// range, wrong types, names of no preset or outside the preset folder, bytes that are no OSC).
void send_random(lo_address to, int udp, const sockaddr_in& addr, std::mt19937& rng) {
  std::uniform_real_distribution<float> u(-0.5f, 1.5f);
  const char* keys[] = {"fluid.viscosity", "rd.reaction.f", "input.brush_radius", "grid.dt",
                        "grid.size",       "no.such.key",   "quality.max_sweeps"};
  const char* names[] = {"small-a",     "small-b", "small-a.toml", "nope", "../small-a",
                         "/etc/passwd", ""};
  const char* modes[] = {"deposit", "orient", "push", "obstacle", "erase", "paint"};
  switch (rng() % 14) {
    case 0:
    case 1:
    case 2:
      lo_send(to, "/ardcell/stroke", "fff", u(rng), u(rng), u(rng));
      break;
    case 3:
      lo_send(to, "/ardcell/stroke/end", "");
      break;
    case 4:
      lo_send(to, "/ardcell/param", "sf", keys[rng() % std::size(keys)], 4 * u(rng));
      break;
    case 5:
      lo_send(to, "/ardcell/param", "ss", "output.colormap", rng() % 2 ? "magma" : "rainbow");
      break;
    case 6:
      lo_send(to, "/ardcell/preset", "s", names[rng() % std::size(names)]);
      break;
    case 7:
      lo_send(to, "/ardcell/mode", "s", modes[rng() % std::size(modes)]);
      break;
    case 8:
      lo_send(to, "/ardcell/mode", "i", int(rng() % 9) - 2);
      break;
    case 9:
      lo_send(to, rng() % 2 ? "/ardcell/hud" : "/ardcell/reset", "");
      break;
    case 10:
      lo_send(to, "/ardcell/pause", "i", int(rng() % 2));
      break;
    case 11:
      lo_send(to, rng() % 20 ? "/ardcell/teleport" : "/ardcell/screenshot", "");
      break;
    default: {
      char junk[96];
      const size_t n = rng() % sizeof junk;
      for (size_t i = 0; i < n; ++i) junk[i] = char(rng());
      if (n > 0 && rng() % 2) junk[0] = '/';
      ::sendto(udp, junk, n, 0, reinterpret_cast<const sockaddr*>(&addr), sizeof addr);
    }
  }
}

long median(std::vector<long> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? -1 : v[v.size() / 2];
}

TEST_F(LiveSoakCli, RandomOscForAWhileKeepsMemoryFlatAndSigtermKeepsTheRecording) {
  const pid_t pid = start_live({"--attract", "1", "--attract-dir", "attract"});
  const int port = osc_port();
  ASSERT_GT(port, 0) << read("stderr");
  lo_address to = lo_address_new("127.0.0.1", std::to_string(port).c_str());
  const int udp = ::socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(uint16_t(port));
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  std::mt19937 rng(18);
  // 8 s of warm-up, then RSS sampled at 8-11 s and again at 25-28 s, messages all along.
  const auto t0 = Clock::now();
  std::vector<long> warm, late;
  auto last_sample = t0;
  for (double t = 0; t < 28; t = std::chrono::duration<double>(Clock::now() - t0).count()) {
    send_random(to, udp, addr, rng);
    if (Clock::now() - last_sample > std::chrono::milliseconds(250)) {
      last_sample = Clock::now();
      if (t >= 8 && t < 11) warm.push_back(rss_kib(pid));
      if (t >= 25) late.push_back(rss_kib(pid));
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(4));
  }
  lo_send(to, "/ardcell/pause", "i", 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  ::close(udp);
  lo_address_free(to);
  ASSERT_EQ(::kill(pid, SIGTERM), 0);
  EXPECT_EQ(wait_for(pid, 30), 143) << read("stderr");
  const long before = median(warm), after = median(late);
  std::printf("RSS %ld KiB after warm-up, %ld KiB at the end\n", before, after);
  ASSERT_GT(before, 0);
  EXPECT_LT(after - before, 24 * 1024)
      << "RSS grew from " << before << " KiB after warm-up to " << after << " KiB";
  const std::string err = read("stderr");
  EXPECT_NE(err.find("recorded rec.y4m"), std::string::npos) << err.substr(err.size() - 2000);
  EXPECT_NE(err.find("deadline misses"), std::string::npos);
  expect_whole_recording();
}

// A preset whose build takes many seconds (a 3072^2 grid with a 4096^2 reaction table: about
// 20 s in a sanitizer build) is loading when SIGTERM comes: the process ends at once, the
// recording finished, instead of after the build.
TEST_F(LiveSoakCli, QuitDoesNotWaitForAPresetStillLoading) {
  write("presets/slow.toml",
        "name = \"slow\"\n[grid]\nsize = [3072, 3072]\n[fluid]\nscene = \"cavity\"\n[rd]\n"
        "enabled = true\n[rd.table]\nenabled = true\nresolution = 4096\n");
  const pid_t pid = start_live();
  const int port = osc_port();
  ASSERT_GT(port, 0) << read("stderr");
  lo_address to = lo_address_new("127.0.0.1", std::to_string(port).c_str());
  std::this_thread::sleep_for(std::chrono::milliseconds(1000));
  lo_send(to, "/ardcell/preset", "s", "slow");
  lo_address_free(to);
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  const auto t0 = Clock::now();
  ASSERT_EQ(::kill(pid, SIGTERM), 0);
  EXPECT_EQ(wait_for(pid, 120), 143) << read("stderr");
  const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  // Building the slow preset's engine takes about 40 s under the sanitizers (its 3072^2 grid and
  // 4096^2 table); the exit itself a few (LeakSanitizer scans the half-built scene), more on a
  // loaded machine (5.8 s seen).
  EXPECT_LT(seconds, 15) << read("stderr");
  EXPECT_NE(read("stderr").find("quit without waiting for preset"), std::string::npos)
      << read("stderr");
  expect_whole_recording();
}

}  // namespace
}  // namespace ardcell
#endif
