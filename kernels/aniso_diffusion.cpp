#include "kernels/aniso_diffusion.h"

#include <cmath>
#include <utility>

#include "kernels/stencil_sweeps.h"
#include "runtime/block_layout.h"

namespace ardcell {

ImplicitDiffusion::ImplicitDiffusion(Int2 size, BoundaryKind boundary, const SolverSettings& solver,
                                     RowExecutor& ex)
    : size_(size),
      ex_(&ex),
      boundary_(boundary),
      op_(assemble_stencil_operator(size, 1.0, 0.0, nullptr, boundary, boundary)),
      settings_(solver),
      solver_(LinearSolver::make(solver, size, ex)),
      rhs_(size, 1),
      x_(size, 1),
      tmp_(size, 1) {}

ImplicitDiffusion::ImplicitDiffusion(Int2 grid, Box2 cells, BoundaryKind boundary,
                                     const SolverSettings& solver, RowExecutor& ex)
    : size_(grid),
      ex_(&ex),
      boundary_(boundary),
      op_(assemble_block_operator(grid, cells, boundary, boundary)),
      settings_(solver),
      rhs_(FieldF::over(cells, 1)),
      x_(FieldF::over(cells, 1)),
      tmp_(FieldF::over(cells, 1)) {
  ARDCELL_CHECK(runs_on_block(solver, grid, boundary) && cells != box_of_size(grid),
                "ImplicitDiffusion: a solver whose sweeps run on a block, and a block");
  ex.reserve_rows(cells.height());
}

ImplicitDiffusion::~ImplicitDiffusion() = default;

void ImplicitDiffusion::copy_rows(const FieldF& from, FieldF& to) const {
  const Box2 cells = op_.diag.interior();
  ex_->for_rows(cells.height(), cells.width(), [&](int y0, int y1) {
    copy_box<float>(from.view(), to.view(),
                    Box2{{cells.min.x, cells.min.y + y0}, {cells.max.x, cells.min.y + y1}});
  });
}

void ImplicitDiffusion::make_rhs(FieldF& field, const FieldF* conductivity, const DiffusionStep& s,
                                 HaloChannel* halo) {
  const Box2 cells = op_.diag.interior();
  if (s.crank_nicolson) {
    // (1 + s/2 L) A = 2 A - (1 - s/2 L) A.
    if (halo) halo->exchange(field, 1);  // L reads the neighbouring blocks' cells
    apply_stencil_operator(op_, field, tmp_);
    ex_->for_rows(cells.height(), cells.width(), [&](int y0, int y1) {
      for (int y = cells.min.y + y0; y < cells.min.y + y1; ++y) {
        const float* f = field.row(y);
        const float* t = tmp_.row(y);
        float* r = rhs_.row(y);
        for (int x = cells.min.x; x < cells.max.x; ++x) r[x] = 2.0f * f[x] - t[x];
      }
    });
  } else {
    copy_rows(field, rhs_);
  }
  if (boundary_ == BoundaryKind::kDirichlet && s.boundary_value != 0.0f) {
    // The fixed ghost's flux s k g moves to the right-hand side (both halves of CN included),
    // on the cells of the domain's edges (a corner's two sides in the order left, right,
    // bottom, top).
    const double g = s.boundary_value * s.rate_dt_over_h2;
    auto add = [&](int x, int y) {
      if (!cells.contains(Int2{x, y})) return;
      if (solid_ && (*solid_)(x, y)) return;
      rhs_(x, y) += float(g * (conductivity ? double((*conductivity)(x, y)) : 1.0));
    };
    for (int y = cells.min.y; y < cells.max.y; ++y) {
      add(0, y);
      add(size_.x - 1, y);
    }
    for (int x = cells.min.x; x < cells.max.x; ++x) {
      add(x, 0);
      add(x, size_.y - 1);
    }
  }
}

SolveReport ImplicitDiffusion::step(FieldF& field, const FieldF* conductivity,
                                    const DiffusionStep& s, HaloChannel* halo) {
  ARDCELL_CHECK(field.interior() == op_.diag.interior(),
                "diffusion: field covers other cells than the solver's");
  ARDCELL_CHECK(on_block() == (halo != nullptr) && !(on_block() && solid_),
                "diffusion: a block's step takes its channel (and no solid cells)");
  const double scale = s.crank_nicolson ? 0.5 * s.rate_dt_over_h2 : s.rate_dt_over_h2;
  const bool isotropic = conductivity == nullptr;
  if (!isotropic || !last_isotropic_ || scale != last_scale_ || solid_) {
    reassemble_stencil_operator(op_, 1.0, scale, conductivity, *ex_);
    if (solid_) isolate_solid_cells(op_, *solid_, 0.0);
    if (solver_) solver_->prepare(op_);
    last_scale_ = scale;
    last_isotropic_ = isotropic;
  }
  make_rhs(field, conductivity, s, halo);
  copy_rows(field, x_);
  const SolveReport report = halo ? sweep_block(*halo) : solver_->solve(op_, rhs_, x_);
  copy_rows(x_, field);
  return report;
}

SolveReport ImplicitDiffusion::sweep_block(HaloChannel& halo) {
  // The whole grid's Jacobi or RBGS solve (kernels/jacobi_solver.cpp, rbgs_solver.cpp) sweep by
  // sweep: the operator has the identity in it, so no null space to take out.
  SolveReport report;
  const double rhs_norm2 = stencil::norm2_squared(rhs_, *ex_);  // the block's; b is fixed
  const auto relative_residual = [&](const FieldF& x) {
    double norms[2] = {stencil::residual(op_, rhs_, x, nullptr, *ex_), rhs_norm2};
    halo.sum(norms);
    return norms[1] > 0.0 ? std::sqrt(norms[0] / norms[1]) : std::sqrt(norms[0]);
  };
  // Each sweep's input goes out to the neighbours while the sweep computes the block's inner
  // cells, which read none of its halo; the ring along the block's edges waits for the exchange.
  // (A tolerance reads the residual, halo included, after every sweep: no overlap then.)
  const Box2 cells = op_.diag.interior(), inner = cells.grown(-1);
  const bool overlap = !inner.empty() && settings_.tolerance <= 0.0;
  const Box2 ring[] = {{cells.min, {cells.max.x, cells.min.y + 1}},
                       {{cells.min.x, cells.max.y - 1}, cells.max},
                       {{cells.min.x, cells.min.y + 1}, {cells.min.x + 1, cells.max.y - 1}},
                       {{cells.max.x - 1, cells.min.y + 1}, {cells.max.x, cells.max.y - 1}}};
  HaloField in_flight{};
  bool pending = false;
  const auto begin = [&](FieldF& f) {
    in_flight = {&f, 1};
    halo.begin({&in_flight, 1});
    pending = true;
  };
  const auto finish = [&] {
    if (pending) halo.finish();
    pending = false;
  };
  // compute(region) over every cell, the inner ones first when they may overlap the exchange.
  const auto sweep = [&](const auto& compute) {
    if (!overlap) {
      finish();
      compute(Box2{});
      return;
    }
    compute(inner);
    finish();
    for (const Box2& r : ring) compute(r);
  };
  const bool rbgs = settings_.kind == SolverKind::kRedBlackGaussSeidel;
  FieldF* from = &x_;
  FieldF* to = &tmp_;
  begin(*from);
  for (int k = 0; k < settings_.max_iterations; ++k) {
    if (rbgs) {
      for (int color : {0, 1}) {
        sweep([&](Box2 r) { stencil::rbgs_half_sweep(op_, rhs_, *from, color, *ex_, r); });
        begin(*from);
      }
    } else {
      sweep([&](Box2 r) { stencil::jacobi_sweep(op_, rhs_, *from, *to, *ex_, nullptr, r); });
      begin(*to);
      std::swap(from, to);
    }
    ++report.iterations;
    if (settings_.tolerance > 0.0) {
      finish();
      if (relative_residual(*from) <= settings_.tolerance) break;
    }
  }
  finish();
  report.relative_residual = relative_residual(*from);  // reads its halo, exchanged
  if (from != &x_) copy_rows(*from, x_);
  return report;
}

}  // namespace ardcell
