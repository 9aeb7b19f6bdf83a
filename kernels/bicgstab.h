#pragma once
// Right-preconditioned BiCGSTAB (van der Vorst 1992) for A x = b with a nonsymmetric A: the
// Krylov solver of the systems ICCG cannot take (kernels/linear_solver.h's are symmetric).
// Its users: the surface solves (host/surface/surface_multigrid.h: a V-cycle preconditions the
// Laplace-Beltrami operator, whose cross terms read corner ghosts each patch fills its own way)
// and seed 003's semi-implicit step with a per-cell tensor (kernels/tensor_field_solve.h:
// Jacobi preconditions div(D(x) grad)).
//
// The algorithm apart from its grid: a Space says what a vector is and how to run over it,
//   using Vector = ...;                      (std::vector<double>-like: operator[], begin/end)
//   double dot(const Vector&, const Vector&) (same bits for any number of workers)
//   double norm(const Vector&)               (the stopping rule's norm)
//   void each(f)                             (f(std::size_t q) on every cell q; f writes q only)
// and the caller gives residual(x, r) (r = b - A x, returns norm(r)), apply(y, out) (out = A y)
// and precondition(q, y) (y = M^-1 q). Every run stops when norm(r) / bnorm <= tolerance, or
// when it has applied the preconditioner max_applications times (two per BiCGSTAB step).
// Each pass starts from the true residual b - A x (a restart when the recurrence's residual has
// drifted from it, or after a breakdown), and ends when the recurrence's residual meets the
// tolerance, the applications run out, or a denominator vanishes. Allocates nothing.
#include <algorithm>
#include <initializer_list>

namespace ardcell {

struct BicgstabStop {
  double tolerance = 0;      // norm(b - A x) / bnorm to stop at
  int max_applications = 0;  // of the preconditioner (and of A), two per step
};

struct BicgstabReport {
  int applications = 0;
  double residual = 0;  // norm(b - A x) / bnorm of the last iterate (recomputed, not the
                        // recurrence's)
};

// The solver's vectors on one grid: residual, shadow residual, search direction, A y, the two
// preconditioned directions and A z.
template <class Vector>
struct BicgstabVectors {
  Vector r, shadow, p, v, y, z, t;
  // f(vector) on each of them (sizing them once, before the solves).
  template <class F>
  void each(const F& f) {
    for (Vector* vector : {&r, &shadow, &p, &v, &y, &z, &t}) f(*vector);
  }
};

template <class Space, class Residual, class Apply, class Precondition>
BicgstabReport bicgstab(const Space& space, BicgstabVectors<typename Space::Vector>& k,
                        typename Space::Vector& x, double bnorm, const BicgstabStop& stop,
                        const Residual& residual, const Apply& apply,
                        const Precondition& precondition) {
  BicgstabReport report;
  const auto done = [&](double norm_r) {
    report.residual = norm_r / bnorm;
    return report.residual <= stop.tolerance || report.applications >= stop.max_applications;
  };
  while (!done(residual(x, k.r))) {
    const int applications_before = report.applications;
    k.shadow = k.r;
    double rho = 1, alpha = 1, omega = 1;
    std::fill(k.p.begin(), k.p.end(), 0.0);
    std::fill(k.v.begin(), k.v.end(), 0.0);
    for (;;) {
      const double rho_next = space.dot(k.shadow, k.r);
      if (rho_next == 0 || omega == 0) break;
      const double beta = (rho_next / rho) * (alpha / omega);
      rho = rho_next;
      space.each([&](std::size_t q) { k.p[q] = k.r[q] + beta * (k.p[q] - omega * k.v[q]); });
      precondition(k.p, k.y);
      apply(k.y, k.v);
      ++report.applications;
      const double shadow_v = space.dot(k.shadow, k.v);
      if (shadow_v == 0) break;
      alpha = rho / shadow_v;
      // r becomes s = r - alpha v; x takes the half step.
      space.each([&](std::size_t q) {
        k.r[q] -= alpha * k.v[q];
        x[q] += alpha * k.y[q];
      });
      if (done(space.norm(k.r))) break;
      precondition(k.r, k.z);
      apply(k.z, k.t);
      ++report.applications;
      const double tt = space.dot(k.t, k.t);
      omega = tt == 0 ? 0 : space.dot(k.t, k.r) / tt;
      space.each([&](std::size_t q) {
        x[q] += omega * k.z[q];
        k.r[q] -= omega * k.t[q];
      });
      if (done(space.norm(k.r))) break;
    }
    // A pass that broke down before its first application (r r underflowing to 0 while r is
    // not 0) takes one plain preconditioned step instead, so every pass makes progress and
    // counts.
    if (report.applications == applications_before) {
      precondition(k.r, k.y);
      space.each([&](std::size_t q) { x[q] += k.y[q]; });
      ++report.applications;
    }
    if (report.applications >= stop.max_applications) {
      report.residual = residual(x, k.r) / bnorm;
      break;
    }
  }
  return report;
}

}  // namespace ardcell
