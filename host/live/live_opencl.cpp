#include "host/live/live_opencl.h"

#if defined(ARDCELL_WITH_OPENCL)
#include <array>

#include "host/engine/opencl_rd_engine.h"
#include "host/engine/rd_step.h"
#include "host/live/live_engine.h"
#include "host/paint/paint.h"

namespace ardcell {

class OpenClLiveSimulations::Simulation final : public LiveSimulation {
 public:
  Simulation(OpenClLiveSimulations& owner, const Preset& preset)
      : owner_(owner),
        engine_(owner.cl_, preset.scene),
        paint_base_(paint_config_for(preset.scene)),
        painter_(preset.scene.size,
                 live_paint_config(paint_base_, preset.input, preset.scene.size)),
        backend_("opencl (" + owner.device_name_ + ")") {
    const std::string& show = preset.scene.output.show;
    shows_ = show == "A" ? Shows::kA : show == "B" ? Shows::kB : Shows::kBoth;
  }

  void step() override {
    std::lock_guard lock(owner_.device_mutex_);
    engine_.step();
    if (shows_ == Shows::kBoth)
      engine_.download_state();
    else
      engine_.download_chemical(shows_ == Shows::kB);
  }
  void reset() override {
    std::lock_guard lock(owner_.device_mutex_);
    engine_.reset();
  }
  const SimState& state() const override {
    return const_cast<OpenClRdEngine&>(engine_).host_state();
  }
  // Refused (structural) changes keep the current parameters, as EngineSimulation.
  void apply(const SceneConfig& config) override {
    std::lock_guard lock(owner_.device_mutex_);
    (void)engine_.update_parameters(config);
  }
  void paint(std::span<const StrokeSample> samples, const InputMapping& input) override {
    std::lock_guard lock(owner_.device_mutex_);
    SimState& s = engine_.host_state();
    const PaintConfig config = live_paint_config(paint_base_, input, s.size);
    if (config.mode == PaintMode::kOrient && !config.orient_deposits) {
      // theta0 only. The painter may have spread it already at the pen lifting
      // (update_theta0 then reports nothing new): upload whenever a stroke came.
      paint_live_samples(painter_, paint_base_, samples, input, pressured_, s);
      painter_.update_theta0(s);
      engine_.upload_theta0();
      return;
    }
    engine_.download_state();  // the chemical not shown is stale on the host
    paint_live_samples(painter_, paint_base_, samples, input, pressured_, s);
    painter_.update_theta0(s);
    engine_.upload_state();
  }
  std::string_view backend() const override { return backend_; }
  double lowest_rd_scale() const override { return 1.0; }

  OpenClRdEngine& engine() { return engine_; }

 private:
  enum class Shows : uint8_t { kA, kB, kBoth };
  OpenClLiveSimulations& owner_;
  OpenClRdEngine engine_;
  PaintConfig paint_base_;
  Painter painter_;
  std::string backend_;
  Shows shows_ = Shows::kBoth;
  std::array<StrokeSample, 512> pressured_{};
};

OpenClLiveSimulations::OpenClLiveSimulations(OpenClKernels& cl, std::FILE* log)
    : cl_(cl), log_(log), device_name_(cl.context().device().device_name) {}

OpenClLiveSimulations::OpenClLiveSimulations(std::unique_ptr<OpenClContext> ctx,
                                             std::unique_ptr<OpenClKernels> cl, std::FILE* log)
    : ctx_(std::move(ctx)),
      owned_(std::move(cl)),
      cl_(*owned_),
      log_(log),
      device_name_(cl_.context().device().device_name) {}

OpenClLiveSimulations::~OpenClLiveSimulations() = default;

std::unique_ptr<LiveSimulation> OpenClLiveSimulations::make(const Preset& preset) {
  // An invalid RD parameter is the CPU engine's error to report, as without OpenCL.
  const bool invalid = preset.scene.rd.enabled && !rd_config_problem(preset.scene).empty();
  std::string why = invalid ? "" : OpenClRdEngine::device_problem(preset.scene);
  if (invalid || !why.empty()) {
    if (!why.empty()) {
      const std::string line = "ardcell live: preset '" + preset.scene.name +
                               "' cannot run on OpenCL: " + why + "; running it on the CPU";
      if (log_) std::fprintf(log_, "%s\n", line.c_str());
      std::lock_guard lock(fallback_mutex_);
      ++fallbacks_;
      last_fallback_ = line;
    }
    return make_engine_simulation(preset);
  }
  // No lock: building an engine (on the loop's worker) creates buffers and makes blocking
  // writes, OpenCL calls that are thread-safe; only kernel launches (clSetKernelArg on the
  // shared kernels) and reads need the device mutex. The running preset keeps stepping.
  return std::make_unique<Simulation>(*this, preset);
}

SimulationFactory OpenClLiveSimulations::factory() {
  return [this](const Preset& preset) { return make(preset); };
}

int64_t OpenClLiveSimulations::cpu_fallbacks() const {
  std::lock_guard lock(fallback_mutex_);
  return fallbacks_;
}

std::string OpenClLiveSimulations::last_fallback() const {
  std::lock_guard lock(fallback_mutex_);
  return last_fallback_;
}

}  // namespace ardcell
#endif
