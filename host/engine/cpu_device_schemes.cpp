// CpuDevice's ops of the second-order reaction-diffusion schemes (host/engine/device.h): the
// per-cell kernels in bands of rows, each band writing its own rows only (same bits on any
// number of workers); the ETDRK4 step runs its own row and column passes on the executor.
#include "host/engine/device.h"
#include "kernels/periodic_etdrk4.h"
#include "runtime/row_executor.h"

namespace ardcell {

void CpuDevice::reaction_trapezoidal(FieldF& a, FieldF& b, const ReactionParams& p, float dt) {
  require(DeviceOp::kReactionTrapezoidal);
  for_bands(a.interior(), [&](Box2 rows) {
    reaction_trapezoidal_tile(a.view(), b.view(), a.view(), b.view(), rows, p, dt);
  });
}

void CpuDevice::sbdf_rhs(FieldF& a, FieldF& b, FieldF& a_prev, FieldF& b_prev,
                         const SbdfRhsParams& p) {
  require(DeviceOp::kSbdfRhs);
  for_bands(a.interior(), [&](Box2 rows) {
    sbdf_rhs_tile(a.view(), b.view(), a_prev.view(), b_prev.view(), rows, p);
  });
}

void CpuDevice::etdrk4_step(PeriodicEtdrk4& etdrk4, FieldF& a, FieldF& b,
                            const ReactionParams* reaction) {
  require(DeviceOp::kEtdrk4);
  if (!gathers(a)) return etdrk4.step(a, b, reaction);
  etdrk4.step(gather(a, 0), gather(b, 1), reaction);
  take(whole_[0], a);
  take(whole_[1], b);
}

}  // namespace ardcell
