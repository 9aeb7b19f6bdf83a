#if defined(ARDCELL_WITH_OPENCL)
#include "host/engine/opencl_rd_engine.h"

#include <array>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "host/engine/rd_step.h"

namespace ardcell {
namespace {

// The CPU Engine that holds the host mirror: the scene with diffusion off, so that it builds no
// linear solver (the device diffuses).
SceneConfig shadow_scene(SceneConfig scene) {
  scene.rd.diffuse = false;
  return scene;
}

// The ghost ring of A or B (host/engine/rd_step.cpp's rule for the chemicals).
BoundaryFill chemical_ghosts(BoundaryKind kind, float value) {
  if (kind == BoundaryKind::kPeriodic) return BoundaryFill::periodic();
  if (kind == BoundaryKind::kDirichlet) return BoundaryFill::fixed(value);
  return BoundaryFill::copy();
}

// Every value a reaction table depends on, to rebuild it only when one changes.
std::array<float, 17> table_inputs(const ReactionParams& p, double dt) {
  return {float(int(p.model)),
          p.F,
          p.k,
          p.turing_s,
          p.turing_beta,
          p.meinhardt_s,
          p.meinhardt_alpha,
          p.meinhardt_p1,
          p.meinhardt_p2,
          p.meinhardt_p3,
          p.fhn_epsilon,
          p.fhn_a0,
          p.fhn_a1,
          p.barkley_epsilon,
          p.barkley_a,
          p.barkley_b,
          float(dt)};
}

std::string number_text(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

}  // namespace

std::string OpenClRdEngine::device_problem(const SceneConfig& scene) {
  const RdConfig& rd = scene.rd;
  if (scene.fluid.kind != FluidSceneKind::kNone)
    return "fluid.scene: the scene has a fluid (or an obstacle's solid cells); the OpenCL engine "
           "runs reaction-diffusion-only scenes (and the table1 scenes), expected a scene "
           "without fluid";
  if (!rd.enabled)
    return "rd.enabled: the scene has no reaction-diffusion; the OpenCL engine runs "
           "reaction-diffusion-only scenes";
  if (rd.scheme != RdScheme::kImplicit)
    return "rd.scheme: the explicit schemes run on the CPU engine only; expected implicit";
  if (rd.diffuse) {
    const SolverKind kind = rd.diffusion_solver.kind;
    if (kind != SolverKind::kJacobi && kind != SolverKind::kRedBlackGaussSeidel)
      return "rd.diffusion_solver.kind=" + std::string(solver_kind_name(kind)) +
             ": the OpenCL engine diffuses with fixed-sweep jacobi or rbgs (expected --set "
             "rd.diffusion_solver.kind=jacobi|rbgs --set rd.diffusion_solver.tolerance=0)";
    if (rd.diffusion_solver.tolerance != 0.0)
      return "rd.diffusion_solver.tolerance=" + number_text(rd.diffusion_solver.tolerance) +
             ": stopping on a residual runs on the CPU engine only; expected 0 (fixed sweeps)";
  }
  return rd_config_problem(scene);
}

OpenClRdEngine::OpenClRdEngine(OpenClKernels& cl, const SceneConfig& scene)
    : cl_(cl), config_(scene) {
  if (std::string why = device_problem(scene); !why.empty()) throw std::invalid_argument(why);
  shadow_ = std::make_unique<Engine>(shadow_scene(scene));
  OpenClContext& ctx = cl_.context();
  const SimState& s = shadow_->state();
  a_ = ctx.allocate_like(s.A);
  b_ = ctx.allocate_like(s.B);
  theta0_ = ctx.allocate_like(s.theta0);
  conductivity_ = ctx.allocate_like(s.A);
  const RdConfig& rd = config_.rd;
  if (rd.diffuse) {
    diffuse_a_ =
        std::make_unique<OpenClDiffusion>(cl_, scene.size, rd.boundary, rd.diffusion_solver);
    diffuse_b_ =
        std::make_unique<OpenClDiffusion>(cl_, scene.size, rd.boundary, rd.diffusion_solver);
  }
  dt_ = rd.dt > 0 ? rd.dt : scene.dt;
  h_ = rd.cell_size > 0 ? rd.cell_size : scene.domain_width / scene.size.x;
  if (rd.use_table && rd.react) rebuild_table();
  upload_state();
}

OpenClRdEngine::~OpenClRdEngine() = default;

void OpenClRdEngine::rebuild_table() {
  const RdConfig& rd = config_.rd;
  const ConcentrationBox range = rd.table_range_auto ? typical_range(rd.reaction) : rd.table_range;
  const ReactionTable table(rd.reaction, dt_, range, rd.table_resolution);
  table_.upload(cl_.context(), table.view());
}

void OpenClRdEngine::reset() {
  shadow_->reset();
  upload_state();
}

void OpenClRdEngine::step() {
  const RdConfig& rd = config_.rd;
  const Box2 interior = a_.interior();
  const bool anisotropic = rd.anisotropy.kind != AnisotropyKind::kIsotropic;
  const double base = dt_ / (h_ * h_) * (anisotropic ? 1.0 : double(rd.anisotropy.isotropic_value));
  for (int k = 0; k < rd.steps_per_frame; ++k) {
    if (rd.react) {
      if (table_.n > 0)
        cl_.reaction_table(a_, b_, a_, b_, interior, table_);
      else
        cl_.reaction_implicit(a_, b_, a_, b_, interior, rd.reaction, float(dt_));
    }
    if (!rd.diffuse) continue;
    const DeviceField* k_cells = nullptr;
    if (anisotropic) {
      // The CPU fills both chemicals' ghosts here; A's feed the gradient of theta(A).
      cl_.fill_boundary(a_, chemical_ghosts(rd.boundary, rd.boundary_a));
      cl_.fill_boundary(b_, chemical_ghosts(rd.boundary, rd.boundary_b));
      cl_.conductivity(a_, &theta0_, conductivity_, interior, rd.anisotropy);
      k_cells = &conductivity_;
    }
    diffuse_a_->step(a_, k_cells, {rd.diffusion_a * base, rd.boundary_a, rd.crank_nicolson});
    diffuse_b_->step(b_, rd.anisotropy_on_b ? k_cells : nullptr,
                     {rd.diffusion_b * base, rd.boundary_b, rd.crank_nicolson});
  }
  SimState& s = shadow_->state();
  s.time += s.dt;
  ++s.step;
}

void OpenClRdEngine::finish() { cl_.context().finish(); }

Status OpenClRdEngine::update_parameters(const SceneConfig& next) {
  // The shadow Engine has diffusion off: the structural keys it cannot see are checked here.
  if (next.rd.diffuse != config_.rd.diffuse)
    return Status::error(
        "rd.diffuse: changes the simulation's structure; rebuild the engine (switch presets) to "
        "change it");
  if (std::string why = device_problem(next); !why.empty()) return Status::error(why);
  if (Status s = shadow_->update_parameters(shadow_scene(next)); !s) return s;
  const auto old_table_inputs = table_inputs(config_.rd.reaction, dt_);
  config_ = next;
  const RdConfig& rd = config_.rd;
  dt_ = rd.dt > 0 ? rd.dt : config_.dt;
  h_ = rd.cell_size > 0 ? rd.cell_size : config_.domain_width / config_.size.x;
  for (OpenClDiffusion* d : {diffuse_a_.get(), diffuse_b_.get()})
    if (d) d->set_sweeps(rd.diffusion_solver.max_iterations);
  if (table_.n > 0 && table_inputs(rd.reaction, dt_) != old_table_inputs) rebuild_table();
  return Status::ok();
}

const SimState& OpenClRdEngine::download_state() {
  download_chemical(false);
  download_chemical(true);
  return shadow_->state();
}

const FieldF& OpenClRdEngine::download_chemical(bool b) {
  FieldF& host = b ? shadow_->state().B : shadow_->state().A;
  cl_.context().download(b ? b_ : a_, host);
  return host;
}

void OpenClRdEngine::upload_theta0() { cl_.context().upload(shadow_->state().theta0, theta0_); }

void OpenClRdEngine::upload_state() {
  const SimState& s = shadow_->state();
  OpenClContext& ctx = cl_.context();
  ctx.upload(s.A, a_);
  ctx.upload(s.B, b_);
  ctx.upload(s.theta0, theta0_);
}

}  // namespace ardcell
#endif
