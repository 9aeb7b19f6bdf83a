#include "host/live/live_engine.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "host/engine/device.h"
#include "host/engine/rd_step.h"
#include "runtime/boundary.h"
#include "runtime/row_executor.h"

namespace ardcell {

namespace {

// A linear map along one axis: out[i] = sum of weight[k] * in[index[k]] for k in
// [start[i], start[i + 1]). Built once per grid pair; applying it allocates nothing.
struct AxisMap {
  std::vector<int> start{0}, index;
  std::vector<float> weight;
  void add(int i, double w) {
    index.push_back(i);
    weight.push_back(float(w));
  }
  void close_row() { start.push_back(int(index.size())); }
  int size() const { return int(start.size()) - 1; }
};

// Area average: coarse cell i covers fine cells [i r, (i + 1) r), r = n_fine / n_coarse.
AxisMap area_restriction(int n_fine, int n_coarse) {
  AxisMap m;
  const double r = double(n_fine) / n_coarse;
  for (int i = 0; i < n_coarse; ++i) {
    const double lo = i * r, hi = (i + 1) * r;
    for (int j = int(std::floor(lo)); j < std::min(n_fine, int(std::ceil(hi))); ++j) {
      const double overlap = std::min(hi, j + 1.0) - std::max(lo, double(j));
      if (overlap > 1e-12) m.add(j, overlap / r);
    }
    m.close_row();
  }
  return m;
}

// Linear interpolation between coarse cell centres (clamped at the edges).
AxisMap linear_prolongation(int n_coarse, int n_fine) {
  AxisMap m;
  for (int j = 0; j < n_fine; ++j) {
    const double xc = std::clamp((j + 0.5) * n_coarse / n_fine - 0.5, 0.0, double(n_coarse - 1));
    const int i0 = std::min(int(std::floor(xc)), n_coarse - 1);
    const double t = xc - i0;
    m.add(i0, 1.0 - t);
    if (t > 0) m.add(std::min(i0 + 1, n_coarse - 1), t);
    m.close_row();
  }
  return m;
}

// The input cell under each output cell's centre (angles, masks: no averaging).
AxisMap nearest(int n_in, int n_out) {
  AxisMap m;
  for (int i = 0; i < n_out; ++i) {
    m.add(std::min(n_in - 1, int((i + 0.5) * n_in / n_out)), 1.0);
    m.close_row();
  }
  return m;
}

// out = Y (X in) over the interiors; tmp holds out.nx x in.ny. Both passes in bands of rows
// on the engine's executor (each output row is written by one band).
template <class In>
void transfer(RowExecutor& ex, const AxisMap& mx, const AxisMap& my, const Field<In>& in,
              FieldF& tmp, FieldF& out) {
  ex.for_rows(in.ny(), mx.size(), [&](int y0, int y1) {
    for (int y = y0; y < y1; ++y) {
      const In* src = in.row(y);
      float* dst = tmp.row(y);
      for (int x = 0; x < mx.size(); ++x) {
        double acc = 0;
        for (int k = mx.start[size_t(x)]; k < mx.start[size_t(x) + 1]; ++k)
          acc += double(mx.weight[size_t(k)]) * double(src[mx.index[size_t(k)]]);
        dst[x] = float(acc);
      }
    }
  });
  ex.for_rows(my.size(), out.nx(), [&](int y0, int y1) {
    for (int y = y0; y < y1; ++y) {
      float* dst = out.row(y);
      for (int x = 0; x < out.nx(); ++x) dst[x] = 0;
      for (int k = my.start[size_t(y)]; k < my.start[size_t(y) + 1]; ++k) {
        const float w = my.weight[size_t(k)];
        const float* src = tmp.row(my.index[size_t(k)]);
        for (int x = 0; x < out.nx(); ++x) dst[x] += w * src[x];
      }
    }
  });
}

}  // namespace

// One coarser RD grid: its own RdStepper, state (A, B, theta0, and the velocity and obstacle
// restricted from the scene's grid) and frame plan of the RD's stages, and the transfers to and
// from the scene's grid.
struct EngineSimulation::RdLevel {
  double scale = 1;
  SceneConfig config;  // the scene at this grid (size, rd.cell_size scaled)
  std::unique_ptr<RdStepper> rd;
  SimState state;
  std::unique_ptr<FramePlan> plan;
  AxisMap down_x, down_y, up_x, up_y, near_x, near_y;
  FieldF down_tmp, up_tmp, a_tmp, b_tmp, solid_tmp;

  // The RD parameters of `fine` at this grid.
  void take_parameters(const SceneConfig& fine) {
    config.dt = fine.dt;
    config.rd = fine.rd;
    if (fine.rd.cell_size > 0)
      config.rd.cell_size = fine.rd.cell_size * fine.size.x / config.size.x;
  }
};

PaintConfig live_paint_config(const PaintConfig& base, const InputMapping& input, Int2 grid) {
  PaintConfig c = base;
  PaintMode mode;
  if (parse_paint_mode(input.mode, mode)) c.mode = mode;
  // As `ardcell run --paint-radius`: the radius at full pressure; min_radius stays the base's.
  c.radius = float(std::max(0.5, input.brush_radius * grid.x));
  c.strength = float(input.strength);
  return c;
}

void paint_live_samples(Painter& painter, const PaintConfig& base,
                        std::span<const StrokeSample> samples, const InputMapping& input,
                        std::array<StrokeSample, 512>& scratch, SimState& state) {
  const PaintConfig config = live_paint_config(base, input, state.size);
  const PaintConfig& now = painter.config();
  if (config.mode != now.mode || config.radius != now.radius ||
      config.min_radius != now.min_radius || config.strength != now.strength)
    painter.set_config(config);
  while (!samples.empty()) {
    const size_t n = std::min(samples.size(), scratch.size());
    for (size_t i = 0; i < n; ++i) {
      scratch[i] = samples[i];
      if (input.pressure_gamma != 1.0 && samples[i].pressure > 0)
        scratch[i].pressure = float(std::pow(double(samples[i].pressure), input.pressure_gamma));
    }
    painter.apply(std::span<const StrokeSample>(scratch.data(), n), state);
    samples = samples.subspan(n);
  }
}

EngineSimulation::EngineSimulation(const Preset& preset, const PaintConfig& paint_base,
                                   const EngineOptions& options)
    : EngineSimulation(preset, paint_base, options, nullptr) {}

EngineSimulation::EngineSimulation(const Preset& preset, const PaintConfig& paint_base,
                                   const EngineOptions& options,
                                   std::shared_ptr<std::mutex> device_mutex)
    : device_mutex_(std::move(device_mutex)),
      paint_base_(paint_base),
      painter_(preset.scene.size, live_paint_config(paint_base, preset.input, preset.scene.size)) {
  const auto lock = lock_device();
  engine_ = std::make_unique<Engine>(preset.scene, options);
  const SceneConfig& scene = engine_->config();
  // A frame plan's RD rides in its fluid passes (the table1 scenes), and a block of a split wall
  // steps its cells of the one grid: no coarser RD grid.
  if (!scene.rd.enabled || !preset.quality.adaptive ||
      scene.fluid.kind == FluidSceneKind::kTable1 || engine_->device().on_block())
    return;
  snap_a_ = FieldF(scene.size, 1);
  snap_b_ = FieldF(scene.size, 1);
  Int2 previous = scene.size;
  for (double scale : rd_scale_ladder(preset.quality.min_rd_scale)) {
    if (scale >= 1.0) continue;
    const Int2 n{std::max(3, int(std::lround(scene.size.x * scale))),
                 std::max(3, int(std::lround(scene.size.y * scale)))};
    if (n == previous) continue;  // too small a grid to tell the rungs apart
    auto l = std::make_unique<RdLevel>();
    l->scale = scale;
    l->config = scene;
    l->config.size = n;
    l->take_parameters(scene);
    if (!rd_config_problem(l->config).empty()) break;
    l->rd = std::make_unique<RdStepper>(l->config, engine_->device());
    l->state.size = n;
    l->state.h = scene.domain_width / n.x;
    l->state.dt = scene.dt;
    l->rd->init_state(l->state);  // allocates A, B, theta0 (and hands them to the device)
    if (!engine_->state().u.empty()) {
      l->state.u = FieldF(n, 1);
      l->state.v = FieldF(n, 1);
    }
    l->down_x = area_restriction(scene.size.x, n.x);
    l->down_y = area_restriction(scene.size.y, n.y);
    l->up_x = linear_prolongation(n.x, scene.size.x);
    l->up_y = linear_prolongation(n.y, scene.size.y);
    l->near_x = nearest(scene.size.x, n.x);
    l->near_y = nearest(scene.size.y, n.y);
    l->down_tmp = FieldF({n.x, scene.size.y}, 0);
    l->up_tmp = FieldF({scene.size.x, n.y}, 0);
    l->a_tmp = FieldF(n, 1);
    l->b_tmp = FieldF(n, 1);
    l->solid_tmp = FieldF(n, 1);
    if (!engine_->state().obstacle.empty()) l->state.obstacle = Field<uint8_t>(n, 1);
    FramePlanOptions po;
    po.grid = n;
    l->plan = std::make_unique<FramePlan>(po);
    l->rd->append_stages(*l->plan, l->state);
    levels_.push_back(std::move(l));
    previous = n;
  }
}

EngineSimulation::~EngineSimulation() {
  const auto lock = lock_device();
  levels_.clear();
  engine_.reset();
}

std::unique_lock<std::mutex> EngineSimulation::lock_device() const {
  return device_mutex_ ? std::unique_lock<std::mutex>(*device_mutex_)
                       : std::unique_lock<std::mutex>();
}

const SimState& EngineSimulation::state() const {
  const auto lock = lock_device();
  return std::as_const(*engine_).state();
}

const SimState& EngineSimulation::state(std::span<const std::string_view> fields) const {
  const auto lock = lock_device();
  return std::as_const(*engine_).state(fields);
}

SimState& EngineSimulation::state_to_write() {
  const auto lock = lock_device();
  fine_written_ = level_ >= 0;
  return engine_->state();
}

double EngineSimulation::lowest_rd_scale() const {
  return levels_.empty() ? 1.0 : levels_.back()->scale;
}

double EngineSimulation::rd_scale() const {
  return level_ < 0 ? 1.0 : levels_[size_t(level_)]->scale;
}

Int2 EngineSimulation::rd_grid() const {
  return level_ < 0 ? engine_->config().size : levels_[size_t(level_)]->state.size;
}

// The coarse grid's obstacle and theta0 (and A, B when `chemicals`) from the scene's grid.
void EngineSimulation::sync_coarse_from_fine(RdLevel& l, bool chemicals) {
  const SimState& f = engine_->state();
  SimState& c = l.state;
  if (chemicals) {
    transfer(engine_->executor(), l.down_x, l.down_y, f.A, l.down_tmp, c.A);
    transfer(engine_->executor(), l.down_x, l.down_y, f.B, l.down_tmp, c.B);
    l.rd->restart();  // A and B are new: no multistep history on this grid
  }
  transfer(engine_->executor(), l.near_x, l.near_y, f.theta0, l.down_tmp, c.theta0);
  if (!f.obstacle.empty()) {
    transfer(engine_->executor(), l.down_x, l.down_y, f.obstacle, l.down_tmp, l.solid_tmp);
    for (int y = 0; y < c.size.y; ++y)
      for (int x = 0; x < c.size.x; ++x) c.obstacle(x, y) = l.solid_tmp(x, y) >= 0.5f ? 1 : 0;
    engine_->device().host_wrote(c.obstacle);
  }
  for (const FieldF* g : {&c.A, &c.B, &c.theta0}) engine_->device().host_wrote(*g);
}

void EngineSimulation::to_level(int level) {
  if (level == level_) return;
  fine_written_ = false;  // the new level starts from the scene's grid anyway
  // The scene's grid holds the running chemicals: the engine's own, or the coarse ones
  // prolongated after every step and paint.
  level_ = level;
  if (level_ >= 0) sync_coarse_from_fine(*levels_[size_t(level_)], true);
}

void EngineSimulation::set_rd_scale(double scale) {
  const auto lock = lock_device();
  // The coarsest grid at or above the scale asked for (levels are finest first).
  int level = -1;
  for (size_t i = 0; i < levels_.size(); ++i)
    if (levels_[i]->scale >= scale - 1e-9) level = int(i);
  to_level(level);
}

void EngineSimulation::step() {
  const auto lock = lock_device();
  if (level_ < 0) {
    engine_->step();
    return;
  }
  RdLevel& l = *levels_[size_t(level_)];
  if (fine_written_) sync_coarse_from_fine(l, true);
  fine_written_ = false;
  engine_->step_without_rd();
  // The coarse grid reads the velocity and gives back A and B (written whole on the host): only
  // those move, and only A and B go back to the device.
  static constexpr std::string_view kVelocity[] = {"u", "v"}, kChemicals[] = {"A", "B"};
  std::as_const(*engine_).state(kVelocity);
  SimState& f = engine_->state(kChemicals);
  SimState& c = l.state;
  if (!c.u.empty()) {
    transfer(engine_->executor(), l.down_x, l.down_y, f.u, l.down_tmp, c.u);
    transfer(engine_->executor(), l.down_x, l.down_y, f.v, l.down_tmp, c.v);
    fill_boundary(c.u.view(), c.size, BoundaryFill::copy());
    fill_boundary(c.v.view(), c.size, BoundaryFill::copy());
    engine_->device().host_wrote(c.u);
    engine_->device().host_wrote(c.v);
  }
  const double rd_time = c.rd_time;
  l.plan->run(engine_->device());
  f.rd_time += c.rd_time - rd_time;
  engine_->device().sync_to_host(c.A);
  engine_->device().sync_to_host(c.B);
  transfer(engine_->executor(), l.up_x, l.up_y, c.A, l.up_tmp, f.A);
  transfer(engine_->executor(), l.up_x, l.up_y, c.B, l.up_tmp, f.B);
}

void EngineSimulation::reset() {
  const auto lock = lock_device();
  // Painted obstacles go too: the engine restores the scene's own solid cells (the obstacle
  // scene's disc) and leaves the mask alone when the scene has none, so clear it first.
  SimState& f = engine_->state();
  if (!f.obstacle.empty()) {
    f.obstacle.fill(0);
    engine_->device().host_wrote(f.obstacle);
  }
  engine_->reset();
  for (size_t i = 0; i < levels_.size(); ++i)
    if (int(i) == level_ || !levels_[i]->state.obstacle.empty())
      sync_coarse_from_fine(*levels_[i], int(i) == level_);
}

void EngineSimulation::apply(const SceneConfig& config) {
  const auto lock = lock_device();
  if (!engine_->update_parameters(config)) return;
  for (auto& l : levels_) {
    l->take_parameters(engine_->config());
    l->rd->update_parameters(l->config);
  }
}

void EngineSimulation::paint(std::span<const StrokeSample> samples, const InputMapping& input,
                             int source) {
  ARDCELL_CHECK(source >= 0 && source < kMaxInputSources, "paint: input source out of range");
  if (source != source_) {  // each source continues its own stroke
    strokes_[size_t(source_)] = painter_.stroke();
    painter_.set_stroke(strokes_[size_t(source)]);
    source_ = source;
  }
  const auto lock = lock_device();
  SimState& f = engine_->state();
  RdLevel* l = level_ >= 0 ? levels_[size_t(level_)].get() : nullptr;
  if (l) {
    snap_a_ = f.A;  // same size: copies into the existing storage
    snap_b_ = f.B;
  }
  paint_live_samples(painter_, paint_base_, samples, input, pressured_, f);
  painter_.update_theta0(f);
  // The first obstacle stroke on a scene without one made its mask: the coarse grids get theirs
  // in the same frame (the one allocation painting ever makes).
  if (!f.obstacle.empty())
    for (auto& level : levels_)
      if (level->state.obstacle.empty())
        level->state.obstacle = Field<uint8_t>(level->state.size, 1);
  if (!l) return;
  // Coarse cells under the stroke take the restriction of the painted cells; the others keep
  // their values exactly (the scene's grid held their prolongation).
  SimState& c = l->state;
  for (int y = 0; y < f.size.y; ++y)
    for (int x = 0; x < f.size.x; ++x)
      snap_a_(x, y) = std::abs(f.A(x, y) - snap_a_(x, y)) + std::abs(f.B(x, y) - snap_b_(x, y));
  transfer(engine_->executor(), l->down_x, l->down_y, snap_a_, l->down_tmp, l->solid_tmp);
  transfer(engine_->executor(), l->down_x, l->down_y, f.A, l->down_tmp, l->a_tmp);
  transfer(engine_->executor(), l->down_x, l->down_y, f.B, l->down_tmp, l->b_tmp);
  for (int y = 0; y < c.size.y; ++y)
    for (int x = 0; x < c.size.x; ++x)
      if (l->solid_tmp(x, y) > 0) {
        c.A(x, y) = l->a_tmp(x, y);
        c.B(x, y) = l->b_tmp(x, y);
      }
  l->rd->restart();                  // A and B were painted: no multistep history, no quiescent box
  sync_coarse_from_fine(*l, false);  // hands c's A, B, theta0 to the device
}

std::unique_ptr<LiveSimulation> make_engine_simulation(const Preset& preset) {
  return std::make_unique<EngineSimulation>(preset, paint_config_for(preset.scene));
}

SimulationFactory engine_simulations(const EngineOptions& options) {
  std::shared_ptr<std::mutex> device_mutex;
  if (options.backend == EngineOptions::Backend::kOpenCl)
    device_mutex = std::make_shared<std::mutex>();
  return [options, device_mutex](const Preset& preset) -> std::unique_ptr<LiveSimulation> {
    return std::make_unique<EngineSimulation>(preset, paint_config_for(preset.scene), options,
                                              device_mutex);
  };
}

}  // namespace ardcell
