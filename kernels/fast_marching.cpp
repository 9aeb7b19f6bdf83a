#include "kernels/fast_marching.h"

#include <algorithm>
#include <cmath>

#include "runtime/check.h"

namespace ardcell {

namespace {
constexpr uint8_t kFar = 0, kTrial = 1, kKnown = 2;
}

FastMarchingWorkspace::FastMarchingWorkspace(Int2 size) : size_(size) {
  const std::size_t n = std::size_t(size.x) * std::size_t(size.y);
  heap_.reserve(n);
  heap_pos_.assign(n, -1);
  state_.assign(n, kFar);
}

// The marching loop over one region; a class only to share the views between the helpers.
class FastMarcher {
 public:
  FastMarcher(View<float> d, std::span<const View<float>> values, const Box2& region,
              const FastMarchingParams& p, FastMarchingWorkspace& ws)
      : d_(d), values_(values), region_(region), p_(p), ws_(ws), w_(region.width()) {
    inv_h2_ = 1.0 / (p.h * p.h);
  }

  int64_t run() {
    const int n = w_ * region_.height();
    ws_.heap_.clear();
    std::fill_n(ws_.state_.begin(), n, kFar);
    std::fill_n(ws_.heap_pos_.begin(), n, -1);
    for (int y = region_.min.y; y < region_.max.y; ++y)
      for (int x = region_.min.x; x < region_.max.x; ++x)
        if (std::isfinite(d_(x, y))) ws_.state_[std::size_t(index(x, y))] = kKnown;
    for (int y = region_.min.y; y < region_.max.y; ++y)
      for (int x = region_.min.x; x < region_.max.x; ++x)
        if (ws_.state_[std::size_t(index(x, y))] == kKnown) update_neighbours(x, y);
    int64_t accepted = 0;
    while (!ws_.heap_.empty()) {
      const int c = pop();
      const int x = region_.min.x + c % w_, y = region_.min.y + c / w_;
      if (double(d_(x, y)) > p_.max_distance) {
        d_(x, y) = kFarDistance;
        ws_.state_[std::size_t(c)] = kFar;
        // Everything left in the heap is farther still.
        for (int32_t r : ws_.heap_) {
          const int rx = region_.min.x + r % w_, ry = region_.min.y + r / w_;
          d_(rx, ry) = kFarDistance;
          ws_.state_[std::size_t(r)] = kFar;
          ws_.heap_pos_[std::size_t(r)] = -1;
        }
        ws_.heap_.clear();
        break;
      }
      ws_.state_[std::size_t(c)] = kKnown;
      extend_values(x, y);
      ++accepted;
      update_neighbours(x, y);
    }
    return accepted;
  }

 private:
  int index(int x, int y) const { return (y - region_.min.y) * w_ + (x - region_.min.x); }
  bool known(int x, int y) const {
    return region_.contains(Int2{x, y}) && ws_.state_[std::size_t(index(x, y))] == kKnown;
  }

  // Along one axis: the known upwind neighbour with the smaller T (offset s = +-1), if any.
  bool upwind(int x, int y, int ax, int ay, int& s, double& t1) const {
    bool found = false;
    for (int sign : {-1, 1}) {
      const int nx = x + sign * ax, ny = y + sign * ay;
      if (!known(nx, ny)) continue;
      const double t = d_(nx, ny);
      if (!found || t < t1) {
        found = true;
        t1 = t;
        s = sign;
      }
    }
    return found;
  }

  double solve(int x, int y) const {
    struct Axis {
      double t1, c1, b1;  // first order: coefficient 1/h^2, centre T1
      double c2, b2;      // second order (if available)
      bool second;
    };
    Axis axes[2];
    int n = 0;
    for (int a = 0; a < 2; ++a) {
      const int ax = a == 0 ? 1 : 0, ay = a == 0 ? 0 : 1;
      int s = 0;
      double t1 = 0;
      if (!upwind(x, y, ax, ay, s, t1)) continue;
      Axis& A = axes[n++];
      A.t1 = t1;
      A.c1 = inv_h2_;
      A.b1 = t1;
      A.second = false;
      if (p_.order >= 2) {
        const int x2 = x + 2 * s * ax, y2 = y + 2 * s * ay;
        if (known(x2, y2)) {
          const double t2 = d_(x2, y2);
          if (t2 <= t1) {
            // (3T - 4T1 + T2) / (2h) = 1.5/h (T - (4T1 - T2)/3)
            A.second = true;
            A.c2 = 2.25 * inv_h2_;
            A.b2 = (4.0 * t1 - t2) / 3.0;
          }
        }
      }
    }
    if (n == 0) return kFarDistance;
    auto one = [](double c, double b) { return b + 1.0 / std::sqrt(c); };
    auto two = [](double ca, double ba, double cb, double bb, double lower, double& t) {
      const double A = ca + cb, B = -2.0 * (ca * ba + cb * bb),
                   C = ca * ba * ba + cb * bb * bb - 1.0;
      const double disc = B * B - 4.0 * A * C;
      if (disc < 0) return false;
      t = (-B + std::sqrt(disc)) / (2.0 * A);
      return t >= lower;
    };
    if (n == 2) {
      const double lower = std::max(axes[0].t1, axes[1].t1);
      double t = 0;
      const Axis &a = axes[0], &b = axes[1];
      if (p_.order >= 2 && (a.second || b.second) &&
          two(a.second ? a.c2 : a.c1, a.second ? a.b2 : a.b1, b.second ? b.c2 : b.c1,
              b.second ? b.b2 : b.b1, lower, t))
        return t;
      if (two(a.c1, a.b1, b.c1, b.b1, lower, t)) return t;
    }
    double best = kFarDistance;
    for (int k = 0; k < n; ++k) {
      const Axis& a = axes[k];
      const double t = a.second ? one(a.c2, a.b2) : one(a.c1, a.b1);
      best = std::min(best, t >= a.t1 ? t : one(a.c1, a.b1));
    }
    return best;
  }

  void update_neighbours(int x, int y) {
    static constexpr int dx[4] = {-1, 1, 0, 0}, dy[4] = {0, 0, -1, 1};
    for (int k = 0; k < 4; ++k) {
      const int nx = x + dx[k], ny = y + dy[k];
      if (!region_.contains(Int2{nx, ny})) continue;
      const int c = index(nx, ny);
      const uint8_t st = ws_.state_[std::size_t(c)];
      if (st == kKnown) continue;
      const double t = solve(nx, ny);
      if (st == kFar) {
        d_(nx, ny) = float(t);
        ws_.state_[std::size_t(c)] = kTrial;
        push(c);
      } else if (t < d_(nx, ny)) {
        d_(nx, ny) = float(t);
        sift_up(ws_.heap_pos_[std::size_t(c)]);
      }
    }
  }

  // Adalsteinsson & Sethian: grad T . grad F = 0 with first-order upwind differences on the
  // neighbours the distance used: sum_a (T - T_a)(F - F_a) = 0, so F = sum w_a F_a / sum w_a
  // with w_a = T - T_a. A convex combination: no overshoot, constants stay exactly constant.
  void extend_values(int x, int y) {
    if (values_.empty()) return;
    const double t = d_(x, y);
    int nb_x[2], nb_y[2];
    double w[2];
    int n = 0;
    for (int a = 0; a < 2; ++a) {
      const int ax = a == 0 ? 1 : 0, ay = a == 0 ? 0 : 1;
      int s = 0;
      double t1 = 0;
      if (!upwind(x, y, ax, ay, s, t1) || t1 > t) continue;
      nb_x[n] = x + s * ax;
      nb_y[n] = y + s * ay;
      w[n] = t - t1;
      ++n;
    }
    if (n == 0) return;
    double wsum = 0;
    for (int k = 0; k < n; ++k) wsum += w[k];
    if (!(wsum > 0)) {
      // Equal distances (a tie on the front): the plain average of the upwind values.
      for (int k = 0; k < n; ++k) w[k] = 1;
      wsum = n;
    }
    for (const View<float>& v : values_) {
      double f = 0;
      for (int k = 0; k < n; ++k) f += w[k] * double(v(nb_x[k], nb_y[k]));
      v(x, y) = float(f / wsum);
    }
  }

  float key(int c) const { return d_(region_.min.x + c % w_, region_.min.y + c / w_); }
  void push(int c) {
    ws_.heap_.push_back(c);
    ws_.heap_pos_[std::size_t(c)] = int32_t(ws_.heap_.size() - 1);
    sift_up(int(ws_.heap_.size() - 1));
  }
  int pop() {
    const int top = ws_.heap_[0];
    ws_.heap_pos_[std::size_t(top)] = -1;
    const int32_t last = ws_.heap_.back();
    ws_.heap_.pop_back();
    if (!ws_.heap_.empty()) {
      ws_.heap_[0] = last;
      ws_.heap_pos_[std::size_t(last)] = 0;
      sift_down(0);
    }
    return top;
  }
  void place(int i, int32_t c) {
    ws_.heap_[std::size_t(i)] = c;
    ws_.heap_pos_[std::size_t(c)] = i;
  }
  void sift_up(int i) {
    const int32_t c = ws_.heap_[std::size_t(i)];
    const float k = key(c);
    while (i > 0) {
      const int parent = (i - 1) / 2;
      const int32_t pc = ws_.heap_[std::size_t(parent)];
      if (key(pc) <= k) break;
      place(i, pc);
      i = parent;
    }
    place(i, c);
  }
  void sift_down(int i) {
    const int n = int(ws_.heap_.size());
    const int32_t c = ws_.heap_[std::size_t(i)];
    const float k = key(c);
    for (;;) {
      int child = 2 * i + 1;
      if (child >= n) break;
      if (child + 1 < n &&
          key(ws_.heap_[std::size_t(child + 1)]) < key(ws_.heap_[std::size_t(child)]))
        ++child;
      const int32_t cc = ws_.heap_[std::size_t(child)];
      if (key(cc) >= k) break;
      place(i, cc);
      i = child;
    }
    place(i, c);
  }

  View<float> d_;
  std::span<const View<float>> values_;
  Box2 region_;
  FastMarchingParams p_;
  FastMarchingWorkspace& ws_;
  int w_;
  double inv_h2_;
};

int64_t fast_marching(View<float> distance, std::span<const View<float>> values, const Box2& region,
                      const FastMarchingParams& params, FastMarchingWorkspace& workspace) {
  if (region.empty()) return 0;
  ARDCELL_CHECK(distance.box().contains(region), "fast_marching: distance view misses region");
  for (const View<float>& v : values)
    ARDCELL_CHECK(v.box().contains(region), "fast_marching: value view misses region");
  ARDCELL_CHECK(region.width() <= workspace.size().x && region.height() <= workspace.size().y,
                "fast_marching: workspace smaller than region");
  ARDCELL_CHECK(params.h > 0 && (params.order == 1 || params.order == 2),
                "fast_marching: h > 0 and order 1 or 2");
  return FastMarcher(distance, values, region, params, workspace).run();
}

float fast_atan2(float y, float x) {
  // Octant reduction, then a degree-9 odd minimax polynomial for atan on [0, 1].
  const float ax = std::fabs(x), ay = std::fabs(y);
  const float mx = std::max(ax, ay), mn = std::min(ax, ay);
  if (mx == 0.f) return 0.f;
  const float a = mn / mx;
  const float s = a * a;
  float r =
      ((((0.0208351f * s - 0.0851330f) * s + 0.1801410f) * s - 0.3302995f) * s + 0.9998660f) * a;
  if (ay > ax) r = 1.57079637f - r;
  if (x < 0) r = 3.14159274f - r;
  return y < 0 ? -r : r;
}

OrientationExtender::OrientationExtender(Int2 size, int coarsening)
    : size_(size), factor_(std::max(1, coarsening)) {
  coarse_ = {(size.x + factor_ - 1) / factor_, (size.y + factor_ - 1) / factor_};
  dist_ = FieldF(coarse_, 0);
  cos_ = FieldF(coarse_, 0);
  sin_ = FieldF(coarse_, 0);
  ws_ = FastMarchingWorkspace(coarse_);
}

bool OrientationExtender::march(View<const float> weight, View<const float> dir_cos,
                                View<const float> dir_sin) {
  bool any = false;
  for (int cy = 0; cy < coarse_.y; ++cy) {
    for (int cx = 0; cx < coarse_.x; ++cx) {
      double c = 0, s = 0, w = 0;
      const int x1 = std::min(size_.x, (cx + 1) * factor_),
                y1 = std::min(size_.y, (cy + 1) * factor_);
      for (int y = cy * factor_; y < y1; ++y) {
        const float* wr = weight.row(y);
        for (int x = cx * factor_; x < x1; ++x) {
          if (wr[x] > 0) {
            w += wr[x];
            c += double(wr[x]) * dir_cos(x, y);
            s += double(wr[x]) * dir_sin(x, y);
          }
        }
      }
      if (w > 0) {
        any = true;
        dist_(cx, cy) = 0.f;
        const double len = std::hypot(c, s);
        cos_(cx, cy) = len > 0 ? float(c / len) : 0.f;
        sin_(cx, cy) = len > 0 ? float(s / len) : 0.f;
      } else {
        dist_(cx, cy) = kFarDistance;
      }
    }
  }
  if (!any) return false;
  const View<float> values[2] = {cos_.view(), sin_.view()};
  FastMarchingParams p;
  p.order = 1;  // only the extension matters here; first order is the cheaper sweep
  fast_marching(dist_.view(), values, box_of_size(coarse_), p, ws_);
  return true;
}

void OrientationExtender::upsample_rows(View<const float> weight, View<const float> dir_cos,
                                        View<const float> dir_sin, View<float> theta0, int y0,
                                        int y1, float scale, float offset) const {
  const float inv = 1.f / float(factor_);
  for (int y = y0; y < y1; ++y) {
    float fy = (float(y) + 0.5f) * inv - 0.5f;
    fy = std::clamp(fy, 0.f, float(coarse_.y - 1));
    const int j0 = std::min(int(fy), coarse_.y - 1), j1 = std::min(j0 + 1, coarse_.y - 1);
    const float ty = fy - float(j0);
    const float *c0 = cos_.row(j0), *c1 = cos_.row(j1), *s0 = sin_.row(j0), *s1 = sin_.row(j1);
    const float* wr = weight.row(y);
    float* out = theta0.row(y);
    for (int x = 0; x < size_.x; ++x) {
      if (wr[x] > 0) {
        out[x] = scale * fast_atan2(dir_sin(x, y), dir_cos(x, y)) + offset;
        continue;
      }
      float fx = (float(x) + 0.5f) * inv - 0.5f;
      fx = std::clamp(fx, 0.f, float(coarse_.x - 1));
      const int i0 = std::min(int(fx), coarse_.x - 1), i1 = std::min(i0 + 1, coarse_.x - 1);
      const float tx = fx - float(i0);
      const float c =
          (1 - ty) * ((1 - tx) * c0[i0] + tx * c0[i1]) + ty * ((1 - tx) * c1[i0] + tx * c1[i1]);
      const float s =
          (1 - ty) * ((1 - tx) * s0[i0] + tx * s0[i1]) + ty * ((1 - tx) * s1[i0] + tx * s1[i1]);
      out[x] = scale * fast_atan2(s, c) + offset;
    }
  }
}

bool OrientationExtender::extend(View<const float> weight, View<const float> dir_cos,
                                 View<const float> dir_sin, View<float> theta0, float scale,
                                 float offset) {
  if (!march(weight, dir_cos, dir_sin)) return false;
  upsample_rows(weight, dir_cos, dir_sin, theta0, 0, size_.y, scale, offset);
  return true;
}

}  // namespace ardcell
