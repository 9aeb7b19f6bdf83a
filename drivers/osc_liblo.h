#pragma once
// OSC remote control over UDP for live performance (`ardcell live --osc PORT`). A UDP socket
// bound to 127.0.0.1 unless told otherwise; each datagram is decoded with liblo and turned
// into a live-loop command or a stroke sample. Address space (docs/live-and-kiosk.md, "OSC"):
//   /ardcell/preset s NAME            switch preset (built-in name, or NAME / NAME.toml found in
//                                     a preset folder), crossfaded
//   /ardcell/preset/next              /ardcell/preset/prev
//   /ardcell/param s KEY f|d|i|T|F V  set a preset parameter (`ardcell live --keys`)
//   /ardcell/param s KEY s CHOICE     ... a choice by name (output.colormap "magma")
//   /ardcell/mode s MODE | i INDEX    painting mode: deposit orient push obstacle erase
//   /ardcell/stroke f X f Y [f P]     stroke sample, x and y in [0, 1] from the top left;
//                                     pressure P (default 1) > 0 touches
//   /ardcell/stroke/end               lift the pen
//   /ardcell/record/start    /ardcell/record/stop
//   /ardcell/screenshot
//   /ardcell/reset   /ardcell/pause [i 0|1]   /ardcell/hud
// A sender cannot name files: presets come only from the preset folders (a symlink that leads
// out of its folder is refused), screenshots and recordings get generated names in the output
// folder. Every line a sender can cause goes through one RemoteLog (host/live/remote_log.h):
// these messages rejected here, and what the loop says about the commands it accepted (each
// marked LiveCommand::remote): at most a few a second, then one line counting the rest, showing
// only a short escaped prefix of the sender's text.
#include <atomic>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "host/live/live_loop.h"
#include "host/live/remote_log.h"
#include "host/paint/stroke.h"

namespace ardcell {

class OscServer {
 public:
  // Binds `bind_address`:port (port 0: any free port) and starts the receive thread; nullptr
  // with `error` set when the socket cannot be bound. Strokes go into `strokes` (single
  // producer: this server), everything else into `commands`; rejections are logged to `log`
  // (the loop's LiveLoop::remote_log(), which must outlive the server).
  // `preset_folders`: where /ardcell/preset may load .toml files from (none: built-in names
  // only).
  static std::unique_ptr<OscServer> start(int port, const std::string& bind_address,
                                          CommandQueue& commands, StrokeRing& strokes,
                                          RemoteLog& log, Status& error,
                                          std::vector<std::string> preset_folders = {});
  ~OscServer();
  int port() const { return port_; }

  // Handles one datagram (the receive thread calls it; tests may too). False, with a line
  // logged, when the message is malformed or its address or arguments are not understood.
  bool dispatch(const void* data, size_t size);
  int64_t handled() const { return handled_.load(); }
  int64_t rejected() const { return rejected_.load(); }
  std::string last_error() const;

 private:
  OscServer(CommandQueue& commands, StrokeRing& strokes, RemoteLog& log)
      : commands_(commands), strokes_(strokes), log_(log) {}
  bool reject(const std::string& why);
  // A preset the sender named, as a name or a real path inside a preset folder; "" + why.
  std::string resolve_preset(const std::string& name, std::string& why) const;
  CommandQueue& commands_;
  StrokeRing& strokes_;
  RemoteLog& log_;
  int fd_ = -1;
  int port_ = 0;
  std::atomic<bool> stop_{false};
  std::atomic<int64_t> handled_{0}, rejected_{0};
  std::thread thread_;
  mutable std::mutex error_mutex_;
  std::string last_error_;
  double start_time_ = 0;
  std::vector<std::string> preset_folders_;
};

}  // namespace ardcell
