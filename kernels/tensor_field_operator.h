#pragma once
// seed 003's Table 1, last row at rank 2: L u = div(D(x) grad u) in flux form, at one cell
// (kernels/generalized_rd.h gives the discretisation and the face field Rank2FaceField):
//   L u (x, y) = F(x + 1/2, y) - F(x - 1/2, y) + G(x, y + 1/2) - G(x, y - 1/2)
// For the explicit step (tensor_field_rd_rows, in float) and the semi-implicit solve
// (kernels/tensor_field_solve.h, in double): one expression for both. Reads the 3 x 3
// neighbourhood through wrapped indices the caller gives (periodic; no halo read). Each face
// flux is written once (face_x, face_y), so both its cells get its bits and the sum over a
// periodic grid telescopes.
#include <type_traits>

#include "kernels/generalized_rd.h"

namespace ardcell {

// Grid: u(x, y) returns the value at a cell (View<const float>, or a flat double grid). The
// arithmetic is in its value type; the float tensor converts to it.
template <class Grid>
struct TensorFieldOperator {
  using T = std::remove_cvref_t<decltype(std::declval<const Grid&>()(0, 0))>;
  const Rank2FaceField& d;
  Grid u;

  // F between (x, y) and (xp, y); rows ym, yp around y.
  T face_x(int x, int xp, int y, int ym, int yp) const {
    const T gx = u(xp, y) - u(x, y);
    const T gy = T(0.25) * ((u(x, yp) + u(xp, yp)) - (u(x, ym) + u(xp, ym)));
    return T(d.x_xx(x, y)) * gx + T(d.x_xy(x, y)) * gy;
  }
  // G between (x, y) and (x, yp); columns xm, xp around x.
  T face_y(int x, int xm, int xp, int y, int yp) const {
    const T gy = u(x, yp) - u(x, y);
    const T gx = T(0.25) * ((u(xp, y) + u(xp, yp)) - (u(xm, y) + u(xm, yp)));
    return T(d.y_yy(x, y)) * gy + T(d.y_xy(x, y)) * gx;
  }
  // At (x, y) with its wrapped neighbours xm, xp and ym, yp (the caller's: a row's ym, yp once,
  // a cell's xm, xp without a division).
  T operator()(int x, int xm, int xp, int y, int ym, int yp) const {
    const T fe = face_x(x, xp, y, ym, yp), fw = face_x(xm, x, y, ym, yp);
    const T gn = face_y(x, xm, xp, y, yp), gs = face_y(x, xm, xp, ym, y);
    return (fe - fw) + (gn - gs);
  }
  // The coefficient of u(x, y) in L u (x, y) is minus this: the four faces' normal terms.
  T diagonal(int x, int xm, int y, int ym) const {
    return (T(d.x_xx(x, y)) + T(d.x_xx(xm, y))) + (T(d.y_yy(x, y)) + T(d.y_yy(x, ym)));
  }
};

}  // namespace ardcell
