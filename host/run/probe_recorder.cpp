#include "host/run/probe_recorder.h"

#include <algorithm>
#include <cstdio>
#include <utility>

namespace ardcell {

ProbeRecorder::ProbeRecorder(Engine& engine) : engine_(engine), probes_(engine) {}

Status ProbeRecorder::open(Engine& engine, const std::filesystem::path& path, int64_t steps,
                           std::unique_ptr<ProbeRecorder>& out) {
  const SceneConfig& scene = engine.config();
  if (scene.fluid.kind != FluidSceneKind::kObstacle || !engine.fluid_step())
    return Status::error("--probe-csv: scene '" + scene.name +
                         "' has no obstacle (expected a scene with fluid.scene obstacle)");
  if (Status s = check_output_path(path, false); !s)
    return Status::error("--probe-csv " + s.message());
  std::unique_ptr<ProbeRecorder> r(new ProbeRecorder(engine));
  if (Status s = r->file_.open(path); !s) return Status::error("--probe-csv " + s.message());
  const std::string header = probe_csv_header(scene.fluid.probe_count()) + "\n";
  if (!r->file_.write(header.data(), header.size()))
    return Status::error("--probe-csv " + path.string() + ": could not write");
  r->samples_.reserve(std::size_t(std::max<int64_t>(0, steps)));
  out = std::move(r);
  return Status::ok();
}

Status ProbeRecorder::after_step(int64_t frame) {
  const FluidProbeSample s = probes_.sample(engine_);
  if (samples_.size() < samples_.capacity()) samples_.push_back(s);
  char row[kProbeCsvRowBytes];
  const std::size_t n = format_probe_csv_row(row, sizeof row, static_cast<long long>(frame), s);
  if (!file_.write(row, n))
    return Status::error("--probe-csv " + file_.final_path().string() + ": could not write");
  return Status::ok();
}

Status ProbeRecorder::commit() {
  if (Status s = file_.commit(); !s) return Status::error("--probe-csv " + s.message());
  return Status::ok();
}

std::string ProbeRecorder::summary() const {
  const FluidConfig& f = engine_.config().fluid;
  const double from = samples_.empty() ? 0.0 : 0.5 * samples_.back().time;
  const ProbeSeriesSummary s =
      summarize_probe_series(samples_, from, f.inflow_speed, 2.0 * f.obstacle_radius);
  char buf[200];
  std::snprintf(buf, sizeof buf,
                "probes: drag_max=%.4f lift_max=%.4f strouhal=%.4f pressure_difference=%.4f "
                "periods=%d (t >= %.3g)",
                s.drag_max, s.lift_max, s.strouhal, s.pressure_difference, s.periods, from);
  return buf;
}

}  // namespace ardcell
