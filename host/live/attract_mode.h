#pragma once
// AttractMode: when nobody has drawn for `idle_seconds`, plays recorded strokes
// (host/paint/stroke_io.h .jsonl files from a folder) one after the other, so a kiosk shows
// something alive. Any real input ends it at once (the replayed pen is lifted in the same frame).
// Recordings are loaded up front; update() never allocates.
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "host/config/status.h"
#include "host/paint/stroke.h"

namespace ardcell {

class AttractMode {
 public:
  explicit AttractMode(double idle_seconds, double gap_seconds = 1.5);
  ~AttractMode();

  // Adds every *.jsonl of `dir` (sorted by name). A file that does not parse is skipped and
  // named in the returned status (one line per file); the others still load.
  Status load_folder(const std::string& dir);
  void add_recording(std::vector<StrokeSample> samples, std::string name);
  size_t recordings() const { return replays_.size(); }

  // Once per frame. `now` in seconds (any origin, monotonic); `user_input`: a real device
  // produced samples or activity this frame. Writes the replayed samples due now into out and
  // returns how many.
  size_t update(double now, bool user_input, std::span<StrokeSample> out);

  bool active() const { return active_; }
  int64_t activations() const { return activations_; }
  double idle_seconds() const { return idle_seconds_; }
  // Name of the recording playing (empty when inactive).
  std::string_view playing() const;

 private:
  double idle_seconds_;
  double gap_seconds_;
  std::vector<std::unique_ptr<ReplayStrokeSource>> replays_;
  std::vector<std::string> names_;
  bool active_ = false;
  bool started_ = false;
  double last_input_ = 0;
  double next_start_ = 0;  // when the next recording starts (between recordings)
  bool between_ = false;
  size_t current_ = 0;
  int64_t activations_ = 0;
};

}  // namespace ardcell
