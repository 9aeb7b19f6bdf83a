#pragma once
// What runs beside `ardcell live`'s loop (host/live/live_loop.h): the writers of its recordings
// and screenshots, and on a kiosk the attract mode, GPIO buttons (libgpiod), the OSC server
// (liblo) and systemd's watchdog (docs/live-and-kiosk.md). Each kiosk service is optional: GPIO
// buttons without libgpiod or without their chip, and an attract mode without recordings, say so
// in one line and the rest runs; --osc in a build without liblo is a usage error.
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "host/config/status.h"

namespace ardcell {

class AttractMode;
class GpioButtons;
class LiveLoop;
class OscServer;
struct LiveOptions;

// The loop's recorder (a video through drivers/ffmpeg_pipe.h, or Y4M) and screenshotter (PNG).
void use_file_writers(LiveOptions& o);

// An IPv4 address outside 127.0.0.0/8: OSC listening there needs --osc-remote.
bool is_remote_address(const std::string& address);

struct LiveServiceFlags {
  double attract_seconds = 0;  // 0: no attract mode
  std::string attract_dir;     // its recordings
  std::string gpio_config;     // "": no buttons
  int osc_port = -1;           // -1: no OSC
  std::string osc_bind;
  std::vector<std::string> preset_dirs;  // what OSC may load presets from
};

// A setting that cannot start: its usage line, and whether it is this host's alone (a file or a
// port), which a wall's screen says on its own (drivers/cli_live.cpp).
struct LiveServiceProblem {
  std::string line;
  bool local = true;
};

class LiveServices {
 public:
  LiveServices();
  ~LiveServices();
  LiveServices(const LiveServices&) = delete;
  LiveServices& operator=(const LiveServices&) = delete;

  // Starts what `flags` asks for on `loop` (the OSC server only where `listen`: one screen of a
  // wall listens), saying on `err` what is off and why. A problem's line is empty when all
  // started.
  LiveServiceProblem start(const LiveServiceFlags& flags, bool listen, LiveLoop& loop,
                           std::FILE* err);
  // Runs the loop to its end (LiveLoop::run). Under systemd with WatchdogSec it says READY=1 and
  // pings the watchdog while frames keep coming, so that a stuck loop gets the kiosk restarted.
  Status run(LiveLoop& loop);

 private:
  std::unique_ptr<AttractMode> attract_;
  std::unique_ptr<GpioButtons> buttons_;
#ifdef ARDCELL_WITH_LIBLO
  std::unique_ptr<OscServer> osc_;
#endif
};

}  // namespace ardcell
