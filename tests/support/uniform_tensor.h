#pragma once
// A uniform rank-2 tensor (xx, xy, yy in cells^2) as the face field of seed 003's tensor-field
// kernels: with it the flux form is Eqn 29's 9-point stencil.
#include "kernels/generalized_rd.h"

namespace ardcell {

inline Rank2FaceField uniform_tensor_faces(Int2 size, float xx, float xy, float yy) {
  FieldF fxx(size, 0), fxy(size, 0), fyy(size, 0);
  fxx.fill(xx);
  fxy.fill(xy);
  fyy.fill(yy);
  return rank2_faces(fxx, fxy, fyy);
}

}  // namespace ardcell
