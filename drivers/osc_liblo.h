#pragma once
// OSC remote control over UDP for live performance (`ardcell live --osc PORT`). A UDP socket
// bound to 127.0.0.1 unless told otherwise; each datagram is decoded with liblo and turned
// into a live-loop command or a stroke sample. Address space (README "OSC"):
//   /ardcell/preset s NAME            switch preset (name or path), crossfaded
//   /ardcell/preset/next              /ardcell/preset/prev
//   /ardcell/param s KEY f|d|i|T|F V  set a preset parameter (`ardcell live --keys`)
//   /ardcell/param s KEY s CHOICE     ... a choice by name (output.colormap "magma")
//   /ardcell/mode s MODE | i INDEX    painting mode: deposit orient push obstacle erase
//   /ardcell/stroke f X f Y [f P]     stroke sample, x and y in [0, 1] from the top left;
//                                     pressure P (default 1) > 0 touches
//   /ardcell/stroke/end               lift the pen
//   /ardcell/record/start [s PATH]    /ardcell/record/stop
//   /ardcell/screenshot [s PATH]
//   /ardcell/reset   /ardcell/pause [i 0|1]   /ardcell/hud
#include <atomic>
#include <memory>
#include <string>
#include <thread>

#include "host/live/live_loop.h"
#include "host/paint/stroke.h"

namespace ardcell {

class OscServer {
 public:
  // Binds `bind_address`:port (port 0: any free port) and starts the receive thread; nullptr
  // with `error` set when the socket cannot be bound. Strokes go into `strokes` (single
  // producer: this server), everything else into `commands`.
  static std::unique_ptr<OscServer> start(int port, const std::string& bind_address,
                                          CommandQueue& commands, StrokeRing& strokes,
                                          Status& error);
  ~OscServer();
  int port() const { return port_; }

  // Handles one datagram (the receive thread calls it; tests may too). False, with a line
  // logged, when the message is malformed or its address or arguments are not understood.
  bool dispatch(const void* data, size_t size);
  int64_t handled() const { return handled_.load(); }
  int64_t rejected() const { return rejected_.load(); }
  std::string last_error() const;

 private:
  OscServer(CommandQueue& commands, StrokeRing& strokes) : commands_(commands), strokes_(strokes) {}
  bool reject(const std::string& why);
  CommandQueue& commands_;
  StrokeRing& strokes_;
  int fd_ = -1;
  int port_ = 0;
  std::atomic<bool> stop_{false};
  std::atomic<int64_t> handled_{0}, rejected_{0};
  std::thread thread_;
  mutable std::mutex error_mutex_;
  std::string last_error_;
  double start_time_ = 0;
};

}  // namespace ardcell
