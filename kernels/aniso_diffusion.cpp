#include "kernels/aniso_diffusion.h"

namespace ardcell {

ImplicitDiffusion::ImplicitDiffusion(Int2 size, BoundaryKind boundary, const SolverSettings& solver,
                                     RowExecutor& ex)
    : size_(size),
      ex_(&ex),
      boundary_(boundary),
      op_(assemble_stencil_operator(size, 1.0, 0.0, nullptr, boundary, boundary)),
      solver_(LinearSolver::make(solver, size, ex)),
      rhs_(size, 1),
      x_(size, 1),
      tmp_(size, 1) {}

ImplicitDiffusion::~ImplicitDiffusion() = default;

void ImplicitDiffusion::copy_rows(const FieldF& from, FieldF& to) const {
  ex_->for_rows(size_.y, size_.x, [&](int y0, int y1) {
    copy_box<float>(from.view(), to.view(), Box2{{0, y0}, {size_.x, y1}});
  });
}

SolveReport ImplicitDiffusion::step(FieldF& field, const FieldF* conductivity,
                                    const DiffusionStep& s) {
  ARDCELL_CHECK(field.size() == size_, "diffusion: field size differs from the solver's");
  const double scale = s.crank_nicolson ? 0.5 * s.rate_dt_over_h2 : s.rate_dt_over_h2;
  const bool isotropic = conductivity == nullptr;
  if (!isotropic || !last_isotropic_ || scale != last_scale_ || solid_) {
    reassemble_stencil_operator(op_, 1.0, scale, conductivity, *ex_);
    if (solid_) isolate_solid_cells(op_, *solid_, 0.0);
    solver_->prepare(op_);
    last_scale_ = scale;
    last_isotropic_ = isotropic;
  }
  if (s.crank_nicolson) {
    // (1 + s/2 L) A = 2 A - (1 - s/2 L) A.
    apply_stencil_operator(op_, field, tmp_);
    ex_->for_rows(size_.y, size_.x, [&](int y0, int y1) {
      for (int y = y0; y < y1; ++y) {
        const float* f = field.row(y);
        const float* t = tmp_.row(y);
        float* r = rhs_.row(y);
        for (int x = 0; x < size_.x; ++x) r[x] = 2.0f * f[x] - t[x];
      }
    });
  } else {
    copy_rows(field, rhs_);
  }
  if (boundary_ == BoundaryKind::kDirichlet && s.boundary_value != 0.0f) {
    // The fixed ghost's flux s k g moves to the right-hand side (both halves of CN included).
    const double g = s.boundary_value * s.rate_dt_over_h2;
    auto add = [&](int x, int y) {
      if (solid_ && (*solid_)(x, y)) return;
      rhs_(x, y) += float(g * (conductivity ? double((*conductivity)(x, y)) : 1.0));
    };
    for (int y = 0; y < size_.y; ++y) {
      add(0, y);
      add(size_.x - 1, y);
    }
    for (int x = 0; x < size_.x; ++x) {
      add(x, 0);
      add(x, size_.y - 1);
    }
  }
  copy_rows(field, x_);
  const SolveReport report = solver_->solve(op_, rhs_, x_);
  copy_rows(x_, field);
  return report;
}

}  // namespace ardcell
