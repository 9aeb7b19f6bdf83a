#pragma once
// What a CFD benchmark reads from the obstacle channel (Schaefer & Turek 1996, the DFG cylinder):
// the force on the disc as drag and lift coefficients, and point probes of velocity and
// physical pressure, with the pressure difference between the first two.
//
// The force comes from a momentum balance over a box around the disc (a control volume whose
// edges lie in the fluid, two disc radii from the centre): the force on the body is what the
// fluid's momentum in the box lost that its edges do not account for,
//   F = -d/dt sum(u h^2) - sum over the box's edge faces of (u (u.n) + P n - nu du/dn) h,
// fluid cells only, face values the mean of the two cells beside each face, P the physical
// pressure of the step (FluidStep::physical_pressure). It needs no surface of the disc, so a
// staircase and a cut-cell disc are measured the same way. Coefficients: C = 2 F / (U^2 D) along
// the inflow direction (drag) and that direction turned 90 degrees counterclockwise (lift), U
// the mean inflow speed, D the disc's diameter.
#include <array>
#include <span>
#include <string>

#include "host/config/scene_config.h"
#include "host/config/sim_state.h"

namespace ardcell {

struct FluidProbeSample {
  double time = 0.0;
  double drag_coefficient = 0.0, lift_coefficient = 0.0;
  double pressure_difference = 0.0;  // P(probe 1) - P(probe 2); 0 with fewer than two
  int probes = 0;
  std::array<float, FluidConfig::kMaxProbes> u{}, v{}, p{};
};

class Engine;

class ObstacleProbes {
 public:
  // For an obstacle scene (fluid.kind obstacle; else std::invalid_argument); sizes from the scene.
  explicit ObstacleProbes(const SceneConfig& scene);
  // For an engine's obstacle scene: also makes its fluid step keep the first projection's
  // pressure (FluidStep::record_pressure), which sample(engine) needs, from the next step on.
  explicit ObstacleProbes(Engine& engine);

  // The sample after the engine's last step (its fields brought to the host).
  FluidProbeSample sample(Engine& engine);
  // The sample after a frame: `pressure` the step's physical pressure, `solid` the obstacle
  // mask (FluidStep::solid). The first call has no previous momentum, so its d/dt term is 0.
  // Allocates nothing.
  FluidProbeSample sample(const SimState& state, const FieldF& pressure,
                          const Field<uint8_t>& solid);

  // The control volume, in cells: [min, max) (tests).
  Box2 box() const { return box_; }

 private:
  FluidConfig fluid_;
  FieldF pressure_;  // sample(engine)'s physical pressure
  double h_;
  Box2 box_;
  double drag_x_, drag_y_;  // unit vector of the inflow direction
  double scale_;            // 2 / (U^2 D)
  double previous_x_ = 0.0, previous_y_ = 0.0;
  bool have_previous_ = false;
};

// "frame,time,drag_coefficient,lift_coefficient,pressure_difference,u1,v1,p1,..." for `probes`
// points, and one row of a sample with its newline, written into `buf` (no allocation; at
// least kProbeCsvRowBytes): returns its length.
std::string probe_csv_header(int probes);
inline constexpr std::size_t kProbeCsvRowBytes = 96 + 3 * 17 * FluidConfig::kMaxProbes;
std::size_t format_probe_csv_row(char* buf, std::size_t size, long long frame,
                                 const FluidProbeSample& s);

// The benchmark's figures from a series of samples, over the samples at t >= from_time:
// the maxima of the coefficients, the Strouhal number St = f D / U of the lift's oscillation
// (f from the mean period between its upward crossings of its mean; 0 when it crosses fewer
// than three times or oscillates by less than kMinLiftAmplitude: the flow is steady), and the
// pressure difference half a period after the lift's last maximum (the DFG's definition; the
// last sample's when there is no period).
inline constexpr double kMinLiftAmplitude = 0.01;
struct ProbeSeriesSummary {
  double drag_max = 0.0, lift_max = 0.0, strouhal = 0.0, pressure_difference = 0.0;
  int periods = 0;
};
ProbeSeriesSummary summarize_probe_series(std::span<const FluidProbeSample> samples,
                                          double from_time, double speed, double diameter);

}  // namespace ardcell
