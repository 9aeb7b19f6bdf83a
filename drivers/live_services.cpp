#include "drivers/live_services.h"

#include <arpa/inet.h>

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <thread>

#include "drivers/ffmpeg_pipe.h"
#include "drivers/gpio_buttons.h"
#include "drivers/png_writer.h"
#include "host/live/attract_mode.h"
#include "host/live/live_loop.h"
#ifdef ARDCELL_WITH_GPIOD
#include "drivers/gpio_gpiod.h"
#endif
#ifdef ARDCELL_WITH_LIBLO
#include "drivers/osc_liblo.h"
#endif
#ifdef ARDCELL_WITH_SYSTEMD
#include <systemd/sd-daemon.h>
#endif

namespace ardcell {

bool is_remote_address(const std::string& address) {
  in_addr a{};
  return inet_pton(AF_INET, address.c_str(), &a) == 1 && (ntohl(a.s_addr) >> 24) != 127;
}

namespace {

// FrameSink (drivers/) as the live loop's FrameWriter.
class SinkWriter final : public FrameWriter {
 public:
  explicit SinkWriter(std::unique_ptr<FrameSink> sink) : sink_(std::move(sink)) {}
  Status write(const ImageRgb8& frame) override { return sink_->write(frame, {index_++, 0, 0}); }
  Status finish() override { return sink_->finish(); }

 private:
  std::unique_ptr<FrameSink> sink_;
  int64_t index_ = 0;
};

class PngWriter final : public FrameWriter {
 public:
  explicit PngWriter(std::string path) : path_(std::move(path)) {}
  Status write(const ImageRgb8& frame) override { return write_png(path_, frame); }
  Status finish() override { return Status::ok(); }

 private:
  std::string path_;
};

}  // namespace

void use_file_writers(LiveOptions& o) {
  o.recorder = [](const std::string& path, Int2 size, double fps,
                  Status& err) -> std::unique_ptr<FrameWriter> {
    std::unique_ptr<FrameSink> sink;
    std::string note;
    err = make_video_sink(path, size.x, size.y, int(fps + 0.5), sink, note);
    if (!note.empty()) std::fprintf(stderr, "ardcell live: %s\n", note.c_str());
    if (!err) return nullptr;
    return std::make_unique<SinkWriter>(std::move(sink));
  };
  o.screenshotter = [](const std::string& path, Int2, double,
                       Status&) -> std::unique_ptr<FrameWriter> {
    return std::make_unique<PngWriter>(path);
  };
}

LiveServices::LiveServices() = default;
LiveServices::~LiveServices() = default;

LiveServiceProblem LiveServices::start(const LiveServiceFlags& flags, bool listen, LiveLoop& loop,
                                       std::FILE* err) {
  if (flags.attract_seconds > 0) {
    attract_ = std::make_unique<AttractMode>(flags.attract_seconds);
    if (!flags.attract_dir.empty())
      if (Status s = attract_->load_folder(flags.attract_dir); !s)
        std::fprintf(err, "ardcell live: attract: %s\n", s.message().c_str());
    if (attract_->recordings() == 0)
      std::fprintf(err, "ardcell live: attract: no recordings; attract mode is off\n");
    loop.set_attract_mode(attract_.get());
  }
#ifdef ARDCELL_WITH_GPIOD
  if (!flags.gpio_config.empty()) {
    GpioConfig cfg;
    if (Status s = load_gpio_config(flags.gpio_config, cfg); !s) return {s.message(), true};
    Status gs = Status::ok();
    auto src = open_gpiod_source(cfg, gs);
    if (src)
      buttons_ = std::make_unique<GpioButtons>(std::move(src), cfg, loop.commands());
    else
      std::fprintf(err, "ardcell live: %s\n", gs.message().c_str());
  }
#else
  if (!flags.gpio_config.empty())
    std::fprintf(err, "ardcell live: --gpio: this build has no libgpiod; buttons are off\n");
#endif
#ifdef ARDCELL_WITH_LIBLO
  if (flags.osc_port >= 0 && listen) {
    Status os = Status::ok();
    osc_ = OscServer::start(flags.osc_port, flags.osc_bind, loop.commands(), loop.remote_input(),
                            loop.remote_log(), os, flags.preset_dirs);
    if (!osc_) return {os.message(), true};
    std::fprintf(err, "ardcell live: OSC on udp://%s:%d\n", flags.osc_bind.c_str(), osc_->port());
    if (is_remote_address(flags.osc_bind))
      std::fprintf(err,
                   "ardcell live: warning: OSC listens beyond this machine (%s): anyone who can "
                   "reach UDP port %d can switch presets, paint and record; there is no "
                   "authentication\n",
                   flags.osc_bind.c_str(), osc_->port());
  }
#else
  (void)listen;
  if (flags.osc_port >= 0)
    return {"--osc: this build has no liblo (ARDCELL_WITH_LIBLO=OFF)", false};
#endif
  return {};
}

Status LiveServices::run(LiveLoop& loop) {
  // The watchdog thread waits on `stopped` between pings, so that the end of the loop wakes it
  // at once (a plain sleep held the exit up to half of WatchdogSec).
  std::mutex watchdog_mutex;
  std::condition_variable stopped;
  bool running = true;
  std::thread watchdog;
#ifdef ARDCELL_WITH_SYSTEMD
  sd_notify(0, "READY=1");
  uint64_t usec = 0;
  if (sd_watchdog_enabled(0, &usec) > 0 && usec > 0) {
    // Pings only while frames keep coming: a stuck loop lets systemd restart the kiosk.
    watchdog = std::thread([&loop, &running, &watchdog_mutex, &stopped, usec] {
      int64_t seen = -1;
      std::unique_lock<std::mutex> lock(watchdog_mutex);
      while (!stopped.wait_for(lock, std::chrono::microseconds(usec / 2),
                               [&running] { return !running; })) {
        const int64_t beat = loop.heartbeat().load();
        if (beat != seen) sd_notify(0, "WATCHDOG=1");
        seen = beat;
      }
    });
  }
#endif
  const Status s = loop.run();
  {
    const std::lock_guard<std::mutex> lock(watchdog_mutex);
    running = false;
  }
  stopped.notify_all();
  if (watchdog.joinable()) watchdog.join();
  return s;
}

}  // namespace ardcell
