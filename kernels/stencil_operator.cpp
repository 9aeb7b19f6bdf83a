#include "kernels/stencil_operator.h"

#include <algorithm>
#include <cmath>

#include "kernels/stencil_sweeps.h"

namespace ardcell {

namespace {

inline double conductivity_at(const FieldF* k, int x, int y) {
  return k ? double((*k)(x, y)) : 1.0;
}

void fill_coefficients(StencilOperator& op, double identity, double scale, const FieldF* k,
                       RowExecutor& ex) {
  const int nx = op.size.x, ny = op.size.y;
  // The operator's cells: the whole grid, or a block whose neighbours' conductivity is k's halo.
  const Box2 c = op.diag.interior();
  const bool block = c != box_of_size(op.size);
  if (k) {
    ARDCELL_CHECK(k->interior() == c && (!block || k->halo() >= 1),
                  "conductivity must cover the operator's cells (a block's with a halo)");
  }
  op.identity = identity;
  // The conductivity across the periodic edge of a row (x = -1 or nx) or column (y = -1 or ny):
  // on the whole grid the cell on the other side, on a block k's halo, exchanged.
  const auto kx = [&](int x, int y) {
    return conductivity_at(k, block ? x : (x < 0 ? nx - 1 : (x >= nx ? 0 : x)), y);
  };
  const auto ky = [&](int x, int y) {
    return conductivity_at(k, x, block ? y : (y < 0 ? ny - 1 : (y >= ny ? 0 : y)));
  };
  // Faces in x: wx(i, j) between cells (i-1, j) and (i, j); the domain's edge faces (i = 0 and
  // i = nx) apart, so that the loop over the others has no branch.
  const int inner_x0 = std::max(c.min.x, 1), inner_x1 = std::min(c.max.x, nx - 1);
  ex.for_rows(c.height(), c.width(), [&](int y0, int y1) {
    for (int j = c.min.y + y0; j < c.min.y + y1; ++j) {
      float* w = op.wx.row(j);
      for (int i = inner_x0; i <= inner_x1; ++i)
        w[i] = float(scale * 0.5 * (conductivity_at(k, i - 1, j) + conductivity_at(k, i, j)));
      for (int i : {0, nx}) {
        if (i < c.min.x || i > c.max.x) continue;
        w[i] = op.boundary_x == BoundaryKind::kPeriodic
                   ? float(scale * 0.5 * (kx(i - 1, j) + kx(i, j)))
                   : 0.0f;
      }
    }
  });
  ex.for_rows(c.height() + 1, c.width(), [&](int y0, int y1) {
    for (int j = c.min.y + y0; j < c.min.y + y1; ++j) {
      float* w = op.wy.row(j);
      if (j > 0 && j < ny) {
        for (int i = c.min.x; i < c.max.x; ++i)
          w[i] = float(scale * 0.5 * (conductivity_at(k, i, j - 1) + conductivity_at(k, i, j)));
      } else if (op.boundary_y == BoundaryKind::kPeriodic) {
        for (int i = c.min.x; i < c.max.x; ++i)
          w[i] = float(scale * 0.5 * (ky(i, j - 1) + ky(i, j)));
      } else {
        for (int i = c.min.x; i < c.max.x; ++i) w[i] = 0.0f;
      }
    }
  });
  ex.for_rows(c.height(), c.width(), [&](int y0, int y1) {
    for (int j = c.min.y + y0; j < c.min.y + y1; ++j) {
      float* d = op.diag.row(j);
      const float* wx = op.wx.row(j);
      const float* wyb = op.wy.row(j);
      const float* wya = op.wy.row(j + 1);
      for (int i = c.min.x; i < c.max.x; ++i) {
        double sum = identity + double(wx[i]) + double(wx[i + 1]) + double(wyb[i]) + double(wya[i]);
        // Dirichlet: the ghost is fixed, so the boundary face keeps its weight on the diagonal
        // but couples to nothing (its value goes into b).
        if (op.boundary_x == BoundaryKind::kDirichlet) {
          if (i == 0) sum += scale * conductivity_at(k, i, j);
          if (i == nx - 1) sum += scale * conductivity_at(k, i, j);
        }
        if (op.boundary_y == BoundaryKind::kDirichlet) {
          if (j == 0) sum += scale * conductivity_at(k, i, j);
          if (j == ny - 1) sum += scale * conductivity_at(k, i, j);
        }
        d[i] = float(sum);
      }
    }
  });
}

}  // namespace

StencilOperator assemble_stencil_operator(Int2 size, double identity, double scale,
                                          const FieldF* conductivity, BoundaryKind boundary_x,
                                          BoundaryKind boundary_y) {
  ARDCELL_CHECK(size.x > 0 && size.y > 0, "operator size must be positive");
  StencilOperator op{size,
                     FieldF(size, 1),
                     FieldF(Int2{size.x + 1, size.y}, 1),
                     FieldF(Int2{size.x, size.y + 1}, 1),
                     boundary_x,
                     boundary_y};
  fill_coefficients(op, identity, scale, conductivity, RowExecutor::serial());
  return op;
}

StencilOperator assemble_block_operator(Int2 grid, Box2 cells, BoundaryKind boundary_x,
                                        BoundaryKind boundary_y) {
  ARDCELL_CHECK(grid.x > 0 && grid.y > 0 && box_of_size(grid).contains(cells) && !cells.empty(),
                "a block operator's cells lie inside its grid");
  StencilOperator op{grid,
                     FieldF::over(cells, 1),
                     FieldF::over(Box2{cells.min, {cells.max.x + 1, cells.max.y}}, 1),
                     FieldF::over(Box2{cells.min, {cells.max.x, cells.max.y + 1}}, 1),
                     boundary_x,
                     boundary_y};
  fill_coefficients(op, 1.0, 0.0, nullptr, RowExecutor::serial());
  return op;
}

void reassemble_stencil_operator(StencilOperator& op, double identity, double scale,
                                 const FieldF* conductivity, RowExecutor& ex) {
  fill_coefficients(op, identity, scale, conductivity, ex);
}

void apply_stencil_operator(const StencilOperator& op, const FieldF& x, FieldF& y) {
  const Box2 c = op.diag.interior();
  ARDCELL_CHECK(x.interior() == c && y.interior() == c, "apply: size mismatch");
  const int nx = op.size.x, ny = op.size.y;
  const bool px = op.boundary_x == BoundaryKind::kPeriodic;
  const bool py = op.boundary_y == BoundaryKind::kPeriodic;
  const EdgeWraps wrap = edge_wraps(op);
  for (int j = c.min.y; j < c.max.y; ++j) {
    const float* xb = x.row(j > 0 ? j - 1 : (py ? wrap.below : j));
    const float* xa = x.row(j < ny - 1 ? j + 1 : (py ? wrap.above : j));
    const float* x0 = x.row(j);
    const float* d = op.diag.row(j);
    const float* wx = op.wx.row(j);
    const float* wyb = op.wy.row(j);
    const float* wya = op.wy.row(j + 1);
    float* out = y.row(j);
    auto cell = [&](int i, int il, int ir) {
      return d[i] * x0[i] - (wx[i] * x0[il] + wx[i + 1] * x0[ir] + wyb[i] * xb[i] + wya[i] * xa[i]);
    };
    const int last = nx - 1;
    const bool first = c.min.x == 0;
    const float first_value =
        first ? cell(0, px ? wrap.left : 0, nx > 1 ? 1 : (px ? wrap.right : 0)) : 0.0f;
    for (int i = std::max(c.min.x, 1); i < std::min(c.max.x, last); ++i)
      out[i] = d[i] * x0[i] -
               (wx[i] * x0[i - 1] + wx[i + 1] * x0[i + 1] + wyb[i] * xb[i] + wya[i] * xa[i]);
    if (last > 0 && c.max.x == nx) out[last] = cell(last, last - 1, px ? wrap.right : last);
    if (first) out[0] = first_value;
  }
}

void add_boundary_diagonal(StencilOperator& op, BoundarySide side, double weight) {
  const int nx = op.size.x, ny = op.size.y;
  const float w = float(weight);
  switch (side) {
    case BoundarySide::kLeft:
      for (int j = 0; j < ny; ++j) op.diag(0, j) += w;
      break;
    case BoundarySide::kRight:
      for (int j = 0; j < ny; ++j) op.diag(nx - 1, j) += w;
      break;
    case BoundarySide::kBottom:
      for (int i = 0; i < nx; ++i) op.diag(i, 0) += w;
      break;
    case BoundarySide::kTop:
      for (int i = 0; i < nx; ++i) op.diag(i, ny - 1) += w;
      break;
  }
}

namespace {}  // namespace

// b += the boundary values' share (factor * scale * value) on the boundary cells.
double boundary_rule_factor(const EdgeFill& e) {
  switch (e.rule) {
    case EdgeRule::kFixed:
      return 1.0;
    case EdgeRule::kMirror:
    case EdgeRule::kParabolic:
      return 2.0;
    default:
      return 0.0;
  }
}

void add_boundary_values(View<float> b, Int2 size, const BoundaryFill& fill, double scale) {
  const int nx = size.x, ny = size.y;
  auto add = [&](const EdgeFill& e, int x0, int y0, int dx, int dy, int count) {
    const float amount = float(boundary_rule_factor(e) * scale * e.value);
    if (amount == 0.0f) return;
    if (e.rule == EdgeRule::kParabolic) {
      for (int k = 0; k < count; ++k)
        b(x0 + k * dx, y0 + k * dy) += amount * parabolic_profile(k, count);
      return;
    }
    for (int k = 0; k < count; ++k) b(x0 + k * dx, y0 + k * dy) += amount;
  };
  add(fill.left, 0, 0, 0, 1, ny);
  add(fill.right, nx - 1, 0, 0, 1, ny);
  add(fill.bottom, 0, 0, 1, 0, nx);
  add(fill.top, 0, ny - 1, 1, 0, nx);
}

void isolate_solid_cells(StencilOperator& op, const Field<uint8_t>& solid, double wall_factor) {
  ARDCELL_CHECK(solid.size() == op.size, "solid mask must have the operator's size");
  const int nx = op.size.x, ny = op.size.y;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      if (!solid(i, j)) continue;
      // Cut every face of the solid cell; the fluid neighbour keeps `wall_factor` on its diagonal
      // in place of the face weight (0: Neumann wall, 2w: no-slip mirror), and the solid cell's
      // row becomes the identity.
      auto cut = [&](float& face, int fx, int fy) {
        const bool inside = fx >= 0 && fx < nx && fy >= 0 && fy < ny;
        if (inside && !solid(fx, fy)) op.diag(fx, fy) += float(wall_factor * face) - face;
        face = 0.0f;
      };
      cut(op.wx(i, j), i - 1, j);
      cut(op.wx(i + 1, j), i + 1, j);
      cut(op.wy(i, j), i, j - 1);
      cut(op.wy(i, j + 1), i, j + 1);
      op.diag(i, j) = 1.0f;
    }
}

void weigh_faces(StencilOperator& op, const FieldF& open_x, const FieldF& open_y) {
  const int nx = op.size.x, ny = op.size.y;
  ARDCELL_CHECK(open_x.size() == op.wx.size() && open_y.size() == op.wy.size(),
                "weigh_faces: open fractions must have the face fields' sizes");
  ARDCELL_CHECK(
      op.boundary_x != BoundaryKind::kDirichlet && op.boundary_y != BoundaryKind::kDirichlet,
      "weigh_faces: Dirichlet axes keep boundary weights the faces do not hold");
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i <= nx; ++i) op.wx(i, j) *= open_x(i, j);
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i < nx; ++i) op.wy(i, j) *= open_y(i, j);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i)
      op.diag(i, j) = float(op.identity + double(op.wx(i, j)) + double(op.wx(i + 1, j)) +
                            double(op.wy(i, j)) + double(op.wy(i, j + 1)));
}

}  // namespace ardcell
