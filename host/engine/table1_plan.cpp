#include "host/engine/table1_plan.h"

#include <cmath>
#include <deque>
#include <span>
#include <stdexcept>

#include "host/engine/device.h"
#include "kernels/advect.h"
#include "kernels/project.h"
#include "kernels/reaction.h"
#include "kernels/sources.h"
#include "kernels/stam_sweeps.h"
#include "runtime/check.h"

namespace ardcell {
namespace {

using Bufs = std::span<const View<float>>;
using WholeFields = std::span<FieldF* const>;  // a device twin's fields
// Stream: sweeps of A's (B's) diffusion per residency riding on a projection pass.
constexpr int kRiderSweeps = 5;
constexpr float kPi = 3.14159265358979f;

// --- Kernel adapters: each names its buffers by index into the pass's buffer list. -------------

struct SourceParams {
  int component = 0;  // 0: u, 1: v, 2: dye
  int8_t buf = 0;
  Int2 grid{};
  const std::int64_t* frame = nullptr;
};

// Splat i of a component (0 u, 1 v, 2 dye): four Gaussian splats at the quarter points whose
// forces turn slowly with the frame number. The OpenCL frame takes the same function.
SplatParams table1_splat(Int2 grid, int component, int i, std::int64_t frame) {
  const float cx = (i == 0 || i == 3) ? 0.25f : 0.75f;
  const float cy = (i < 2) ? 0.25f : 0.75f;
  const float angle = 0.05f * float(frame) + float(i) * 0.5f * kPi + 0.25f * kPi;
  SplatParams s;
  s.cx = cx * float(grid.x);
  s.cy = cy * float(grid.y);
  s.radius = std::max(1.0f, float(std::min(grid.x, grid.y)) / 32.0f);
  s.amount = component == 0   ? Table1Constants::kSplatForce * std::cos(angle)
             : component == 1 ? Table1Constants::kSplatForce * std::sin(angle)
                              : Table1Constants::kSplatDye;
  return s;
}

void sources_kernel(const void* params, Bufs b, Box2 region) {
  const auto& p = *static_cast<const SourceParams*>(params);
  for (int i = 0; i < Table1Constants::kSplats; ++i)
    add_splat(b[std::size_t(p.buf)], region, table1_splat(p.grid, p.component, i, *p.frame));
}
void sources_on_device(const void* params, Device& dev, WholeFields f) {
  const auto& p = *static_cast<const SourceParams*>(params);
  for (int i = 0; i < Table1Constants::kSplats; ++i)
    dev.add_splat(*f[std::size_t(p.buf)], table1_splat(p.grid, p.component, i, *p.frame));
}

struct ReactParams {
  GrayScottImplicitParams gs;
  int8_t a = 0, b = 1;
};
void reaction_kernel(const void* params, Bufs b, Box2 region) {
  const auto& p = *static_cast<const ReactParams*>(params);
  gray_scott_implicit_tile(b[std::size_t(p.a)], b[std::size_t(p.b)], b[std::size_t(p.a)],
                           b[std::size_t(p.b)], region, p.gs);
}
void reaction_on_device(const void* params, Device& dev, WholeFields f) {
  const auto& p = *static_cast<const ReactParams*>(params);
  ReactionParams rp;
  rp.model = ReactionModel::kGrayScott;
  rp.F = p.gs.F;
  rp.k = p.gs.k;
  dev.reaction_implicit(*f[std::size_t(p.a)], *f[std::size_t(p.b)], rp, p.gs.dt);
}

struct CopyParams {
  int8_t from = 0, to = 1;
};
// Copies the whole box of `to` (a buffer of the same box as `from`): no fill needed after.
void copy_kernel(const void* params, Bufs b, Box2 /*region*/) {
  const auto& p = *static_cast<const CopyParams*>(params);
  const View<float>& to = b[std::size_t(p.to)];
  copy_box<float>(b[std::size_t(p.from)], to, to.box());
}

struct ZeroParams {
  int8_t buf = 0;
};
void zero_kernel(const void* params, Bufs b, Box2 /*region*/) {
  const View<float>& v = b[std::size_t(static_cast<const ZeroParams*>(params)->buf)];
  for (int y = v.box().min.y; y < v.box().max.y; ++y)
    for (int x = v.box().min.x; x < v.box().max.x; ++x) v(x, y) = 0.0f;
}
// A pressure solve zeroes its first iterate and sweeps from it; on a device the sweeps start
// from a field of zeros instead (jacobi_from_zeros_on_device) and the zeroing is skipped.
void zero_skipped_on_device(const void*, Device&, WholeFields) {}

struct DivParams {
  ProjectParams pp;
  int8_t u = 0, v = 1, div = 2;
};
void divergence_kernel(const void* params, Bufs b, Box2 region) {
  const auto& p = *static_cast<const DivParams*>(params);
  pressure_rhs(b[std::size_t(p.u)], b[std::size_t(p.v)], b[std::size_t(p.div)], region, p.pp);
}
void divergence_on_device(const void* params, Device& dev, WholeFields f) {
  const auto& p = *static_cast<const DivParams*>(params);
  dev.pressure_rhs(*f[std::size_t(p.u)], *f[std::size_t(p.v)], *f[std::size_t(p.div)], p.pp);
}

struct GradParams {
  ProjectParams pp;
  int8_t p = 0, u = 1, v = 2;
};
void gradient_kernel(const void* params, Bufs b, Box2 region) {
  const auto& p = *static_cast<const GradParams*>(params);
  subtract_gradient(b[std::size_t(p.p)], b[std::size_t(p.u)], b[std::size_t(p.v)], region, p.pp);
}
void gradient_on_device(const void* params, Device& dev, WholeFields f) {
  const auto& p = *static_cast<const GradParams*>(params);
  dev.subtract_gradient(*f[std::size_t(p.p)], *f[std::size_t(p.u)], *f[std::size_t(p.v)], p.pp);
}

// Semi-Lagrangian advection of up to kMaxAdvectFields fields by (u, v), one shared back-trace
// (kernels/advect.h advect_fields): velocity self-advection is q0 = {u, v}.
struct AdvectManyParams {
  AdvectParams ap;
  int8_t u = 0, v = 1;
  int count = 0;
  std::array<int8_t, kMaxAdvectFields> q0{}, q{};
};
void advect_many_kernel(const void* params, Bufs b, Box2 region) {
  const auto& p = *static_cast<const AdvectManyParams*>(params);
  std::array<View<const float>, kMaxAdvectFields> in;
  std::array<View<float>, kMaxAdvectFields> out;
  for (int i = 0; i < p.count; ++i) {
    in[std::size_t(i)] = b[std::size_t(p.q0[std::size_t(i)])];
    out[std::size_t(i)] = b[std::size_t(p.q[std::size_t(i)])];
  }
  advect_fields(b[std::size_t(p.u)], b[std::size_t(p.v)],
                std::span<const View<const float>>(in.data(), std::size_t(p.count)),
                std::span<const View<float>>(out.data(), std::size_t(p.count)), region, p.ap);
}
void advect_many_on_device(const void* params, Device& dev, WholeFields f) {
  const auto& p = *static_cast<const AdvectManyParams*>(params);
  if (p.count == 2 && p.q0[0] == p.u && p.q0[1] == p.v) {  // self-advection of the velocity
    dev.advect_velocity(*f[std::size_t(p.u)], *f[std::size_t(p.v)], *f[std::size_t(p.q[0])],
                        *f[std::size_t(p.q[1])], p.ap);
    return;
  }
  std::array<const FieldF*, kMaxAdvectFields> in{};
  std::array<FieldF*, kMaxAdvectFields> out{};
  for (int i = 0; i < p.count; ++i) {
    in[std::size_t(i)] = f[std::size_t(p.q0[std::size_t(i)])];
    out[std::size_t(i)] = f[std::size_t(p.q[std::size_t(i)])];
  }
  dev.advect_scalars(std::span<const FieldF* const>(in.data(), std::size_t(p.count)),
                     *f[std::size_t(p.u)], *f[std::size_t(p.v)],
                     std::span<FieldF* const>(out.data(), std::size_t(p.count)), p.ap);
}

void jacobi_kernel(const void* params, View<const float> x, View<const float> rhs, View<float> out,
                   Box2 region) {
  stam_jacobi_sweep(rhs, x, out, region, *static_cast<const StamSweepParams*>(params));
}
void jacobi_on_device(const void* params, Device& dev, const FieldF& rhs, FieldF& a, FieldF& b,
                      int sweeps, const BoundaryFill& fill) {
  dev.stam_jacobi_sweeps(rhs, a, b, sweeps, *static_cast<const StamSweepParams*>(params), fill);
}
// A solve's only residency copies its right-hand side (the initial guess) into a and sweeps
// from there; on a device the sweeps start from the right-hand side itself and the copy is
// skipped (its twin does nothing): one pass over the field less.
void jacobi_from_rhs_on_device(const void* params, Device& dev, const FieldF& rhs, FieldF& a,
                               FieldF& b, int sweeps, const BoundaryFill& fill) {
  dev.stam_jacobi_sweeps(rhs, a, b, sweeps, *static_cast<const StamSweepParams*>(params), fill,
                         &rhs);
}
void copy_skipped_on_device(const void*, Device&, WholeFields) {}

// The pressure's sweeps when the first iterate is zero: the same sweep on the CPU, and on a
// device sweeps that start from `zeros`.
struct ZeroStartSweep {
  StamSweepParams sweep;
  const FieldF* zeros = nullptr;  // never written
};
void jacobi_zero_start_kernel(const void* params, View<const float> x, View<const float> rhs,
                              View<float> out, Box2 region) {
  stam_jacobi_sweep(rhs, x, out, region, static_cast<const ZeroStartSweep*>(params)->sweep);
}
void jacobi_from_zeros_on_device(const void* params, Device& dev, const FieldF& rhs, FieldF& a,
                                 FieldF& b, int sweeps, const BoundaryFill& fill) {
  const auto& p = *static_cast<const ZeroStartSweep*>(params);
  dev.stam_jacobi_sweeps(rhs, a, b, sweeps, p.sweep, fill, p.zeros);
}

int8_t add_buffer(PassDesc& d, const FieldF* src, FieldF* dst, int halo, bool gather = false) {
  // Reserved up front: GCC 12 at -O3 warns (-Wstringop-overflow, a false positive) on the
  // reallocating path of push_back here.
  if (d.buffers.capacity() == 0) d.buffers.reserve(FramePlan::kMaxBuffers);
  d.buffers.push_back(PassBufferDesc{src, dst, halo, gather});
  return int8_t(d.buffers.size() - 1);
}

PassOpDesc map_op(MapKernel k, DeviceMapKernel twin, const void* params, int reach,
                  std::initializer_list<int> writes,
                  std::initializer_list<std::pair<int, BoundaryFill>> fills) {
  PassOpDesc op;
  op.kind = PassOpDesc::Kind::kMap;
  op.map = k;
  op.device = twin;
  op.params = params;
  op.reach = reach;
  int i = 0;
  for (int w : writes) op.writes[std::size_t(i++)] = int8_t(w);
  i = 0;
  for (const auto& [buf, fill] : fills) {
    op.fill_buffers[std::size_t(i)] = int8_t(buf);
    op.fills[std::size_t(i++)] = fill;
  }
  return op;
}

PassOpDesc jacobi_op(const StamSweepParams* p, int8_t a, int8_t b, int8_t rhs, int sweeps,
                     int extra_reach, int stam_b) {
  PassOpDesc op;
  op.kind = PassOpDesc::Kind::kJacobi;
  op.sweep = jacobi_kernel;
  op.device_sweeps = jacobi_on_device;
  op.params = p;
  op.a = a;
  op.b = b;
  op.rhs = rhs;
  op.sweeps = sweeps;
  op.extra_reach = extra_reach;
  op.fill = BoundaryFill::stam(stam_b);
  return op;
}

}  // namespace

std::string table1_config_problem(const SceneConfig& c) {
  const FluidConfig& f = c.fluid;
  const RdConfig& r = c.rd;
  const std::string runs = ": the table1 plan (host/engine/table1_plan.h) runs ";
  if (c.size.x < 8 || c.size.y < 8) return "grid.size" + runs + "at least 8 x 8 cells";
  if (f.walls != FluidWalls::kFreeSlip) return "fluid.walls" + runs + "free-slip walls only";
  if (!f.emitters.empty()) return "fluid.emitters" + runs + "its four splats, no emitters";
  if (f.advection != AdvectionScheme::kSemiLagrangian)
    return "fluid.advection" + runs + "semi-lagrangian advection only";
  if (f.conserve_dye) return "fluid.conserve_dye" + runs + "no mass fix (expected false)";
  const auto fixed_jacobi = [&](const SolverSettings& s, const char* key) -> std::string {
    if (s.kind != SolverKind::kJacobi || s.tolerance != 0.0)
      return std::string(key) + runs + "fixed Jacobi sweeps (expected kind jacobi, tolerance 0)";
    if (s.max_iterations != f.pressure_solver.max_iterations)
      return std::string(key) + ".iterations" + runs +
             "one sweep count for every solve (expected fluid.pressure_solver.iterations, " +
             std::to_string(f.pressure_solver.max_iterations) + ")";
    return "";
  };
  if (std::string why = fixed_jacobi(f.pressure_solver, "fluid.pressure_solver"); !why.empty())
    return why;
  if (std::string why = fixed_jacobi(f.viscosity_solver, "fluid.viscosity_solver"); !why.empty())
    return why;
  if (f.pressure_solver.max_iterations < 1 || f.pressure_solver.max_iterations > 64)
    return "fluid.pressure_solver.iterations" + runs + "1..64 sweeps a solve";
  if (!r.enabled) return "";
  if (std::string why = fixed_jacobi(r.diffusion_solver, "rd.diffusion_solver"); !why.empty())
    return why;
  if (r.reaction.model != ReactionModel::kGrayScott)
    return "rd.reaction.model" + runs + "gray-scott only";
  if (r.diffusion_operator != RdOperator::kLaplacian || r.scheme != RdScheme::kImplicit ||
      r.crank_nicolson)
    return "rd.scheme" + runs + "the implicit scheme with the Laplacian only";
  if (r.use_table || r.map) return "rd.table / rd.map" + runs + "the Newton reaction, one F and k";
  if (r.anisotropy.kind != AnisotropyKind::kIsotropic || r.anisotropy.isotropic_value != 1.0f)
    return "rd.anisotropy" + runs + "isotropic diffusion only";
  if (r.boundary != BoundaryKind::kNeumann) return "rd.boundary" + runs + "neumann only";
  if (!r.react || !r.diffuse || !r.advect)
    return "rd.react / diffuse / advect" + runs + "all three";
  if (r.steps_per_frame != 1) return "rd.steps_per_frame" + runs + "one RD step a frame";
  return "";
}

struct Table1Plan::Fields {
  // u, v, dye, A, B are the scene's (SimState); the rest is the plan's scratch.
  Fields(SimState& s, Box2 block, int halo, bool rd)
      : u(s.u), v(s.v), dye(s.dye), A(s.A), B(s.B), rd_(rd) {
    zeros = FieldF::over(block, halo);
    for_each_scratch([&](FieldF& f) { f = FieldF::over(block, halo); });
  }
  // The plan's scratch fields (zeros aside, which is never written).
  template <class F>
  void for_each_scratch(const F& f) {
    for (FieldF* x : {&u0, &v0, &u1, &v1, &dye0, &tu, &tv, &tdye, &p0, &p1, &div}) f(*x);
    if (rd_)
      for (FieldF* x : {&A0, &B0, &tA, &tB}) f(*x);
  }
  FieldF &u, &v, &dye, &A, &B;
  FieldF u0, v0, u1, v1, dye0, tu, tv, tdye, p0, p1, div;
  FieldF zeros;  // never written: what a device twin zeroes a field from
  FieldF A0, B0, tA, tB;
  bool rd_;
};

Table1Coefficients table1_coefficients(const SceneConfig& config) {
  Table1Coefficients c;
  c.sweeps = config.fluid.pressure_solver.max_iterations;
  // Stam's solver in cell units: h = domain width / grid.x (square cells).
  const float h = float(config.domain_width / double(config.size.x));
  const float dt = float(config.dt);
  const auto diffusion = [](float a) { return StamSweepParams{a, 1.0f / (1.0f + 4.0f * a)}; };
  c.viscosity = diffusion(dt * float(config.fluid.viscosity) / (h * h));
  c.dye_diffusion = diffusion(dt * float(config.fluid.dye_diffusion) / (h * h));
  c.pressure = StamSweepParams{1.0f, 0.25f};
  c.project = ProjectParams{h};
  c.advect = AdvectParams{dt / h, config.size, false};
  if (config.rd.enabled) {
    // D_A, D_B in cells^2 per unit of rd.dt.
    const float rd_dt = float(config.rd.dt > 0.0 ? config.rd.dt : config.dt);
    c.rd_a = diffusion(rd_dt * float(config.rd.diffusion_a));
    c.rd_b = diffusion(rd_dt * float(config.rd.diffusion_b));
    c.reaction = GrayScottImplicitParams{config.rd.reaction.F, config.rd.reaction.k, rd_dt};
  }
  return c;
}

int table1_block_halo(const SceneConfig& config) {
  return config.fluid.pressure_solver.max_iterations + 3;
}

bool operator==(const Table1Coefficients& a, const Table1Coefficients& b) {
  const auto same = [](const StamSweepParams& x, const StamSweepParams& y) {
    return x.a == y.a && x.inv_c == y.inv_c;
  };
  return a.sweeps == b.sweeps && same(a.viscosity, b.viscosity) &&
         same(a.dye_diffusion, b.dye_diffusion) && same(a.pressure, b.pressure) &&
         same(a.rd_a, b.rd_a) && same(a.rd_b, b.rd_b) && a.project.h == b.project.h &&
         a.advect.dt_over_h == b.advect.dt_over_h && a.reaction.F == b.reaction.F &&
         a.reaction.k == b.reaction.k && a.reaction.dt == b.reaction.dt;
}

// Parameters the passes point at: kept at stable addresses for the plan's lifetime.
struct Table1Plan::Params : Table1Coefficients {
  std::deque<std::shared_ptr<void>> keep_alive;
  template <class T>
  const T* keep(const T& value) {
    auto owned = std::make_shared<T>(value);
    keep_alive.push_back(owned);
    return owned.get();
  }
};

FramePlanOptions table1_frame_plan_options(const SceneConfig& config, const PlanOptions& options,
                                           int workers) {
  FramePlanOptions po;
  po.grid = config.size;
  po.block = options.block.empty() ? box_of_size(config.size) : options.block;
  po.halo = options.halo;
  // One block: halo 1 (the domain's ring); several: the exchange's width.
  po.field_halo = options.halo ? options.halo->width() : 1;
  po.local_store_bytes = options.local_store_bytes;
  po.workers = workers;
  po.max_tile_width = options.max_tile_width;
  po.max_tile_height = options.max_tile_height;
  return po;
}

void Table1Plan::init(const SceneConfig& config) {
  if (std::string why = table1_config_problem(config); !why.empty())
    throw std::invalid_argument(why);
  grid_ = config.size;
  rd_ = config.rd.enabled;
  p_ = std::make_unique<Params>();
  static_cast<Table1Coefficients&>(*p_) = table1_coefficients(config);
  sweeps_ = p_->sweeps;
  if (options_.sweeps_per_residency == 0) options_.sweeps_per_residency = sweeps_;
  ARDCELL_CHECK(options_.sweeps_per_residency >= 1 && options_.sweeps_per_residency <= sweeps_,
                "Table1Plan: sweeps per residency must be 1 .. the sweeps of a solve");
  ARDCELL_CHECK(plan_->options().grid == grid_ && plan_->pass_count() == 0,
                "Table1Plan: builds an empty plan of the scene's grid");
  // The scene's fields over the plan's block, on the state: the plan's passes hold their
  // addresses.
  options_.block = plan_->options().block;
  field_halo_ = plan_->options().field_halo;
  for (FieldF* f : {&state_.u, &state_.v, &state_.dye})
    *f = FieldF::over(options_.block, field_halo_);
  if (rd_)
    for (FieldF* f : {&state_.A, &state_.B}) *f = FieldF::over(options_.block, field_halo_);
}

Table1Plan::Table1Plan(const SceneConfig& config, SimState& state, FramePlan& plan, Device& device,
                       const PlanOptions& options)
    : state_(state), options_(options), plan_(&plan) {
  init(config);
  f_ = std::make_unique<Fields>(state_, options_.block, field_halo_, rd_);
  ARDCELL_CHECK(!options_.halo || device.fields_on_host(),
                "Table1Plan: a block of a decomposed grid runs on a CPU back end");
  if (!device.fields_on_host()) device_ = &device;
  build();
  reset();
}

Table1Plan::~Table1Plan() = default;

double Table1Plan::bytes_per_frame() const {
  const double cells = double(grid_.x) * grid_.y;
  return cells *
         (Table1Constants::kFluidBytesPerCell + (rd_ ? Table1Constants::kRdBytesPerCell : 0.0));
}

void Table1Plan::reset() {
  SimState& s = state_;
  for (FieldF* x : {&s.u, &s.v, &s.dye}) x->fill(0.0f);
  if (rd_) {
    // A = 1, B = 0, with four seeded squares (A = 0.5, B = 0.25) between the splats.
    s.A.fill(1.0f);
    s.B.fill(0.0f);
    const int side = std::max(2, grid_.x / 16);
    for (int q = 0; q < 4; ++q) {
      const int cx = grid_.x * (q % 2 == 0 ? 3 : 5) / 8, cy = grid_.y * (q < 2 ? 3 : 5) / 8;
      const Box2 seed =
          Box2{{cx - side / 2, cy - side / 2}, {cx + side / 2, cy + side / 2}}.intersected(
              options_.block);
      for (int y = seed.min.y; y < seed.max.y; ++y)
        for (int x = seed.min.x; x < seed.max.x; ++x) {
          s.A(x, y) = 0.5f;
          s.B(x, y) = 0.25f;
        }
    }
  }
  Fields& f = *f_;
  f.for_each_scratch([](FieldF& x) { x.fill(0.0f); });
  if (device_) {  // the device takes the new fields before the next frame
    for (FieldF* x : {&s.u, &s.v, &s.dye}) device_->host_wrote(*x);
    if (rd_)
      for (FieldF* x : {&s.A, &s.B}) device_->host_wrote(*x);
    f.for_each_scratch([&](FieldF& x) { device_->host_wrote(x); });
  }
}

// Sources (stream, serial, and blocked with several residencies per solve): u, v, dye in place,
// with the RD reaction riding along on A and B.
void Table1Plan::add_sources_pass(bool with_reaction) {
  Fields& f = *f_;
  PassDesc d;
  d.name = with_reaction ? "sources+reaction" : "sources";
  const int8_t bu = add_buffer(d, &f.u, &f.u, 0), bv = add_buffer(d, &f.v, &f.v, 0),
               bd = add_buffer(d, &f.dye, &f.dye, 0);
  int comp = 0;
  for (int8_t buf : {bu, bv, bd}) {
    const auto* sp = p_->keep(SourceParams{comp, buf, grid_, &state_.step});
    d.ops.push_back(map_op(sources_kernel, sources_on_device, sp, 0, {buf},
                           {{buf, BoundaryFill::stam(comp == 2 ? 0 : comp + 1)}}));
    ++comp;
  }
  if (with_reaction) {
    const int8_t ba = add_buffer(d, &f.A, &f.A, 0), bb = add_buffer(d, &f.B, &f.B, 0);
    const auto* rp = p_->keep(ReactParams{p_->reaction, ba, bb});
    d.ops.push_back(map_op(reaction_kernel, reaction_on_device, rp, 0, {ba, bb},
                           {{ba, BoundaryFill::stam(0)}, {bb, BoundaryFill::stam(0)}}));
  }
  plan_->add_pass(std::move(d));
}

// x -> out by 20 Jacobi sweeps of (c I - a nbrs) out = x, initial guess x, for each solve;
// the solves share their passes. Stream: one pass per sweep, through out/tmp; blocked: one load
// per `k` sweeps. With `with_sources` (blocked, one residency) the splats are added in store to
// the loaded x first.
void Table1Plan::add_diffusion(const char* name, std::span<const DiffusionSpec> solves,
                               bool with_sources) {
  const int total = sweeps_;
  const int k = options_.schedule == PlanSchedule::kBlocked ? options_.sweeps_per_residency : 1;
  const int passes = (total + k - 1) / k;
  std::array<const FieldF*, 4> cur{};
  for (std::size_t i = 0; i < solves.size(); ++i) cur[i] = solves[i].x;
  for (int j = 1; j <= passes; ++j) {
    const int sweeps = std::min(k, total - (j - 1) * k);
    PassDesc d;
    d.name = name;
    for (std::size_t i = 0; i < solves.size(); ++i) {
      const DiffusionSpec& sv = solves[i];
      // The last pass writes `out`; earlier ones alternate so that this holds.
      FieldF* next = ((passes - j) % 2 == 0) ? sv.out : sv.tmp;
      append_residency(d, sv, cur[i], next, sweeps, j == 1 && sweeps == total, with_sources);
      cur[i] = next;
    }
    plan_->add_pass(std::move(d));
  }
}

// One residency of a solve in pass d: `sweeps` sweeps from the iterate `cur`, the result put in
// `next`. `whole` (the solve's only residency): x is loaded once with halo `sweeps`, (the
// sources added to it in store,) copied as the first iterate; otherwise the iterate is loaded
// with halo `sweeps` and x with halo sweeps - 1.
void Table1Plan::append_residency(PassDesc& d, const DiffusionSpec& sv, const FieldF* cur,
                                  FieldF* next, int sweeps, bool whole, bool with_sources) {
  if (whole) {
    const int8_t rhs = add_buffer(d, sv.x, nullptr, sweeps);
    const int8_t a = add_buffer(d, nullptr, sweeps % 2 == 0 ? next : nullptr, sweeps);
    const int8_t bb = add_buffer(d, nullptr, sweeps % 2 == 1 ? next : nullptr, sweeps);
    if (with_sources) {
      const int comp = sv.b == 1 ? 0 : sv.b == 2 ? 1 : 2;
      const auto* sp = p_->keep(SourceParams{comp, rhs, grid_, &state_.step});
      d.ops.push_back(map_op(sources_kernel, sources_on_device, sp, sweeps, {rhs},
                             {{rhs, BoundaryFill::stam(sv.b)}}));
    }
    d.ops.push_back(
        map_op(copy_kernel, copy_skipped_on_device, p_->keep(CopyParams{rhs, a}), 0, {a}, {}));
    d.ops.push_back(jacobi_op(sv.params, a, bb, rhs, sweeps, 0, sv.b));
    d.ops.back().device_sweeps = jacobi_from_rhs_on_device;
  } else {
    const int8_t a = add_buffer(d, cur, sweeps % 2 == 0 ? next : nullptr, sweeps);
    const int8_t bb = add_buffer(d, nullptr, sweeps % 2 == 1 ? next : nullptr, sweeps);
    const int8_t rhs = add_buffer(d, sv.x, nullptr, sweeps - 1);
    d.ops.push_back(jacobi_op(sv.params, a, bb, rhs, sweeps, 0, sv.b));
  }
}

// Divergence, 20-sweep pressure solve, gradient subtraction: (u, v) -> (u_out, v_out).
// rd_rider: 1 = A's diffusion rides on the passes, 2 = B's, 0 = none.
void Table1Plan::add_projection(const char* name, FieldF& u, FieldF& v, FieldF& u_out,
                                FieldF& v_out, int rd_rider) {
  Fields& f = *f_;
  const int total = sweeps_;
  const bool blocked = options_.schedule == PlanSchedule::kBlocked;
  const int k = blocked ? options_.sweeps_per_residency : 1;
  std::string base(name);
  if (blocked && k == total) {
    // One pass: u, v loaded with halo k + 2; div over core + k, p zeroed, k sweeps exact to
    // core + 1, gradient on the core.
    PassDesc d;
    d.name = base;
    const int8_t bu = add_buffer(d, &u, &u_out, k + 1), bv = add_buffer(d, &v, &v_out, k + 1);
    const int8_t bdiv = add_buffer(d, nullptr, nullptr, k);
    const int8_t pa = add_buffer(d, nullptr, nullptr, k + 1),
                 pb = add_buffer(d, nullptr, nullptr, k + 1);
    d.ops.push_back(map_op(divergence_kernel, divergence_on_device,
                           p_->keep(DivParams{p_->project, bu, bv, bdiv}), k, {bdiv},
                           {{bdiv, BoundaryFill::stam(0)}}));
    d.ops.push_back(
        map_op(zero_kernel, zero_skipped_on_device, p_->keep(ZeroParams{pa}), 0, {pa}, {}));
    d.ops.push_back(jacobi_op(&p_->pressure, pa, pb, bdiv, k, 1, 0));
    start_from_zeros(d.ops.back());
    const int8_t pres = k % 2 == 0 ? pa : pb;
    d.ops.push_back(map_op(gradient_kernel, gradient_on_device,
                           p_->keep(GradParams{p_->project, pres, bu, bv}), 0, {bu, bv},
                           {{bu, BoundaryFill::stam(1)}, {bv, BoundaryFill::stam(2)}}));
    plan_->add_pass(std::move(d));
    return;
  }
  // Several passes of k sweeps (stream: k = 1). The first computes the divergence over its
  // tiles grown by k (u, v read with halo k + 1), starts from p = 0 and runs the first k sweeps;
  // it carries the RD rider. The last runs the last sweeps one cell further (extra reach 1) and
  // subtracts the gradient in store. Pressure iterates alternate p0 / p1.
  const int passes = (total + k - 1) / k;
  FieldF* cur = nullptr;
  const DiffusionSpec rider = rd_rider == 1 ? DiffusionSpec{&f.A, &f.A0, &f.tA, &p_->rd_a, 0}
                                            : DiffusionSpec{&f.B, &f.B0, &f.tB, &p_->rd_b, 0};
  const int rider_every = std::max(1, passes / ((total + kRiderSweeps - 1) / kRiderSweeps));
  const FieldF* rider_cur = rider.x;
  int rider_done = 0;
  for (int j = 1; j <= passes; ++j) {
    const int sweeps = std::min(k, total - (j - 1) * k);
    const bool first = j == 1, last = j == passes;
    FieldF* next = cur == &f.p0 ? &f.p1 : &f.p0;
    const int reach = last ? 1 : 0;  // cells beyond the core the last sweep leaves exact
    PassDesc d;
    d.name = base + (first ? ":div+pressure" : last ? ":pressure+gradient" : ":pressure");
    int8_t a, b, rhs;
    if (first) {
      const int8_t bu = add_buffer(d, &u, nullptr, sweeps + reach + 1),
                   bv = add_buffer(d, &v, nullptr, sweeps + reach + 1);
      rhs = add_buffer(d, nullptr, &f.div, sweeps + reach);
      a = add_buffer(d, nullptr, !last && sweeps % 2 == 0 ? next : nullptr, sweeps + reach);
      b = add_buffer(d, nullptr, !last && sweeps % 2 == 1 ? next : nullptr, sweeps + reach);
      d.ops.push_back(map_op(divergence_kernel, divergence_on_device,
                             p_->keep(DivParams{p_->project, bu, bv, rhs}), sweeps + reach, {rhs},
                             {{rhs, BoundaryFill::stam(0)}}));
      d.ops.push_back(
          map_op(zero_kernel, zero_skipped_on_device, p_->keep(ZeroParams{a}), 0, {a}, {}));
    } else {
      a = add_buffer(d, cur, !last && sweeps % 2 == 0 ? next : nullptr, sweeps + reach);
      b = add_buffer(d, nullptr, !last && sweeps % 2 == 1 ? next : nullptr, sweeps + reach);
      rhs = add_buffer(d, &f.div, nullptr, sweeps + reach - 1);
    }
    d.ops.push_back(jacobi_op(&p_->pressure, a, b, rhs, sweeps, reach, 0));
    if (first) start_from_zeros(d.ops.back());
    if (last) {
      const int8_t bu = add_buffer(d, &u, &u_out, 0), bv = add_buffer(d, &v, &v_out, 0);
      const int8_t pres = sweeps % 2 == 0 ? a : b;
      d.ops.push_back(map_op(gradient_kernel, gradient_on_device,
                             p_->keep(GradParams{p_->project, pres, bu, bv}), 0, {bu, bv},
                             {{bu, BoundaryFill::stam(1)}, {bv, BoundaryFill::stam(2)}}));
    }
    // The RD rider: the chemical's 20 sweeps in residencies of kRiderSweeps on every
    // (kRiderSweeps)-th pass (a small halo keeps the ghost zone of a 256 KiB store's tiles
    // small), through tmp, ending in out.
    if (rd_rider != 0 && (j - 1) % rider_every == 0 && rider_done < total) {
      const int rs = std::min(kRiderSweeps, total - rider_done);
      const int left = (total - rider_done - rs + kRiderSweeps - 1) / kRiderSweeps;
      FieldF* rider_next = left % 2 == 0 ? rider.out : rider.tmp;
      append_residency(d, rider, rider_cur, rider_next, rs, false, false);
      rider_cur = rider_next;
      rider_done += rs;
      d.name += rd_rider == 1 ? "+rdA" : "+rdB";
    }
    plan_->add_pass(std::move(d));
    cur = next;
  }
  ARDCELL_CHECK(rd_rider == 0 || rider_done == total, "RD rider needs a pass per residency");
}

void Table1Plan::start_from_zeros(PassOpDesc& op) {
  op.params = p_->keep(ZeroStartSweep{*static_cast<const StamSweepParams*>(op.params), &f_->zeros});
  op.sweep = jacobi_zero_start_kernel;
  op.device_sweeps = jacobi_from_zeros_on_device;
}

// Blocked schedule: both RD diffusions in one residency of A and B (reacted earlier, in the
// velocity advection pass: the reaction is per cell, so in a halo-20 pass it would be computed
// again on every halo cell).
void Table1Plan::add_rd_diffusion_pass() {
  Fields& f = *f_;
  const int k = sweeps_;
  PassDesc d;
  d.name = "rd:diffuse:AB";
  const int8_t ra = add_buffer(d, &f.A, nullptr, k), rb = add_buffer(d, &f.B, nullptr, k);
  for (int which = 0; which < 2; ++which) {
    const int8_t rhs = which == 0 ? ra : rb;
    // The result is in a after an even number of sweeps, else in b: that one goes to A0 / B0.
    FieldF* out = which == 0 ? &f.A0 : &f.B0;
    const int8_t a = add_buffer(d, nullptr, k % 2 == 0 ? out : nullptr, k);
    const int8_t b = add_buffer(d, nullptr, k % 2 == 1 ? out : nullptr, k);
    d.ops.push_back(
        map_op(copy_kernel, copy_skipped_on_device, p_->keep(CopyParams{rhs, a}), 0, {a}, {}));
    d.ops.push_back(jacobi_op(which == 0 ? &p_->rd_a : &p_->rd_b, a, b, rhs, k, 0, 0));
    d.ops.back().device_sweeps = jacobi_from_rhs_on_device;
  }
  plan_->add_pass(std::move(d));
}

void Table1Plan::build() {
  Fields& f = *f_;
  const bool rd = rd_;
  const bool blocked = options_.schedule == PlanSchedule::kBlocked;
  const bool one_residency = blocked && options_.sweeps_per_residency == sweeps_;
  // vel_step: sources, diffuse (u -> u0), project (u0 -> u1), advect (u1 -> u0), project
  // (u0 -> u). dens_step: diffuse (dye -> dye0), advect (dye0 -> dye). RD: react, diffuse
  // (A -> A0), advect (A0 -> A).
  if (!one_residency) add_sources_pass(rd);
  const DiffusionSpec du{&f.u, &f.u0, &f.tu, &p_->viscosity, 1};
  const DiffusionSpec dv{&f.v, &f.v0, &f.tv, &p_->viscosity, 2};
  const DiffusionSpec ddye{&f.dye, &f.dye0, &f.tdye, &p_->dye_diffusion, 0};
  if (one_residency) {
    // Each solve alone: three halo-20 buffers already fill a local store.
    add_diffusion("diffuse:u", {&du, 1}, true);
    add_diffusion("diffuse:v", {&dv, 1}, true);
  } else {
    // Sweep by sweep, u, v and the dye share each pass (same tiles, one barrier): the dye's
    // diffusion reads only the dye, so dens_step's solve can run beside vel_step's.
    const DiffusionSpec all[] = {du, dv, ddye};
    add_diffusion("diffuse:uv+dye", all, false);
  }
  add_projection("project1", f.u0, f.v0, f.u1, f.v1, rd && !blocked ? 1 : 0);
  {
    PassDesc d;
    d.name = "advect:uv";
    const int8_t u1 = add_buffer(d, &f.u1, nullptr, 0, true),
                 v1 = add_buffer(d, &f.v1, nullptr, 0, true);
    const int8_t bu = add_buffer(d, nullptr, &f.u0, 0), bv = add_buffer(d, nullptr, &f.v0, 0);
    d.ops.push_back(map_op(advect_many_kernel, advect_many_on_device,
                           p_->keep(AdvectManyParams{p_->advect, u1, v1, 2, {u1, v1}, {bu, bv}}), 0,
                           {bu, bv}, {{bu, BoundaryFill::stam(1)}, {bv, BoundaryFill::stam(2)}}));
    if (rd && one_residency) {
      // The reaction rides on this halo-0 pass (A and B in place).
      const int8_t ba = add_buffer(d, &f.A, &f.A, 0), bb = add_buffer(d, &f.B, &f.B, 0);
      d.ops.push_back(map_op(reaction_kernel, reaction_on_device,
                             p_->keep(ReactParams{p_->reaction, ba, bb}), 0, {ba, bb},
                             {{ba, BoundaryFill::stam(0)}, {bb, BoundaryFill::stam(0)}}));
      d.name += "+react";
    }
    plan_->add_pass(std::move(d));
  }
  add_projection("project2", f.u0, f.v0, f.u, f.v, rd && !blocked ? 2 : 0);
  if (one_residency) add_diffusion("diffuse:dye", {&ddye, 1}, true);
  if (rd && blocked) {
    if (one_residency) {
      add_rd_diffusion_pass();
    } else {
      // Reacted in the sources pass; each chemical's 20 sweeps in residencies of k.
      const DiffusionSpec rda[] = {{&f.A, &f.A0, &f.tA, &p_->rd_a, 0},
                                   {&f.B, &f.B0, &f.tB, &p_->rd_b, 0}};
      add_diffusion("rd:diffuse:AB", rda, false);
    }
  }
  {
    PassDesc d;
    d.name = rd ? "advect:dye+A+B" : "advect:dye";
    // The velocity is read where the back-trace lands (RK2 midpoint): in main memory, like q0.
    const int8_t bu = add_buffer(d, &f.u, nullptr, 0, true),
                 bv = add_buffer(d, &f.v, nullptr, 0, true);
    // One back-trace for the dye and (RD) A and B.
    AdvectManyParams ap{p_->advect, bu, bv, 1, {}, {}};
    ap.q0[0] = add_buffer(d, &f.dye0, nullptr, 0, true);
    ap.q[0] = add_buffer(d, nullptr, &f.dye, 0);
    if (rd) {
      ap.q0[1] = add_buffer(d, &f.A0, nullptr, 0, true);
      ap.q[1] = add_buffer(d, nullptr, &f.A, 0);
      ap.q0[2] = add_buffer(d, &f.B0, nullptr, 0, true);
      ap.q[2] = add_buffer(d, nullptr, &f.B, 0);
      ap.count = 3;
    }
    d.ops.push_back(map_op(advect_many_kernel, advect_many_on_device, p_->keep(ap), 0,
                           {ap.q[0], rd ? ap.q[1] : -1, rd ? ap.q[2] : -1},
                           {{ap.q[0], BoundaryFill::stam(0)},
                            {rd ? ap.q[1] : -1, BoundaryFill::stam(0)},
                            {rd ? ap.q[2] : -1, BoundaryFill::stam(0)}}));
    plan_->add_pass(std::move(d));
  }
}

}  // namespace ardcell
