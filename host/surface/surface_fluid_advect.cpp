// SurfaceFluid's semi-Lagrangian advection across patches and its viscosity sweeps (see
// host/surface/surface_fluid.h).
#include <algorithm>
#include <cmath>

#include "host/surface/surface_fluid.h"

namespace ardcell {

namespace {

// v turned by `turns` quarter turns counterclockwise.
void turn(int turns, double v[2]) {
  const double x = v[0], y = v[1];
  switch (turns & 3) {
    case 1:
      v[0] = -y, v[1] = x;
      break;
    case 2:
      v[0] = -x, v[1] = -y;
      break;
    case 3:
      v[0] = y, v[1] = -x;
      break;
    default:
      break;
  }
}

// A trace crosses at most this many patch edges (a step that long has left any sense behind).
constexpr int kMaxCrossings = 64;

}  // namespace

SurfaceFluid::Landing SurfaceFluid::walk(int p, double x0, double x1, double d0, double d1) const {
  Landing at{p, {x0, x1}, 0};
  for (int crossing = 0; crossing < kMaxCrossings; ++crossing) {
    // The first edge the segment x + t d, t in [0, 1], leaves the unit square through.
    double t = 1;
    int e = -1;
    const auto exit = [&](double x, double d, int lo_edge, int hi_edge) {
      if (d > 0 && x + d > 1) {
        const double s = (1 - x) / d;
        if (s < t) t = s, e = hi_edge;
      } else if (d < 0 && x + d < 0) {
        const double s = -x / d;
        if (s < t) t = s, e = lo_edge;
      }
    };
    exit(at.x[0], d0, 3, 1);
    exit(at.x[1], d1, 0, 2);
    if (e < 0) {
      at.x[0] = std::clamp(at.x[0] + d0, 0.0, 1.0);
      at.x[1] = std::clamp(at.x[1] + d1, 0.0, 1.0);
      return at;
    }
    t = std::max(t, 0.0);
    // On the edge, exactly: the transition then maps it onto the neighbour's edge exactly.
    at.x[0] = e == 3 ? 0.0 : e == 1 ? 1.0 : std::clamp(at.x[0] + t * d0, 0.0, 1.0);
    at.x[1] = e == 0 ? 0.0 : e == 2 ? 1.0 : std::clamp(at.x[1] + t * d1, 0.0, 1.0);
    d0 *= 1 - t, d1 *= 1 - t;
    const EdgeTransition& tr = topo_.transition(at.patch, e);
    if (tr.patch < 0) return at;  // a boundary: the trace stops at the wall
    const auto y = tr.map_point({at.x[0], at.x[1]});
    const auto d = tr.map_vector({d0, d1});
    at.patch = tr.patch;
    at.x[0] = std::clamp(y[0], 0.0, 1.0), at.x[1] = std::clamp(y[1], 0.0, 1.0);
    d0 = d[0], d1 = d[1];
    at.turns = (at.turns + tr.quarter_turns) & 3;
  }
  return at;
}

void SurfaceFluid::velocity_at(int q, double x0, double x1, double out[2]) const {
  out[0] = sample_u1(u1_view(vel_, q), x0, x1, n_);
  out[1] = sample_u2(u2_view(vel_, q), x0, x1, n_);
}

void SurfaceFluid::trace_velocity_at(int q, double x0, double x1, double out[2]) const {
  velocity_at(q, x0, x1, out);
  if (params_.trace != FluidTrace::kSeedInverseMetric) return;
  const int n = n_;
  // The nearest cell (a coordinate that is not a number, from a velocity that is not, gives 0).
  const auto cell = [n](double x) { return x * n >= 1 ? std::min(int(x * n), n - 1) : 0; };
  const int i = cell(x0), j = cell(x1);
  const double* g = &cell_gi_[3 * ((std::size_t(q) * n + j) * n + i)];
  const double u0 = out[0], u1 = out[1];
  out[0] = g[0] * u0 + g[1] * u1;
  out[1] = g[1] * u0 + g[2] * u1;
}

SurfaceFluid::Landing SurfaceFluid::trace_back(int p, double x0, double x1) const {
  const double dt = params_.dt;
  double v[2];
  trace_velocity_at(p, x0, x1, v);
  const Landing mid = walk(p, x0, x1, -0.5 * dt * v[0], -0.5 * dt * v[1]);
  trace_velocity_at(mid.patch, mid.x[0], mid.x[1], v);
  turn(-mid.turns, v);  // into p's frame
  return walk(p, x0, x1, -dt * v[0], -dt * v[1]);
}

void SurfaceFluid::advect_dye() {
  const int n = n_;
  const double h = 1.0 / n;
  const PatchGrid& g = op_.grid();
  const double before = params_.conserve_dye ? dye_total() : 0;
  op_.executor().for_rows(patches_, n * n, [&](int p0, int p1) {
    for (int p = p0; p < p1; ++p) exchange_velocity(vel_, p), g.exchange(s_, p);
  });
  op_.executor().for_rows(patches_, n * n, [&](int p0, int p1) {
    for (int p = p0; p < p1; ++p)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          const Landing at = trace_back(p, (i + 0.5) * h, (j + 0.5) * h);
          s_next_[g.index(p, i, j)] =
              sample_cells(g.view(std::as_const(s_), at.patch), at.x[0], at.x[1], n);
        }
  });
  std::swap(s_, s_next_);
  if (params_.conserve_dye && before > 0) conserve_dye(before);
}

void SurfaceFluid::conserve_dye(double before) {
  const int n = n_;
  const PatchGrid& g = op_.grid();
  // The dye into [0, 1] first (an extrapolated corner ghost may take a trace's value past it).
  // Then the one factor c with sum area min(1, c s) = before: c = before / after when no cell
  // reaches 1; otherwise the cells at 1 stay there and c changes to put the rest on the others
  // (a fixed-point iteration that settles in a few passes; at most 64). held: the area of the
  // cells with c s >= 1; rest: sum area s over the others. Per patch, then summed in patch
  // order: the same bits for any number of workers. A c that is not finite (a total that does
  // not fit beside a dye of denormal size) stops the iteration at the last finite c.
  double c = 1;
  for (int pass = 0; pass < 64; ++pass) {
    op_.executor().for_rows(patches_, n * n, [&](int p0, int p1) {
      for (int p = p0; p < p1; ++p) {
        double held = 0, rest = 0;
        for (int j = 0; j < n; ++j)
          for (int i = 0; i < n; ++i) {
            double& s = s_[g.index(p, i, j)];
            s = std::clamp(s, 0.0, 1.0);
            const double area = area_[(std::size_t(p) * n + j) * n + i];
            if (c * s >= 1)
              held += area;
            else
              rest += area * s;
          }
        patch_sums_[2 * std::size_t(p)] = held, patch_sums_[2 * std::size_t(p) + 1] = rest;
      }
    });
    double held = 0, rest = 0;
    for (int p = 0; p < patches_; ++p)
      held += patch_sums_[2 * std::size_t(p)], rest += patch_sums_[2 * std::size_t(p) + 1];
    if (!(rest > 0)) break;  // all the dye at 1: it holds what fits
    const double next = std::max(0.0, before - held) / rest;
    if (!std::isfinite(next)) break;
    const bool settled = next == c;
    c = next;
    if (settled) break;
  }
  op_.executor().for_rows(patches_, n * n, [&](int p0, int p1) {
    for (int p = p0; p < p1; ++p)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          double& s = s_[g.index(p, i, j)];
          s = std::min(1.0, c * s);
        }
  });
}

void SurfaceFluid::advect_velocity() {
  const int n = n_;
  const double h = 1.0 / n;
  exchange_velocity();
  op_.executor().for_rows(patches_, n * n, [&](int p0, int p1) {
    double v[2];
    for (int p = p0; p < p1; ++p) {
      for (int j = 0; j < n; ++j)
        for (int i = 0; i <= n; ++i) {
          const Landing at = trace_back(p, i * h, (j + 0.5) * h);
          velocity_at(at.patch, at.x[0], at.x[1], v);
          turn(-at.turns, v);
          vel_next_[u1_index(p, i, j)] = v[0];
        }
      for (int j = 0; j <= n; ++j)
        for (int i = 0; i < n; ++i) {
          const Landing at = trace_back(p, (i + 0.5) * h, j * h);
          velocity_at(at.patch, at.x[0], at.x[1], v);
          turn(-at.turns, v);
          vel_next_[u2_index(p, i, j)] = v[1];
        }
    }
  });
  std::swap(vel_, vel_next_);  // the ghosts are stale until the next exchange
  stitch(vel_);
}

int SurfaceFluid::apply_viscosity() {
  if (!(params_.viscosity > 0)) return 0;
  const int n = n_;
  const double c = params_.dt * params_.viscosity;
  vel_rhs_ = vel_;  // same size: a copy
  op_.executor().for_rows(patches_, n * n, [&](int p0, int p1) {
    for (int p = p0; p < p1; ++p) {  // the patch faces only, not the (stale) ghost ring
      double m = 0;
      for (int j = 0; j < n; ++j)
        for (int i = 0; i <= n; ++i) m = std::max(m, std::abs(vel_rhs_[u1_index(p, i, j)]));
      for (int j = 0; j <= n; ++j)
        for (int i = 0; i < n; ++i) m = std::max(m, std::abs(vel_rhs_[u2_index(p, i, j)]));
      patch_max_[std::size_t(p)] = m;
    }
  });
  double bmax = *std::max_element(patch_max_.begin(), patch_max_.end());
  if (bmax == 0) bmax = 1;
  int sweeps = 0;
  for (; sweeps < params_.viscous.max_sweeps; ++sweeps) {
    op_.executor().for_rows(patches_, n * n, [&](int p0, int p1) {
      for (int p = p0; p < p1; ++p) exchange_velocity(vel_, p);
    });
    op_.executor().for_rows(patches_, n * n, [&](int p0, int p1) {
      for (int p = p0; p < p1; ++p)
        patch_max_[std::size_t(p)] = mac_viscosity_sweep(
            u1_view(std::as_const(vel_), p), u2_view(std::as_const(vel_), p),
            u1_view(std::as_const(vel_rhs_), p), u2_view(std::as_const(vel_rhs_), p), stencil(p), c,
            u1_view(vel_next_, p).crop(Box2{{0, 0}, {n + 1, n}}),
            u2_view(vel_next_, p).crop(Box2{{0, 0}, {n, n + 1}}), n);
    });
    const double residual = *std::max_element(patch_max_.begin(), patch_max_.end()) / bmax;
    if (residual <= params_.viscous.tolerance) break;
    std::swap(vel_, vel_next_);
    stitch(vel_);
  }
  return sweeps;
}

}  // namespace ardcell
