#include "host/engine/rd_step.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <type_traits>
#include <utility>

#include "kernels/advect.h"
#include "kernels/explicit_rd.h"
#include "runtime/boundary.h"

namespace ardcell {
namespace {

// splitmix64: the same initial pattern for a seed on every platform.
struct SplitMix {
  uint64_t state;
  double uniform() {  // [0, 1)
    uint64_t z = (state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    z ^= z >> 31;
    return double(z >> 11) * (1.0 / 9007199254740992.0);
  }
};

BoundaryFill chemical_fill(BoundaryKind kind, float value) {
  switch (kind) {
    case BoundaryKind::kPeriodic:
      return BoundaryFill::periodic();
    case BoundaryKind::kNeumann:
      return BoundaryFill::copy();
    case BoundaryKind::kDirichlet:
      return BoundaryFill::fixed(value);
  }
  return BoundaryFill::copy();
}

double rd_step_of(const SceneConfig& scene) { return scene.rd.dt > 0 ? scene.rd.dt : scene.dt; }
double rd_cell_of(const SceneConfig& scene) {
  return scene.rd.cell_size > 0 ? scene.rd.cell_size : scene.domain_width / scene.size.x;
}
// What multiplies the operator's stencil for A (or B): dt D / h^2 with the Laplacian; dt D with
// the generalized operator, whose stencil carries h itself (generalized_stencil).
double diffusion_scale(const SceneConfig& scene, bool b) {
  const double h =
      scene.rd.diffusion_operator == RdOperator::kGeneralized ? 1.0 : rd_cell_of(scene);
  return rd_step_of(scene) / (h * h) * scene.rd.anisotropy.isotropic_value *
         (b ? scene.rd.diffusion_b : scene.rd.diffusion_a);
}

// K in cells for a cell of size h: a rank-l term D_l d^l u in the domain's units is
// h^-l D_l d^l u in cells, so the ranks scale apart (h sets the length at which the rank-4 terms
// overtake the rank-2 ones: sqrt(|D_4| / |D_2|) / h cells).
Stencil5x5 generalized_stencil(const SceneConfig& scene) {
  const RdConfig& rd = scene.rd;
  const double h = rd_cell_of(scene);
  TensorSequence d = rd.generalized.tensors;
  for (int rank = 2; rank <= 4; ++rank)
    for (int nx = 0; nx <= rank; ++nx) d.component(nx, rank - nx) *= std::pow(h, -rank);
  GeneralizedDiffusionOptions options;
  options.savitzky_golay_degree = rd.generalized.savitzky_golay_degree;
  options.second_derivatives = rd.generalized.second_derivatives;
  return assemble_generalized_stencil(d, options);
}

bool second_order_scheme(RdScheme s) {
  return s == RdScheme::kCrankNicolsonAm2 || s == RdScheme::kSbdf2 || s == RdScheme::kEtdrk4;
}

const char* generalized_problem(const SceneConfig& scene) {
  const RdConfig& rd = scene.rd;
  if (rd.diffusion_operator != RdOperator::kGeneralized) {
    if (rd.scheme == RdScheme::kExplicit || rd.scheme == RdScheme::kSemiImplicit)
      return "rd.scheme: explicit and semi-implicit are seed 003's schemes; they need rd.operator "
             "generalized";
    return nullptr;
  }
  if (rd.boundary != BoundaryKind::kPeriodic)
    return "rd.operator generalized needs rd.boundary periodic (its textures tile)";
  if (rd.scheme == RdScheme::kExplicit5 || rd.scheme == RdScheme::kExplicit9 ||
      second_order_scheme(rd.scheme))
    return "rd.scheme: explicit5, explicit9, crank-nicolson-am2, sbdf2 and etdrk4 are the "
           "Laplacian's; use implicit, explicit or semi-implicit with rd.operator generalized";
  if (rd.anisotropy.kind != AnisotropyKind::kIsotropic)
    return "rd.anisotropy.kind: the generalized operator's anisotropy is its tensor sequence; "
           "use isotropic";
  if (rd.generalized.savitzky_golay_degree != 4 && rd.generalized.savitzky_golay_degree != 5)
    return "rd.generalized.sg_degree must be 4 or 5";
  const TensorSequence& d = rd.generalized.tensors;
  for (int nx = 0; nx <= 4; ++nx)
    for (int ny = 0; nx + ny <= 4; ++ny)
      if (nx + ny >= 2 && !std::isfinite(d.component(nx, ny)))
        return "rd.generalized: every tensor component must be a finite number";
  if (scene.size.x < 5 || scene.size.y < 5)
    return "rd.operator generalized needs a grid of at least 5x5 cells (a 5x5 stencil)";
  if (rd.generalized.field != TensorFieldKind::kUniform) {
    for (int nx = 0; nx <= 4; ++nx)
      for (int ny = 0; nx + ny <= 4; ++ny)
        if (nx + ny >= 3 && d.component(nx, ny) != 0)
          return "rd.generalized.field: the tensor field is rank 2; set the rank-3 and rank-4 "
                 "components of rd.generalized to 0";
    const GeneralizedRdConfig& g = rd.generalized;
    if (!(g.d_along >= 0 && g.d_across >= 0) || !std::isfinite(g.d_along + g.d_across))
      return "rd.generalized.d_along and d_across must be finite and >= 0 (a positive "
             "semidefinite tensor)";
  }
  return nullptr;
}

// The per-cell tensor field of rd.generalized.field in cells (the domain's D times h^-2).
Rank2FaceField tensor_field(const SceneConfig& scene) {
  const GeneralizedRdConfig& g = scene.rd.generalized;
  const double h = rd_cell_of(scene);
  return rank2_tensor_field(scene.size, g.field, g.d_along / (h * h), g.d_across / (h * h));
}

}  // namespace

std::string generalized_stability_line(const SceneConfig& scene) {
  const RdConfig& rd = scene.rd;
  if (!rd.enabled || rd.diffusion_operator != RdOperator::kGeneralized ||
      rd.scheme != RdScheme::kExplicit || !rd.diffuse || generalized_problem(scene))
    return "";
  // The symbol is smooth in the wavenumber: 128 samples per axis find its extremes.
  const int n = std::min(128, std::min(scene.size.x, scene.size.y));
  double rho_a = 0, rho_b = 0;
  const GeneralizedRdConfig& g = rd.generalized;
  const auto add = [&](const Stencil5x5& k) {
    rho_a = std::max(rho_a, explicit_spectral_radius(k, diffusion_scale(scene, false), n));
    rho_b = std::max(rho_b, explicit_spectral_radius(k, diffusion_scale(scene, true), n));
  };
  if (g.field == TensorFieldKind::kUniform) {
    add(generalized_stencil(scene));
  } else {  // frozen coefficients: the worst of the field's tensors over 16 directions
    const double h2 = std::pow(rd_cell_of(scene), 2);
    for (int i = 0; i < 16; ++i) {
      const double phi = 3.14159265358979323846 * i / 16, c = std::cos(phi), s = std::sin(phi);
      add(gaussian_stencil((g.d_along * c * c + g.d_across * s * s) / h2,
                           (g.d_along - g.d_across) * c * s / h2,
                           (g.d_along * s * s + g.d_across * c * c) / h2));
    }
  }
  char line[256];
  std::snprintf(line, sizeof line,
                "rd: explicit update (seed 003, Eqn 27): rho(I + dt D_A K) = %.4f, "
                "rho(I + dt D_B K) = %.4f%s",
                rho_a, rho_b,
                std::max(rho_a, rho_b) > 1.0
                    ? "; above 1, errors grow: lower rd.dt or use rd.scheme semi-implicit"
                    : "");
  return line;
}

std::string rd_config_problem(const SceneConfig& scene) {
  const RdConfig& rd = scene.rd;
  if (const char* why = reaction_params_problem(rd.reaction)) return std::string("rd.") + why;
  if (const char* why = anisotropy_params_problem(rd.anisotropy)) return std::string("rd.") + why;
  if (!(rd.diffusion_a >= 0 && rd.diffusion_b >= 0))
    return "rd.diffusion_a and rd.diffusion_b must be >= 0";
  if (!(rd.dt >= 0) || !std::isfinite(rd.dt)) return "rd.dt must be >= 0 (0: the scene's dt)";
  if (!(rd.cell_size >= 0) || !std::isfinite(rd.cell_size))
    return "rd.cell_size must be >= 0 (0: the scene's h)";
  if (rd.steps_per_frame < 1 || rd.steps_per_frame > 1000)
    return "rd.steps_per_frame must be 1 to 1000";
  if (rd.scheme != RdScheme::kImplicit && rd.scheme != RdScheme::kCrankNicolsonAm2 &&
      rd.scheme != RdScheme::kSbdf2 && rd.anisotropy.kind != AnisotropyKind::kIsotropic)
    return "rd.scheme: the explicit schemes and etdrk4 are isotropic; use scheme implicit, "
           "crank-nicolson-am2 or sbdf2 with anisotropy";
  if (rd.scheme == RdScheme::kEtdrk4 && rd.boundary != BoundaryKind::kPeriodic)
    return "rd.scheme etdrk4 needs rd.boundary periodic (its Fourier modes wrap around)";
  if (rd.use_table) {
    if (rd.table_resolution < 2 || rd.table_resolution > 4096)
      return "rd.table_resolution must be 2 to 4096";
    const ConcentrationBox r = rd.table_range_auto ? typical_range(rd.reaction) : rd.table_range;
    if (!(r.a_hi > r.a_lo && r.b_hi > r.b_lo) || !std::isfinite(r.a_hi - r.a_lo) ||
        !std::isfinite(r.b_hi - r.b_lo))
      return "rd.table_range must be a finite, non-empty box";
  }
  if (rd.map) {
    if (rd.reaction.model != ReactionModel::kGrayScott)
      return "rd.map: a parameter map varies Gray-Scott's F and k (expected rd.reaction.model "
             "gray-scott)";
    if (rd.diffusion_operator != RdOperator::kGeneralized ||
        (rd.scheme != RdScheme::kExplicit && rd.scheme != RdScheme::kSemiImplicit))
      return "rd.map: a parameter map runs with rd.operator generalized and rd.scheme explicit "
             "or semi-implicit";
    if (!(rd.map_f >= 0.0f && rd.map_k >= 0.0f))
      return "rd.map.f_right and rd.map.k_top must be >= 0 (Gray-Scott's F and k)";
  }
  if (!(rd.noise >= 0 && rd.noise <= 1)) return "rd.noise must be in [0, 1]";
  if (scene.size.x < 3 || scene.size.y < 3) return "rd needs a grid of at least 3x3 cells";
  if (const char* why = generalized_problem(scene)) return why;
  return "";
}

namespace {

// The schemes whose diffusion is ImplicitDiffusion's solve (with the Laplacian).
bool diffusion_solves(RdScheme scheme) {
  return scheme == RdScheme::kImplicit || scheme == RdScheme::kCrankNicolsonAm2 ||
         scheme == RdScheme::kSbdf2;
}

}  // namespace

bool rd_block_sweeps(const SceneConfig& scene) {
  return ImplicitDiffusion::runs_on_block(scene.rd.diffusion_solver, scene.size,
                                          scene.rd.boundary) &&
         scene.fluid.kind != FluidSceneKind::kObstacle;
}

bool rd_block_gathers(const SceneConfig& scene) {
  const RdConfig& rd = scene.rd;
  const bool on_its_cells = rd.scheme == RdScheme::kExplicit5 ||
                            rd.scheme == RdScheme::kExplicit9 ||
                            (diffusion_solves(rd.scheme) && rd_block_sweeps(scene));
  return rd.diffusion_operator != RdOperator::kLaplacian || !on_its_cells ||
         (rd.advect && scene.fluid.kind != FluidSceneKind::kNone);
}

int rd_block_halo(const SceneConfig& scene) {
  const bool explicit_steps =
      scene.rd.scheme == RdScheme::kExplicit5 || scene.rd.scheme == RdScheme::kExplicit9;
  return explicit_steps && scene.rd.boundary == BoundaryKind::kPeriodic ? kExplicitBlockSteps : 1;
}

RdStepper::RdStepper(const SceneConfig& scene, Device& device)
    : scene_(scene),
      dev_(&device),
      rd_(scene.rd),
      cells_(device.on_block() ? device.block().block : box_of_size(scene.size)) {
  RowExecutor& ex = device.executor();
  if (std::string why = rd_config_problem(scene); !why.empty()) throw std::invalid_argument(why);
  if (device.on_block()) {
    block_steps_ = std::min(rd_block_halo(scene), device.block().halo->width());
  }
  const double scene_h = scene.domain_width / scene.size.x;
  dt_ = rd_.dt > 0 ? rd_.dt : scene.dt;
  h_ = rd_.cell_size > 0 ? rd_.cell_size : scene_h;
  const bool generalized = rd_.diffusion_operator == RdOperator::kGeneralized;
  if (generalized) {
    const Stencil5x5 k = generalized_stencil(scene);
    generalized_ = std::make_unique<GeneralizedTaps>(k);
    if (rd_.generalized.field != TensorFieldKind::kUniform)
      tensor_field_ = std::make_unique<Rank2FaceField>(tensor_field(scene));
    if (rd_.diffuse && rd_.scheme != RdScheme::kExplicit && tensor_field_) {
      tensor_solve_ = std::make_unique<TensorFieldSolve>(*tensor_field_, ex);
      tensor_solve_->set_limits(rd_.diffusion_solver.max_iterations,
                                rd_.diffusion_solver.tolerance);
    } else if (rd_.diffuse && rd_.scheme != RdScheme::kExplicit) {
      // Throw std::invalid_argument with problem()'s line when (I - dt D K) is singular.
      periodic_a_ = std::make_unique<PeriodicStencilSolve>(scene.size, k, ex);
      periodic_b_ = std::make_unique<PeriodicStencilSolve>(scene.size, k, ex);
      periodic_a_->set_delta(diffusion_scale(scene, false));
      periodic_b_->set_delta(diffusion_scale(scene, true));
    }
  }
  if (diffusion_solves(rd_.scheme) && rd_.diffuse && !generalized) {
    // On a block, the sweeps run on its cells where they can (else on the gathered grid).
    const bool block_sweeps =
        device.on_block() && cells_ != box_of_size(scene.size) && rd_block_sweeps(scene);
    for (std::unique_ptr<ImplicitDiffusion>* d : {&diff_a_, &diff_b_})
      *d = block_sweeps ? std::make_unique<ImplicitDiffusion>(scene.size, cells_, rd_.boundary,
                                                              rd_.diffusion_solver, ex)
                        : std::make_unique<ImplicitDiffusion>(scene.size, rd_.boundary,
                                                              rd_.diffusion_solver, ex);
  }
  if (rd_.use_table && rd_.react && rd_.scheme == RdScheme::kImplicit) {
    const ConcentrationBox r = rd_.table_range_auto ? typical_range(rd_.reaction) : rd_.table_range;
    table_ = ReactionTable(rd_.reaction, dt_, r, rd_.table_resolution);
    device.host_wrote(table_);
  }
  // Seed 001's scheme: a frame's steps in one op, temporally blocked, where the device has it.
  if (rd_.scheme == RdScheme::kExplicit9 && rd_.reaction.model == ReactionModel::kGrayScott &&
      rd_.react && rd_.diffuse && rd_.boundary == BoundaryKind::kPeriodic &&
      device.supports(DeviceOp::kGrayScott9Steps))
    gray_scott9_ = std::make_unique<GrayScott9Blocked>(
        cells_.size(), ex, 0, std::min(GrayScott9Blocked::kBlockSteps, kExplicitBlockSteps),
        device.on_block() ? GrayScott9Blocked::Rows::kFromHalo
                          : GrayScott9Blocked::Rows::kPeriodic);
  conductivity_ = FieldF::over(cells_, 1);
  scratch_a_ = FieldF::over(cells_, chemical_halo());
  scratch_b_ = FieldF::over(cells_, chemical_halo());
  if (scene.fluid.kind != FluidSceneKind::kNone && rd_.advect &&
      scene.fluid.advection == AdvectionScheme::kMacCormack) {
    back_a_ = FieldF::over(cells_, chemical_halo());
    back_b_ = FieldF::over(cells_, chemical_halo());
  }
  if (rd_.scheme == RdScheme::kSbdf2) {
    prev_a_ = FieldF::over(cells_, 1);
    prev_b_ = FieldF::over(cells_, 1);
  }
  if (rd_.scheme == RdScheme::kEtdrk4) {
    etdrk4_ = std::make_unique<PeriodicEtdrk4>(scene.size, ex);
    set_etdrk4_step();
  }
  device.reserve(scene.size);
}

void RdStepper::set_etdrk4_step() {
  // L's rates per unit time in cells: D / h^2 (times the isotropic a); none without diffusion.
  const double base = rd_.diffuse ? rd_.anisotropy.isotropic_value / (h_ * h_) : 0.0;
  etdrk4_->set_step(dt_, rd_.diffusion_a * base, rd_.diffusion_b * base);
}

int RdStepper::chemical_halo() const {
  if (gray_scott9_) return GrayScott9Blocked::kHalo;
  return dev_->on_block() ? std::max(block_steps_, dev_->block().halo->width()) : 1;
}

GrayScott9Params RdStepper::gray_scott9_params() const {
  const double base = dt_ / (h_ * h_) * rd_.anisotropy.isotropic_value;
  return {rd_.reaction.F, rd_.reaction.k, float(dt_), float(rd_.diffusion_a * base),
          float(rd_.diffusion_b * base)};
}

RdStepper::~RdStepper() = default;

namespace {
bool same_reaction(const ReactionParams& a, const ReactionParams& b) {
  return a.model == b.model && a.F == b.F && a.k == b.k && a.turing_s == b.turing_s &&
         a.turing_beta == b.turing_beta && a.turing_supply == b.turing_supply &&
         a.meinhardt_s == b.meinhardt_s && a.meinhardt_alpha == b.meinhardt_alpha &&
         a.meinhardt_p1 == b.meinhardt_p1 && a.meinhardt_p2 == b.meinhardt_p2 &&
         a.meinhardt_p3 == b.meinhardt_p3 && a.fhn_epsilon == b.fhn_epsilon &&
         a.fhn_a0 == b.fhn_a0 && a.fhn_a1 == b.fhn_a1 && a.barkley_epsilon == b.barkley_epsilon &&
         a.barkley_a == b.barkley_a && a.barkley_b == b.barkley_b;
}
}  // namespace

void RdStepper::update_parameters(const SceneConfig& scene) {
  const ReactionParams old_reaction = rd_.reaction;
  const double old_dt = dt_, old_h = h_;
  const double old_rates[3] = {rd_.diffusion_a, rd_.diffusion_b, rd_.anisotropy.isotropic_value};
  rd_ = scene.rd;
  scene_.rd = scene.rd;
  scene_.dt = scene.dt;
  dt_ = rd_.dt > 0 ? rd_.dt : scene.dt;
  h_ = rd_.cell_size > 0 ? rd_.cell_size : scene_.domain_width / scene_.size.x;
  for (ImplicitDiffusion* d : {diff_a_.get(), diff_b_.get()})
    if (d)
      d->set_solver_limits(rd_.diffusion_solver.max_iterations, rd_.diffusion_solver.tolerance);
  if (rd_.use_table && rd_.react && rd_.scheme == RdScheme::kImplicit &&
      (dt_ != old_dt || !same_reaction(old_reaction, rd_.reaction))) {
    const ConcentrationBox r = rd_.table_range_auto ? typical_range(rd_.reaction) : rd_.table_range;
    table_ = ReactionTable(rd_.reaction, dt_, r, rd_.table_resolution);
    dev_->host_wrote(table_);
  }
  // SBDF2's coefficients hold for a constant step: a new dt starts it again.
  if (dt_ != old_dt) restart();
  if (etdrk4_ &&
      (dt_ != old_dt || h_ != old_h || rd_.diffusion_a != old_rates[0] ||
       rd_.diffusion_b != old_rates[1] || rd_.anisotropy.isotropic_value != old_rates[2]))
    set_etdrk4_step();
  if (tensor_solve_)
    tensor_solve_->set_limits(rd_.diffusion_solver.max_iterations, rd_.diffusion_solver.tolerance);
  if (periodic_a_) periodic_a_->set_delta(diffusion_scale(scene_, false));
  if (periodic_b_) periodic_b_->set_delta(diffusion_scale(scene_, true));
}

std::string RdStepper::parameter_problem(const SceneConfig& scene) const {
  if (periodic_a_)
    if (std::string why = periodic_a_->problem(diffusion_scale(scene, false)); !why.empty())
      return "rd.diffusion_a: " + why;
  if (periodic_b_)
    if (std::string why = periodic_b_->problem(diffusion_scale(scene, true)); !why.empty())
      return "rd.diffusion_b: " + why;
  return "";
}

void RdStepper::init_state(SimState& s) {
  restart();
  const int halo = chemical_halo();
  if (s.A.empty() || s.A.interior() != cells_ || s.A.halo() != halo)
    s.A = FieldF::over(cells_, halo);
  if (s.B.empty() || s.B.interior() != cells_ || s.B.halo() != halo)
    s.B = FieldF::over(cells_, halo);
  if (s.theta0.empty() || s.theta0.interior() != cells_) {
    s.theta0 = FieldF::over(cells_, 1);
    s.theta0.fill(rd_.anisotropy.theta0);
  }
  write_initial_pattern(s.A, s.B);
  for (const FieldF* f : {&s.A, &s.B, &s.theta0}) dev_->host_wrote(*f);
}

void RdStepper::write_initial_pattern(FieldF& A, FieldF& B) const {
  // The pattern is laid out over the whole grid (one random sequence); the cells outside these
  // fields' (a block's) are skipped.
  const Int2 n = scene_.size;
  const Box2 cells = A.interior();
  A.fill(rd_.background_a);
  B.fill(rd_.background_b);
  SplitMix rng{rd_.seed};
  auto put_a = [&](int x, int y, float v) {
    if (cells.contains(Int2{x, y})) A(x, y) = v;
  };
  auto put_b = [&](int x, int y, float v) {
    if (cells.contains(Int2{x, y})) B(x, y) = v;
  };
  auto put = [&](int x, int y) {
    put_a(x, y, rd_.seed_a);
    put_b(x, y, rd_.seed_b);
  };
  switch (rd_.initial) {
    case RdInitialPattern::kUniform:
      break;
    case RdInitialPattern::kCentreSquare: {
      const int side = std::max(1, int(std::lround(rd_.seed_size * n.x)));
      const int x0 = (n.x - side) / 2, y0 = (n.y - side) / 2;
      for (int y = std::max(0, y0); y < std::min(n.y, y0 + side); ++y)
        for (int x = std::max(0, x0); x < std::min(n.x, x0 + side); ++x) put(x, y);
      break;
    }
    case RdInitialPattern::kSeedSquare:
      for (int y = 0; y < rd_.seed_cells; ++y)
        for (int x = 0; x < rd_.seed_cells; ++x) {
          const int px = n.x / 2 + x - rd_.seed_cells / 2, py = n.y / 2 + y - rd_.seed_cells / 2;
          if (px >= 0 && px < n.x && py >= 0 && py < n.y) put(px, py);
        }
      break;
    case RdInitialPattern::kRandomSpots:
      for (int k = 0; k < rd_.spots; ++k) {
        const double cx = rng.uniform() * n.x, cy = rng.uniform() * n.y, r = rd_.seed_radius;
        for (int y = std::max(0, int(cy - r)); y <= std::min(n.y - 1, int(cy + r)); ++y)
          for (int x = std::max(0, int(cx - r)); x <= std::min(n.x - 1, int(cx + r)); ++x)
            if ((x - cx) * (x - cx) + (y - cy) * (y - cy) <= r * r) put(x, y);
      }
      break;
    case RdInitialPattern::kCentreDisc: {
      // Centred on the middle of the grid (between cells when a side is even), so the disc keeps
      // the grid's mirror and quarter-turn symmetries and favours no direction over another.
      const double cx = 0.5 * (n.x - 1), cy = 0.5 * (n.y - 1), r = rd_.seed_radius;
      const int x0 = std::max(0, int(std::floor(cx - r))), x1 = std::min(n.x - 1, int(cx + r));
      const int y0 = std::max(0, int(std::floor(cy - r))), y1 = std::min(n.y - 1, int(cy + r));
      for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x)
          if ((x - cx) * (x - cx) + (y - cy) * (y - cy) <= r * r) put(x, y);
      break;
    }
    case RdInitialPattern::kStripe: {
      // An excited band over the lower half and a refractory band behind it: a broken wave
      // whose free end curls into a spiral (Barkley, FitzHugh-Nagumo).
      const int w = std::max(1, int(std::lround(rd_.seed_size * n.x)));
      for (int y = 0; y < n.y / 2; ++y)
        for (int x = w; x < std::min(n.x, 2 * w); ++x) put_a(x, y, rd_.seed_a);
      for (int y = 0; y < n.y; ++y)
        for (int x = 0; x < std::min(n.x, w); ++x) put_b(x, y, rd_.seed_b);
      break;
    }
  }
  if (rd_.noise > 0) {
    const ConcentrationBox box = invariant_box(rd_.reaction);
    for (int y = 0; y < n.y; ++y)
      for (int x = 0; x < n.x; ++x) {
        const double ua = 2.0 * rng.uniform() - 1.0, ub = 2.0 * rng.uniform() - 1.0;
        if (!cells.contains(Int2{x, y})) continue;
        A(x, y) = float(std::clamp(A(x, y) * (1.0 + rd_.noise * ua), box.a_lo, box.a_hi));
        B(x, y) = float(std::clamp(B(x, y) * (1.0 + rd_.noise * ub), box.b_lo, box.b_hi));
      }
  }
}

void RdStepper::fill_chemical_ghosts(SimState& s) {
  dev_->fill_boundary(s.A, chemical_fill(rd_.boundary, rd_.boundary_a));
  dev_->fill_boundary(s.B, chemical_fill(rd_.boundary, rd_.boundary_b));
}

void RdStepper::react(SimState& s) {
  if (!table_.empty())
    dev_->reaction_table(s.A, s.B, table_);
  else
    dev_->reaction_implicit(s.A, s.B, rd_.reaction, float(dt_));
}

const FieldF* RdStepper::conductivity(SimState& s) {
  if (rd_.anisotropy.kind == AnisotropyKind::kIsotropic) return nullptr;
  fill_chemical_ghosts(s);
  FieldF* const a[] = {&s.A};
  dev_->exchange_halos(a, 1);  // the gradient of A reads across a block's edges
  dev_->conductivity(s.A, s.theta0, conductivity_, rd_.anisotropy);
  if (diff_a_ && diff_a_->on_block()) {
    FieldF* const k[] = {&conductivity_};
    dev_->exchange_halos(k, 1);  // the block's faces on its edges average its neighbours' k
  }
  return &conductivity_;
}

void RdStepper::diffuse(SimState& s, const FieldF* k, double fraction, bool crank_nicolson) {
  const double iso = k ? 1.0 : rd_.anisotropy.isotropic_value;
  const Field<uint8_t>* solid = s.obstacle.empty() ? nullptr : &s.obstacle;
  diff_a_->set_solid(solid);
  diff_b_->set_solid(solid);
  const double base = dt_ * fraction / (h_ * h_) * iso;
  const SolveReport ra = dev_->implicit_diffusion(
      *diff_a_, s.A, k, {rd_.diffusion_a * base, rd_.boundary_a, crank_nicolson});
  const SolveReport rb =
      dev_->implicit_diffusion(*diff_b_, s.B, rd_.anisotropy_on_b ? k : nullptr,
                               {rd_.diffusion_b * base, rd_.boundary_b, crank_nicolson});
  record_solves(ra, rb);
}

void RdStepper::record_solves(const SolveReport& a, const SolveReport& b) {
  stats_.diffusion_iterations_a = a.iterations;
  stats_.diffusion_iterations_b = b.iterations;
  stats_.diffusion_residual_a = a.relative_residual;
  stats_.diffusion_residual_b = b.relative_residual;
}

void RdStepper::crank_nicolson_am2_step(SimState& s) {
  const float half = float(0.5 * dt_);
  if (rd_.react) dev_->reaction_trapezoidal(s.A, s.B, rd_.reaction, half);
  if (rd_.diffuse) diffuse(s, conductivity(s), 1.0, true);
  if (rd_.react) dev_->reaction_trapezoidal(s.A, s.B, rd_.reaction, half);
}

void RdStepper::sbdf2_step(SimState& s) {
  const int order = history_ ? 2 : 1;
  // a(theta) of u^n, before the right-hand side takes A's place.
  const FieldF* k = rd_.diffuse ? conductivity(s) : nullptr;
  dev_->sbdf_rhs(s.A, s.B, prev_a_, prev_b_, {rd_.reaction, float(dt_), order, rd_.react});
  if (rd_.diffuse) diffuse(s, k, sbdf_diffusion_fraction(order), false);
  history_ = true;
}

void RdStepper::explicit_step(SimState& s, int steps_left) {
  if (halo_left_ == 0) {
    // The 5- and 9-point stencils read one cell across the block's edges: an exchange as deep
    // as the steps it serves, each of which steps the halo cells the next one reads.
    fill_chemical_ghosts(s);
    halo_left_ = std::min(block_steps_, steps_left);
    FieldF* const chemicals[] = {&s.A, &s.B};
    dev_->exchange_halos(chemicals, halo_left_);
    quiescent_.halo_exchanged();
  }
  --halo_left_;
  const double base = dt_ / (h_ * h_) * rd_.anisotropy.isotropic_value;
  const float da = rd_.diffuse ? float(rd_.diffusion_a * base) : 0.0f;
  const float db = rd_.diffuse ? float(rd_.diffusion_b * base) : 0.0f;
  using Scheme = Device::ExplicitScheme;
  const ExplicitRdParams p{rd_.reaction, rd_.react ? float(dt_) : 0.0f, da, db};
  const Scheme scheme = rd_.scheme == RdScheme::kExplicit5 ? Scheme::k5
                        : rd_.reaction.model == ReactionModel::kGrayScott && rd_.react
                            ? Scheme::kGrayScott9
                            : Scheme::k9;
  dev_->explicit_rd(s.A, s.B, scratch_a_, scratch_b_, scheme, p,
                    scheme == Scheme::kGrayScott9 ? &quiescent_ : nullptr, halo_left_);
  dev_->swap(s.A, scratch_a_);
  dev_->swap(s.B, scratch_b_);
}

GeneralizedRdParams RdStepper::generalized_params(bool react, bool diffuse) const {
  GeneralizedRdParams p;
  p.reaction = rd_.reaction;
  p.dt = react ? float(dt_) : 0.0f;
  p.scale_a = diffuse ? float(diffusion_scale(scene_, false)) : 0.0f;
  p.scale_b = diffuse ? float(diffusion_scale(scene_, true)) : 0.0f;
  const ConcentrationBox box = typical_range(rd_.reaction);
  p.a_lo = float(box.a_lo), p.a_hi = float(box.a_hi);
  p.b_lo = float(box.b_lo), p.b_hi = float(box.b_hi);
  if (rd_.map) {  // F and k across the grid, per cell (rd_config.h)
    p.f_step = float((double(rd_.map_f) - rd_.reaction.F) / scene_.size.x);
    p.k_step = float((double(rd_.map_k) - rd_.reaction.k) / scene_.size.y);
  }
  return p;
}

bool RdStepper::fuses_generalized_steps() const {
  // Eqn 27 with the uniform stencil and nothing between the steps.
  return rd_.scheme == RdScheme::kExplicit && !tensor_field_ && (rd_.react || rd_.diffuse);
}

void RdStepper::generalized_step(SimState& s) {
  const bool solve = rd_.diffuse && rd_.scheme != RdScheme::kExplicit;
  if (rd_.scheme == RdScheme::kImplicit) {
    if (rd_.react) react(s);  // Eqn 6
  } else if (rd_.react || rd_.diffuse) {
    // Eqn 27 (explicit), or Eqn 28's u + dt f(u) (semi-implicit: diffusion by the solve below);
    // with a tensor field, Table 1's inhomogeneous rank-2 operator in place of the stencil.
    const GeneralizedRdParams p = generalized_params(rd_.react, rd_.diffuse && !solve);
    if (tensor_field_)
      dev_->tensor_field_rd(s.A, s.B, scratch_a_, scratch_b_, *tensor_field_, p);
    else
      dev_->generalized_rd(s.A, s.B, scratch_a_, scratch_b_, *generalized_, p);
    dev_->swap(s.A, scratch_a_);
    dev_->swap(s.B, scratch_b_);
  }
  if (solve && tensor_solve_) {  // (I - dt D_A L)^-1 by BiCGSTAB (Eqn 28, Table 1's last row)
    const SolveReport ra =
        dev_->tensor_field_solve(*tensor_solve_, s.A, diffusion_scale(scene_, false));
    const SolveReport rb =
        dev_->tensor_field_solve(*tensor_solve_, s.B, diffusion_scale(scene_, true));
    record_solves(ra, rb);
  } else if (solve) {  // (I - dt D K)^-1, exactly (Eqn 28)
    dev_->periodic_solve(*periodic_a_, s.A, *periodic_b_, s.B);
  }
  if (solve) {
    // The solve's result clamped like every other result (kernels/generalized_rd.h says why).
    dev_->generalized_rd(s.A, s.B, scratch_a_, scratch_b_, *generalized_,
                         generalized_params(false, false));
    dev_->swap(s.A, scratch_a_);
    dev_->swap(s.B, scratch_b_);
  }
}

void RdStepper::advect(SimState& s) {
  fill_chemical_ghosts(s);
  const double scene_h = scene_.domain_width / scene_.size.x;
  const AdvectParams p{float(scene_.dt / scene_h), scene_.size,
                       rd_.boundary == BoundaryKind::kPeriodic};
  // A and B share one back-trace.
  const FieldF* const from[] = {&s.A, &s.B};
  FieldF* const to[] = {&scratch_a_, &scratch_b_};
  dev_->advect_scalars(from, s.u, s.v, to, p);
  if (!back_a_.empty()) {
    // MacCormack, as the fluid carries its dye (kernels/advect.h maccormack_correct): the
    // forward result carried back by the same velocity, then corrected and limited in place.
    dev_->fill_boundary(scratch_a_, chemical_fill(rd_.boundary, rd_.boundary_a));
    dev_->fill_boundary(scratch_b_, chemical_fill(rd_.boundary, rd_.boundary_b));
    AdvectParams backward = p;
    backward.dt_over_h = -p.dt_over_h;
    const FieldF* const hat[] = {&scratch_a_, &scratch_b_};
    FieldF* const back[] = {&back_a_, &back_b_};
    dev_->advect_scalars(hat, s.u, s.v, back, backward);
    const FieldF* const back_in[] = {&back_a_, &back_b_};
    dev_->maccormack_correct(from, hat, back_in, s.u, s.v, to, p, false);
  }
  dev_->swap(s.A, scratch_a_);
  dev_->swap(s.B, scratch_b_);
  restart_skipping();  // the advection wrote both pairs
}

void RdStepper::append_stages(FramePlan& plan, SimState& s) {
  ARDCELL_CHECK(!s.A.empty() && s.A.interior() == cells_ && s.B.interior() == cells_,
                "RD stages need A and B over the device's cells (RdStepper::init_state)");
  plan.add_stage({"rd: reaction-diffusion", [this, &s] { react_diffuse(s); }, true});
  // The velocity is allocated by now (over the same cells) when the scene has one.
  if (!s.u.empty() && !s.v.empty() && s.u.interior() == cells_)
    plan.add_stage({"rd: advection",
                    [this, &s] {
                      if (rd_.advect) advect(s);
                    },
                    true});
}

void RdStepper::react_diffuse(SimState& s) {
  halo_left_ = 0;  // the fields may have been written since the last frame
  if (gray_scott9_) {
    // The whole grid: the frame's steps in one op. A block of whole rows: each op steps as deep
    // as the rows exchanged above and below it.
    const bool block = dev_->on_block();
    const int per_op = block ? gray_scott9_->block_steps() : rd_.steps_per_frame;
    for (int done = 0; done < rd_.steps_per_frame;) {
      const int steps = std::min(per_op, rd_.steps_per_frame - done);
      if (block) {
        fill_chemical_ghosts(s);
        FieldF* const chemicals[] = {&s.A, &s.B};
        dev_->exchange_halos(chemicals, steps);
      }
      dev_->gray_scott9_steps(*gray_scott9_, s.A, s.B, steps, gray_scott9_params(),
                              gray_scott9_resumes_);
      gray_scott9_resumes_ = true;
      done += steps;
    }
  } else {
    for (int k = 0; k < rd_.steps_per_frame; ++k) {
      if (generalized_ && fuses_generalized_steps()) {
        // Up to kGeneralizedFusedSteps explicit steps in one pass over the fields (the same
        // bits as one at a time).
        const int steps = std::min(kGeneralizedFusedSteps, rd_.steps_per_frame - k);
        dev_->generalized_rd_steps(s.A, s.B, scratch_a_, scratch_b_, *generalized_,
                                   generalized_params(rd_.react, rd_.diffuse), steps);
        dev_->swap(s.A, scratch_a_);
        dev_->swap(s.B, scratch_b_);
        k += steps - 1;
      } else if (generalized_) {
        generalized_step(s);
      } else if (rd_.scheme == RdScheme::kImplicit) {
        if (rd_.react) react(s);
        if (rd_.diffuse) diffuse(s, conductivity(s), 1.0, rd_.crank_nicolson);
      } else if (rd_.scheme == RdScheme::kCrankNicolsonAm2) {
        crank_nicolson_am2_step(s);
      } else if (rd_.scheme == RdScheme::kSbdf2) {
        sbdf2_step(s);
      } else if (rd_.scheme == RdScheme::kEtdrk4) {
        dev_->etdrk4_step(*etdrk4_, s.A, s.B, rd_.react ? &rd_.reaction : nullptr);
      } else {
        explicit_step(s, rd_.steps_per_frame - k);
      }
    }
  }
  s.rd_time += dt_ * rd_.steps_per_frame;
}

}  // namespace ardcell
