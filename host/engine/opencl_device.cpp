#if defined(ARDCELL_WITH_OPENCL)
#include "host/engine/opencl_device.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <utility>

#include "runtime/row_executor.h"

namespace ardcell {

OpenClDevice::OpenClDevice(OpenClContext& ctx, RowExecutor& cpu) : ctx_(ctx), cpu_(cpu) {
  std::string error;
  cl_ = OpenClKernels::create(ctx, &error);
  if (!cl_) throw std::runtime_error(error.substr(0, error.find('\n')));
}

OpenClDevice::~OpenClDevice() = default;

int OpenClDevice::workers() const { return int(ctx_.device().compute_units); }

void OpenClDevice::reserve(Int2 grid) {
  cpu_.reserve(grid);
  const int rows = grid.y + 1;  // face fields have one row more
  if (partial_sum_.rows < rows) {
    partial_sum_ = cl_->row_partials(rows);
    partial_lo_ = cl_->row_partials(rows);
    partial_hi_ = cl_->row_partials(rows);
    host_lo_.assign(std::size_t(rows), 0.0);
    host_hi_.assign(std::size_t(rows), 0.0);
  }
}

// Every op has a twin; solves run here with every solver (ICCG where the device has doubles),
// implicit diffusion with ICCG or fixed Jacobi or RBGS sweeps, the FFT steps at the sizes the
// device FFT transforms, and the per-cell tensor's BiCGSTAB where the device has doubles; the
// other settings fall back (implicit_diffusion, solve, periodic_solve, etdrk4_step,
// tensor_field_solve).
bool OpenClDevice::supports(DeviceOp op) const {
  // Seed 001's temporal blocking is the CPU's: the engine steps the 9-point twin here.
  if (op == DeviceOp::kGrayScott9Steps) return false;
  // The per-cell tensor's BiCGSTAB needs double vectors (OpenClTensorFieldSolve).
  if (op == DeviceOp::kTensorFieldSolve) return cl_->has_fp64();
  return op != DeviceOp::kCount;
}

// --- residency ---------------------------------------------------------------------------

OpenClDevice::Mirror& OpenClDevice::mirror(const FieldF& f) {
  for (Mirror& m : mirrors_)
    if (m.host == &f) {
      if (m.device.size == f.size() && m.device.halo == f.halo()) return m;
      // The host field was reallocated (a loaded state of another layout): copy it anew.
      m.device = ctx_.allocate_like(f);
      m.current = Current::kHost;
      return m;
    }
  Mirror m;
  m.host = &f;
  m.device = ctx_.allocate_like(f);
  m.current = Current::kHost;
  mirrors_.push_back(std::move(m));
  return mirrors_.back();
}

OpenClDevice::Mirror& OpenClDevice::current_on_device(const FieldF& f) {
  Mirror& m = mirror(f);
  if (m.current == Current::kHost) {
    ctx_.upload(f, m.device);
    uploaded_ += std::int64_t(f.raw_size() * sizeof(float));
    m.current = Current::kBoth;
  }
  return m;
}

const DeviceField& OpenClDevice::in(const FieldF& f) { return current_on_device(f).device; }

DeviceField& OpenClDevice::out(FieldF& f) {
  Mirror& m = current_on_device(f);
  m.current = Current::kDevice;
  return m.device;
}

void OpenClDevice::host_in(const FieldF& f) {
  for (Mirror& m : mirrors_)
    if (m.host == &f && m.current == Current::kDevice) {
      ctx_.download(m.device, const_cast<FieldF&>(f));  // the host copy is a cache of it
      downloaded_ += std::int64_t(f.raw_size() * sizeof(float));
      m.current = Current::kBoth;
    }
}

void OpenClDevice::host_out(FieldF& f) {
  host_in(f);
  host_wrote(f);
}

void OpenClDevice::sync_to_host(const FieldF& f) { host_in(f); }

void OpenClDevice::host_wrote(const FieldF& f) {
  for (Mirror& m : mirrors_)
    if (m.host == &f) m.current = Current::kHost;
  for (OperatorTwin& t : operators_)
    if (&t.host->diag == &f || &t.host->wx == &f || &t.host->wy == &f) t.stale = true;
}

void OpenClDevice::host_wrote(const Field<uint8_t>& m) {
  for (MaskMirror& mm : masks_)
    if (mm.host == &m) mm.stale = true;
}

const DeviceField& OpenClDevice::mask(const Field<uint8_t>& m) {
  MaskMirror* found = nullptr;
  for (MaskMirror& mm : masks_)
    if (mm.host == &m) found = &mm;
  if (!found) {
    masks_.push_back({&m, {}, true});
    found = &masks_.back();
  }
  if (found->stale) {
    found->device = upload_mask(ctx_, m);
    found->stale = false;
  }
  return found->device;
}

void OpenClDevice::host_wrote(const ReactionTable&) { table_stale_ = true; }

void OpenClDevice::finish() { ctx_.finish(); }

void OpenClDevice::say_fallback(DeviceOp op, const char* setting, const char* why) {
  bool& said = said_[std::size_t(op)];
  if (said) return;
  said = true;
  std::fprintf(stderr, "ardcell: opencl: %s runs on the CPU (%s: %s)\n", device_op_name(op),
               setting, why);
}

// --- fields --------------------------------------------------------------------------------

void OpenClDevice::copy(const FieldF& from, FieldF& to) {
  ARDCELL_CHECK(from.raw_size() == to.raw_size(), "copy: fields of different layouts");
  const DeviceField& src = in(from);
  Mirror& m = mirror(to);
  m.current = Current::kDevice;  // every byte is overwritten: nothing to upload first
  cl_->copy_field(src, m.device);
}

void OpenClDevice::swap(FieldF& a, FieldF& b) {
  Mirror& ma = mirror(a);
  Mirror& mb = mirror(b);
  std::swap(a, b);
  std::swap(ma.host, mb.host);
}

// --- boundaries ----------------------------------------------------------------------------

void OpenClDevice::fill_boundary(FieldF& f, const BoundaryFill& fill) {
  cl_->fill_boundary(out(f), fill);
}

void OpenClDevice::fill_obstacle(FieldF& f, const Field<uint8_t>& solid, ObstacleRule rule) {
  if (solid.empty()) return;
  const DeviceField& m = mask(solid);
  cl_->fill_obstacle(out(f), m, box_of_size(f.size()), rule);
}

void OpenClDevice::add_boundary_values(FieldF& b, const BoundaryFill& fill, double scale) {
  cl_->add_boundary_values(out(b), fill, scale);
}

// --- fluid ---------------------------------------------------------------------------------

void OpenClDevice::add_splat(FieldF& f, const SplatParams& splat) {
  cl_->add_splat(out(f), box_of_size(f.size()), splat);
}

void OpenClDevice::set_inflow_stripes(FieldF& dye, int stripes, BoundarySide side) {
  cl_->set_inflow_stripes(out(dye), stripes, side);
}

void OpenClDevice::pressure_rhs(const FieldF& u, const FieldF& v, FieldF& rhs,
                                const ProjectParams& p, const FieldF* open_x,
                                const FieldF* open_y) {
  if (open_x && open_y) {
    cl_->pressure_rhs_cut(in(u), in(v), in(*open_x), in(*open_y), out(rhs), box_of_size(rhs.size()),
                          p);
    return;
  }
  cl_->pressure_rhs(in(u), in(v), out(rhs), box_of_size(rhs.size()), p);
}

void OpenClDevice::face_velocities(const FieldF& u, const FieldF& v, const FieldF& p, FieldF& uf,
                                   FieldF& vf, const ProjectParams& params, bool periodic) {
  const DeviceField& du = in(u);
  const DeviceField& dv = in(v);
  const DeviceField& dp = in(p);
  DeviceField& duf = out(uf);
  DeviceField& dvf = out(vf);
  cl_->face_velocities(du, dv, dp, duf, dvf, box_of_size(p.size()), params);
  if (!periodic) return;
  // Ghost rows of uf and ghost columns of vf, wrapped, for the periodic back-trace (as
  // CpuDevice::face_velocities): rows are contiguous copies, columns rectangle copies.
  const Int2 n = p.size();
  const std::size_t f = sizeof(float);
  auto at = [](const DeviceField& d, int x, int y) {
    return std::size_t(d.origin + y * d.stride + x);
  };
  cl_command_queue q = ctx_.queue();
  cl_mem ub = duf.buffer.get(), vb = dvf.buffer.get();
  const std::size_t row = std::size_t(n.x + 1) * f;
  opencl_check(clEnqueueCopyBuffer(q, ub, ub, at(duf, 0, n.y - 1) * f, at(duf, 0, -1) * f, row, 0,
                                   nullptr, nullptr),
               "clEnqueueCopyBuffer(uf row)");
  opencl_check(clEnqueueCopyBuffer(q, ub, ub, at(duf, 0, 0) * f, at(duf, 0, n.y) * f, row, 0,
                                   nullptr, nullptr),
               "clEnqueueCopyBuffer(uf row)");
  const std::size_t pitch = std::size_t(dvf.stride) * f;
  const std::size_t region[3] = {f, std::size_t(n.y + 1), 1};
  auto column = [&](int from_x, int to_x) {
    const std::size_t src[3] = {at(dvf, from_x, 0) * f, 0, 0};
    const std::size_t dst[3] = {at(dvf, to_x, 0) * f, 0, 0};
    opencl_check(clEnqueueCopyBufferRect(q, vb, vb, src, dst, region, pitch, 0, pitch, 0, 0,
                                         nullptr, nullptr),
                 "clEnqueueCopyBufferRect(vf column)");
  };
  column(n.x - 1, -1);
  column(0, n.x);
}

void OpenClDevice::subtract_gradient(const FieldF& p, FieldF& u, FieldF& v,
                                     const ProjectParams& params) {
  const DeviceField& dp = in(p);
  DeviceField& du = out(u);
  cl_->subtract_gradient(dp, du, out(v), box_of_size(p.size()), params);
}

void OpenClDevice::stam_jacobi_sweeps(const FieldF& rhs, FieldF& a, FieldF& b, int sweeps,
                                      const StamSweepParams& p, const BoundaryFill& fill,
                                      const FieldF* start) {
  const DeviceField& r = in(rhs);
  DeviceField& da = out(a);
  DeviceField& db = out(b);
  const DeviceField* from = start ? &in(*start) : &da;
  DeviceField& want = sweeps % 2 == 0 ? da : db;
  DeviceField& other = sweeps % 2 == 0 ? db : da;
  bool periodic = false;
  for (const EdgeFill& e : {fill.left, fill.right, fill.bottom, fill.top})
    periodic = periodic || e.rule == EdgeRule::kPeriodic;
  const bool blocked = sweeps > 1 && !periodic;
  const int per_launch = blocked ? cl_->blocked_sweeps(sweeps) : 1;
  const Int2 tile = blocked ? cl_->blocked_tile(per_launch) : Int2{};
  // Each launch goes from one buffer into another and the last must write `want`: launch l of
  // L writes want when L - 1 - l is even, else the other buffer. From a or b that takes L of
  // the sweeps' parity (one launch more than the local memory asks for when it differs, the
  // sweeps spread evenly); from `start` any L. One sweep a launch when not blocked.
  int launches = sweeps;
  if (blocked && tile.x > 0) {
    launches = (sweeps + per_launch - 1) / per_launch;
    if (!start && launches % 2 != sweeps % 2) ++launches;
  }
  const DeviceField* cur = from;
  for (int l = 0, done = 0; l < launches; ++l) {
    DeviceField& next = (launches - 1 - l) % 2 == 0 ? want : other;
    const int s = (sweeps - done) / (launches - l);
    if (launches == sweeps) {
      cl_->stam_jacobi_sweep(r, *cur, next, box_of_size(a.size()), p);
      cl_->fill_boundary(next, fill);
    } else {
      cl_->stam_jacobi_blocked(r, *cur, next, s, p, fill, tile);
    }
    cur = &next;
    done += s;
  }
}

void OpenClDevice::advect_velocity(const FieldF& u0, const FieldF& v0, FieldF& u, FieldF& v,
                                   const AdvectParams& p) {
  const DeviceField& du0 = in(u0);
  const DeviceField& dv0 = in(v0);
  DeviceField& du = out(u);
  cl_->advect_velocity(du0, dv0, du, out(v), box_of_size(u.size()), p);
}

void OpenClDevice::advect_scalars(std::span<const FieldF* const> q0, const FieldF& u,
                                  const FieldF& v, std::span<FieldF* const> q,
                                  const AdvectParams& p) {
  const DeviceField& du = in(u);
  const DeviceField& dv = in(v);
  if (q.size() == 3) {  // the dye, A and B: one back-trace, as the CPU's advect_fields
    const DeviceField &a = in(*q0[0]), &b = in(*q0[1]), &c = in(*q0[2]);
    DeviceField &oa = out(*q[0]), &ob = out(*q[1]);
    cl_->advect_scalar3(a, b, c, du, dv, oa, ob, out(*q[2]), box_of_size(q[0]->size()), p);
    return;
  }
  // One kernel per field: each recomputes the back-trace, which is cheap beside the gathers.
  for (std::size_t i = 0; i < q.size(); ++i) {
    const DeviceField& dq0 = in(*q0[i]);
    cl_->advect_scalar(dq0, du, dv, out(*q[i]), box_of_size(q[i]->size()), p);
  }
}

void OpenClDevice::advect_scalar_mac(const FieldF& q0, const FieldF& uf, const FieldF& vf,
                                     FieldF& q, const AdvectParams& p) {
  const DeviceField& dq0 = in(q0);
  const DeviceField& duf = in(uf);
  const DeviceField& dvf = in(vf);
  cl_->advect_scalar_mac(dq0, duf, dvf, out(q), box_of_size(q.size()), p);
}

void OpenClDevice::maccormack_correct(std::span<const FieldF* const> q0,
                                      std::span<const FieldF* const> q_hat,
                                      std::span<const FieldF* const> q_back, const FieldF& u,
                                      const FieldF& v, std::span<FieldF* const> q,
                                      const AdvectParams& p, bool mac) {
  const DeviceField& du = in(u);
  const DeviceField& dv = in(v);
  for (std::size_t i = 0; i < q.size(); ++i) {
    const DeviceField& dq0 = in(*q0[i]);
    const DeviceField& dhat = in(*q_hat[i]);
    const DeviceField& dback = in(*q_back[i]);
    cl_->maccormack_correct(dq0, dhat, dback, du, dv, out(*q[i]), box_of_size(q[i]->size()), p,
                            mac);
  }
}

FieldRange OpenClDevice::range(const FieldF& f) {
  const int ny = f.ny();
  cl_->row_ranges(in(f), 0, ny, partial_sum_, partial_lo_, partial_hi_);
  FieldRange r;
  r.sum = partial_sum_.sum(ctx_, 0, ny);
  partial_lo_.read(ctx_, 0, ny, host_lo_.data());
  partial_hi_.read(ctx_, 0, ny, host_hi_.data());
  r.lo = float(host_lo_[0]);
  r.hi = float(host_hi_[0]);
  for (int j = 1; j < ny; ++j) {
    r.lo = std::min(r.lo, float(host_lo_[std::size_t(j)]));
    r.hi = std::max(r.hi, float(host_hi_[std::size_t(j)]));
  }
  return r;
}

void OpenClDevice::restore_mass(FieldF& f, double missing, float lo, float hi) {
  DeviceField& d = out(f);
  cl_->row_mass_weights(d, 0, f.ny(), lo, hi, partial_sum_);
  const double total_weight = partial_sum_.sum(ctx_, 0, f.ny());
  if (!(total_weight > 0.0)) return;
  cl_->restore_mass_rows(d, 0, f.ny(), missing / total_weight, lo, hi);
}

// --- linear systems ------------------------------------------------------------------------

OpenClDevice::OperatorTwin& OpenClDevice::operator_twin(const StencilOperator& op,
                                                        const LinearSolver& solver) {
  OperatorTwin* t = nullptr;
  for (OperatorTwin& o : operators_)
    if (o.host == &op) t = &o;
  if (!t) {
    operators_.emplace_back();
    t = &operators_.back();
    t->host = &op;
    t->device = ClStencilOperator::allocate(ctx_, op.size, op.boundary_x, op.boundary_y);
    t->null_space = std::make_unique<stencil::NullSpace>(op.size);
    const FieldF like(op.size, 1);
    t->other = ctx_.allocate_like(like);
    t->r = ctx_.allocate_like(like);
  }
  const int levels = solver.coarse_levels();
  if (levels > 0 && t->levels_of != &solver) {
    // The first multigrid solve on op (or another solver's levels): the levels' device memory,
    // allocated once; the solver's coarse operators follow op's uploads from here on.
    t->levels.clear();
    for (int k = 0; k < levels; ++k) {
      const StencilOperator& c = solver.coarse_operator(k);
      const FieldF like(c.size, 1);
      t->levels.push_back({ClStencilOperator::allocate(ctx_, c.size, c.boundary_x, c.boundary_y),
                           ctx_.allocate_like(like), ctx_.allocate_like(like),
                           ctx_.allocate_like(like)});
    }
    t->levels_of = &solver;
    t->stale = true;
  }
  if (t->stale) {
    t->device.upload(ctx_, op);
    t->null_space->analyse(op, cpu_.executor());
    if (t->null_space->singular()) t->null_mask = upload_mask(ctx_, t->null_space->mask());
    // prepare(op) built the coarse operators before the host said it wrote op (fluid_step).
    for (std::size_t k = 0; k < t->levels.size(); ++k)
      t->levels[k].op.upload(ctx_, solver.coarse_operator(int(k)));
    t->factored = false;
    t->stale = false;
  }
  return *t;
}

double OpenClDevice::consistent_part(double all, const DeviceField& f, const OperatorTwin& t) {
  if (!t.null_space->singular()) return all;
  const int ny = t.host->size.y;
  cl_->row_masked_sums(f, t.null_mask, 0, ny, partial_sum_);
  const double sum = partial_sum_.sum(ctx_, 0, ny);
  return std::max(0.0, all - sum * sum / double(t.null_space->count()));
}

double OpenClDevice::relative_residual(OperatorTwin& t, const DeviceField& b, const DeviceField& x,
                                       double bb) {
  cl_->residual(t.device, b, x, &t.r, partial_sum_);
  const double rr = consistent_part(partial_sum_.sum(ctx_, 0, t.host->size.y), t.r, t);
  return bb > 0.0 ? std::sqrt(rr / bb) : std::sqrt(rr);
}

void OpenClDevice::remove_null_mean(DeviceField& f, const OperatorTwin& t) {
  if (!t.null_space->singular()) return;
  const int ny = t.host->size.y;
  cl_->row_masked_sums(f, t.null_mask, 0, ny, partial_sum_);
  const double sum = partial_sum_.sum(ctx_, 0, ny);
  cl_->subtract_masked(f, t.null_mask, float(sum / double(t.null_space->count())));
}

// Every solver runs on the device (below); ICCG needs doubles there, and runs on the CPU
// without them.
SolveReport OpenClDevice::solve(LinearSolver& solver, const StencilOperator& op, const FieldF& b,
                                FieldF& x) {
  const SolverSettings& settings = solver.settings();
  if (settings.kind == SolverKind::kIccg && !cl_->has_fp64()) {
    say_fallback(DeviceOp::kSolve, solver_kind_name(settings.kind).data(),
                 "the device has no doubles (cl_khr_fp64)");
    host_in(b);
    host_in(x);
    const SolveReport report = cpu_.solve(solver, op, b, x);
    host_wrote(x);
    return report;
  }
  OperatorTwin& t = operator_twin(op, solver);
  const DeviceField& db = in(b);
  DeviceField& dx = out(x);
  switch (settings.kind) {
    case SolverKind::kMultigrid:
      return solve_multigrid(settings, t, db, dx);
    case SolverKind::kIccg:
      return solve_iccg(settings, t, db, dx);
    case SolverKind::kJacobi:
    case SolverKind::kRedBlackGaussSeidel:
      break;
  }
  return solve_sweeps(settings, t, db, dx);
}

// kernels/iccg_solver.cpp's solve, step for step (OpenClIccg), on the pivots of the uploaded
// operator, factored on the device after each upload.
SolveReport OpenClDevice::solve_iccg(const SolverSettings& settings, OperatorTwin& t,
                                     const DeviceField& b, DeviceField& x) {
  if (!t.iccg) {
    // The first ICCG solve on this operator allocates the solver's vectors.
    t.iccg = std::make_unique<OpenClIccg>(*cl_, t.host->size);
    t.factored = false;
  }
  if (!t.factored) {
    t.iccg->factor(t.device);
    t.factored = true;
  }
  const int ny = t.host->size.y;
  cl_->row_sums_of_squares(b, 0, ny, partial_sum_);
  const double bb = consistent_part(partial_sum_.sum(ctx_, 0, ny), b, t);
  const ClNullSpace null{&t.null_mask, t.null_space->count(), bb};
  SolveReport report{};
  report.iterations =
      t.iccg->iterate(t.device, b, x, settings, t.null_space->singular() ? &null : nullptr);
  remove_null_mean(x, t);
  report.relative_residual = relative_residual(t, b, x, bb);
  return report;
}

// The fixed-sweep solvers of kernels/jacobi_solver.cpp and rbgs_solver.cpp, sweep for sweep.
SolveReport OpenClDevice::solve_sweeps(const SolverSettings& settings, OperatorTwin& t,
                                       const DeviceField& db, DeviceField& dx) {
  const bool jacobi = settings.kind == SolverKind::kJacobi;
  const int ny = t.host->size.y;
  cl_->row_sums_of_squares(db, 0, ny, partial_sum_);
  const double bb = consistent_part(partial_sum_.sum(ctx_, 0, ny), db, t);
  const bool check = settings.tolerance > 0.0;
  SolveReport report{};
  DeviceField* from = &dx;
  DeviceField* to = &t.other;
  for (int k = 0; k < settings.max_iterations; ++k) {
    if (jacobi) {
      cl_->stencil_jacobi_sweep(t.device, db, *from, *to);
      std::swap(from, to);
    } else {
      cl_->stencil_rbgs_half_sweep(t.device, db, dx, 0);
      cl_->stencil_rbgs_half_sweep(t.device, db, dx, 1);
    }
    ++report.iterations;
    if (check && relative_residual(t, db, *from, bb) <= settings.tolerance) break;
  }
  if (from != &dx) cl_->copy_field(*from, dx);
  remove_null_mean(dx, t);
  report.relative_residual = relative_residual(t, db, dx, bb);
  return report;
}

// kernels/multigrid_solver.cpp's solve, step for step: the same V-cycles on the same (uploaded)
// coarse operators, the same stopping rule on the same residuals.
SolveReport OpenClDevice::solve_multigrid(const SolverSettings& settings, OperatorTwin& t,
                                          const DeviceField& b, DeviceField& x) {
  // A singular system is solvable only for b in the range: drop b's null-space component (in
  // t.other, free during a multigrid solve).
  const DeviceField* rhs = &b;
  if (t.null_space->singular()) {
    cl_->copy_field(b, t.other);
    remove_null_mean(t.other, t);
    rhs = &t.other;
  }
  const int ny = t.host->size.y;
  cl_->row_sums_of_squares(*rhs, 0, ny, partial_sum_);
  const double bb = consistent_part(partial_sum_.sum(ctx_, 0, ny), *rhs, t);
  SolveReport report{};
  report.relative_residual = relative_residual(t, *rhs, x, bb);
  for (int k = 0; k < settings.max_iterations; ++k) {
    if (settings.tolerance > 0.0 && report.relative_residual <= settings.tolerance) break;
    v_cycle(t.device, *rhs, x, t.r, t.levels);
    remove_null_mean(x, t);
    ++report.iterations;
    const double before = report.relative_residual;
    report.relative_residual = relative_residual(t, *rhs, x, bb);
    if (settings.tolerance > 0.0 && report.relative_residual > multigrid::kStagnation * before)
      break;
  }
  return report;
}

namespace {
// Multigrid levels of at most this many cells smooth in one work-group (64 x 64).
constexpr int kOneGroupCells = 4096;
}  // namespace

void OpenClDevice::v_cycle(const ClStencilOperator& op, const DeviceField& b, DeviceField& x,
                           DeviceField& r, std::span<CoarseLevel> coarser) {
  if (coarser.empty()) {
    // The coarsest grid (fewer than 4 cells on a side: a dozen or so cells on the presets'
    // grids) relaxes on the device too, all its sweeps in one launch: no transfer, no read.
    cl_->stencil_rbgs_sweeps_one_group(op, b, x, multigrid::kCoarsestSweeps);
    return;
  }
  // A small level's sweeps cost less than their launches: one work-group runs them all in one
  // launch (the same bits as the half sweeps).
  const bool small = op.size.x * op.size.y <= kOneGroupCells;
  auto smooth = [&](int sweeps) {
    if (small) {
      cl_->stencil_rbgs_sweeps_one_group(op, b, x, sweeps);
      return;
    }
    for (int k = 0; k < sweeps; ++k) {
      cl_->stencil_rbgs_half_sweep(op, b, x, 0);
      cl_->stencil_rbgs_half_sweep(op, b, x, 1);
    }
  };
  smooth(multigrid::kPreSmooth);
  // The residual's row partials are written (the kernel's reduction) and not read.
  cl_->residual(op, b, x, &r, partial_sum_);
  CoarseLevel& coarse = coarser.front();
  cl_->restrict_sum(r, coarse.b);
  cl_->fill_field(coarse.x, 0.0f);
  v_cycle(coarse.op, coarse.b, coarse.x, coarse.r, coarser.subspan(1));
  cl_->prolong_add(coarse.x, x);
  smooth(multigrid::kPostSmooth);
}

// --- reaction-diffusion --------------------------------------------------------------------

void OpenClDevice::reaction_implicit(FieldF& a, FieldF& b, const ReactionParams& p, float dt) {
  DeviceField& da = out(a);
  DeviceField& db = out(b);
  cl_->reaction_implicit(da, db, da, db, box_of_size(a.size()), p, dt);
}

void OpenClDevice::reaction_table(FieldF& a, FieldF& b, const ReactionTable& table) {
  if (table_stale_) {
    table_.upload(ctx_, table.view());
    table_stale_ = false;
  }
  DeviceField& da = out(a);
  DeviceField& db = out(b);
  cl_->reaction_table(da, db, da, db, box_of_size(a.size()), table_);
}

void OpenClDevice::conductivity(const FieldF& a, const FieldF& theta0, FieldF& k,
                                const AnisotropyParams& p) {
  const DeviceField& da = in(a);
  const DeviceField& dt = in(theta0);
  cl_->conductivity(da, &dt, out(k), box_of_size(a.size()), p);
}

SolveReport OpenClDevice::implicit_diffusion(ImplicitDiffusion& diffusion, FieldF& field,
                                             const FieldF* conductivity, const DiffusionStep& s) {
  const SolverSettings& solver = diffusion.solver_settings();
  if (!OpenClDiffusion::supports(*cl_, solver)) {
    const bool iccg = solver.kind == SolverKind::kIccg;
    const bool sweeps =
        solver.kind == SolverKind::kJacobi || solver.kind == SolverKind::kRedBlackGaussSeidel;
    say_fallback(DeviceOp::kImplicitDiffusion,
                 sweeps ? "sweeps with a tolerance" : solver_kind_name(solver.kind).data(),
                 iccg ? "the device has no doubles (cl_khr_fp64)"
                      : "OpenCL runs iccg, or fixed jacobi or rbgs sweeps (tolerance 0)");
    host_in(field);
    if (conductivity) host_in(*conductivity);
    const SolveReport r = cpu_.implicit_diffusion(diffusion, field, conductivity, s);
    host_wrote(field);
    return r;
  }
  DiffusionTwin* twin = nullptr;
  for (DiffusionTwin& t : diffusions_)
    if (t.cpu == &diffusion) twin = &t;
  if (!twin) {
    diffusions_.push_back({&diffusion, std::make_unique<OpenClDiffusion>(
                                           *cl_, diffusion.size(), diffusion.boundary(), solver)});
    twin = &diffusions_.back();
  }
  twin->device->set_limits(solver.max_iterations, solver.tolerance);
  const DeviceField* k = conductivity ? &in(*conductivity) : nullptr;
  const DeviceField* solid = diffusion.solid() ? &mask(*diffusion.solid()) : nullptr;
  return twin->device->step(out(field), k, s, solid);
}

void OpenClDevice::explicit_rd(const FieldF& a, const FieldF& b, FieldF& a_out, FieldF& b_out,
                               ExplicitScheme scheme, const ExplicitRdParams& p, QuiescentBox*,
                               int grow) {
  ARDCELL_CHECK(grow == 0, "explicit_rd: the OpenCL device steps the whole grid (grow 0)");
  const DeviceField& da = in(a);
  const DeviceField& db = in(b);
  DeviceField& da_out = out(a_out);
  DeviceField& db_out = out(b_out);
  const Box2 all = box_of_size(a.size());
  switch (scheme) {
    case ExplicitScheme::kGrayScott9:
      cl_->gray_scott9_explicit(da, db, da_out, db_out, all,
                                {p.reaction.F, p.reaction.k, p.dt, p.diffusion_a, p.diffusion_b});
      break;
    case ExplicitScheme::k9:
      cl_->explicit_rd9(da, db, da_out, db_out, all, p);
      break;
    case ExplicitScheme::k5:
      cl_->explicit_rd5(da, db, da_out, db_out, all, p);
      break;
  }
}

void OpenClDevice::gray_scott9_steps(GrayScott9Blocked& blocked, FieldF& a, FieldF& b, int steps,
                                     const GrayScott9Params& p, bool /*resume*/) {
  say_fallback(DeviceOp::kGrayScott9Steps, "rd.scheme explicit9",
               "temporal blocking is the CPU's; the engine steps the 9-point twin here");
  host_in(a);
  host_in(b);
  // The host copies may have come from the device since the last run: every row is scanned.
  cpu_.gray_scott9_steps(blocked, a, b, steps, p, false);
  host_wrote(a);
  host_wrote(b);
}

}  // namespace ardcell
#endif
