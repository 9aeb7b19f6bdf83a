// CpuDevice: every op of host/engine/device.h as the kernels of kernels/ over bands of rows on
// the RowExecutor. Each band writes its own rows only, and reductions store one partial per
// row and add them in row order, so any number of workers gives the serial reference's bits.
#include <algorithm>
#include <array>
#include <cstring>
#include <type_traits>
#include <utility>

#include "host/engine/device.h"
#include "kernels/field_reductions.h"
#include "kernels/gray_scott9.h"
#include "kernels/periodic_stencil_solve.h"
#include "kernels/stencil_operator.h"
#include "kernels/tensor_field_solve.h"
#include "runtime/row_executor.h"

namespace ardcell {
const char* device_op_name(DeviceOp op) {
  switch (op) {
    case DeviceOp::kCopy:
      return "copy";
    case DeviceOp::kFillBoundary:
      return "boundary fill";
    case DeviceOp::kFillObstacle:
      return "obstacle fill";
    case DeviceOp::kAddBoundaryValues:
      return "boundary values";
    case DeviceOp::kAddSplat:
      return "splat";
    case DeviceOp::kInflowStripes:
      return "inflow stripes";
    case DeviceOp::kPressureRhs:
      return "pressure right-hand side";
    case DeviceOp::kFaceVelocities:
      return "face velocities";
    case DeviceOp::kSubtractGradient:
      return "gradient subtraction";
    case DeviceOp::kAdvectVelocity:
      return "velocity advection";
    case DeviceOp::kAdvectScalar:
      return "scalar advection";
    case DeviceOp::kAdvectScalarMac:
      return "scalar advection (MAC faces)";
    case DeviceOp::kMacCormack:
      return "MacCormack correction";
    case DeviceOp::kRange:
      return "field range";
    case DeviceOp::kRestoreMass:
      return "mass fix";
    case DeviceOp::kSolve:
      return "linear solve";
    case DeviceOp::kReactionImplicit:
      return "implicit reaction";
    case DeviceOp::kReactionTable:
      return "reaction table";
    case DeviceOp::kConductivity:
      return "conductivity";
    case DeviceOp::kImplicitDiffusion:
      return "implicit diffusion";
    case DeviceOp::kExplicitRd:
      return "explicit reaction-diffusion";
    case DeviceOp::kGrayScott9Steps:
      return "seed 001's temporally blocked steps";
    case DeviceOp::kGeneralizedRd:
      return "generalized reaction-diffusion";
    case DeviceOp::kTensorFieldRd:
      return "tensor-field reaction-diffusion";
    case DeviceOp::kPeriodicSolve:
      return "periodic solve (FFT)";
    case DeviceOp::kTensorFieldSolve:
      return "tensor-field solve (BiCGSTAB)";
    case DeviceOp::kReactionTrapezoidal:
      return "trapezoidal reaction";
    case DeviceOp::kSbdfRhs:
      return "SBDF right-hand side";
    case DeviceOp::kEtdrk4:
      return "ETDRK4 step (FFT)";
    case DeviceOp::kStamJacobi:
      return "Stam's Jacobi sweeps";
    case DeviceOp::kCount:
      break;
  }
  return "?";
}

CpuDevice::CpuDevice(RowExecutor& ex, const DeviceBlock& block) : ex_(&ex), block_(block) {
  ARDCELL_CHECK(
      !block.halo || (!block.block.empty() && box_of_size(block.grid).contains(block.block)),
      "CpuDevice: a block inside its grid");
}
CpuDevice::~CpuDevice() = default;

bool CpuDevice::supports(DeviceOp op) const {
  if (!block_.halo) return true;
  switch (op) {
    case DeviceOp::kCopy:
    case DeviceOp::kFillBoundary:
    case DeviceOp::kAddBoundaryValues:
    case DeviceOp::kAddSplat:
    case DeviceOp::kInflowStripes:
    case DeviceOp::kReactionImplicit:
    case DeviceOp::kReactionTable:
    case DeviceOp::kReactionTrapezoidal:
    case DeviceOp::kSbdfRhs:
    case DeviceOp::kConductivity:
    case DeviceOp::kExplicitRd:
      return true;
    // Its rows above and below from the halo; rows wrap in x, so the block must hold them whole.
    case DeviceOp::kGrayScott9Steps:
      return block_.block.min.x == 0 && block_.block.max.x == block_.grid.x;
    // On the grid gathered from every block (CpuDevice::gathers).
    case DeviceOp::kImplicitDiffusion:
    case DeviceOp::kGeneralizedRd:
    case DeviceOp::kTensorFieldRd:
    case DeviceOp::kPeriodicSolve:
    case DeviceOp::kTensorFieldSolve:
    case DeviceOp::kEtdrk4:
    case DeviceOp::kAdvectScalar:
    case DeviceOp::kMacCormack:
      return true;
    default:
      return false;
  }
}

void CpuDevice::require(DeviceOp op) const {
  if (!supports(op)) detail::check_failed("supports(op)", __FILE__, __LINE__, device_op_name(op));
}

CpuDevice& CpuDevice::serial() {
  thread_local CpuDevice device(RowExecutor::serial());
  return device;
}

const char* CpuDevice::name() const { return ex_->workers() > 1 ? "threads" : "serial"; }
int CpuDevice::workers() const { return ex_->workers(); }

void CpuDevice::reserve(Int2 grid) {
  ex_->reserve_rows(grid.y + 1);  // the faces of a grid have one more row
  // A block's explicit steps may also compute its halo's columns (explicit_rd's grow).
  const int wide = grid.x + (block_.halo ? 2 * block_.halo->width() : 0);
  const std::size_t floats =
      std::max(2 * std::size_t(wide + 2) + 16, generalized_rd_scratch_floats(grid.x));
  const std::size_t stride = (floats + 15) / 16 * 16;
  if (stride > row_scratch_stride_) {
    row_scratch_stride_ = stride;
    row_scratch_.assign(row_scratch_stride_ * std::size_t(ex_->workers()), 0.0f);
  }
  band_boxes_.resize(2 * std::size_t(ex_->workers()));
}

void CpuDevice::copy(const FieldF& from, FieldF& to) {
  ARDCELL_CHECK(from.raw_size() == to.raw_size(), "copy: fields of different layouts");
  const int rows = from.ny() + 2 * from.halo();
  const std::size_t stride = std::size_t(from.stride());
  ex_->for_rows(rows, int(stride), [&](int y0, int y1) {
    std::memcpy(to.raw() + stride * std::size_t(y0), from.raw() + stride * std::size_t(y0),
                stride * std::size_t(y1 - y0) * sizeof(float));
  });
}

void CpuDevice::swap(FieldF& a, FieldF& b) { std::swap(a, b); }

void CpuDevice::exchange_halos(std::span<FieldF* const> fields, int depth) {
  if (!block_.halo || fields.empty()) return;
  constexpr std::size_t kMaxFields = 8;
  ARDCELL_CHECK(fields.size() <= kMaxFields && depth <= block_.halo->width(),
                "exchange_halos: at most 8 fields, as deep as the channel's width");
  std::array<HaloField, kMaxFields> halo;
  for (std::size_t i = 0; i < fields.size(); ++i) halo[i] = {fields[i], depth};
  block_.halo->begin(std::span(halo.data(), fields.size()));
  block_.halo->finish();
}

void CpuDevice::fill_boundary(FieldF& f, const BoundaryFill& fill) {
  ardcell::fill_boundary(f.view(), domain_of(f), fill);
}

void CpuDevice::stam_jacobi_sweeps(const FieldF& rhs, FieldF& a, FieldF& b, int sweeps,
                                   const StamSweepParams& p, const BoundaryFill& fill,
                                   const FieldF* start) {
  require(DeviceOp::kStamJacobi);
  const FieldF* cur = start ? start : &a;
  FieldF* next = &b;
  for (int s = 0; s < sweeps; ++s) {
    for_bands(a.interior(), [&](Box2 rows) {
      ardcell::stam_jacobi_sweep(rhs.view(), cur->view(), next->view(), rows, p);
    });
    ardcell::fill_boundary(next->view(), domain_of(*next), fill);
    cur = next;
    next = next == &b ? &a : &b;
  }
}

void CpuDevice::fill_obstacle(FieldF& f, const Field<uint8_t>& solid, ObstacleRule rule) {
  require(DeviceOp::kFillObstacle);
  // Solid cells are written from fluid cells only: bands of rows do not interfere.
  for_bands(f.interior(),
            [&](Box2 rows) { ardcell::fill_obstacle(f.view(), solid.view(), rows, rule); });
}

void CpuDevice::add_boundary_values(FieldF& b, const BoundaryFill& fill, double scale) {
  ardcell::add_boundary_values(b.view(), domain_of(b), fill, scale);
}

void CpuDevice::add_splat(FieldF& f, const SplatParams& splat) {
  for_bands(f.interior(), [&](Box2 rows) { ardcell::add_splat(f.view(), rows, splat); });
}

void CpuDevice::set_inflow_stripes(FieldF& dye, int stripes, BoundarySide side) {
  ardcell::set_inflow_stripes(dye.view(), domain_of(dye), stripes, side);
}

void CpuDevice::pressure_rhs(const FieldF& u, const FieldF& v, FieldF& rhs, const ProjectParams& p,
                             const FieldF* open_x, const FieldF* open_y) {
  require(DeviceOp::kPressureRhs);
  if (open_x && open_y) {
    for_bands(rhs.interior(), [&](Box2 rows) {
      ardcell::pressure_rhs_cut(u.view(), v.view(), open_x->view(), open_y->view(), rhs.view(),
                                rows, p);
    });
    return;
  }
  for_bands(rhs.interior(),
            [&](Box2 rows) { ardcell::pressure_rhs(u.view(), v.view(), rhs.view(), rows, p); });
}

void CpuDevice::face_velocities(const FieldF& u, const FieldF& v, const FieldF& p, FieldF& uf,
                                FieldF& vf, const ProjectParams& params, bool periodic) {
  require(DeviceOp::kFaceVelocities);
  const Int2 n = p.size();
  for_bands(box_of_size(n), [&](Box2 rows) {
    ardcell::face_velocities(u.view(), v.view(), p.view(), uf.view(), vf.view(), rows, params,
                             rows.max.y == n.y);
  });
  if (periodic) {
    // Ghost rows of uf and ghost columns of vf, wrapped, for the periodic back-trace.
    for (int i = 0; i <= n.x; ++i) {
      uf(i, -1) = uf(i, n.y - 1);
      uf(i, n.y) = uf(i, 0);
    }
    for (int j = 0; j <= n.y; ++j) {
      vf(-1, j) = vf(n.x - 1, j);
      vf(n.x, j) = vf(0, j);
    }
  }
}

void CpuDevice::subtract_gradient(const FieldF& p, FieldF& u, FieldF& v,
                                  const ProjectParams& params) {
  require(DeviceOp::kSubtractGradient);
  for_bands(p.interior(), [&](Box2 rows) {
    ardcell::subtract_gradient(p.view(), u.view(), v.view(), rows, params);
  });
}

void CpuDevice::advect_velocity(const FieldF& u0, const FieldF& v0, FieldF& u, FieldF& v,
                                const AdvectParams& p) {
  require(DeviceOp::kAdvectVelocity);
  for_bands(u.interior(), [&](Box2 rows) {
    ardcell::advect_velocity(u0.view(), v0.view(), u.view(), v.view(), rows, p);
  });
}

void CpuDevice::advect_scalars(std::span<const FieldF* const> q0, const FieldF& u, const FieldF& v,
                               std::span<FieldF* const> q, const AdvectParams& p) {
  require(DeviceOp::kAdvectScalar);
  ARDCELL_CHECK(q0.size() == q.size() && q.size() <= std::size_t(kMaxAdvectFields) && !q.empty(),
                "advect_scalars: one output per input, 1 to kMaxAdvectFields");
  const std::size_t n = q.size();
  // On a block the back-trace (and the velocity at its midpoint) may leave the block: it reads
  // the grid gathered from every block, and the block computes its own cells.
  const bool gathered = gathers(*q[0]);
  int slot = 0;
  std::array<View<const float>, kMaxAdvectFields> in;
  std::array<View<float>, kMaxAdvectFields> out;
  for (std::size_t i = 0; i < n; ++i) {
    in[i] = gathered ? gather(*q0[i], slot++).view() : q0[i]->view();
    out[i] = q[i]->view();
  }
  const View<const float> uv[] = {gathered ? gather(u, slot++).view() : u.view(),
                                  gathered ? gather(v, slot++).view() : v.view()};
  for_bands(q[0]->interior(), [&](Box2 rows) {
    ardcell::advect_fields(uv[0], uv[1], std::span(in.data(), n), std::span(out.data(), n), rows,
                           p);
  });
}

void CpuDevice::advect_scalar_mac(const FieldF& q0, const FieldF& uf, const FieldF& vf, FieldF& q,
                                  const AdvectParams& p) {
  require(DeviceOp::kAdvectScalarMac);
  for_bands(q.interior(), [&](Box2 rows) {
    ardcell::advect_scalar_mac(q0.view(), uf.view(), vf.view(), q.view(), rows, p);
  });
}

void CpuDevice::maccormack_correct(std::span<const FieldF* const> q0,
                                   std::span<const FieldF* const> q_hat,
                                   std::span<const FieldF* const> q_back, const FieldF& u,
                                   const FieldF& v, std::span<FieldF* const> q,
                                   const AdvectParams& p, bool mac) {
  require(DeviceOp::kMacCormack);
  ARDCELL_CHECK(q0.size() == q.size() && q_hat.size() == q.size() && q_back.size() == q.size() &&
                    q.size() <= std::size_t(kMaxAdvectFields) && !q.empty() &&
                    (!mac || q.size() == 1),
                "maccormack_correct: one q_hat, q_back and output per input, 1 to "
                "kMaxAdvectFields (one with mac)");
  const std::size_t n = q.size();
  // On a block the bounds are read at a departure point that may leave it: q0 and the velocity
  // come from the grid gathered from every block, q_hat and q_back are read at each cell only.
  const bool gathered = gathers(*q[0]);
  ARDCELL_CHECK(!(gathered && mac),
                "maccormack_correct: a block's face velocities are not gathered");
  if (mac) {
    for_bands(q[0]->interior(), [&](Box2 rows) {
      ardcell::maccormack_correct_mac(q0[0]->view(), q_hat[0]->view(), q_back[0]->view(), u.view(),
                                      v.view(), q[0]->view(), rows, p);
    });
    return;
  }
  int slot = 0;
  std::array<View<const float>, kMaxAdvectFields> in, hat, back;
  std::array<View<float>, kMaxAdvectFields> out;
  for (std::size_t i = 0; i < n; ++i) {
    in[i] = gathered ? gather(*q0[i], slot++).view() : q0[i]->view();
    hat[i] = q_hat[i]->view();
    back[i] = q_back[i]->view();
    out[i] = q[i]->view();
  }
  const View<const float> uv[] = {gathered ? gather(u, slot++).view() : u.view(),
                                  gathered ? gather(v, slot++).view() : v.view()};
  for_bands(q[0]->interior(), [&](Box2 rows) {
    ardcell::maccormack_correct(uv[0], uv[1], std::span(in.data(), n), std::span(hat.data(), n),
                                std::span(back.data(), n), std::span(out.data(), n), rows, p);
  });
}

FieldRange CpuDevice::range(const FieldF& f) {
  require(DeviceOp::kRange);
  const int ny = f.ny();
  double* lo = ex_->rows_scratch(ny, 0);
  double* hi = ex_->rows_scratch(ny, 1);
  FieldRange r;
  r.sum = ex_->sum_rows(ny, f.nx(), [&](int y0, int y1, double* partials) {
    row_ranges(f.view(), f.nx(), y0, y1, partials, lo, hi);
  });
  r.lo = float(lo[0]);
  r.hi = float(hi[0]);
  for (int j = 1; j < ny; ++j) {
    r.lo = std::min(r.lo, float(lo[j]));
    r.hi = std::max(r.hi, float(hi[j]));
  }
  return r;
}

void CpuDevice::restore_mass(FieldF& f, double missing, float lo, float hi) {
  require(DeviceOp::kRestoreMass);
  const double total_weight = ex_->sum_rows(f.ny(), f.nx(), [&](int y0, int y1, double* partials) {
    row_mass_weights(f.view(), f.nx(), y0, y1, lo, hi, partials);
  });
  if (!(total_weight > 0.0)) return;
  const double k = missing / total_weight;
  ex_->for_rows(f.ny(), f.nx(),
                [&](int y0, int y1) { restore_mass_rows(f.view(), f.nx(), y0, y1, k, lo, hi); });
}

SolveReport CpuDevice::solve(LinearSolver& solver, const StencilOperator& op, const FieldF& b,
                             FieldF& x) {
  require(DeviceOp::kSolve);
  return solver.solve(op, b, x);
}

void CpuDevice::reaction_implicit(FieldF& a, FieldF& b, const ReactionParams& p, float dt) {
  for_bands(a.interior(), [&](Box2 rows) {
    reaction_implicit_tile(a.view(), b.view(), a.view(), b.view(), rows, p, dt);
  });
}

void CpuDevice::reaction_table(FieldF& a, FieldF& b, const ReactionTable& table) {
  for_bands(a.interior(), [&](Box2 rows) {
    reaction_table_tile(a.view(), b.view(), a.view(), b.view(), rows, table.view());
  });
}

void CpuDevice::conductivity(const FieldF& a, const FieldF& theta0, FieldF& k,
                             const AnisotropyParams& p) {
  require(DeviceOp::kConductivity);
  for_bands(a.interior(),
            [&](Box2 rows) { conductivity_tile(a.view(), theta0.view(), k.view(), rows, p); });
}

bool CpuDevice::gathers(const FieldF& f) const {
  return block_.halo && f.interior() != box_of_size(block_.grid);
}

FieldF& CpuDevice::gather(const FieldF& f, int slot) {
  FieldF& whole = whole_[std::size_t(slot)];
  if (whole.empty()) whole = FieldF(block_.grid, 1);  // the first frame only
  block_.halo->gather_all(f, whole);
  return whole;
}

FieldF& CpuDevice::whole_scratch(int slot) {
  FieldF& whole = whole_[std::size_t(slot)];
  if (whole.empty()) whole = FieldF(block_.grid, 1);
  return whole;
}

void CpuDevice::take(const FieldF& whole, FieldF& f) {
  for_bands(f.interior(), [&](Box2 rows) { copy_box<float>(whole.view(), f.view(), rows); });
}

SolveReport CpuDevice::implicit_diffusion(ImplicitDiffusion& diffusion, FieldF& field,
                                          const FieldF* conductivity, const DiffusionStep& s) {
  require(DeviceOp::kImplicitDiffusion);
  if (diffusion.on_block()) return diffusion.step(field, conductivity, s, block_.halo);
  if (!gathers(field)) return diffusion.step(field, conductivity, s);
  FieldF& x = gather(field, 0);
  const SolveReport report =
      diffusion.step(x, conductivity ? &gather(*conductivity, 1) : nullptr, s);
  take(x, field);
  return report;
}

void CpuDevice::explicit_rd(const FieldF& a, const FieldF& b, FieldF& a_out, FieldF& b_out,
                            ExplicitScheme scheme, const ExplicitRdParams& p, QuiescentBox* quiet,
                            int grow) {
  const Box2 inner = a.interior(), cells = inner.grown(grow);
  ARDCELL_CHECK(grow >= 0 && std::min(a.halo(), b.halo()) > grow &&
                    std::min(a_out.halo(), b_out.halo()) >= grow,
                "explicit_rd: the fields' halo holds the cells it steps and one more");
  ARDCELL_CHECK(row_scratch_stride_ >= 2 * std::size_t(cells.width() + 2) &&
                    band_boxes_.size() >= 2 * std::size_t(workers()),
                "explicit_rd: reserve() the grid first");
  const GrayScott9Params gs{p.reaction.F, p.reaction.k, p.dt, p.diffusion_a, p.diffusion_b};
  // Every cell of `box`, each band then handing its rows to `stepped(rows, worker)` while they
  // are in cache.
  const auto step = [&](Box2 box, const auto& stepped) {
    for_bands(box, [&](Box2 rows, int worker) {
      switch (scheme) {
        case ExplicitScheme::kGrayScott9:
          gray_scott9_explicit_tile(a.view(), b.view(), a_out.view(), b_out.view(), rows, gs,
                                    row_scratch(worker));
          break;
        case ExplicitScheme::k9:
          explicit_rd9_tile(a.view(), b.view(), a_out.view(), b_out.view(), rows, p);
          break;
        case ExplicitScheme::k5:
          explicit_rd5_tile(a.view(), b.view(), a_out.view(), b_out.view(), rows, p);
          break;
      }
      stepped(rows, worker);
    });
  };
  const auto nothing = [](Box2, int) {};
  if (scheme != ExplicitScheme::kGrayScott9 || !quiet || !quiet->skips(gs)) {
    step(cells, nothing);
    return;
  }
  // The halo cells: the rows above and below the interior whole (short rows of few cells), of
  // the columns left and right only the rows that can change.
  // (Fields of halo 1 never step halo columns: nothing to scan.)
  if (a.halo() > 1) quiet->begin_sides(a.view(), b.view(), inner, grow);
  if (grow > 0) {
    step({cells.min, {cells.max.x, inner.min.y}}, nothing);
    step({{cells.min.x, inner.max.y}, cells.max}, nothing);
    for (int side = 0; side < 2; ++side) {
      const Int2 rows = quiet->side_rows(a.view(), b.view(), side, inner, grow);
      Int2 written{};
      if (rows.y > rows.x) {
        const Box2 box = side == 0 ? Box2{{cells.min.x, rows.x}, {inner.min.x, rows.y}}
                                   : Box2{{inner.max.x, rows.x}, {cells.max.x, rows.y}};
        step(box, nothing);
        const Box2 w = quiet->differing(a_out.view(), b_out.view(), box);
        if (!w.empty()) written = {w.min.y, w.max.y};
      }
      quiet->side_stepped(side, written);
    }
  }
  // Of the interior, only the cells that can change; each band notes where its output (and, on
  // a run's first step, its input) differs from the fixed point, while the rows are in cache.
  const Box2 region = quiet->region(a.view(), b.view(), inner);
  const bool first = !quiet->known();
  std::fill(band_boxes_.begin(), band_boxes_.end(), Box2{});
  if (!region.empty())
    step(region, [&](Box2 rows, int worker) {
      Box2& out = band_boxes_[std::size_t(worker)];
      out = out.united(quiet->differing(a_out.view(), b_out.view(), rows));
      if (first) {
        Box2& in = band_boxes_[std::size_t(workers() + worker)];
        in = in.united(quiet->differing(a.view(), b.view(), rows));
      }
    });
  Box2 written{}, input{};
  for (int w = 0; w < workers(); ++w) {
    written = written.united(band_boxes_[std::size_t(w)]);
    input = input.united(band_boxes_[std::size_t(workers() + w)]);
  }
  quiet->stepped(written, input, grow);
}

void CpuDevice::gray_scott9_steps(GrayScott9Blocked& blocked, FieldF& a, FieldF& b, int steps,
                                  const GrayScott9Params& p, bool resume) {
  require(DeviceOp::kGrayScott9Steps);
  GrayScott9Blocked::adopt(a);
  GrayScott9Blocked::adopt(b);
  blocked.run(a, b, steps, p, resume);
}

void CpuDevice::generalized_rd(const FieldF& a, const FieldF& b, FieldF& a_out, FieldF& b_out,
                               const GeneralizedTaps& k, const GeneralizedRdParams& p) {
  require(DeviceOp::kGeneralizedRd);
  if (gathers(a)) {
    generalized_rd(gather(a, 0), gather(b, 1), whole_scratch(2), whole_scratch(3), k, p);
    take(whole_[2], a_out);
    take(whole_[3], b_out);
    return;
  }
  ARDCELL_CHECK(row_scratch_stride_ >= generalized_rd_scratch_floats(a.nx()),
                "generalized_rd: reserve() the grid first");
  for_bands(a.interior(), [&](Box2 rows, int worker) {
    generalized_rd_rows(k, a.view(), b.view(), a_out.view(), b_out.view(), a.size(), rows.min.y,
                        rows.max.y, p, row_scratch(worker));
  });
}

void CpuDevice::generalized_rd_steps(FieldF& a, FieldF& b, FieldF& a_out, FieldF& b_out,
                                     const GeneralizedTaps& k, const GeneralizedRdParams& p,
                                     int steps) {
  require(DeviceOp::kGeneralizedRd);
  if (gathers(a)) {
    // The steps swap the whole fields among themselves: slots 2 and 3 end with a_out's, b_out's.
    generalized_rd_steps(gather(a, 0), gather(b, 1), whole_scratch(2), whole_scratch(3), k, p,
                         steps);
    take(whole_[2], a_out);
    take(whole_[3], b_out);
    return;
  }
  // Nothing to fuse without a diffusion (no neighbour is read). Up to 512^2 the fields stay in
  // the caches between steps and fusing does not pay (bench/RESULTS_SEED003.md); and each band
  // computes S (S - 1) rows twice at each edge, so bands (up to 4 per worker) under 64 rows
  // would pay more in rows than they save in memory traffic.
  const int rows_per_band = a.ny() / (4 * workers());
  if ((p.scale_a == 0.0f && p.scale_b == 0.0f) || a.nx() * a.ny() <= 512 * 512 ||
      rows_per_band < 64) {
    Device::generalized_rd_steps(a, b, a_out, b_out, k, p, steps);
    return;
  }
  ARDCELL_CHECK(row_scratch_stride_ >= generalized_rd_scratch_floats(a.nx()),
                "generalized_rd_steps: reserve() the grid first");
  for_bands(a.interior(), [&](Box2 rows, int worker) {
    generalized_rd_fused_rows(k, a.view(), b.view(), a_out.view(), b_out.view(), a.size(),
                              rows.min.y, rows.max.y, p, steps, row_scratch(worker));
  });
}

void CpuDevice::tensor_field_rd(const FieldF& a, const FieldF& b, FieldF& a_out, FieldF& b_out,
                                const Rank2FaceField& d, const GeneralizedRdParams& p) {
  require(DeviceOp::kTensorFieldRd);
  if (gathers(a)) {
    tensor_field_rd(gather(a, 0), gather(b, 1), whole_scratch(2), whole_scratch(3), d, p);
    take(whole_[2], a_out);
    take(whole_[3], b_out);
    return;
  }
  for_bands(a.interior(), [&](Box2 rows, int) {
    tensor_field_rd_rows(d, a.view(), b.view(), a_out.view(), b_out.view(), a.size(), rows.min.y,
                         rows.max.y, p);
  });
}

void CpuDevice::periodic_solve(PeriodicStencilSolve& solve_a, FieldF& a,
                               PeriodicStencilSolve& solve_b, FieldF& b) {
  require(DeviceOp::kPeriodicSolve);
  if (!gathers(a)) return PeriodicStencilSolve::solve_pair(solve_a, a, solve_b, b);
  PeriodicStencilSolve::solve_pair(solve_a, gather(a, 0), solve_b, gather(b, 1));
  take(whole_[0], a);
  take(whole_[1], b);
}

SolveReport CpuDevice::tensor_field_solve(TensorFieldSolve& solve, FieldF& x, double s) {
  require(DeviceOp::kTensorFieldSolve);
  if (!gathers(x)) return solve.solve(x, s);
  const SolveReport report = solve.solve(gather(x, 0), s);
  take(whole_[0], x);
  return report;
}

}  // namespace ardcell
