#include "host/live/attract_mode.h"

#include <algorithm>
#include <filesystem>

#include "host/paint/stroke_io.h"

namespace ardcell {

AttractMode::AttractMode(double idle_seconds, double gap_seconds)
    : idle_seconds_(idle_seconds), gap_seconds_(gap_seconds) {}

AttractMode::~AttractMode() = default;

Status AttractMode::load_folder(const std::string& dir) {
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec))
    return Status::error(dir + ": attract folder not found (expected a folder of .jsonl strokes)");
  std::vector<std::filesystem::path> files;
  for (const auto& e : std::filesystem::directory_iterator(dir, ec))
    if (e.path().extension() == ".jsonl") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  std::string problems;
  for (const auto& f : files) {
    std::vector<StrokeSample> samples;
    std::string error;
    if (!read_stroke_file(f.string(), samples, error)) {
      problems += (problems.empty() ? "" : "\n") + error;
      continue;
    }
    if (samples.empty()) continue;
    add_recording(std::move(samples), f.filename().string());
  }
  if (files.empty() && problems.empty())
    problems = dir + ": no .jsonl stroke recordings (expected files from `--record-strokes`)";
  return problems.empty() ? Status::ok() : Status::error(problems);
}

void AttractMode::add_recording(std::vector<StrokeSample> samples, std::string name) {
  replays_.push_back(
      std::make_unique<ReplayStrokeSource>(std::move(samples), "attract " + name, false));
  names_.push_back(std::move(name));
}

std::string_view AttractMode::playing() const {
  return active_ && !replays_.empty() ? std::string_view(names_[current_]) : std::string_view();
}

size_t AttractMode::update(double now, bool user_input, std::span<StrokeSample> out) {
  if (!started_) {
    started_ = true;
    last_input_ = now;
  }
  if (user_input) {
    last_input_ = now;
    if (!active_) return 0;
    active_ = false;
    // Lift the replayed pen so the painter does not join its stroke to the user's.
    if (out.empty()) return 0;
    out[0] = StrokeSample{};
    out[0].time = now;
    out[0].x = out[0].y = -1;
    return 1;
  }
  if (replays_.empty()) return 0;
  if (!active_) {
    if (now - last_input_ < idle_seconds_) return 0;
    active_ = true;
    ++activations_;
    between_ = false;
    replays_[current_]->restart(now);
  }
  if (between_) {
    if (now < next_start_) return 0;
    between_ = false;
    replays_[current_]->restart(now);
  }
  ReplayStrokeSource& r = *replays_[current_];
  const size_t n = r.poll(now, out);
  if (r.finished()) {
    current_ = (current_ + 1) % replays_.size();
    between_ = true;
    next_start_ = now + gap_seconds_;
  }
  return n;
}

}  // namespace ardcell
