#pragma once
// StrokePlayback: paints a StrokeSource into a simulation once per frame, the glue behind
// `ardcell run --strokes FILE` / `--replay FILE` (and usable by any loop): before each step,
// poll the samples due at the frame's time, paint them, update theta0 when orientation
// changed. Allocates nothing per frame.
#include <array>
#include <memory>

#include "host/paint/paint.h"
#include "host/paint/stroke.h"

namespace ardcell {

class StrokePlayback {
 public:
  StrokePlayback(std::unique_ptr<StrokeSource> source, Int2 grid, const PaintConfig& config)
      : source_(std::move(source)), painter_(grid, config) {}

  // time: seconds since the run started (e.g. step * dt). Returns the samples painted.
  std::size_t before_step(SimState& state, double time) {
    std::size_t total = 0;
    for (;;) {
      const std::size_t n = source_->poll(time, buffer_);
      painter_.apply(std::span<const StrokeSample>(buffer_.data(), n), state);
      total += n;
      if (n < buffer_.size()) break;
    }
    painter_.update_theta0(state);
    return total;
  }

  Painter& painter() { return painter_; }
  StrokeSource& source() { return *source_; }

 private:
  std::unique_ptr<StrokeSource> source_;
  Painter painter_;
  std::array<StrokeSample, 256> buffer_{};
};

}  // namespace ardcell
