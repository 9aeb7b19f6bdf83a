#include "kernels/generalized_diffusion.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "runtime/check.h"

namespace ardcell {

double& TensorSequence::component(int nx, int ny) {
  switch (nx * 10 + ny) {
    case 20:
      return xx;
    case 11:
      return xy;
    case 2:
      return yy;
    case 30:
      return xxx;
    case 21:
      return xxy;
    case 12:
      return xyy;
    case 3:
      return yyy;
    case 40:
      return xxxx;
    case 31:
      return xxxy;
    case 22:
      return xxyy;
    case 13:
      return xyyy;
    case 4:
      return yyyy;
  }
  ARDCELL_CHECK(false, "TensorSequence: ranks 2..4 only");
  return xx;
}

double multiplicity(int nx, int ny) { return factorial(nx + ny) / (factorial(nx) * factorial(ny)); }

Stencil5x5 assemble_generalized_stencil(const TensorSequence& d,
                                        const GeneralizedDiffusionOptions& options) {
  const SavitzkyGolay5x5 filters(options.savitzky_golay_degree);
  ARDCELL_CHECK(filters.degree() >= 4, "generalized diffusion needs a fit of degree >= 4");
  Stencil5x5 k;
  for (int rank = 2; rank <= 4; ++rank)
    for (int ny = 0; ny <= rank; ++ny) {
      const int nx = rank - ny;
      const double c = d.component(nx, ny);
      if (c == 0) continue;
      const bool central =
          rank == 2 && options.second_derivatives == SecondDerivatives::kCentralDifference;
      const Stencil5x5 derivative =
          central ? central_second_derivative(nx, ny) : filters.derivative(nx, ny);
      k += (multiplicity(nx, ny) * c) * derivative;
    }
  return k;
}

Stencil5x5 isotropic_stencil(double d) {
  Stencil5x5 k;
  k.at(0, 0) = -4 * d;
  k.at(-1, 0) = k.at(1, 0) = k.at(0, -1) = k.at(0, 1) = d;
  return k;
}

Stencil5x5 gaussian_stencil(double dxx, double dxy, double dyy) {
  // Eqn 29 = 1/2 [-Dxy 2Dyy Dxy; 2Dxx -4(Dxx + Dyy) 2Dxx; Dxy 2Dyy -Dxy], corners by offset.
  Stencil5x5 k;
  k.at(0, 0) = -2 * (dxx + dyy);
  k.at(-1, 0) = k.at(1, 0) = dxx;
  k.at(0, -1) = k.at(0, 1) = dyy;
  k.at(1, 1) = k.at(-1, -1) = dxy / 2;
  k.at(-1, 1) = k.at(1, -1) = -dxy / 2;
  return k;
}

std::complex<double> stencil_symbol(const Stencil5x5& k, double kx, double ky) {
  std::complex<double> s = 0;
  for (int dy = -2; dy <= 2; ++dy)
    for (int dx = -2; dx <= 2; ++dx)
      if (k.at(dx, dy) != 0) s += k.at(dx, dy) * std::polar(1.0, kx * dx + ky * dy);
  return s;
}

double explicit_spectral_radius(const Stencil5x5& k, double delta, int n) {
  ARDCELL_CHECK(n > 0, "explicit_spectral_radius: n > 0");
  double rho = 0;
  const double step = 2 * std::numbers::pi / n;
  for (int my = 0; my < n; ++my)
    for (int mx = 0; mx < n; ++mx)
      rho = std::max(rho, std::abs(1.0 + delta * stencil_symbol(k, mx * step, my * step)));
  return rho;
}

GeneralizedDiffusion::GeneralizedDiffusion(const Stencil5x5& stencil) : stencil_(stencil) {
  for (int dy = -2; dy <= 2; ++dy)
    for (int dx = -2; dx <= 2; ++dx)
      if (stencil.at(dx, dy) != 0) taps_[tap_count_++] = {dx, dy, stencil.at(dx, dy)};
}

template <bool kAddInput>
void GeneralizedDiffusion::run(View<const float> u, View<float> out, Box2 region,
                               double scale) const {
  ARDCELL_DCHECK(u.box().contains(region.grown(2)), "generalized diffusion reads halo 2");
  ARDCELL_DCHECK(out.box().contains(region), "generalized diffusion: output outside its view");
  for (int y = region.min.y; y < region.max.y; ++y) {
    // One row pointer per tap, shifted by the tap's dx: the inner loop is a plain weighted sum.
    const float* rows[25];
    for (int t = 0; t < tap_count_; ++t) rows[t] = u.row(y + taps_[t].dy) + taps_[t].dx;
    const float* centre = u.row(y);
    float* o = out.row(y);
    for (int x = region.min.x; x < region.max.x; ++x) {
      double acc = 0;
      for (int t = 0; t < tap_count_; ++t) acc += taps_[t].weight * rows[t][x];
      o[x] = kAddInput ? float(centre[x] + scale * acc) : float(scale * acc);
    }
  }
}

void GeneralizedDiffusion::apply_tile(View<const float> u, View<float> out, Box2 region) const {
  run<false>(u, out, region, 1.0);
}

void GeneralizedDiffusion::explicit_step_tile(View<const float> u, View<float> out, Box2 region,
                                              double delta) const {
  run<true>(u, out, region, delta);
}

void fill_periodic_halo(FieldF& f) {
  const int nx = f.nx(), ny = f.ny(), h = f.halo();
  ARDCELL_CHECK(h <= nx && h <= ny, "fill_periodic_halo: halo wider than the interior");
  const auto wrap = [](int i, int n) { return (i % n + n) % n; };
  for (int y = -h; y < ny + h; ++y)
    for (int x = -h; x < nx + h; ++x)
      if (x < 0 || x >= nx || y < 0 || y >= ny) f(x, y) = f(wrap(x, nx), wrap(y, ny));
}

}  // namespace ardcell
