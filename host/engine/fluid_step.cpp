#include "host/engine/fluid_step.h"

#include <cmath>
#include <cstring>

#include "host/config/scene_config.h"
#include "kernels/advect.h"
#include "kernels/project.h"
#include "kernels/sources.h"

namespace ardcell {

namespace {

BoundaryKind axis_kind(const EdgeFill& a, const EdgeFill& b) {
  return a.rule == EdgeRule::kPeriodic && b.rule == EdgeRule::kPeriodic ? BoundaryKind::kPeriodic
                                                                        : BoundaryKind::kNeumann;
}

// Weight of a ghost rule on the boundary cell's diagonal, per unit face weight: the fixed ghost
// sits one cell away (1), the mirrored one puts the value on the face half a cell away (2).
double rule_factor(const EdgeFill& e) {
  switch (e.rule) {
    case EdgeRule::kFixed:
      return 1.0;
    case EdgeRule::kMirror:
      return 2.0;
    default:
      return 0.0;
  }
}

// Folds the ghost rules of `fill` into an operator assembled with Neumann (or periodic) axes.
void fold_boundary(StencilOperator& op, const BoundaryFill& fill, double scale) {
  const struct {
    const EdgeFill& e;
    BoundarySide side;
  } sides[] = {{fill.left, BoundarySide::kLeft},
               {fill.right, BoundarySide::kRight},
               {fill.bottom, BoundarySide::kBottom},
               {fill.top, BoundarySide::kTop}};
  for (const auto& s : sides)
    if (rule_factor(s.e) > 0.0) add_boundary_diagonal(op, s.side, rule_factor(s.e) * scale);
}

// b += the boundary values' share (factor * scale * value) on the boundary cells.
void add_boundary_rhs(FieldF& b, const BoundaryFill& fill, double scale) {
  const int nx = b.nx(), ny = b.ny();
  auto add = [&](const EdgeFill& e, int x0, int y0, int dx, int dy, int count) {
    const float amount = float(rule_factor(e) * scale * e.value);
    if (amount == 0.0f) return;
    for (int k = 0; k < count; ++k) b(x0 + k * dx, y0 + k * dy) += amount;
  };
  add(fill.left, 0, 0, 0, 1, ny);
  add(fill.right, nx - 1, 0, 0, 1, ny);
  add(fill.bottom, 0, 0, 1, 0, nx);
  add(fill.top, 0, ny - 1, 1, 0, nx);
}

void zero_solid(FieldF& f, const Field<uint8_t>& solid, RowExecutor& ex) {
  if (solid.empty()) return;
  ex.for_rows(f.ny(), f.nx(), [&](int y0, int y1) {
    for (int j = y0; j < y1; ++j) {
      const uint8_t* s = solid.row(j);
      float* r = f.row(j);
      for (int i = 0; i < f.nx(); ++i)
        if (s[i]) r[i] = 0.0f;
    }
  });
}

double interior_sum(const FieldF& f, RowExecutor& ex) {
  return ex.sum_rows(f.ny(), f.nx(), [&](int y0, int y1, double* partials) {
    for (int j = y0; j < y1; ++j) {
      const float* r = f.row(j);
      double row_total = 0.0;
      for (int i = 0; i < f.nx(); ++i) row_total += r[i];
      partials[j] = row_total;
    }
  });
}

struct Range {
  double sum = 0.0;
  float lo = 0.0f, hi = 0.0f;
};

// Sum (rows added in order), minimum and maximum of the interior.
Range interior_range(const FieldF& f, RowExecutor& ex) {
  const int ny = f.ny();
  double* lo = ex.rows_scratch(ny, 0);
  double* hi = ex.rows_scratch(ny, 1);
  Range r;
  r.sum = ex.sum_rows(ny, f.nx(), [&](int y0, int y1, double* partials) {
    for (int j = y0; j < y1; ++j) {
      const float* row = f.row(j);
      double row_total = 0.0;
      float row_lo = row[0], row_hi = row[0];
      for (int i = 0; i < f.nx(); ++i) {
        row_total += row[i];
        row_lo = std::min(row_lo, row[i]);
        row_hi = std::max(row_hi, row[i]);
      }
      partials[j] = row_total;
      lo[j] = row_lo;
      hi[j] = row_hi;
    }
  });
  r.lo = float(lo[0]);
  r.hi = float(hi[0]);
  for (int j = 1; j < ny; ++j) {
    r.lo = std::min(r.lo, float(lo[j]));
    r.hi = std::max(r.hi, float(hi[j]));
  }
  return r;
}

// Puts `missing` mass back where advection is least certain: weights (q - lo)(hi - q) vanish at
// the extremes of the field before advection, so plateaus (and the max principle) survive; the
// result is clamped to [lo, hi] (the mass then stays short only when the weights cannot hold
// it, far beyond any normal step).
void restore_mass(FieldF& f, double missing, float lo, float hi, RowExecutor& ex) {
  const double total_weight = ex.sum_rows(f.ny(), f.nx(), [&](int y0, int y1, double* partials) {
    for (int j = y0; j < y1; ++j) {
      const float* row = f.row(j);
      double row_total = 0.0;
      for (int i = 0; i < f.nx(); ++i) row_total += double(row[i] - lo) * double(hi - row[i]);
      partials[j] = row_total;
    }
  });
  if (!(total_weight > 0.0)) return;
  const double k = missing / total_weight;
  ex.for_rows(f.ny(), f.nx(), [&](int y0, int y1) {
    for (int j = y0; j < y1; ++j) {
      float* row = f.row(j);
      for (int i = 0; i < f.nx(); ++i) {
        const float q = row[i] + float(k * double(row[i] - lo) * double(hi - row[i]));
        row[i] = std::min(std::max(q, lo), hi);
      }
    }
  });
}

// The whole allocation (halo included), in bands of rows of storage.
void copy_all(const FieldF& from, FieldF& to, RowExecutor& ex) {
  const int rows = from.ny() + 2 * from.halo();
  const std::size_t stride = std::size_t(from.stride());
  ex.for_rows(rows, int(stride), [&](int y0, int y1) {
    std::memcpy(to.raw() + stride * std::size_t(y0), from.raw() + stride * std::size_t(y0),
                stride * std::size_t(y1 - y0) * sizeof(float));
  });
}

}  // namespace

struct FluidStep::Operators {
  StencilOperator visc_u, visc_v, pressure, dye;
  std::unique_ptr<LinearSolver> solver_u, solver_v, solver_p, solver_dye;
};

template <class F>
void FluidStep::for_bands(const F& f) const {
  ex_->for_rows(size_.y, size_.x, [&](int y0, int y1) { f(Box2{{0, y0}, {size_.x, y1}}); });
}

FluidStep::FluidStep(const FluidConfig& config, Int2 size, double h, double dt, RowExecutor& ex)
    : config_(config),
      ex_(&ex),
      size_(size),
      h_(h),
      scratch_u_(size, 1),
      scratch_v_(size, 1),
      scratch_b_(size, 1),
      rhs_(size, 1),
      face_u_(Int2{size.x + 1, size.y}, 1),
      face_v_(Int2{size.x, size.y + 1}, 1) {
  ARDCELL_CHECK(size.x > 0 && size.y > 0 && h > 0.0, "FluidStep: size and h must be positive");
  const EdgeFill copy{EdgeRule::kCopy, 0.0f};
  const EdgeFill wall{EdgeRule::kMirror, 0.0f};
  fill_p_ = BoundaryFill::copy();
  fill_dye_ = BoundaryFill::copy();
  switch (config_.kind) {
    case FluidSceneKind::kCavity:
      fill_u_ = BoundaryFill::no_slip(float(config_.lid_speed));
      fill_v_ = BoundaryFill::no_slip(0.0f);
      break;
    case FluidSceneKind::kObstacle: {
      // Inflow through the top wall (v = -inflow_speed), outflow through the bottom (velocity
      // copied, pressure 0), free-slip side walls.
      fill_u_ = {wall, wall, copy, wall};
      fill_v_ = {copy, copy, copy, {EdgeRule::kMirror, float(-config_.inflow_speed)}};
      fill_p_ = {copy, copy, {EdgeRule::kFixed, 0.0f}, copy};
      solid_ = Field<uint8_t>(size, 1);
      const double cx = config_.obstacle_x / h - 0.5, cy = config_.obstacle_y / h - 0.5;
      const double r = config_.obstacle_radius / h;
      for (int j = 0; j < size.y; ++j)
        for (int i = 0; i < size.x; ++i)
          solid_(i, j) = (i - cx) * (i - cx) + (j - cy) * (j - cy) <= r * r ? 1 : 0;
      break;
    }
    case FluidSceneKind::kInk:
      if (config_.walls == FluidWalls::kPeriodic) {
        fill_u_ = fill_v_ = fill_p_ = fill_dye_ = BoundaryFill::periodic();
      } else if (config_.walls == FluidWalls::kNoSlip) {
        fill_u_ = fill_v_ = BoundaryFill::no_slip(0.0f);
      } else {
        fill_u_ = BoundaryFill::stam(1);
        fill_v_ = BoundaryFill::stam(2);
      }
      break;
    case FluidSceneKind::kNone:
      fill_u_ = fill_v_ = BoundaryFill::copy();
      break;
  }

  auto make_op = [&](const BoundaryFill& fill) {
    return assemble_stencil_operator(size, 1.0, 0.0, nullptr, axis_kind(fill.left, fill.right),
                                     axis_kind(fill.bottom, fill.top));
  };
  ops_ = std::make_unique<Operators>(Operators{make_op(fill_u_), make_op(fill_v_), make_op(fill_p_),
                                               make_op(fill_dye_), nullptr, nullptr, nullptr,
                                               nullptr});
  ops_->solver_u = LinearSolver::make(config_.viscosity_solver, size, ex);
  ops_->solver_v = LinearSolver::make(config_.viscosity_solver, size, ex);
  ops_->solver_p = LinearSolver::make(config_.pressure_solver, size, ex);
  ops_->solver_dye = LinearSolver::make(config_.viscosity_solver, size, ex);
  ex.reserve_rows(size.y);

  // Pressure: 4 p - sum of neighbours = rhs, Neumann at walls and obstacle faces.
  reassemble_stencil_operator(ops_->pressure, 0.0, 1.0, nullptr);
  fold_boundary(ops_->pressure, fill_p_, 1.0);
  if (!solid_.empty()) isolate_solid_cells(ops_->pressure, solid_, 0.0);
  ops_->solver_p->prepare(ops_->pressure);
  prepare(dt);
}

FluidStep::~FluidStep() = default;

void FluidStep::update_parameters(const FluidConfig& c) {
  config_.viscosity = c.viscosity;
  config_.lid_speed = c.lid_speed;
  config_.dye_diffusion = c.dye_diffusion;
  config_.conserve_dye = c.conserve_dye;
  config_.inflow_speed = c.inflow_speed;
  config_.inflow_dye_stripes = c.inflow_dye_stripes;
  if (c.emitters.size() == config_.emitters.size())
    std::copy(c.emitters.begin(), c.emitters.end(), config_.emitters.begin());
  config_.viscosity_solver.max_iterations = c.viscosity_solver.max_iterations;
  config_.viscosity_solver.tolerance = c.viscosity_solver.tolerance;
  config_.pressure_solver.max_iterations = c.pressure_solver.max_iterations;
  config_.pressure_solver.tolerance = c.pressure_solver.tolerance;
  for (LinearSolver* s : {ops_->solver_u.get(), ops_->solver_v.get(), ops_->solver_dye.get()})
    s->set_limits(c.viscosity_solver.max_iterations, c.viscosity_solver.tolerance);
  ops_->solver_p->set_limits(c.pressure_solver.max_iterations, c.pressure_solver.tolerance);
  if (config_.kind == FluidSceneKind::kCavity)
    fill_u_ = BoundaryFill::no_slip(float(config_.lid_speed));
  if (config_.kind == FluidSceneKind::kObstacle)
    fill_v_.top = {EdgeRule::kMirror, float(-config_.inflow_speed)};
  prepared_dt_ = -1.0;  // the viscous operators depend on the viscosity
}

void FluidStep::prepare(double dt) {
  prepared_dt_ = dt;
  const double s_visc = dt * config_.viscosity / (h_ * h_);
  auto setup = [&](StencilOperator& op, LinearSolver& solver, const BoundaryFill& fill, double s,
                   bool no_slip_obstacle) {
    reassemble_stencil_operator(op, 1.0, s, nullptr, *ex_);
    fold_boundary(op, fill, s);
    if (!solid_.empty()) isolate_solid_cells(op, solid_, no_slip_obstacle ? 2.0 : 0.0);
    solver.prepare(op);
  };
  setup(ops_->visc_u, *ops_->solver_u, fill_u_, s_visc, true);
  setup(ops_->visc_v, *ops_->solver_v, fill_v_, s_visc, true);
  setup(ops_->dye, *ops_->solver_dye, fill_dye_, dt * config_.dye_diffusion / (h_ * h_), false);
}

void FluidStep::allocate(SimState& state) const {
  state.size = size_;
  state.h = h_;
  for (FieldF* f : {&state.u, &state.v, &state.p, &state.dye})
    if (f->empty() || f->size() != size_ || f->halo() < 1) *f = FieldF(size_, 1);
  if (!solid_.empty()) state.obstacle = solid_;
}

void FluidStep::reset(SimState& state) const {
  allocate(state);
  for (FieldF* f : {&state.u, &state.v, &state.p, &state.dye}) f->fill(0.0f);
  const Int2 n = size_;
  if (config_.kind == FluidSceneKind::kCavity) {
    // Eight horizontal bands of dye for the vortex to roll up.
    for (int j = 0; j < n.y; ++j) {
      const float value = (j * 8 / n.y) % 2 ? 1.0f : 0.0f;
      for (int i = 0; i < n.x; ++i) state.dye(i, j) = value;
    }
  } else if (config_.kind == FluidSceneKind::kObstacle) {
    // Start from the uniform inflow; the first projection turns it around the disc.
    state.v.fill(float(-config_.inflow_speed));
    zero_solid(state.v, solid_, *ex_);
  }
  if (config_.kind != FluidSceneKind::kNone) {
    fill_velocity(state);
    fill_boundary(state.dye.view(), n, fill_dye_);
  }
}

void FluidStep::fill_velocity(SimState& state) const {
  fill_boundary(state.u.view(), size_, fill_u_);
  fill_boundary(state.v.view(), size_, fill_v_);
  if (!solid_.empty()) {
    // Solid cells are written from fluid cells only: bands of rows do not interfere.
    for_bands([&](Box2 rows) {
      fill_obstacle(state.u.view(), solid_.view(), rows, ObstacleRule::kNoSlip);
      fill_obstacle(state.v.view(), solid_.view(), rows, ObstacleRule::kNoSlip);
    });
  }
}

void FluidStep::add_forces_and_sources(SimState& state) {
  const float dt = float(state.dt);
  if (config_.kind == FluidSceneKind::kInk) {
    for (const FluidEmitter& e : config_.emitters) {
      const float cx = float(e.x / h_ - 0.5), cy = float(e.y / h_ - 0.5);
      const float r = float(e.radius / h_);
      const double angle = e.swirl * state.time;
      const double fx = e.force_x * std::cos(angle) - e.force_y * std::sin(angle);
      const double fy = e.force_x * std::sin(angle) + e.force_y * std::cos(angle);
      for_bands([&](Box2 rows) {
        add_splat(state.dye.view(), rows, {cx, cy, r, float(dt * e.dye_rate)});
        add_splat(state.u.view(), rows, {cx, cy, r, float(dt * fx)});
        add_splat(state.v.view(), rows, {cx, cy, r, float(dt * fy)});
      });
    }
  } else if (config_.kind == FluidSceneKind::kObstacle && config_.inflow_dye_stripes > 0) {
    // Dye enters with the inflow in vertical stripes (the top row is refreshed each frame).
    const int top = size_.y - 1;
    const int stripes = 2 * config_.inflow_dye_stripes;
    for (int i = 0; i < size_.x; ++i) state.dye(i, top) = (i * stripes / size_.x) % 2 ? 1.0f : 0.0f;
  }
}

void FluidStep::diffuse_velocity(SimState& state) {
  if (!(config_.viscosity > 0.0)) return;
  const double s = state.dt * config_.viscosity / (h_ * h_);
  auto solve = [&](FieldF& x, const StencilOperator& op, LinearSolver& solver,
                   const BoundaryFill& fill) {
    copy_all(x, scratch_b_, *ex_);
    add_boundary_rhs(scratch_b_, fill, s);
    zero_solid(scratch_b_, solid_, *ex_);
    return solver.solve(op, scratch_b_, x);
  };
  report_.viscosity_u = solve(state.u, ops_->visc_u, *ops_->solver_u, fill_u_);
  report_.viscosity_v = solve(state.v, ops_->visc_v, *ops_->solver_v, fill_v_);
}

SolveReport FluidStep::project(SimState& state) {
  fill_velocity(state);
  const ProjectParams params{float(h_)};
  for_bands(
      [&](Box2 rows) { pressure_rhs(state.u.view(), state.v.view(), rhs_.view(), rows, params); });
  add_boundary_rhs(rhs_, fill_p_, 1.0);
  zero_solid(rhs_, solid_, *ex_);
  const SolveReport report = ops_->solver_p->solve(ops_->pressure, rhs_, state.p);
  fill_boundary(state.p.view(), size_, fill_p_);
  if (!solid_.empty())
    for_bands([&](Box2 rows) {
      fill_obstacle(state.p.view(), solid_.view(), rows, ObstacleRule::kCopy);
    });
  for_bands([&](Box2 rows) {
    face_velocities(state.u.view(), state.v.view(), state.p.view(), face_u_.view(), face_v_.view(),
                    rows, params, rows.max.y == size_.y);
  });
  if (fill_u_.bottom.rule == EdgeRule::kPeriodic) {
    // Ghost rows of uf and ghost columns of vf, wrapped, for the periodic back-trace.
    const int nx = size_.x, ny = size_.y;
    for (int i = 0; i <= nx; ++i) {
      face_u_(i, -1) = face_u_(i, ny - 1);
      face_u_(i, ny) = face_u_(i, 0);
    }
    for (int j = 0; j <= ny; ++j) {
      face_v_(-1, j) = face_v_(nx - 1, j);
      face_v_(nx, j) = face_v_(0, j);
    }
  }
  for_bands([&](Box2 rows) {
    subtract_gradient(state.p.view(), state.u.view(), state.v.view(), rows, params);
  });
  fill_velocity(state);
  return report;
}

void FluidStep::advect(SimState& state) {
  fill_velocity(state);
  copy_all(state.u, scratch_u_, *ex_);
  copy_all(state.v, scratch_v_, *ex_);
  const bool periodic = fill_u_.left.rule == EdgeRule::kPeriodic;
  const AdvectParams params{float(state.dt / h_), size_, periodic};
  for_bands([&](Box2 rows) {
    advect_velocity(scratch_u_.view(), scratch_v_.view(), state.u.view(), state.v.view(), rows,
                    params);
  });
}

void FluidStep::diffuse_dye(SimState& state) {
  if (!(config_.dye_diffusion > 0.0)) return;
  copy_all(state.dye, scratch_b_, *ex_);
  zero_solid(scratch_b_, solid_, *ex_);
  report_.dye = ops_->solver_dye->solve(ops_->dye, scratch_b_, state.dye);
}

void FluidStep::step(SimState& state) {
  if (config_.kind == FluidSceneKind::kNone) return;
  if (state.dt != prepared_dt_) prepare(state.dt);
  add_forces_and_sources(state);
  diffuse_velocity(state);
  report_.pressure_first = project(state);
  advect(state);
  report_.pressure_second = project(state);

  diffuse_dye(state);
  fill_boundary(state.dye.view(), size_, fill_dye_);
  if (!solid_.empty())
    for_bands([&](Box2 rows) {
      fill_obstacle(state.dye.view(), solid_.view(), rows, ObstacleRule::kCopy);
    });
  copy_all(state.dye, scratch_b_, *ex_);
  const bool closed =
      config_.kind == FluidSceneKind::kCavity || config_.kind == FluidSceneKind::kInk;
  const bool fix_mass = config_.conserve_dye && closed;
  const Range before = fix_mass ? interior_range(state.dye, *ex_) : Range{};
  const bool periodic = fill_dye_.left.rule == EdgeRule::kPeriodic;
  const AdvectParams params{float(state.dt / h_), size_, periodic};
  for_bands([&](Box2 rows) {
    advect_scalar_mac(scratch_b_.view(), face_u_.view(), face_v_.view(), state.dye.view(), rows,
                      params);
  });
  if (fix_mass) {
    restore_mass(state.dye, before.sum - interior_sum(state.dye, *ex_), before.lo, before.hi, *ex_);
  }
  fill_boundary(state.dye.view(), size_, fill_dye_);
}

std::unique_ptr<FluidStep> make_fluid_step(const SceneConfig& scene, RowExecutor& ex) {
  return std::make_unique<FluidStep>(scene.fluid, scene.size, scene.domain_width / scene.size.x,
                                     scene.dt, ex);
}

}  // namespace ardcell
