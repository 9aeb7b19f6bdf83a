#include "host/engine/fluid_step.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <utility>

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
    if (boundary_rule_factor(s.e) > 0.0)
      add_boundary_diagonal(op, s.side, boundary_rule_factor(s.e) * scale);
}

EdgeFill& side_of(BoundaryFill& fill, BoundarySide side) {
  switch (side) {
    case BoundarySide::kLeft:
      return fill.left;
    case BoundarySide::kRight:
      return fill.right;
    case BoundarySide::kBottom:
      return fill.bottom;
    case BoundarySide::kTop:
      break;
  }
  return fill.top;
}

BoundarySide opposite(BoundarySide side) {
  switch (side) {
    case BoundarySide::kLeft:
      return BoundarySide::kRight;
    case BoundarySide::kRight:
      return BoundarySide::kLeft;
    case BoundarySide::kBottom:
      return BoundarySide::kTop;
    case BoundarySide::kTop:
      break;
  }
  return BoundarySide::kBottom;
}

bool along_x(BoundarySide inflow) {
  return inflow == BoundarySide::kLeft || inflow == BoundarySide::kRight;
}

// The obstacle channel's ghost rules: inflow into the domain through config.inflow_side (the
// normal component at inflow_speed, plug or parabolic; no tangential inflow), do-nothing outflow
// through the opposite side (velocity copied, pressure 0), and the two walls (free-slip: normal
// component zero, tangential copied; no-slip: both zero).
void channel_fills(const FluidConfig& c, BoundaryFill& fu, BoundaryFill& fv, BoundaryFill& fp) {
  const EdgeFill copy{EdgeRule::kCopy, 0.0f};
  const EdgeFill zero{EdgeRule::kMirror, 0.0f};
  const bool x_flow = along_x(c.inflow_side);
  const float into = c.inflow_side == BoundarySide::kLeft || c.inflow_side == BoundarySide::kBottom
                         ? float(c.inflow_speed)
                         : float(-c.inflow_speed);
  BoundaryFill& normal_to_inflow = x_flow ? fu : fv;
  BoundaryFill& along_inflow = x_flow ? fv : fu;
  fp = BoundaryFill::copy();
  side_of(normal_to_inflow, c.inflow_side) = {
      c.inflow_profile == InflowProfile::kParabolic ? EdgeRule::kParabolic : EdgeRule::kMirror,
      into};
  side_of(along_inflow, c.inflow_side) = zero;
  const BoundarySide out = opposite(c.inflow_side);
  side_of(fu, out) = copy;
  side_of(fv, out) = copy;
  side_of(fp, out) = {EdgeRule::kFixed, 0.0f};
  const BoundarySide low = x_flow ? BoundarySide::kBottom : BoundarySide::kLeft;
  for (const auto& [side, kind] :
       {std::pair{low, c.wall_low}, std::pair{opposite(low), c.wall_high}}) {
    side_of(x_flow ? fv : fu, side) = zero;  // the normal component at a wall
    side_of(x_flow ? fu : fv, side) = kind == FluidWalls::kNoSlip ? zero : copy;
  }
}

// The open fraction of the cell face from (x, y0) to (x, y0 + 1) outside the disc of centre
// (cx, cy) and radius r, all in cells: 1 - the covered length. Fractions under 1% count as
// closed: a face so nearly shut couples its cells too weakly to matter and slows the solvers.
float open_fraction(double x, double y0, double cx, double cy, double r) {
  const double dx = x - cx;
  if (dx * dx >= r * r) return 1.0f;
  const double d = std::sqrt(r * r - dx * dx);
  const double covered = std::max(0.0, std::min(y0 + 1.0, cy + d) - std::max(y0, cy - d));
  const double open = 1.0 - covered;
  return open < 0.01 ? 0.0f : float(open);
}

}  // namespace

std::string fluid_config_problem(const SceneConfig& scene) {
  const FluidConfig& f = scene.fluid;
  if (f.kind != FluidSceneKind::kObstacle) return {};
  if (f.wall_low == FluidWalls::kPeriodic || f.wall_high == FluidWalls::kPeriodic)
    return "fluid.wall_low / fluid.wall_high: expected free-slip or no-slip (a channel's walls)";
  for (int i = 0; i < FluidConfig::kMaxProbes; ++i) {
    const bool x_set = f.probes[2 * i] >= 0.0f, y_set = f.probes[2 * i + 1] >= 0.0f;
    if (x_set != y_set)
      return "fluid.probes: expected x, y pairs (point " + std::to_string(i + 1) +
             " has one coordinate)";
  }
  if (!(f.obstacle_radius > 0.0))
    return "fluid.obstacle_radius: expected a positive radius for the obstacle scene";
  return {};
}

struct FluidStep::Operators {
  StencilOperator visc_u, visc_v, pressure, dye;
  std::unique_ptr<LinearSolver> solver_u, solver_v, solver_p, solver_dye;
};

FluidStep::FluidStep(const FluidConfig& config, Int2 size, double h, double dt, Device& device)
    : config_(config),
      block_(device.on_block() ? device.block() : DeviceBlock{}),
      whole_device_(block_.halo ? std::make_unique<CpuDevice>(device.executor()) : nullptr),
      dev_(whole_device_ ? whole_device_.get() : &device),
      size_(size),
      h_(h),
      scratch_u_(size, 1),
      scratch_v_(size, 1),
      scratch_b_(size, 1),
      rhs_(size, 1),
      face_u_(Int2{size.x + 1, size.y}, 1),
      face_v_(Int2{size.x, size.y + 1}, 1) {
  ARDCELL_CHECK(size.x > 0 && size.y > 0 && h > 0.0, "FluidStep: size and h must be positive");
  if (config_.advection == AdvectionScheme::kMacCormack) back_ = FieldF(size, 1);
  fill_p_ = BoundaryFill::copy();
  fill_dye_ = BoundaryFill::copy();
  switch (config_.kind) {
    case FluidSceneKind::kCavity:
      fill_u_ = BoundaryFill::no_slip(float(config_.lid_speed));
      fill_v_ = BoundaryFill::no_slip(0.0f);
      break;
    case FluidSceneKind::kObstacle: {
      channel_fills(config_, fill_u_, fill_v_, fill_p_);
      solid_ = Field<uint8_t>(size, 1);
      const double cx = config_.obstacle_x / h - 0.5, cy = config_.obstacle_y / h - 0.5;
      const double r = config_.obstacle_radius / h;
      for (int j = 0; j < size.y; ++j)
        for (int i = 0; i < size.x; ++i)
          solid_(i, j) = (i - cx) * (i - cx) + (j - cy) * (j - cy) <= r * r ? 1 : 0;
      if (config_.obstacle_boundary == ObstacleBoundary::kCutCell) cut_cells(cx + 0.5, cy + 0.5, r);
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
    case FluidSceneKind::kTable1:  // a frame plan of its own (host/engine/table1_plan.h)
      ARDCELL_CHECK(false, "FluidStep: the table1 scene runs as tile passes (Table1Plan)");
      break;
  }

  auto make_op = [&](const BoundaryFill& fill) {
    return assemble_stencil_operator(size, 1.0, 0.0, nullptr, axis_kind(fill.left, fill.right),
                                     axis_kind(fill.bottom, fill.top));
  };
  ops_ = std::make_unique<Operators>(Operators{make_op(fill_u_), make_op(fill_v_), make_op(fill_p_),
                                               make_op(fill_dye_), nullptr, nullptr, nullptr,
                                               nullptr});
  RowExecutor& ex = device.executor();
  ops_->solver_u = LinearSolver::make(config_.viscosity_solver, size, ex);
  ops_->solver_v = LinearSolver::make(config_.viscosity_solver, size, ex);
  ops_->solver_p = LinearSolver::make(config_.pressure_solver, size, ex);
  ops_->solver_dye = LinearSolver::make(config_.viscosity_solver, size, ex);
  dev_->reserve(size);

  // Pressure: 4 p - sum of neighbours = rhs, Neumann at walls and obstacle faces (cut cells:
  // each face weighed by its open fraction, and only the covered cells isolated).
  reassemble_stencil_operator(ops_->pressure, 0.0, 1.0, nullptr);
  if (!open_x_.empty()) weigh_faces(ops_->pressure, open_x_, open_y_);
  fold_boundary(ops_->pressure, fill_p_, 1.0);
  if (!solid_.empty()) isolate_solid_cells(ops_->pressure, pressure_solid(), 0.0);
  ops_->solver_p->prepare(ops_->pressure);
  dev_->host_wrote(ops_->pressure);
  dev_->host_wrote(solid_);
  if (!open_x_.empty()) {
    dev_->host_wrote(open_x_);
    dev_->host_wrote(open_y_);
    dev_->host_wrote(covered_);
  }
  prepare(dt);
}

// Cut cells: the open fraction of every face (the disc of centre (cx, cy) and radius r, in
// cells, faces at integer coordinates), and the cells whose four faces are all closed.
void FluidStep::cut_cells(double cx, double cy, double r) {
  open_x_ = FieldF(Int2{size_.x + 1, size_.y}, 1);
  open_y_ = FieldF(Int2{size_.x, size_.y + 1}, 1);
  covered_ = Field<uint8_t>(size_, 1);
  for (int j = 0; j < size_.y; ++j)
    for (int i = 0; i <= size_.x; ++i) open_x_(i, j) = open_fraction(i, j, cx, cy, r);
  for (int j = 0; j <= size_.y; ++j)  // a horizontal face: the same with x and y exchanged
    for (int i = 0; i < size_.x; ++i) open_y_(i, j) = open_fraction(j, i, cy, cx, r);
  for (int j = 0; j < size_.y; ++j)
    for (int i = 0; i < size_.x; ++i)
      covered_(i, j) = open_x_(i, j) == 0.0f && open_x_(i + 1, j) == 0.0f &&
                       open_y_(i, j) == 0.0f && open_y_(i, j + 1) == 0.0f;
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
  if (config_.kind == FluidSceneKind::kObstacle) channel_fills(config_, fill_u_, fill_v_, fill_p_);
  prepared_dt_ = -1.0;  // the viscous operators depend on the viscosity
}

void FluidStep::prepare(double dt) {
  prepared_dt_ = dt;
  const double s_visc = dt * config_.viscosity / (h_ * h_);
  auto setup = [&](StencilOperator& op, LinearSolver& solver, const BoundaryFill& fill, double s,
                   bool no_slip_obstacle) {
    reassemble_stencil_operator(op, 1.0, s, nullptr, dev_->executor());
    fold_boundary(op, fill, s);
    if (!solid_.empty()) isolate_solid_cells(op, solid_, no_slip_obstacle ? 2.0 : 0.0);
    solver.prepare(op);
    dev_->host_wrote(op);
  };
  setup(ops_->visc_u, *ops_->solver_u, fill_u_, s_visc, true);
  setup(ops_->visc_v, *ops_->solver_v, fill_v_, s_visc, true);
  setup(ops_->dye, *ops_->solver_dye, fill_dye_, dt * config_.dye_diffusion / (h_ * h_), false);
}

void FluidStep::allocate_whole(SimState& state) const {
  state.size = size_;
  state.h = h_;
  for (FieldF* f : {&state.u, &state.v, &state.p, &state.dye})
    if (f->empty() || f->size() != size_ || f->halo() < 1) *f = FieldF(size_, 1);
  if (!solid_.empty()) state.obstacle = solid_;
}

void FluidStep::allocate(SimState& state) {
  allocate_whole(block_.halo ? whole_ : state);
  if (!block_.halo) return;
  state.size = size_;
  state.h = h_;
  for (FieldF* f : {&state.u, &state.v, &state.p, &state.dye})
    if (f->empty() || f->interior() != block_.block || f->halo() < 1)
      *f = FieldF::over(block_.block, 1);
  // Like a painted one, the mask covers the grid on every block (host/paint/paint.h).
  if (!solid_.empty()) state.obstacle = solid_;
}

void FluidStep::gather(const SimState& state) {
  whole_.dt = state.dt;
  whole_.time = state.time;
  whole_.step = state.step;
  for (auto [from, to] : {std::pair{&state.u, &whole_.u}, std::pair{&state.v, &whole_.v},
                          std::pair{&state.p, &whole_.p}, std::pair{&state.dye, &whole_.dye}})
    block_.halo->gather_all(*from, *to);
}

void FluidStep::take(SimState& state) const {
  const Box2 allocated = box_of_size(size_).grown(1);
  for (auto [from, to] : {std::pair{&whole_.u, &state.u}, std::pair{&whole_.v, &state.v},
                          std::pair{&whole_.p, &state.p}, std::pair{&whole_.dye, &state.dye}})
    copy_box<float>(from->view(), to->view(),
                    to->interior().grown(to->halo()).intersected(allocated));
}

void FluidStep::reset(SimState& engine_state) {
  allocate(engine_state);
  SimState& state = stepped(engine_state);
  for (FieldF* f : {&state.u, &state.v, &state.p, &state.dye}) f->fill(0.0f);
  const Int2 n = size_;
  if (config_.kind == FluidSceneKind::kCavity) {
    // Eight horizontal bands of dye for the vortex to roll up.
    for (int j = 0; j < n.y; ++j) {
      const float value = (j * 8 / n.y) % 2 ? 1.0f : 0.0f;
      for (int i = 0; i < n.x; ++i) state.dye(i, j) = value;
    }
  } else if (config_.kind == FluidSceneKind::kObstacle) {
    // Start from the inflow carried through the channel; the first projection turns it around
    // the disc.
    const BoundarySide in = config_.inflow_side;
    const bool x_flow = along_x(in);
    FieldF& normal = x_flow ? state.u : state.v;
    const float into = in == BoundarySide::kLeft || in == BoundarySide::kBottom
                           ? float(config_.inflow_speed)
                           : float(-config_.inflow_speed);
    const bool parabolic = config_.inflow_profile == InflowProfile::kParabolic;
    for (int j = 0; j < n.y; ++j)
      for (int i = 0; i < n.x; ++i)
        normal(i, j) =
            parabolic ? into * parabolic_profile(x_flow ? j : i, x_flow ? n.y : n.x) : into;
  }
  for (const FieldF* f : {&state.u, &state.v, &state.p, &state.dye}) dev_->host_wrote(*f);
  if (!solid_.empty()) dev_->fill_obstacle(state.v, solid_, ObstacleRule::kZero);
  if (config_.kind != FluidSceneKind::kNone) {
    fill_velocity(state);
    dev_->fill_boundary(state.dye, fill_dye_);
  }
  if (block_.halo) take(engine_state);
}

void FluidStep::fill_velocity(SimState& state) const {
  dev_->fill_boundary(state.u, fill_u_);
  dev_->fill_boundary(state.v, fill_v_);
  if (!solid_.empty()) {
    dev_->fill_obstacle(state.u, solid_, ObstacleRule::kNoSlip);
    dev_->fill_obstacle(state.v, solid_, ObstacleRule::kNoSlip);
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
      dev_->add_splat(state.dye, {cx, cy, r, float(dt * e.dye_rate)});
      dev_->add_splat(state.u, {cx, cy, r, float(dt * fx)});
      dev_->add_splat(state.v, {cx, cy, r, float(dt * fy)});
    }
  } else if (config_.kind == FluidSceneKind::kObstacle && config_.inflow_dye_stripes > 0) {
    // Dye enters with the inflow in vertical stripes (the top row is refreshed each frame).
    dev_->set_inflow_stripes(state.dye, config_.inflow_dye_stripes, config_.inflow_side);
  }
}

void FluidStep::diffuse_velocity(SimState& state) {
  if (!(config_.viscosity > 0.0)) return;
  const double s = state.dt * config_.viscosity / (h_ * h_);
  auto solve = [&](FieldF& x, const StencilOperator& op, LinearSolver& solver,
                   const BoundaryFill& fill) {
    dev_->copy(x, scratch_b_);
    dev_->add_boundary_values(scratch_b_, fill, s);
    if (!solid_.empty()) dev_->fill_obstacle(scratch_b_, solid_, ObstacleRule::kZero);
    return dev_->solve(solver, op, scratch_b_, x);
  };
  report_.viscosity_u = solve(state.u, ops_->visc_u, *ops_->solver_u, fill_u_);
  report_.viscosity_v = solve(state.v, ops_->visc_v, *ops_->solver_v, fill_v_);
}

SolveReport FluidStep::project(SimState& state) {
  fill_velocity(state);
  const ProjectParams params{float(h_)};
  if (open_x_.empty())
    dev_->pressure_rhs(state.u, state.v, rhs_, params);
  else
    dev_->pressure_rhs(state.u, state.v, rhs_, params, &open_x_, &open_y_);
  dev_->add_boundary_values(rhs_, fill_p_, 1.0);
  if (!solid_.empty()) dev_->fill_obstacle(rhs_, pressure_solid(), ObstacleRule::kZero);
  const SolveReport report = dev_->solve(*ops_->solver_p, ops_->pressure, rhs_, state.p);
  dev_->fill_boundary(state.p, fill_p_);
  if (!solid_.empty()) dev_->fill_obstacle(state.p, pressure_solid(), ObstacleRule::kCopy);
  dev_->face_velocities(state.u, state.v, state.p, face_u_, face_v_, params,
                        fill_u_.bottom.rule == EdgeRule::kPeriodic);
  dev_->subtract_gradient(state.p, state.u, state.v, params);
  fill_velocity(state);
  return report;
}

void FluidStep::advect(SimState& state) {
  fill_velocity(state);
  dev_->copy(state.u, scratch_u_);
  dev_->copy(state.v, scratch_v_);
  const bool periodic = fill_u_.left.rule == EdgeRule::kPeriodic;
  const AdvectParams params{float(state.dt / h_), size_, periodic};
  dev_->advect_velocity(scratch_u_, scratch_v_, state.u, state.v, params);
  if (config_.advection != AdvectionScheme::kMacCormack) return;
  // MacCormack: the forward result carried back by the same velocity, then corrected by half
  // the round trip's error (kernels/advect.h maccormack_correct).
  fill_velocity(state);
  AdvectParams backward = params;
  backward.dt_over_h = -params.dt_over_h;
  const FieldF* hat[] = {&state.u, &state.v};
  FieldF* back[] = {&rhs_, &back_};
  dev_->advect_scalars(hat, scratch_u_, scratch_v_, back, backward);
  const FieldF* before[] = {&scratch_u_, &scratch_v_};
  const FieldF* back_in[] = {&rhs_, &back_};
  FieldF* out[] = {&state.u, &state.v};
  dev_->maccormack_correct(before, hat, back_in, scratch_u_, scratch_v_, out, params, false);
}

// The dye from scratch_b_ (its value before, ghosts filled) by the divergence-free face
// velocities, and with MacCormack the same correction as the velocity's.
void FluidStep::advect_dye(SimState& state, const AdvectParams& params) {
  dev_->advect_scalar_mac(scratch_b_, face_u_, face_v_, state.dye, params);
  if (config_.advection != AdvectionScheme::kMacCormack) return;
  dev_->fill_boundary(state.dye, fill_dye_);
  if (!solid_.empty()) dev_->fill_obstacle(state.dye, solid_, ObstacleRule::kCopy);
  AdvectParams backward = params;
  backward.dt_over_h = -params.dt_over_h;
  dev_->advect_scalar_mac(state.dye, face_u_, face_v_, rhs_, backward);
  const FieldF* before[] = {&scratch_b_};
  const FieldF* hat[] = {&state.dye};
  const FieldF* back[] = {&rhs_};
  FieldF* out[] = {&state.dye};
  dev_->maccormack_correct(before, hat, back, face_u_, face_v_, out, params, true);
}

void FluidStep::diffuse_dye(SimState& state) {
  if (!(config_.dye_diffusion > 0.0)) return;
  dev_->copy(state.dye, scratch_b_);
  if (!solid_.empty()) dev_->fill_obstacle(scratch_b_, solid_, ObstacleRule::kZero);
  report_.dye = dev_->solve(*ops_->solver_dye, ops_->dye, scratch_b_, state.dye);
}

void FluidStep::append_stages(FramePlan& plan, SimState& engine_state) {
  if (config_.kind == FluidSceneKind::kNone) return;
  if (block_.halo)
    plan.add_stage({"fluid: gather the blocks", [this, &engine_state] { gather(engine_state); }});
  SimState& state = stepped(engine_state);
  plan.add_stage({"fluid: forces, sources", [this, &state] {
                    if (state.dt != prepared_dt_) prepare(state.dt);
                    add_forces_and_sources(state);
                  }});
  plan.add_stage({"fluid: viscosity", [this, &state] { diffuse_velocity(state); }});
  plan.add_stage({"fluid: projection", [this, &state] {
                    report_.pressure_first = project(state);
                    if (!p_first_.empty()) dev_->copy(state.p, p_first_);
                  }});
  plan.add_stage({"fluid: self-advection", [this, &state] { advect(state); }});
  plan.add_stage(
      {"fluid: projection 2", [this, &state] { report_.pressure_second = project(state); }});
  plan.add_stage({"fluid: dye", [this, &state] { step_dye(state); }});
  if (block_.halo)
    plan.add_stage({"fluid: the block's cells", [this, &engine_state] { take(engine_state); }});
}

void FluidStep::step_dye(SimState& state) {
  diffuse_dye(state);
  dev_->fill_boundary(state.dye, fill_dye_);
  if (!solid_.empty()) dev_->fill_obstacle(state.dye, solid_, ObstacleRule::kCopy);
  dev_->copy(state.dye, scratch_b_);
  const bool closed =
      config_.kind == FluidSceneKind::kCavity || config_.kind == FluidSceneKind::kInk;
  const bool fix_mass = config_.conserve_dye && closed;
  const FieldRange before = fix_mass ? dev_->range(state.dye) : FieldRange{};
  const bool periodic = fill_dye_.left.rule == EdgeRule::kPeriodic;
  const AdvectParams params{float(state.dt / h_), size_, periodic};
  advect_dye(state, params);
  if (fix_mass) {
    // Advection's mass error, put back where it is least certain (Device::restore_mass).
    const double after = dev_->range(state.dye).sum;
    dev_->restore_mass(state.dye, before.sum - after, before.lo, before.hi);
  }
  dev_->fill_boundary(state.dye, fill_dye_);
}

void FluidStep::record_pressure(bool on) {
  if (!on) {
    p_first_ = FieldF();
    return;
  }
  if (p_first_.empty()) p_first_ = FieldF(size_, 1);
}

void FluidStep::physical_pressure(const SimState& engine_state, FieldF& out) const {
  const SimState& state = block_.halo ? whole_ : engine_state;
  ARDCELL_CHECK(!p_first_.empty(), "physical_pressure: record_pressure(true) first");
  ARDCELL_CHECK(out.size() == size_, "physical_pressure: out must have the grid's size");
  dev_->sync_to_host(p_first_);
  dev_->sync_to_host(state.p);
  const float inv_dt = float(1.0 / state.dt);
  for (int j = -1; j <= size_.y; ++j)
    for (int i = -1; i <= size_.x; ++i) out(i, j) = (p_first_(i, j) + state.p(i, j)) * inv_dt;
}

std::unique_ptr<FluidStep> make_fluid_step(const SceneConfig& scene, Device& device) {
  return std::make_unique<FluidStep>(scene.fluid, scene.size, scene.domain_width / scene.size.x,
                                     scene.dt, device);
}

}  // namespace ardcell
