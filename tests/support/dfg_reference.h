#pragma once
// The published ranges of the DFG benchmark "laminar flow around a cylinder" (Schaefer & Turek,
// Benchmark computations of laminar flow around a cylinder, Notes on Numerical Fluid Mechanics
// 52, 1996, Table 3 (2D-1, Re 20) and Table 4 (2D-2, Re 100)): the bounds the best submitted
// solutions fell within. Drag and lift coefficients C = 2 F / (U_mean^2 D), pressure difference
// P(0.15, 0.2) - P(0.25, 0.2) (2D-2: half a period after the lift's maximum), Strouhal number
// St = f D / U_mean.
namespace ardcell::dfg {

struct Range {
  double lo, hi;
  double mid() const { return 0.5 * (lo + hi); }
};

// 2D-1, steady.
inline constexpr Range kDrag2D1{5.57, 5.59};
inline constexpr Range kLift2D1{0.0104, 0.0110};
inline constexpr Range kPressureDifference2D1{0.1172, 0.1176};

// 2D-2, periodic.
inline constexpr Range kDragMax2D2{3.22, 3.24};
inline constexpr Range kLiftMax2D2{0.99, 1.01};
inline constexpr Range kStrouhal2D2{0.295, 0.305};
inline constexpr Range kPressureDifference2D2{2.46, 2.50};

// Distance of x from the range (0 inside it), relative to its middle.
inline double relative_miss(double x, Range r) {
  const double d = x < r.lo ? r.lo - x : x > r.hi ? x - r.hi : 0.0;
  return d / r.mid();
}

}  // namespace ardcell::dfg
