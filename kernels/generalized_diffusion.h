#pragma once
// Homogeneous generalized (non-Gaussian) diffusion, seed 003 (McGraw), as ONE 5x5 stencil:
//   seed 003, Eqn 19: du/dt = D_ij d_ij u + D_ijk d_ijk u + D_ijkl d_ijkl u
//     (Eqn 12, the Kramers-Moyal expansion, homogeneous and truncated at rank 4; d_ij... the
//     partial derivatives of Eqn 13; each sum a full contraction, Eqn 17)
//   seed 003, Eqn 20 and Eqn 21: the 12 terms (Eqn 20 the rank-2 ones, Eqn 21 the ranks 3 and
//     4), each unique component of a symmetric tensor (Eqn 14, Eqn 15) times its multiplicity
//     mu = l! / (nx! ny!) (Eqn 16; the contraction over unique components of Eqn 18) times the
//     derivative d^l / dx^nx dy^ny:
//       D_xx u_xx + 2 D_xy u_xy + D_yy u_yy
//     + D_xxx u_xxx + 3 D_xxy u_xxy + 3 D_xyy u_xyy + D_yyy u_yyy
//     + D_xxxx u_xxxx + 4 D_xxxy u_xxxy + 6 D_xxyy u_xxyy + 4 D_xyyy u_xyyy + D_yyyy u_yyyy
//   seed 003, Eqn 37: A = sum_l l! sum_{i+j=l} D_ij X^+_ij (the same operator: the derivative
//     kernel is i! j! X^+_ij (Eqn 35) and mu i! j! = l!, so Eqn 37's 2, 6, 24 are Eqn 21's
//     multiplicities with Eqn 35's factorials folded in; nothing to correct there).
// Corrected labels: the printed Eqn 21 and Table 2 write the rank-4 components D_xxxxy,
// D_xxyyy, D_xyyyy, D_yyyyy with five indices; they are D_xxxy, D_xxyy, D_xyyy, D_yyyy
// (Eqn 36, Eqn 37 and the multiplicities 4, 6, 4, 1 of Eqn 21 say so). Eqn 35's first "d_xyyy = 4
// a_22" is d_xxyy (2! 2! = 4). Derivative kernels: Savitzky-Golay (kernels/savitzky_golay.h, degree
// 4 default, 5 option) for the ranks 3 and 4; the second derivatives by central differences (the
// paper's final choice, end of sec. 5.1) or, as an option, Savitzky-Golay too. Note that the
// central difference ones replace i! j! X^+_ij (the derivative), not X^+_ij: put into Eqn 37
// literally (2 D_xx times the [1 -2 1] kernel) they would double the rank-2 part. Special cases:
// Eqn 25 (isotropic, 3x3) and Eqn 29 (anisotropic Gaussian, 3x3) are the rank-2 sequences with
// central differences (tests/kernels/generalized_diffusion_test.cpp).
//   seed 003, Eqn 27: u' = (I + delta A) u  (explicit update), stable when its spectral radius,
//     max over wavenumbers k of |1 + delta symbol(k)|, is <= 1.
// apply reads halo 2 (a 5x5 stencil); fill_periodic_halo wraps a field's halo for a periodic
// (tileable) domain.
#include <complex>
#include <string_view>

#include "kernels/savitzky_golay.h"
#include "runtime/field.h"

namespace ardcell {

// The unique components of symmetric 2D tensors of rank 2, 3 and 4 (Eqn 15): D_xxy is the
// component with two x indices and one y index, in any order.
struct TensorSequence {
  double xx = 0, xy = 0, yy = 0;
  double xxx = 0, xxy = 0, xyy = 0, yyy = 0;
  double xxxx = 0, xxxy = 0, xxyy = 0, xyyy = 0, yyyy = 0;

  // The component with nx x indices and ny y indices (rank nx + ny in 2..4).
  double component(int nx, int ny) const {
    return const_cast<TensorSequence*>(this)->component(nx, ny);
  }
  double& component(int nx, int ny);
};

// The multiplicity l! / (nx! ny!) of a component (Eqn 16).
double multiplicity(int nx, int ny);

// Table 2 of seed 003, the sequences behind Figs. 1-5 (rank-4 labels corrected, see above).
inline constexpr TensorSequence kTable2A{.xx = 1, .yy = 1};  // isotropic Gaussian
inline constexpr TensorSequence kTable2B{.xx = 1, .yy = 2};  // anisotropic Gaussian
inline constexpr TensorSequence kTable2C{
    .xx = 1, .yy = 1, .xxx = 1, .xxy = -1, .xyy = -1, .yyy = 1};  // rank 3
inline constexpr TensorSequence kTable2D{
    .xx = 1, .yy = 1, .xxxx = 1, .xxyy = -1, .yyyy = 1};  // rank 4, axes
inline constexpr TensorSequence kTable2E{
    .xx = 1, .yy = 1, .xxxx = -1, .xxyy = 1, .yyyy = -1};  // rank 4, diagonals
inline constexpr TensorSequence kTable2F{
    .xx = 1, .yy = 2, .xxxx = -1, .xxyy = 1, .yyyy = -1};  // rank 4, anisotropic base

struct NamedTensorSequence {
  std::string_view name;  // "a" .. "f", as in Table 2 and Fig. 1
  TensorSequence tensors;
};
inline constexpr NamedTensorSequence kTable2[] = {{"a", kTable2A}, {"b", kTable2B},
                                                  {"c", kTable2C}, {"d", kTable2D},
                                                  {"e", kTable2E}, {"f", kTable2F}};

enum class SecondDerivatives {
  kCentralDifference,  // 3x3 central differences (the paper's final choice)
  kSavitzkyGolay,      // Savitzky-Golay of the same degree as the higher ranks
};

struct GeneralizedDiffusionOptions {
  int savitzky_golay_degree = 4;  // 4, or 5 through the minimum-norm pseudo-inverse
  SecondDerivatives second_derivatives = SecondDerivatives::kCentralDifference;
};

// Eqn 21 / Eqn 37 as one 25-point stencil: sum of multiplicity x component x derivative kernel.
Stencil5x5 assemble_generalized_stencil(const TensorSequence& d,
                                        const GeneralizedDiffusionOptions& options = {});

// seed 003, Eqn 25: d times the 5-point Laplacian [0 1 0; 1 -4 1; 0 1 0].
Stencil5x5 isotropic_stencil(double d);
// seed 003, Eqn 29: div(D grad u) = D_xx u_xx + 2 D_xy u_xy + D_yy u_yy, 3x3. The printed
// corners (-D_xy/2 at top-left and bottom-right) are right when the first printed row is
// y = +1; read with Eqn 30's layout (first row y = -2) they would give -2 D_xy u_xy. Here
// the corners are stored by offset: +D_xy/2 at (1, 1) and (-1, -1).
Stencil5x5 gaussian_stencil(double dxx, double dxy, double dyy);

// The Fourier symbol of the stencil: K applied to exp(i (kx x + ky y)) gives
// symbol(kx, ky) exp(i (kx x + ky y)). Complex when the sequence has odd ranks.
std::complex<double> stencil_symbol(const Stencil5x5& k, double kx, double ky);

// rho(I + delta A) of Eqn 27 on a periodic n x n grid: A is circulant, hence normal, so its
// spectral radius is the largest |1 + delta symbol(k)| over k = 2 pi (m_x, m_y) / n. Table 2's
// figures, and why the paper's 1.102 / 1.03 are not reproduced: docs/numerics.md (seed 003).
double explicit_spectral_radius(const Stencil5x5& k, double delta, int n = 256);

// A 5x5 stencil ready to run: its nonzero taps, precomputed once (apply allocates nothing).
class GeneralizedDiffusion {
 public:
  explicit GeneralizedDiffusion(const Stencil5x5& stencil);
  GeneralizedDiffusion(const TensorSequence& d, const GeneralizedDiffusionOptions& options = {})
      : GeneralizedDiffusion(assemble_generalized_stencil(d, options)) {}

  const Stencil5x5& stencil() const { return stencil_; }

  // out = K u over region; u must cover region grown by 2. out must not alias u.
  void apply_tile(View<const float> u, View<float> out, Box2 region) const;
  // Eqn 27 without reaction: out = u + delta K u over region (reads halo 2).
  void explicit_step_tile(View<const float> u, View<float> out, Box2 region, double delta) const;

 private:
  template <bool kAddInput>
  void run(View<const float> u, View<float> out, Box2 region, double scale) const;

  struct Tap {
    int dx, dy;
    double weight;
  };
  Stencil5x5 stencil_;
  Tap taps_[25];
  int tap_count_ = 0;
};

// Wraps the whole halo of f (any width) from the opposite side of its interior: the periodic
// boundary that makes a texture tile. Needs halo <= interior size on both axes.
void fill_periodic_halo(FieldF& f);

}  // namespace ardcell
