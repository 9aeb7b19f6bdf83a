#pragma once
// `ardcell run --probe-csv FILE`: after every frame of an obstacle scene, the drag and lift
// coefficients, the probes' velocity and pressure and their pressure difference
// (host/engine/fluid_probes.h) as one CSV row, streamed through AtomicFile (the file appears
// complete when the run ends, Ctrl-C included, or not at all); and the benchmark's figures over
// the second half of the run for the summary.
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "host/engine/engine.h"
#include "host/engine/fluid_probes.h"
#include "host/io/atomic_file.h"
#include "host/run/offline_run.h"

namespace ardcell {

class ProbeRecorder final : public StepObserver {
 public:
  // Error (one line) when the engine's scene has no obstacle or the file cannot be made. Keeps
  // the samples of up to `steps` frames for the summary, allocated here.
  static Status open(Engine& engine, const std::filesystem::path& path, int64_t steps,
                     std::unique_ptr<ProbeRecorder>& out);
  Status after_step(int64_t frame) override;
  // Renames the CSV into place.
  Status commit();
  // "probes: drag_max=... lift_max=... strouhal=... pressure_difference=... (t >= T)".
  std::string summary() const;

 private:
  explicit ProbeRecorder(Engine& engine);
  Engine& engine_;
  ObstacleProbes probes_;
  AtomicFile file_;
  std::vector<FluidProbeSample> samples_;
};

}  // namespace ardcell
