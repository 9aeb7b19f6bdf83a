#include "host/live_engine.h"

#include <algorithm>
#include <cmath>

#include "host/engine.h"

namespace ardcell {

namespace {

// Image row 0 is the top (y = ny - 1 in the grid, frame_render's convention).
struct Brush {
  double cx, cy, radius;
};

template <class F>
void for_cells(const SimState& s, const Brush& b, F&& f) {
  const int x0 = std::max(0, int(std::floor(b.cx - b.radius)));
  const int x1 = std::min(s.size.x - 1, int(std::ceil(b.cx + b.radius)));
  const int y0 = std::max(0, int(std::floor(b.cy - b.radius)));
  const int y1 = std::min(s.size.y - 1, int(std::ceil(b.cy + b.radius)));
  const double r2 = b.radius * b.radius;
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) {
      const double dx = x + 0.5 - b.cx, dy = y + 0.5 - b.cy;
      const double d2 = dx * dx + dy * dy;
      if (d2 <= r2) f(x, y, 1.0 - std::sqrt(d2) / b.radius);
    }
}

class EngineSimulation final : public LiveSimulation {
 public:
  explicit EngineSimulation(const Preset& p) : engine_(p.scene) {}
  void step() override { engine_.step(); }
  void reset() override { engine_.reset(); }
  const SimState& state() const override { return engine_.state(); }
  // The live loop applies only parameters that keep the running structure (it switches presets
  // otherwise, presets_share_structure); a refused change keeps the current parameters.
  void apply(const SceneConfig& config) override { (void)engine_.update_parameters(config); }
  void paint(std::span<const StrokeSample> samples, const InputMapping& input) override {
    paint_brush(engine_.state(), samples, input, previous_);
  }
  std::string_view backend() const override { return "cpu"; }

 private:
  Engine engine_;
  StrokeSample previous_{};
};

}  // namespace

void paint_brush(SimState& s, std::span<const StrokeSample> samples, const InputMapping& input,
                 StrokeSample& previous) {
  const double radius = std::max(0.75, input.brush_radius * s.size.x);
  for (const StrokeSample& sample : samples) {
    if (!sample.touching()) {
      previous = sample;
      continue;
    }
    const double p = std::pow(std::clamp<double>(sample.pressure, 0.0, 1.0), input.pressure_gamma);
    const Brush b{sample.x * s.size.x, (1.0 - sample.y) * s.size.y, radius};
    const bool joined = previous.touching();
    const double tx = joined ? (sample.x - previous.x) * s.size.x : 0;
    const double ty = joined ? -(sample.y - previous.y) * s.size.y : 0;
    const double len = std::hypot(tx, ty);
    const float amount = float(std::min(1.0, p * input.strength));
    if (input.mode == "erase" || sample.eraser) {
      for_cells(s, b, [&](int x, int y, double) {
        if (!s.dye.empty()) s.dye(x, y) = 0;
        if (!s.B.empty()) s.B(x, y) = 0;
        if (!s.A.empty()) s.A(x, y) = 1;
      });
    } else if (input.mode == "push") {
      if (len > 0 && !s.u.empty()) {
        const double scale = input.strength * p / std::max(s.dt, 1e-9) / s.size.x;
        for_cells(s, b, [&](int x, int y, double w) {
          s.u(x, y) += float(tx / len * scale * w * len * 0.1);
          s.v(x, y) += float(ty / len * scale * w * len * 0.1);
        });
      }
    } else if (input.mode == "orient") {
      if (len > 0 && !s.theta0.empty()) {
        const float theta = float(std::atan2(ty, tx));
        for_cells(s, b, [&](int x, int y, double) { s.theta0(x, y) = theta; });
      }
    } else if (input.mode == "obstacle") {
      if (!s.obstacle.empty()) for_cells(s, b, [&](int x, int y, double) { s.obstacle(x, y) = 1; });
    } else {  // deposit
      for_cells(s, b, [&](int x, int y, double w) {
        const float a = amount * float(std::min(1.0, 2.0 * w));
        if (!s.dye.empty()) s.dye(x, y) = std::max(s.dye(x, y), a);
        if (!s.B.empty()) s.B(x, y) = std::max(s.B(x, y), a * 0.5f);
      });
    }
    previous = sample;
  }
}

std::unique_ptr<LiveSimulation> make_engine_simulation(const Preset& preset) {
  return std::make_unique<EngineSimulation>(preset);
}

}  // namespace ardcell
