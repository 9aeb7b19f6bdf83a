#include "host/surface/surface_fluid.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>

#include "runtime/check.h"

namespace ardcell {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

}  // namespace

int connected_pieces(const PatchTopology& topo) {
  const std::vector<int> pieces = patch_pieces(topo);
  return pieces.empty() ? 0 : *std::max_element(pieces.begin(), pieces.end()) + 1;
}

SurfaceFluid::SurfaceFluid(const LimitSurface& surface, const PatchMetric& metric,
                           const SurfaceLaplacian& op, const SurfaceMultigrid& multigrid,
                           const SurfaceFluidParams& params)
    : topo_(surface.topology()),
      op_(op),
      mg_(multigrid),
      params_(params),
      n_(op.n()),
      patches_(op.patches()) {
  ARDCELL_CHECK(metric.n() == n_ && metric.patches() == patches_,
                "SurfaceFluid: the metric is not the operator's");
  const int n = n_;
  const double h = 1.0 / n;
  face_block_ = std::size_t(n + 3) * (n + 2);
  u2_offset_ = face_block_ * patches_;
  faces1_ = std::size_t(n + 1) * n;
  const std::size_t faces = faces1_ * patches_;
  for (auto* v : {&s1_, &a1_, &b1_, &gii1_, &gjj1_, &s2_, &a2_, &b2_, &gii2_, &gjj2_})
    v->assign(faces, 0.0);
  axis1_.assign(3 * faces, 0.0), axis2_.assign(3 * faces, 0.0);
  down1_.assign(faces, 0.0), down2_.assign(faces, 0.0);
  LimitSample t;
  for (int p = 0; p < patches_; ++p) {
    for (int j = 0; j < n; ++j)
      for (int i = 0; i <= n; ++i) {
        const MetricSample& m = metric.at(p, 2 * i + 1, 2 * j + 2);  // x1-face (i - 1/2, j)
        const std::size_t k = p * faces1_ + std::size_t(j) * (n + 1) + i;
        s1_[k] = m.sqrt_g, a1_[k] = m.sqrt_g * m.gi11, b1_[k] = m.sqrt_g * m.gi12;
        gii1_[k] = m.gi11, gjj1_[k] = m.gi22;
        surface.evaluate(p, i * h, (j + 0.5) * h, t);
        for (int a = 0; a < 3; ++a) axis1_[3 * k + a] = m.gi11 * t.du[a] + m.gi12 * t.dv[a];
      }
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i < n; ++i) {
        const MetricSample& m = metric.at(p, 2 * i + 2, 2 * j + 1);  // x2-face (i, j - 1/2)
        const std::size_t k = p * faces1_ + std::size_t(j) * n + i;
        s2_[k] = m.sqrt_g, a2_[k] = m.sqrt_g * m.gi22, b2_[k] = m.sqrt_g * m.gi12;
        gii2_[k] = m.gi11, gjj2_[k] = m.gi22;
        surface.evaluate(p, (i + 0.5) * h, j * h, t);
        for (int a = 0; a < 3; ++a) axis2_[3 * k + a] = m.gi12 * t.du[a] + m.gi22 * t.dv[a];
      }
  }
  area_.resize(std::size_t(n) * n * patches_);
  cell_gi_.resize(3 * area_.size());
  for (int p = 0; p < patches_; ++p)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const std::size_t k = (std::size_t(p) * n + j) * n + i;
        area_[k] = op.cell_area(p, i, j);
        const MetricSample& m = metric.at(p, 2 * i + 2, 2 * j + 2);
        cell_gi_[3 * k] = m.gi11, cell_gi_[3 * k + 1] = m.gi12, cell_gi_[3 * k + 2] = m.gi22;
      }
  build_exchange();
  // The source disc, at least the cells around the centre (a coarse grid has none within it).
  const double r = std::max(params_.source_radius, 0.75 * h);
  const double r2 = r * r;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double dx = (i + 0.5) * h - 0.5, dy = (j + 0.5) * h - 0.5;
      if (dx * dx + dy * dy < r2) source_cells_.push_back({i, j});
    }
  vel_.assign(2 * u2_offset_, 0.0);
  vel_next_ = vel_rhs_ = vel_;
  const PatchGrid& g = op.grid();
  s_ = g.make_field(), s_next_ = s_, s_rhs_ = s_, div_ = s_, phi_ = s_;
  patch_max_.assign(std::size_t(patches_), 0.0);
  patch_sums_.assign(2 * std::size_t(patches_), 0.0);
  set_down(params_.down);
  // Every path of a step once, so that the solvers' scratch is sized here, not in a step (the
  // projection of a field with a divergence runs the V-cycles and factors the coarsest grid).
  op.executor().reserve_rows(patches_);
  for (std::size_t k = 0; k < vel_.size(); ++k) vel_[k] = std::sin(0.37 * double(k));
  stitch(vel_);
  project();
  if (params_.viscosity > 0) apply_viscosity();
  if (params_.dye_diffusion > 0) diffuse_dye();
  dye_total();
  clear();  // none of that scratch may reach a step
  timings_ = FluidTimings{};
}

View<double> SurfaceFluid::u1_view(std::vector<double>& v, int p) const {
  return View<double>(v.data() + p * face_block_, n_ + 3, Box2{{-1, -1}, {n_ + 2, n_ + 1}});
}
View<double> SurfaceFluid::u2_view(std::vector<double>& v, int p) const {
  return View<double>(v.data() + u2_offset_ + p * face_block_, n_ + 2,
                      Box2{{-1, -1}, {n_ + 1, n_ + 2}});
}
View<const double> SurfaceFluid::u1_view(const std::vector<double>& v, int p) const {
  return View<const double>(v.data() + p * face_block_, n_ + 3, Box2{{-1, -1}, {n_ + 2, n_ + 1}});
}
View<const double> SurfaceFluid::u2_view(const std::vector<double>& v, int p) const {
  return View<const double>(v.data() + u2_offset_ + p * face_block_, n_ + 2,
                            Box2{{-1, -1}, {n_ + 1, n_ + 2}});
}

MacStencil SurfaceFluid::stencil(int p) const {
  const int n = n_;
  const Box2 xf{{0, 0}, {n + 1, n}}, yf{{0, 0}, {n, n + 1}};
  const auto x1 = [&](const std::vector<double>& v) {
    return View<const double>(v.data() + p * faces1_, n + 1, xf);
  };
  const auto x2 = [&](const std::vector<double>& v) {
    return View<const double>(v.data() + p * faces1_, n, yf);
  };
  return MacStencil{
      x1(s1_),
      x1(a1_),
      x1(b1_),
      x1(gii1_),
      x1(gjj1_),
      x2(s2_),
      x2(a2_),
      x2(b2_),
      x2(gii2_),
      x2(gjj2_),
      View<const double>(area_.data() + std::size_t(p) * n * n, n, Box2{{0, 0}, {n, n}})};
}

void SurfaceFluid::build_exchange() {
  const int n = n_;
  const double h = 1.0 / n;
  // The stored face of component `comp` at point y of patch q: must be a patch face, not a ghost.
  const auto face_at = [&](int q, int comp, double y0, double y1) {
    const double fi = comp == 0 ? y0 * n : y0 * n - 0.5, fj = comp == 0 ? y1 * n - 0.5 : y1 * n;
    const int i = int(std::lround(fi)), j = int(std::lround(fj));
    ARDCELL_CHECK(std::abs(fi - i) < 1e-6 && std::abs(fj - j) < 1e-6,
                  "SurfaceFluid: a ghost face maps off the neighbour's faces");
    ARDCELL_CHECK(i >= 0 && j >= 0 && i <= (comp == 0 ? n : n - 1) && j <= (comp == 0 ? n - 1 : n),
                  "SurfaceFluid: a ghost face maps onto a ghost");
    return comp == 0 ? u1_index(q, i, j) : u2_index(q, i, j);
  };
  const auto index = [&](int p, int comp, int i, int j) {
    return comp == 0 ? u1_index(p, i, j) : u2_index(p, i, j);
  };
  // The ghost (comp, i, j) of patch p at point (x0, x1) from the neighbour(s) holding it:
  // u_p = R^T u_q, so its component c is R_dc u_q^d for the one d with R_dc != 0.
  const auto mapped = [&](int p, int comp, int i, int j, double x0, double x1) {
    const PatchPoint at = locate(topo_, p, {x0, x1});
    if (at.patch < 0) return false;
    EdgeTransition turn;
    turn.quarter_turns = at.quarter_turns;
    const auto r = turn.rotation();
    const int d = r[comp] != 0 ? 0 : 1;
    const std::size_t src = face_at(at.patch, d, at.x[0], at.x[1]);
    ghosts_.push_back({index(p, comp, i, j), {src, src, src}, {double(r[2 * d + comp]), 0, 0}});
    return true;
  };
  ghost_begin_.assign(std::size_t(patches_) + 1, 0);
  for (int p = 0; p < patches_; ++p) {
    ghost_begin_[std::size_t(p)] = ghosts_.size();
    // Edge ghosts: (component, i, j) and the edge they lie beyond.
    const auto edge_ghost = [&](int comp, int i, int j, int e) {
      const double x0 = comp == 0 ? i * h : (i + 0.5) * h;
      const double x1 = comp == 0 ? (j + 0.5) * h : j * h;
      if (mapped(p, comp, i, j, x0, x1)) return;
      // A boundary edge: mirror the face across it; the normal component changes sign.
      const int normal = (e == 0 || e == 2) ? 1 : 0;
      const int mi = e == 3   ? -i + (comp == 0 ? 0 : -1)
                     : e == 1 ? 2 * n - i - (comp == 0 ? 0 : 1)
                              : i;
      const int mj = e == 0   ? -j + (comp == 1 ? 0 : -1)
                     : e == 2 ? 2 * n - j - (comp == 1 ? 0 : 1)
                              : j;
      const std::size_t src = index(p, comp, mi, mj);
      ghosts_.push_back(
          {index(p, comp, i, j), {src, src, src}, {comp == normal ? -1.0 : 1.0, 0, 0}});
    };
    for (int j = 0; j < n; ++j) edge_ghost(0, -1, j, 3), edge_ghost(0, n + 1, j, 1);
    for (int i = 0; i <= n; ++i) edge_ghost(0, i, -1, 0), edge_ghost(0, i, n, 2);
    for (int i = 0; i < n; ++i) edge_ghost(1, i, -1, 0), edge_ghost(1, i, n + 1, 2);
    for (int j = 0; j <= n; ++j) edge_ghost(1, -1, j, 3), edge_ghost(1, n, j, 1);
    // Corner ghosts, after the edge ghosts they may read.
    for (int comp = 0; comp < 2; ++comp)
      for (int k = 0; k < 4; ++k) {
        const int hi_i = comp == 0 ? n + 1 : n, hi_j = comp == 0 ? n : n + 1;
        const int ci = (k == 1 || k == 2) ? hi_i : -1, cj = k >= 2 ? hi_j : -1;
        const int di = ci < 0 ? 1 : -1, dj = cj < 0 ? 1 : -1;
        const double x0 = comp == 0 ? ci * h : (ci + 0.5) * h;
        const double x1 = comp == 0 ? (cj + 0.5) * h : cj * h;
        if (topo_.regular_corner(p, k) && mapped(p, comp, ci, cj, x0, x1)) continue;
        ghosts_.push_back({index(p, comp, ci, cj),
                           {index(p, comp, ci + di, cj), index(p, comp, ci, cj + dj),
                            index(p, comp, ci + di, cj + dj)},
                           {1, 1, -1}});
      }
  }
  ghost_begin_[std::size_t(patches_)] = ghosts_.size();
  for (const auto& [p, e] : op_.grid().boundary_edges())
    for (int m = 0; m < n; ++m) boundary_faces_.push_back(edge_face(p, e, m).index);
}

SurfaceFluid::EdgeFace SurfaceFluid::edge_face(int p, int e, int m) const {
  const int n = n_;
  switch (e) {
    case 0:
      return {u2_index(p, m, 0), s2_[p * faces1_ + m], -1};
    case 1:
      return {u1_index(p, n, m), s1_[p * faces1_ + std::size_t(m) * (n + 1) + n], 1};
    case 2:
      return {u2_index(p, n - 1 - m, n), s2_[p * faces1_ + std::size_t(n) * n + (n - 1 - m)], 1};
    default:
      return {u1_index(p, 0, n - 1 - m), s1_[p * faces1_ + std::size_t(n - 1 - m) * (n + 1)], -1};
  }
}

void SurfaceFluid::exchange_velocity(std::vector<double>& v, int p) const {
  for (std::size_t k = ghost_begin_[std::size_t(p)]; k < ghost_begin_[std::size_t(p) + 1]; ++k) {
    const Ghost& g = ghosts_[k];
    v[g.dst] = g.w[0] * v[g.src[0]] + g.w[1] * v[g.src[1]] + g.w[2] * v[g.src[2]];
  }
}

void SurfaceFluid::exchange_velocity() {
  op_.executor().for_rows(patches_, n_ * n_, [&](int p0, int p1) {
    for (int p = p0; p < p1; ++p) exchange_velocity(vel_, p);
  });
}

void SurfaceFluid::stitch(std::vector<double>& v) const {
  const int n = n_;
  // Each shared edge writes its own faces only: the edges run side by side.
  const auto& shared = op_.grid().shared_edges();
  op_.executor().for_rows(int(shared.size()), n, [&](int e0, int e1) {
    for (int e = e0; e < e1; ++e) {
      const auto& s = shared[std::size_t(e)];
      for (int m = 0; m < n; ++m) {
        const EdgeFace a = edge_face(s.p, s.e, m), b = edge_face(s.q, s.f, n - 1 - m);
        // The mean outward flux from p (over h).
        const double mean = 0.5 * (a.sign * a.sqrt_g * v[a.index] - b.sign * b.sqrt_g * v[b.index]);
        v[a.index] = a.sign * mean / a.sqrt_g;
        v[b.index] = -b.sign * mean / b.sqrt_g;
      }
    }
  });
  for (std::size_t k : boundary_faces_) v[k] = 0;
}

void SurfaceFluid::stitch_velocity() { stitch(vel_); }

void SurfaceFluid::divergence(PatchField& out) const {
  const int n = n_;
  op_.executor().for_rows(patches_, n * n, [&](int p0, int p1) {
    for (int p = p0; p < p1; ++p)
      mac_divergence(u1_view(vel_, p), u2_view(vel_, p), stencil(p),
                     op_.grid().view(out, p).crop(Box2{{0, 0}, {n, n}}), n);
  });
}

double SurfaceFluid::max_divergence() const {
  divergence(div_);
  return op_.max_abs(div_);
}

double SurfaceFluid::dye_total() const { return op_.total(s_); }

void SurfaceFluid::set_down(const std::array<double, 3>& down) {
  params_.down = down;
  // Scaled by the largest component first, so that neither 1e200 nor 1e-200 over- or underflows.
  const double big = std::max({std::abs(down[0]), std::abs(down[1]), std::abs(down[2])});
  ARDCELL_CHECK(big > 0 && std::isfinite(big), "SurfaceFluid: down is not a direction");
  const double e[3] = {down[0] / big, down[1] / big, down[2] / big};
  const double len = std::sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
  const double d[3] = {e[0] / len, e[1] / len, e[2] / len};
  for (std::size_t k = 0; k < down1_.size(); ++k) {
    down1_[k] = d[0] * axis1_[3 * k] + d[1] * axis1_[3 * k + 1] + d[2] * axis1_[3 * k + 2];
    down2_[k] = d[0] * axis2_[3 * k] + d[1] * axis2_[3 * k + 1] + d[2] * axis2_[3 * k + 2];
  }
}

void SurfaceFluid::set_params(const SurfaceFluidParams& params) {
  const double radius = params_.source_radius;
  params_ = params;
  params_.source_radius = radius;
  set_down(params_.down);
}

void SurfaceFluid::clear() {
  for (auto* v : {&vel_, &vel_next_, &vel_rhs_}) std::fill(v->begin(), v->end(), 0.0);
  for (auto* f : {&s_, &s_next_, &s_rhs_, &phi_, &div_}) std::fill(f->begin(), f->end(), 0.0);
  time_ = 0;
}

double SurfaceFluid::tangential_u1(int p, int i, int j, const std::array<double, 3>& v) const {
  const double* a = &axis1_[3 * (p * faces1_ + std::size_t(j) * (n_ + 1) + i)];
  return v[0] * a[0] + v[1] * a[1] + v[2] * a[2];
}

double SurfaceFluid::tangential_u2(int p, int i, int j, const std::array<double, 3>& v) const {
  const double* a = &axis2_[3 * (p * faces1_ + std::size_t(j) * n_ + i)];
  return v[0] * a[0] + v[1] * a[1] + v[2] * a[2];
}

void SurfaceFluid::fill_sources(double value) {
  const PatchGrid& g = op_.grid();
  for (int p = 0; p < patches_; ++p)
    for (const auto& [i, j] : source_cells_) s_[g.index(p, i, j)] = value;
}

void SurfaceFluid::add_sources() {
  if (!(params_.source_rate > 0)) return;
  const double add = params_.dt * params_.source_rate;
  const PatchGrid& g = op_.grid();
  op_.executor().for_rows(patches_, int(source_cells_.size()) + 1, [&](int p0, int p1) {
    for (int p = p0; p < p1; ++p)
      for (const auto& [i, j] : source_cells_) {
        double& s = s_[g.index(p, i, j)];
        s = std::min(1.0, s + add);  // the seed: no more than 100%
      }
  });
}

void SurfaceFluid::diffuse_dye() {
  if (!(params_.dye_diffusion > 0)) return;
  s_rhs_ = s_;  // same size: a copy
  op_.implicit_diffusion(s_, s_rhs_, params_.dt * params_.dye_diffusion, DiffusionSolve{1e-6, 500});
}

void SurfaceFluid::add_forces() {
  if (params_.force == FluidForce::kNone || params_.strength == 0) return;
  const int n = n_;
  const double h = 1.0 / n, k = params_.dt * params_.strength;
  const PatchGrid& g = op_.grid();
  const double angle = 2 * std::numbers::pi * time_ / params_.walk_period;
  const double wx = 0.5 + params_.walk_radius * std::cos(angle);
  const double wy = 0.5 + params_.walk_radius * std::sin(angle);
  const double tx = -std::sin(angle), ty = std::cos(angle);  // the walker's direction
  const double inv_w2 = 1 / (params_.walk_width * params_.walk_width);
  // The walker's push at a face: the unit tangent (on the surface) times the Gaussian; g^ij at
  // the face gives the metric g_ij = (g^ij)^-1 that measures T.
  const auto push = [&](double x0, double x1, double gi11, double gi12, double gi22) {
    const double r2 = (x0 - wx) * (x0 - wx) + (x1 - wy) * (x1 - wy);
    const double fall = std::exp(-r2 * inv_w2);
    const double det = gi11 * gi22 - gi12 * gi12;
    const double len2 = (gi22 * tx * tx - 2 * gi12 * tx * ty + gi11 * ty * ty) / det;
    return fall / std::sqrt(len2);
  };
  const bool gravity = params_.force == FluidForce::kGravity;
  op_.executor().for_rows(patches_, n * n, [&](int p0, int p1) {
    for (int p = p0; p < p1; ++p) {
      if (gravity) g.exchange(s_, p);  // the dye at the faces: the mean of the two cells
      for (int j = 0; j < n; ++j)
        for (int i = 0; i <= n; ++i) {
          const std::size_t f = p * faces1_ + std::size_t(j) * (n + 1) + i;
          if (gravity)
            vel_[u1_index(p, i, j)] +=
                k * 0.5 * (s_[g.index(p, i - 1, j)] + s_[g.index(p, i, j)]) * down1_[f];
          else
            vel_[u1_index(p, i, j)] +=
                k * tx * push(i * h, (j + 0.5) * h, gii1_[f], b1_[f] / s1_[f], gjj1_[f]);
        }
      for (int j = 0; j <= n; ++j)
        for (int i = 0; i < n; ++i) {
          const std::size_t f = p * faces1_ + std::size_t(j) * n + i;
          if (gravity)
            vel_[u2_index(p, i, j)] +=
                k * 0.5 * (s_[g.index(p, i, j - 1)] + s_[g.index(p, i, j)]) * down2_[f];
          else
            vel_[u2_index(p, i, j)] +=
                k * ty * push((i + 0.5) * h, j * h, gii2_[f], b2_[f] / s2_[f], gjj2_[f]);
        }
    }
  });
  stitch(vel_);
}

FluidReport SurfaceFluid::project() {
  const int n = n_;
  divergence(div_);
  const DiffusionReport r = mg_.solve_poisson(phi_, div_, params_.projection);
  const PatchGrid& g = op_.grid();
  op_.executor().for_rows(patches_, n * n, [&](int p0, int p1) {
    for (int p = p0; p < p1; ++p) {
      g.exchange(phi_, p);
      mac_subtract_gradient(g.view(std::as_const(phi_), p), stencil(p), u1_view(vel_, p),
                            u2_view(vel_, p), n);
    }
  });
  stitch(vel_);
  FluidReport report;
  report.cycles = r.cycles;
  report.residual = r.residual;
  return report;
}

FluidReport SurfaceFluid::step() {
  auto t0 = Clock::now();
  add_sources();
  timings_.sources += seconds_since(t0);
  t0 = Clock::now();
  diffuse_dye();
  timings_.dye_diffusion += seconds_since(t0);
  t0 = Clock::now();
  advect_dye();
  timings_.dye_advection += seconds_since(t0);
  t0 = Clock::now();
  advect_velocity();
  timings_.velocity_advection += seconds_since(t0);
  t0 = Clock::now();
  add_forces();
  timings_.forces += seconds_since(t0);
  t0 = Clock::now();
  const int sweeps = apply_viscosity();
  timings_.viscosity += seconds_since(t0);
  t0 = Clock::now();
  FluidReport report = project();
  timings_.projection += seconds_since(t0);
  report.viscosity_sweeps = sweeps;
  time_ += params_.dt;
  return report;
}

}  // namespace ardcell
