#include "host/engine/fluid_probes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string_view>
#include <utility>

#include "host/engine/engine.h"
#include "host/engine/fluid_step.h"

namespace ardcell {

namespace {

// Bilinear interpolation of a cell-centred field at (x, y) in domain units, clamped to the
// cells of the grid.
float sample_at(const FieldF& f, double h, double x, double y) {
  const Int2 n = f.size();
  const double cx = std::clamp(x / h - 0.5, 0.0, double(n.x - 1));
  const double cy = std::clamp(y / h - 0.5, 0.0, double(n.y - 1));
  const int i = std::min(int(cx), std::max(0, n.x - 2));
  const int j = std::min(int(cy), std::max(0, n.y - 2));
  const double fx = cx - i, fy = cy - j;
  const int i1 = std::min(i + 1, n.x - 1), j1 = std::min(j + 1, n.y - 1);
  return float((1 - fy) * ((1 - fx) * f(i, j) + fx * f(i1, j)) +
               fy * ((1 - fx) * f(i, j1) + fx * f(i1, j1)));
}

}  // namespace

ObstacleProbes::ObstacleProbes(const SceneConfig& scene) : fluid_(scene.fluid) {
  if (fluid_.kind != FluidSceneKind::kObstacle)
    throw std::invalid_argument("probes: the scene has no obstacle (fluid.scene obstacle)");
  const Int2 n = scene.size;
  h_ = scene.domain_width / n.x;
  const double reach = 2.0 * fluid_.obstacle_radius;  // two radii from the centre
  const auto cells = [&](double lo, double hi, int count) {
    // Edges on cell faces, at least two cells inside the domain's walls.
    const int a = std::max(2, int(std::floor(lo / h_)));
    const int b = std::min(count - 2, int(std::ceil(hi / h_)));
    return std::pair{a, std::max(a, b)};
  };
  const auto [x0, x1] = cells(fluid_.obstacle_x - reach, fluid_.obstacle_x + reach, n.x);
  const auto [y0, y1] = cells(fluid_.obstacle_y - reach, fluid_.obstacle_y + reach, n.y);
  box_ = Box2{{x0, y0}, {x1, y1}};
  switch (fluid_.inflow_side) {
    case BoundarySide::kLeft:
      drag_x_ = 1, drag_y_ = 0;
      break;
    case BoundarySide::kRight:
      drag_x_ = -1, drag_y_ = 0;
      break;
    case BoundarySide::kBottom:
      drag_x_ = 0, drag_y_ = 1;
      break;
    case BoundarySide::kTop:
      drag_x_ = 0, drag_y_ = -1;
      break;
  }
  const double u = fluid_.inflow_speed, d = 2.0 * fluid_.obstacle_radius;
  scale_ = u != 0.0 && d > 0.0 ? 2.0 / (u * u * d) : 0.0;
}

ObstacleProbes::ObstacleProbes(Engine& engine) : ObstacleProbes(engine.config()) {
  ARDCELL_CHECK(engine.fluid_step() != nullptr, "ObstacleProbes: the engine has no fluid");
  engine.fluid_step()->record_pressure(true);
  pressure_ = FieldF(engine.config().size, 1);
}

FluidProbeSample ObstacleProbes::sample(Engine& engine) {
  static constexpr std::array<std::string_view, 3> kFields{"u", "v", "p"};
  const SimState& state = std::as_const(engine).state(kFields);
  const FluidStep& fluid = *engine.fluid_step();
  fluid.physical_pressure(state, pressure_);
  return sample(state, pressure_, fluid.solid());
}

FluidProbeSample ObstacleProbes::sample(const SimState& state, const FieldF& pressure,
                                        const Field<uint8_t>& solid) {
  const FieldF &u = state.u, &v = state.v;
  const double h = h_, nu = fluid_.viscosity;
  const Box2 b = box_;
  // Momentum of the fluid cells in the box.
  double mx = 0.0, my = 0.0;
  for (int j = b.min.y; j < b.max.y; ++j)
    for (int i = b.min.x; i < b.max.x; ++i)
      if (solid.empty() || !solid(i, j)) mx += u(i, j), my += v(i, j);
  mx *= h * h;
  my *= h * h;
  // Flux of momentum, pressure and viscous stress out through the box's edges: the face between
  // cells `in` (inside) and `out` (outside), outward normal (nx, ny).
  double sx = 0.0, sy = 0.0;
  const auto face = [&](int ii, int ji, int io, int jo, double nx, double ny) {
    const double uf = 0.5 * (double(u(ii, ji)) + u(io, jo));
    const double vf = 0.5 * (double(v(ii, ji)) + v(io, jo));
    const double pf = 0.5 * (double(pressure(ii, ji)) + pressure(io, jo));
    const double un = uf * nx + vf * ny;
    const double dudn = (double(u(io, jo)) - u(ii, ji)) / h;
    const double dvdn = (double(v(io, jo)) - v(ii, ji)) / h;
    sx += (uf * un + pf * nx - nu * dudn) * h;
    sy += (vf * un + pf * ny - nu * dvdn) * h;
  };
  for (int j = b.min.y; j < b.max.y; ++j) {
    face(b.min.x, j, b.min.x - 1, j, -1, 0);
    face(b.max.x - 1, j, b.max.x, j, 1, 0);
  }
  for (int i = b.min.x; i < b.max.x; ++i) {
    face(i, b.min.y, i, b.min.y - 1, 0, -1);
    face(i, b.max.y - 1, i, b.max.y, 0, 1);
  }
  double fx = -sx, fy = -sy;
  if (have_previous_ && state.dt > 0.0) {
    fx -= (mx - previous_x_) / state.dt;
    fy -= (my - previous_y_) / state.dt;
  }
  previous_x_ = mx;
  previous_y_ = my;
  have_previous_ = true;

  FluidProbeSample s;
  s.time = state.time;
  s.drag_coefficient = scale_ * (fx * drag_x_ + fy * drag_y_);
  s.lift_coefficient = scale_ * (-fx * drag_y_ + fy * drag_x_);
  s.probes = fluid_.probe_count();
  for (int k = 0; k < s.probes; ++k) {
    const double x = fluid_.probes[2 * k], y = fluid_.probes[2 * k + 1];
    s.u[k] = sample_at(u, h, x, y);
    s.v[k] = sample_at(v, h, x, y);
    s.p[k] = sample_at(pressure, h, x, y);
  }
  s.pressure_difference = s.probes >= 2 ? double(s.p[0]) - double(s.p[1]) : 0.0;
  return s;
}

std::string probe_csv_header(int probes) {
  std::string h = "frame,time,drag_coefficient,lift_coefficient,pressure_difference";
  for (int k = 1; k <= probes; ++k) {
    const std::string n = std::to_string(k);
    h += ",u" + n + ",v" + n + ",p" + n;
  }
  return h;
}

std::size_t format_probe_csv_row(char* buf, std::size_t size, long long frame,
                                 const FluidProbeSample& s) {
  std::size_t n = 0;
  const auto put = [&](int written) {
    if (written > 0) n = std::min(size - 1, n + std::size_t(written));
  };
  put(std::snprintf(buf, size, "%lld,%.9g,%.9g,%.9g,%.9g", frame, s.time, s.drag_coefficient,
                    s.lift_coefficient, s.pressure_difference));
  for (int k = 0; k < s.probes; ++k)
    put(std::snprintf(buf + n, size - n, ",%.9g,%.9g,%.9g", double(s.u[k]), double(s.v[k]),
                      double(s.p[k])));
  put(std::snprintf(buf + n, size - n, "\n"));
  return n;
}

ProbeSeriesSummary summarize_probe_series(std::span<const FluidProbeSample> samples,
                                          double from_time, double speed, double diameter) {
  ProbeSeriesSummary out;
  std::size_t first = 0;
  while (first < samples.size() && samples[first].time < from_time) ++first;
  const std::span<const FluidProbeSample> s = samples.subspan(first);
  if (s.empty()) return out;
  out.drag_max = s[0].drag_coefficient;
  out.lift_max = s[0].lift_coefficient;
  double mean = 0.0, lift_min = s[0].lift_coefficient;
  for (const FluidProbeSample& x : s) {
    out.drag_max = std::max(out.drag_max, x.drag_coefficient);
    out.lift_max = std::max(out.lift_max, x.lift_coefficient);
    lift_min = std::min(lift_min, x.lift_coefficient);
    mean += x.lift_coefficient / double(s.size());
  }
  out.pressure_difference = s.back().pressure_difference;
  if (out.lift_max - lift_min < 2.0 * kMinLiftAmplitude) return out;  // steady: no period
  // Upward crossings of the mean, at linearly interpolated times.
  double first_crossing = 0.0, last_crossing = 0.0;
  int crossings = 0;
  for (std::size_t i = 1; i < s.size(); ++i) {
    const double a = s[i - 1].lift_coefficient - mean, b = s[i].lift_coefficient - mean;
    if (a < 0.0 && b >= 0.0) {
      const double t = s[i - 1].time + (s[i].time - s[i - 1].time) * (-a / (b - a));
      if (crossings == 0) first_crossing = t;
      last_crossing = t;
      ++crossings;
    }
  }
  if (crossings < 3 || !(speed != 0.0)) return out;
  out.periods = crossings - 1;
  const double period = (last_crossing - first_crossing) / out.periods;
  out.strouhal = diameter / (period * std::abs(speed));
  // The pressure difference half a period after the last maximum of the lift that has one.
  std::size_t peak = s.size();
  for (std::size_t i = s.size(); i-- > 1;) {
    if (s[i].time + 0.5 * period > s.back().time) continue;
    if (s[i].lift_coefficient >= s[i - 1].lift_coefficient &&
        (i + 1 >= s.size() || s[i].lift_coefficient >= s[i + 1].lift_coefficient) &&
        s[i].lift_coefficient > mean) {
      peak = i;
      break;
    }
  }
  if (peak < s.size()) {
    const double when = s[peak].time + 0.5 * period;
    std::size_t k = peak;
    while (k + 1 < s.size() && s[k + 1].time <= when) ++k;
    out.pressure_difference = s[k].pressure_difference;
  }
  return out;
}

}  // namespace ardcell
