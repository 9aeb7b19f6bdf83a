#pragma once
// FrameSink: where rendered frames go (PNG sequence, Y4M file, ffmpeg pipe, a window). The run
// loop renders into one caller-owned image and hands it to every sink; the sinks live in
// drivers/ (drivers/png_writer.h, drivers/y4m_writer.h, drivers/ffmpeg_pipe.h).
#include <cstdint>
#include <string>

#include "host/config/status.h"
#include "host/render/image.h"

namespace ardcell {

struct FrameInfo {
  int64_t index = 0;  // 0, 1, 2, ... in the order frames are written
  int64_t step = 0;   // the simulation step the frame shows
  double time = 0;    // the simulation time it shows
};

class FrameSink {
 public:
  virtual ~FrameSink() = default;
  // Takes one frame; every frame of one run has the same size.
  virtual Status write(const ImageRgb8& image, const FrameInfo& info) = 0;
  // Completes the output (closes a video, renames its temporary file into place). Called once
  // after the last frame; a sink destroyed without finish() removes its partial output.
  virtual Status finish() = 0;
  // Where the frames went, for the summary ("out/cavity/dye_*.png", "clip.mp4").
  virtual std::string describe() const = 0;
};

}  // namespace ardcell
