#pragma once
// Forward Euler reaction-diffusion, the explicit schemes the implicit one is compared against.
//
// Eqn 5 (seed 000), 5-point Laplacian. Reads halo 1:
//   A' = A + dt R_A(A, B) + (DA dt / h^2) (A_W + A_E + A_S + A_N - 4 A)
// Seed 001's 9-point Laplacian (corners 0.05, edges 0.2, centre -1; it approximates
// 0.3 h^2 lap, and seed 001 uses it unscaled with dt = 1, h = 1). Reads halo 1:
//   A' = A + dt R_A(A, B) + (DA dt / h^2) L9(A)
// Stable only for 2 DA dt / h^2 < 1 (5-point); the stability test shows the blow-up.
#include <cstdint>

#include "kernels/reaction.h"
#include "runtime/field.h"

namespace ardcell {

struct ExplicitRdParams {
  ReactionParams reaction;
  float dt = 1.0f;
  float diffusion_a = 1.0f;  // DA dt / h^2 multiplies the Laplacian stencil
  float diffusion_b = 0.5f;  // DB dt / h^2
};

// a, b must cover region grown by 1. Outputs must not alias inputs.
void explicit_rd5_tile(View<const float> a, View<const float> b, View<float> a_out,
                       View<float> b_out, Box2 region, const ExplicitRdParams& p);
void explicit_rd9_tile(View<const float> a, View<const float> b, View<float> a_out,
                       View<float> b_out, Box2 region, const ExplicitRdParams& p);

// Seed 001's Gray-Scott step, 9-point Laplacian, specialised for speed: rows are processed as
// a separable (1 4 1) x (1 4 1) sum, L9 = 0.05 * S - 1.8 * c (seed 001's own rewrite), in
// float, in contiguous row buffers the compiler vectorises. Reads halo 1. With the constants
// folded (GrayScott9Coeffs), each multiply-add fused as written:
//   v = fma(4, f(x, y), f(x, y - 1) + f(x, y + 1)),  S = fma(4, v(x), v(x - 1) + v(x + 1))
//   A' = fma(-A, dt B^2, fma(ca, S_A, fma(pa, A, q))),  B' = fma(A, dt B^2, fma(cb, S_B, pb B))
// - the expressions of the temporally blocked kernel (kernels/gray_scott9.h) and of the OpenCL
// twin, so that every schedule, block layout and back end steps seed 001 to the same bits.
struct GrayScott9Params {
  float F = 0.055f, k = 0.062f;
  float dt = 1.0f;
  float diffusion_a = 1.0f;  // DA dt / h^2
  float diffusion_b = 0.5f;  // DB dt / h^2
};
//   ca = 0.05 DA, pa = 1 - 1.8 DA - dt F, q = dt F; cb = 0.05 DB, pb = 1 - 1.8 DB - dt (F + k)
// (in float, unfused: this file is compiled with -ffp-contract=off).
struct GrayScott9Coeffs {
  float ca = 0, cb = 0, pa = 0, pb = 0, q = 0, dt = 0;
};
GrayScott9Coeffs gray_scott9_coeffs(const GrayScott9Params& p);
// scratch: at least 2 * (region.width() + 2) floats (row sums), 64-byte aligned preferred.
void gray_scott9_explicit_tile(View<const float> a, View<const float> b, View<float> a_out,
                               View<float> b_out, Box2 region, const GrayScott9Params& p,
                               float* scratch);

// Seed 001's quiescent cells on the per-step schedule, skipped as GrayScott9Blocked skips them: a
// uniform state that the float update maps to itself exactly (seed 001's background settles on
// A = 1.00000036, B = 0 after 2 steps) stays so wherever its whole 3x3 neighbourhood has it, so a
// step that computes only the cells within one cell of those that differ from it, and leaves the
// rest as they are, gives the same bits. Over a run of steps that ping-pong between two pairs of
// fields - the state (a, b) and the pair a step writes (a_out, b_out), which then become the state
// - a QuiescentBox keeps a box of the cells of each pair that may differ from the fixed point:
// the state's from the cells the last step wrote (differing()), the other pair's from the state
// before. The ring around the cells (what the boundary fill, the halo exchange or the step
// before wrote there) is scanned every step. One box: a wall whose value is not the fixed point
// (Dirichlet A = 1) puts every cell in it, so the gain is on periodic grids and blocks (and
// Neumann walls). Who steps (host/engine/device.h explicit_rd) asks region() before a step and
// reports stepped() after it; who writes the fields otherwise calls restart(), and who exchanges
// or fills the state's halo calls halo_exchanged().
// A block that steps halo cells too (explicit_rd's grow: the steps a deep exchange serves) steps
// the rows of its halo above and below whole, and of the halo columns left and right of it only
// the rows that can change: per side and per column d (1 next to the interior), the rows of each
// pair that may differ, scanned in the state after an exchange (halo_exchanged()) and kept as
// steps write it.
class QuiescentBox {
 public:
  // Halo columns a step may step on either side (explicit_rd's grow), at most.
  static constexpr int kMaxGrow = 15;

  QuiescentBox() { restart(); }

  // The fields were written other than by the steps (a new state, painting, advection): the
  // next step computes every cell and finds both boxes again.
  void restart();
  // Whether steps of p can skip: p's update maps a uniform state reached from (1, 0) to itself.
  // Finds that state again when p changed (then restart()s); allocates nothing.
  bool skips(const GrayScott9Params& p);
  // The cells of `cells` the next step from (a, b) must compute, the others keeping what the
  // pair it writes holds: all of them after restart(). Reads (a, b)'s ring around `cells`.
  Box2 region(View<const float> a, View<const float> b, Box2 cells) const;
  // The box of `rows` where a or b differs from the fixed point (empty when none does): the step's
  // output over the rows it wrote, and, on the step after restart(), its input over every cell.
  Box2 differing(View<const float> a, View<const float> b, Box2 rows) const;
  // The state's halo was just exchanged (or filled), as deep as the steps it serves: the next
  // begin_sides() scans it.
  void halo_exchanged() { exchanged_ = true; }
  // Before a step that steps `grow` (>= 0) halo columns on either side of the interior `inner`:
  // after halo_exchanged(), the rows of the state's columns 1 .. grow + 1, which the exchange
  // wrote, that differ.
  void begin_sides(View<const float> a, View<const float> b, Box2 inner, int grow);
  // The rows [x, y) of `inner` the step must step in the `grow` halo columns of side 0 (left) or
  // 1 (right), the others' output already holding their new value; then side_stepped() with the
  // rows of its output there that differ from the fixed point (none: y <= x).
  // Reads the state's halo rows just above and below the interior next to the columns.
  Int2 side_rows(View<const float> a, View<const float> b, int side, Box2 inner, int grow) const;
  void side_stepped(int side, Int2 written) { side_written_[side] = written; }
  // The step wrote `region`, in which its output differs from the fixed point within `written`;
  // `input` is differing() of its input over every cell when that step followed restart(); it
  // stepped `grow` halo columns on either side (side_stepped() for both sides when grow > 0).
  void stepped(Box2 written, Box2 input, int grow);
  bool known() const { return known_; }
  // The fixed point (valid while skips()).
  float fixed_a() const;
  float fixed_b() const;

 private:
  // The rows [x, y) of side s's column d of the state that may differ (column 0 from state_).
  Int2 column_rows(int side, int d, Box2 inner) const;

  bool known_ = false;
  Box2 state_{}, other_{};  // the cells of the state and of the other pair that may differ
  // Per side and halo column d (index d; 0 unused), the rows of each pair that may differ.
  Int2 side_state_[2][kMaxGrow + 2], side_other_[2][kMaxGrow + 2];
  Int2 side_written_[2] = {};
  bool exchanged_ = false;  // halo_exchanged() since the last begin_sides()
  GrayScott9Params params_{};
  bool found_ = false;  // params_ is the p the fixed point was sought for
  bool skips_ = false;
  uint32_t fixed_a_ = 0, fixed_b_ = 0;  // its bits
};

}  // namespace ardcell
