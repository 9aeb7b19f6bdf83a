#include "kernels/tensor_field_solve.h"

#include <cmath>

#include "kernels/tensor_field_operator.h"
#include "runtime/check.h"

namespace ardcell {
namespace {

// A flat row-major grid of doubles as TensorFieldOperator's u.
struct FlatGrid {
  const double* v;
  int nx;
  double operator()(int x, int y) const { return v[std::size_t(y) * nx + x]; }
};

}  // namespace

double TensorFieldSolve::Space::dot(const Vector& a, const Vector& b) const {
  const int nx = n.x;
  return ex->sum_rows(n.y, nx, [&](int y0, int y1, double* partial) {
    for (int y = y0; y < y1; ++y) {
      const std::size_t row = std::size_t(y) * nx;
      double sum = 0;
      for (int x = 0; x < nx; ++x) sum += a[row + x] * b[row + x];
      partial[y] = sum;
    }
  });
}

double TensorFieldSolve::Space::norm(const Vector& a) const { return std::sqrt(dot(a, a)); }

TensorFieldSolve::TensorFieldSolve(const Rank2FaceField& d, RowExecutor& ex)
    : d_(&d), ex_(&ex), n_(d.size()) {
  ARDCELL_CHECK(n_.x >= 2 && n_.y >= 2, "TensorFieldSolve needs at least 2 x 2 cells");
  ex.reserve_rows(n_.y);  // dot products allocate nothing later
  const std::size_t cells = std::size_t(n_.x) * n_.y;
  for (std::vector<double>* v : {&b_, &x_, &diagonal_}) v->assign(cells, 0.0);
  k_.each([&](std::vector<double>& v) { v.assign(cells, 0.0); });
  const TensorFieldOperator<FlatGrid> op{d, {x_.data(), n_.x}};
  for (int y = 0; y < n_.y; ++y)
    for (int x = 0; x < n_.x; ++x)
      diagonal_[std::size_t(y) * n_.x + x] =
          op.diagonal(x, x == 0 ? n_.x - 1 : x - 1, y, y == 0 ? n_.y - 1 : y - 1);
}

void TensorFieldSolve::apply(const std::vector<double>& y, std::vector<double>& out, double s,
                             const std::vector<double>* b) const {
  const int nx = n_.x, ny = n_.y;
  const TensorFieldOperator<FlatGrid> op{*d_, {y.data(), nx}};
  ex_->for_rows(ny, nx, [&](int y0, int y1) {
    for (int j = y0; j < y1; ++j) {
      const int jm = j == 0 ? ny - 1 : j - 1, jp = j == ny - 1 ? 0 : j + 1;
      const std::size_t row = std::size_t(j) * nx;
      const auto cell = [&](int i, int im, int ip) {
        const double a = y[row + i] - s * op(i, im, ip, j, jm, jp);
        out[row + i] = b ? (*b)[row + i] - a : a;
      };
      cell(0, nx - 1, 1 % nx);
      for (int i = 1; i + 1 < nx; ++i) cell(i, i - 1, i + 1);
      cell(nx - 1, nx - 2, 0);
    }
  });
}

SolveReport TensorFieldSolve::solve(FieldF& x, double s) {
  ARDCELL_CHECK(x.size() == n_, "TensorFieldSolve: a field of another size");
  ARDCELL_CHECK(s >= 0 && std::isfinite(s), "TensorFieldSolve: the step must be finite and >= 0");
  const int nx = n_.x;
  const Space space{ex_, n_};
  ex_->for_rows(n_.y, nx, [&](int y0, int y1) {
    for (int y = y0; y < y1; ++y)
      for (int i = 0; i < nx; ++i)
        b_[std::size_t(y) * nx + i] = x_[std::size_t(y) * nx + i] = x(i, y);
  });
  double bnorm = space.norm(b_);
  if (bnorm == 0) bnorm = 1;
  const BicgstabReport r = bicgstab(
      space, k_, x_, bnorm, {tolerance_, 2 * max_iterations_},
      [&](const std::vector<double>& y, std::vector<double>& out) {
        apply(y, out, s, &b_);
        return space.norm(out);
      },
      [&](const std::vector<double>& y, std::vector<double>& out) { apply(y, out, s, nullptr); },
      [&](const std::vector<double>& q, std::vector<double>& y) {
        space.each([&](std::size_t c) { y[c] = q[c] / (1 + s * diagonal_[c]); });
      });
  ex_->for_rows(n_.y, nx, [&](int y0, int y1) {
    for (int y = y0; y < y1; ++y)
      for (int i = 0; i < nx; ++i) x(i, y) = float(x_[std::size_t(y) * nx + i]);
  });
  return {(r.applications + 1) / 2, r.residual};
}

}  // namespace ardcell
