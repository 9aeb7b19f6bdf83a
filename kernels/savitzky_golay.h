#pragma once
// Savitzky-Golay derivative filters on the 5x5 neighbourhood, seed 003 (McGraw, "Generalized
// Reaction-Diffusion Textures"), Eqn 30 to Eqn 35:
//   seed 003, Eqn 30: the 5x5 neighbourhood, offsets (r, s) in [-2, 2]^2 (Stencil5x5::at)
//   seed 003, Eqn 31: p_rs(x, y) = a_00 + a_10 x + a_01 y + a_20 x^2 + ... fitted around (r, s)
//   seed 003, Eqn 32: p(x, y) = sum_{i + j <= n} a_ij x^i y^j       (read as TOTAL degree n)
//   seed 003, Eqn 33: X a = u,  X's rows (x^i y^j) at the 25 offsets (x, y) in [-2, 2]^2
//   seed 003, Eqn 34: a = X^+ u  (least squares; X^+_ij is the row with X^+_ij u = a_ij)
//   seed 003, Eqn 35: d^{i+j} p / dx^i dy^j (0, 0) = i! j! a_ij  ->  kernel i! j! X^+_ij
// The filters are computed here, in double, by a one-sided Jacobi SVD of X (nothing is typed
// in). A kernel reads halo 2 (offsets -2..2 on both axes).
//
// Degree 4 (15 terms, X of rank 15) is the default. Degree 5 (21 terms) is RANK-DEFICIENT on a
// 5x5 grid: on x in {-2..2}, x (x^2 - 1)(x^2 - 4) = 0, so the columns x^5 = 5 x^3 - 4 x (and
// likewise in y) and X has rank 19. Its pseudo-inverse is then the minimum-norm one: the fit
// still reproduces the data, but the coefficients a_10, a_30, a_50 (a_01, a_03, a_05) are no
// longer determined, and the minimum-norm choice spreads them over the null vector
// (4, -5, 1): the degree-5 d/dx and d^3/dx^3 kernels (and their y twins) are NOT exact on x,
// x^3, x^5 (e.g. d^3/dx^3 of x^3 comes out 6 * 17/42). Every other degree-5 kernel is exact on
// every monomial of total degree <= 5. The paper (sec. 6) used degree 5 for the derivatives of
// order > 2; docs/numerics.md says what that does to its spectral radius.
//
// Second derivatives: the paper finally replaces the Savitzky-Golay X^+_20, X^+_11, X^+_02 by
// central differences (end of sec. 5.1); central_second_derivative gives those 3x3 kernels.
#include <array>
#include <vector>

namespace ardcell {

// A 5x5 stencil stored by offset: at(dx, dy) weighs u(x + dx, y + dy), dx, dy in [-2, 2]
// (applied as a correlation, never flipped, so the sign of odd derivatives is plain).
struct Stencil5x5 {
  std::array<double, 25> w{};

  double& at(int dx, int dy) { return w[(dy + 2) * 5 + (dx + 2)]; }
  double at(int dx, int dy) const { return w[(dy + 2) * 5 + (dx + 2)]; }
  double sum() const;
  Stencil5x5& operator+=(const Stencil5x5& o);
  friend Stencil5x5 operator*(double s, Stencil5x5 k) {
    for (double& v : k.w) v *= s;
    return k;
  }
};

class SavitzkyGolay5x5 {
 public:
  // degree: total polynomial degree of the fit, 1..5 (4 default; 5 is rank-deficient).
  explicit SavitzkyGolay5x5(int degree = 4);

  int degree() const { return degree_; }
  int term_count() const { return int(terms_.size()); }
  // Numerical rank of X (15 at degree 4, 19 at degree 5).
  int rank() const { return rank_; }
  bool full_rank() const { return rank_ == term_count(); }

  // X^+_ij as a 5x5 stencil: applied to u it gives the fitted coefficient a_ij (Eqn 34).
  Stencil5x5 coefficient_row(int i, int j) const;
  // i! j! X^+_ij: the kernel of d^{i+j} / dx^i dy^j at the centre (Eqn 35). i + j <= degree.
  Stencil5x5 derivative(int i, int j) const;

 private:
  struct Term {
    int i, j;  // x^i y^j
  };
  int term_index(int i, int j) const;
  int degree_;
  int rank_ = 0;
  std::vector<Term> terms_;
  std::vector<Stencil5x5> pinv_rows_;  // one per term, in terms_ order
};

// Second-order central differences for d^2/dx^2 (i = 2, j = 0), d^2/dxdy (1, 1) and
// d^2/dy^2 (0, 2): [1 -2 1] along the axis, and (u(1,1) - u(-1,1) - u(1,-1) + u(-1,-1)) / 4.
Stencil5x5 central_second_derivative(int i, int j);

double factorial(int n);

}  // namespace ardcell
