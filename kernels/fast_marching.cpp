#include "kernels/fast_marching.h"

#include <algorithm>
#include <cmath>

#include "runtime/check.h"

namespace ardcell {

namespace {
constexpr uint8_t kFar = 0, kTrial = 1, kFrozen = 2, kMasked = 3;
constexpr double kNoValue = std::numeric_limits<double>::quiet_NaN();
// scikit-fmm masks cells slower than this: 1 / F^2 would overflow the quadratic.
constexpr double kSlowestSpeed = std::numeric_limits<double>::epsilon();
// The axes in scikit-fmm's order for an array indexed [y][x] (y is its dimension 0), so that
// sums and heap insertions happen in the same order.
constexpr int kAxisOrder[2] = {1, 0};

enum class MarchMode {
  kDistance,    // signed values; a cell's root takes the side of its phi
  kTravelTime,  // values >= 0; a second-order stencil cell across the interface counts negative
};

struct MarchSetup {
  Box2 region;
  double cell[2] = {1.0, 1.0};  // cell size along x, y
  bool periodic[2] = {false, false};
  int order = 2;
  double stop_beyond = std::numeric_limits<double>::infinity();
  MarchMode mode = MarchMode::kDistance;
  View<const float> speed;                // kTravelTime: F per cell
  std::span<const View<float>> extended;  // extension channels written while marching
};
}  // namespace

FastMarchingWorkspace::FastMarchingWorkspace(Int2 size) : size_(size) {
  const std::size_t n = std::size_t(size.x) * std::size_t(size.y);
  heap_.reserve(n);
  batch_.reserve(n);
  heap_pos_.assign(n, -1);
  state_.assign(n, kFar);
  side_.assign(n, 1);
  value_.assign(n, 0.0);
}

// The marching loop over one region; a class only to share the views between the helpers.
// Cells are indexed c = y * width + x relative to the region.
class FastMarcher {
 public:
  FastMarcher(const MarchSetup& setup, FastMarchingWorkspace& ws)
      : s_(setup), ws_(ws), w_(setup.region.width()), h_(setup.region.height()) {
    for (int a = 0; a < 2; ++a) inv_cell2_[a] = 1.0 / (s_.cell[a] * s_.cell[a]);
    ws_.heap_.clear();
    std::fill_n(ws_.heap_pos_.begin(), cells(), -1);
  }

  int cells() const { return w_ * h_; }
  bool frozen(int c) const { return ws_.state_[std::size_t(c)] == kFrozen; }
  double value(int c) const { return ws_.value_[std::size_t(c)]; }
  Int2 at(int c) const { return {s_.region.min.x + c % w_, s_.region.min.y + c / w_}; }

  // Stroke entry point: cells with a finite distance are the frozen sources, all on one side.
  void freeze_sources(View<const float> distance) {
    for (int c = 0; c < cells(); ++c) {
      const float d = distance(at(c));
      const bool source = std::isfinite(d);
      ws_.state_[std::size_t(c)] = source ? kFrozen : kFar;
      ws_.side_[std::size_t(c)] = 1;
      ws_.value_[std::size_t(c)] = source ? double(d) : 0.0;
    }
  }

  // Level-set entry point: freezes the cells next to phi's zero contour (scikit-fmm's
  // initialisation, see the header). `source` is the speed: the travel-time divisor, or the
  // value to extend. Returns the number of frozen cells.
  int64_t freeze_interface(View<const float> phi, View<const float> source,
                           const LevelSetMasks& masks) {
    const bool travel = s_.mode == MarchMode::kTravelTime;
    for (int c = 0; c < cells(); ++c) {
      const Int2 p = at(c);
      const float f = phi(p);
      bool masked = masks.mask.data() != nullptr && masks.mask(p) != 0;
      if (travel && !(double(source(p)) >= kSlowestSpeed)) masked = true;
      ws_.state_[std::size_t(c)] = masked ? kMasked : kFar;
      ws_.side_[std::size_t(c)] = f > 0 ? 1 : (f < 0 ? -1 : 0);
      ws_.value_[std::size_t(c)] = 0.0;
    }
    int64_t frozen_count = 0;
    for (int c = 0; c < cells(); ++c) {
      if (ws_.state_[std::size_t(c)] != kFar || phi(at(c)) != 0.f) continue;
      ws_.state_[std::size_t(c)] = kFrozen;
      for (const View<float>& e : s_.extended) e(at(c)) = source(at(c));
      ++frozen_count;
    }
    for (int c = 0; c < cells(); ++c) {
      if (ws_.state_[std::size_t(c)] != kFar) continue;
      const Int2 p = at(c);
      const double phi_c = phi(p);
      double crossing[2] = {0, 0}, crossing_value[2] = {0, 0};
      bool borders = false;
      for (int axis : kAxisOrder) {
        for (int step : {-1, 1}) {
          const int nb = neighbour(c, axis, step);
          if (nb < 0) continue;
          const double phi_n = phi(at(nb));
          if (!(phi_c * phi_n < 0)) continue;
          borders = true;
          const double d = s_.cell[axis] * phi_c / (phi_c - phi_n);
          if (crossing[axis] != 0 && crossing[axis] <= d) continue;
          crossing[axis] = d;
          if (s_.extended.empty()) continue;
          const Int2 q = at(nb);
          const bool exclude_c = masks.ext_mask.data() != nullptr && masks.ext_mask(p) != 0;
          const bool exclude_n = masks.ext_mask.data() != nullptr && masks.ext_mask(q) != 0;
          const double f_c = source(p), f_n = source(q);
          crossing_value[axis] =
              exclude_c ? f_n : (exclude_n ? f_c : f_c + d / s_.cell[axis] * (f_n - f_c));
        }
      }
      if (!borders) continue;
      double weight_sum = 0, weighted = 0;
      for (int axis : kAxisOrder) {
        if (!(crossing[axis] > 0)) continue;
        const double w = 1.0 / (crossing[axis] * crossing[axis]);
        weight_sum += w;
        weighted += crossing_value[axis] * w;
      }
      const double distance = std::sqrt(1.0 / weight_sum);
      ws_.value_[std::size_t(c)] =
          travel ? std::fabs(distance / double(source(p))) : (phi_c < 0 ? -distance : distance);
      ws_.state_[std::size_t(c)] = kFrozen;
      for (const View<float>& e : s_.extended) e(p) = float(weighted / weight_sum);
      ++frozen_count;
    }
    return frozen_count;
  }

  // Marches from the frozen cells; returns the number of cells frozen by marching.
  int64_t march() {
    for (int c = 0; c < cells(); ++c) {
      if (ws_.state_[std::size_t(c)] != kFar || !has_frozen_neighbour(c)) continue;
      const double t = solve(c);
      if (std::isnan(t)) continue;
      ws_.value_[std::size_t(c)] = t;
      ws_.state_[std::size_t(c)] = kTrial;
      push(c);
    }
    int64_t accepted = 0;
    std::vector<int32_t>& batch = ws_.batch_;
    while (!ws_.heap_.empty()) {
      const int first = pop();
      const double key = std::fabs(value(first));
      if (key > s_.stop_beyond) {
        ws_.state_[std::size_t(first)] = kFar;
        break;
      }
      // Cells tied with the smallest value are frozen together before any neighbour is
      // updated, as scikit-fmm does (ties are common on grid-aligned fronts).
      batch.clear();
      freeze(first);
      batch.push_back(first);
      while (!ws_.heap_.empty() && key_of(ws_.heap_[0]) == key) {
        const int tied = pop();
        freeze(tied);
        batch.push_back(tied);
      }
      accepted += int64_t(batch.size());
      for (const int32_t c : batch) update_around(c);
    }
    for (const int32_t r : ws_.heap_) {
      ws_.heap_pos_[std::size_t(r)] = -1;
      if (ws_.state_[std::size_t(r)] == kTrial) ws_.state_[std::size_t(r)] = kFar;
    }
    ws_.heap_.clear();
    return accepted;
  }

 private:
  // The axis neighbour `step` cells away (wrapped on a periodic axis), or -1 outside the grid
  // or masked.
  int neighbour(int c, int axis, int step) const {
    int coord[2] = {c % w_, c / w_};
    const int n = axis == 0 ? w_ : h_;
    coord[axis] += step;
    if (coord[axis] < 0 || coord[axis] >= n) {
      if (!s_.periodic[axis]) return -1;
      coord[axis] = ((coord[axis] % n) + n) % n;
    }
    const int nb = coord[1] * w_ + coord[0];
    return ws_.state_[std::size_t(nb)] == kMasked ? -1 : nb;
  }

  bool has_frozen_neighbour(int c) const {
    for (int axis : kAxisOrder)
      for (int step : {-1, 1}) {
        const int nb = neighbour(c, axis, step);
        if (nb >= 0 && frozen(nb)) return true;
      }
    return false;
  }

  // The value of cell c from its frozen neighbours: sum_a A_a (T - t_a)^2 = 1 / F^2 with, per
  // axis, the frozen neighbour nearest the interface (smallest |T|): A = 1 / h^2 and t = T1
  // (first order), or A = 9 / (4 h^2) and t = (4 T1 - T2) / 3 where the cell beyond it is
  // frozen too and no farther from the interface (second order). NaN with no frozen neighbour.
  double solve(int c) const {
    const bool travel = s_.mode == MarchMode::kTravelTime;
    double coefficient[2], centre[2];
    int used = 0;
    for (int axis : kAxisOrder) {
      double t1 = 0, t2 = 0;
      bool have1 = false, have2 = false;
      for (int step : {-1, 1}) {
        const int nb = neighbour(c, axis, step);
        if (nb < 0 || !frozen(nb)) continue;
        const double t = value(nb);
        if (have1 && !(std::fabs(t) < std::fabs(t1))) continue;
        t1 = t;
        have1 = true;
        // A second cell belongs with its own first one (scikit-fmm keeps one found on the other
        // side, a mismatched pair; none of its published values depends on it).
        have2 = false;
        if (s_.order < 2) continue;
        const int nb2 = neighbour(c, axis, 2 * step);
        if (nb2 < 0 || !frozen(nb2)) continue;
        const double t_beyond = value(nb2);
        if (!((t_beyond <= t1 && t1 >= 0) || (t_beyond >= t1 && t1 <= 0))) continue;
        t2 = t_beyond;
        have2 = true;
        // Travel times are unsigned: a stencil cell across the interface counts negative.
        const int8_t side_c = ws_.side_[std::size_t(c)], side_1 = ws_.side_[std::size_t(nb)],
                     side_2 = ws_.side_[std::size_t(nb2)];
        if (travel && (side_2 * side_1 < 0 || side_2 * side_c < 0)) t2 = -t2;
      }
      if (!have1) continue;
      if (have2) {
        coefficient[used] = 2.25 * inv_cell2_[axis];
        centre[used] = (4.0 * t1 - t2) / 3.0;
      } else {
        coefficient[used] = inv_cell2_[axis];
        centre[used] = t1;
      }
      ++used;
    }
    if (used == 0) return kNoValue;
    const double rhs = travel ? 1.0 / (double(s_.speed(at(c))) * double(s_.speed(at(c)))) : 1.0;
    // Distances take the root on the side of phi; travel times the larger one.
    const double root_sign = (travel || ws_.side_[std::size_t(c)] > 0) ? 1.0 : -1.0;
    double a = 0, b = 0, k = -rhs;
    for (int i = 0; i < used; ++i) {
      a += coefficient[i];
      b -= 2 * coefficient[i] * centre[i];
      k += coefficient[i] * centre[i] * centre[i];
    }
    const double det = b * b - 4 * a * k;
    if (det > 0 || (travel && det == 0)) return (-b + root_sign * std::sqrt(det)) / (2 * a);
    // No real root: the smallest solution from one axis alone (scikit-fmm's fallback for
    // travel times, which this uses for distances too).
    double best = kNoValue;
    for (int i = 0; i < used; ++i) {
      const double t = centre[i] + root_sign * std::sqrt(rhs / coefficient[i]);
      if (std::isnan(best) || std::fabs(t) < std::fabs(best)) best = t;
    }
    return best;
  }

  void freeze(int c) {
    ws_.state_[std::size_t(c)] = kFrozen;
    extend_values(c);
  }

  // After c froze: re-solve its unfrozen neighbours; with second order also the cell two
  // away when the cell between is frozen (its stencil just gained a second cell).
  void update_around(int c) {
    for (int axis : kAxisOrder) {
      for (int step : {-1, 1}) {
        const int nb = neighbour(c, axis, step);
        if (nb >= 0 && !frozen(nb)) resolve(nb);
        if (s_.order == 2 && nb >= 0 && frozen(nb)) {
          const int nb2 = neighbour(c, axis, 2 * step);
          if (nb2 >= 0 && ws_.state_[std::size_t(nb2)] == kTrial) resolve(nb2);
        }
      }
    }
  }

  void resolve(int c) {
    const double t = solve(c);
    if (std::isnan(t)) return;
    ws_.value_[std::size_t(c)] = t;
    if (ws_.state_[std::size_t(c)] == kTrial) {
      reposition(ws_.heap_pos_[std::size_t(c)]);
    } else {
      ws_.state_[std::size_t(c)] = kTrial;
      push(c);
    }
  }

  // Adalsteinsson & Sethian: grad T . grad f = 0 with first-order one-sided differences,
  // sum_a (T - T_a) (f - f_a) / h_a^2 = 0, so f = sum w_a f_a / sum w_a with
  // w_a = |T - T_a| / h_a^2: a convex combination (no overshoot; a constant stays exact). Per
  // axis T_a is the frozen neighbour nearest the interface, the one the value was solved from.
  // (scikit-fmm takes the neighbour with the smaller signed T - T_a, which is that one on the
  // negative side but the farther one on the positive side; none of its published values
  // depends on the difference.)
  void extend_values(int c) {
    if (s_.extended.empty()) return;
    const double t = value(c);
    int from[4];
    double weight[4];
    int used = 0;
    for (int axis : kAxisOrder) {
      double chosen = 0;
      int chosen_cell = -1;
      for (int step : {-1, 1}) {
        const int nb = neighbour(c, axis, step);
        if (nb < 0 || !frozen(nb)) continue;
        const double d = t - value(nb);
        if (!(std::fabs(d) > std::numeric_limits<double>::epsilon())) continue;
        if (chosen_cell >= 0 && std::fabs(value(chosen_cell)) <= std::fabs(value(nb))) continue;
        chosen = d;
        chosen_cell = nb;
      }
      if (chosen_cell < 0) continue;
      from[used] = chosen_cell;
      weight[used] = std::fabs(chosen) * inv_cell2_[axis];
      ++used;
    }
    if (used == 0) {
      // Every frozen neighbour ties with this cell: their plain mean.
      for (int axis : kAxisOrder)
        for (int step : {-1, 1}) {
          const int nb = neighbour(c, axis, step);
          if (nb >= 0 && frozen(nb)) {
            from[used] = nb;
            weight[used++] = 1.0;
          }
        }
      if (used == 0) return;
    }
    double weight_sum = 0;
    for (int i = 0; i < used; ++i) weight_sum += weight[i];
    const Int2 p = at(c);
    for (const View<float>& e : s_.extended) {
      double f = 0;
      for (int i = 0; i < used; ++i) f += weight[i] * double(e(at(from[i])));
      e(p) = float(f / weight_sum);
    }
  }

  double key_of(int c) const { return std::fabs(value(c)); }
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
  // A re-solved value may rise as well as fall (second order).
  void reposition(int i) { sift_down(sift_up(i)); }
  void place(int i, int32_t c) {
    ws_.heap_[std::size_t(i)] = c;
    ws_.heap_pos_[std::size_t(c)] = i;
  }
  int sift_up(int i) {
    const int32_t c = ws_.heap_[std::size_t(i)];
    const double k = key_of(c);
    while (i > 0) {
      const int parent = (i - 1) / 2;
      const int32_t pc = ws_.heap_[std::size_t(parent)];
      if (key_of(pc) <= k) break;
      place(i, pc);
      i = parent;
    }
    place(i, c);
    return i;
  }
  void sift_down(int i) {
    const int n = int(ws_.heap_.size());
    const int32_t c = ws_.heap_[std::size_t(i)];
    const double k = key_of(c);
    for (;;) {
      int child = 2 * i + 1;
      if (child >= n) break;
      if (child + 1 < n &&
          key_of(ws_.heap_[std::size_t(child + 1)]) < key_of(ws_.heap_[std::size_t(child)]))
        ++child;
      const int32_t cc = ws_.heap_[std::size_t(child)];
      if (key_of(cc) >= k) break;
      place(i, cc);
      i = child;
    }
    place(i, c);
  }

  MarchSetup s_;
  FastMarchingWorkspace& ws_;
  int w_, h_;
  double inv_cell2_[2];
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
  MarchSetup setup;
  setup.region = region;
  setup.cell[0] = setup.cell[1] = params.h;
  setup.order = params.order;
  setup.stop_beyond = params.max_distance;
  setup.extended = values;
  FastMarcher marcher(setup, workspace);
  marcher.freeze_sources(distance);
  const int64_t accepted = marcher.march();
  for (int c = 0; c < marcher.cells(); ++c)
    distance(marcher.at(c)) = marcher.frozen(c) ? float(marcher.value(c)) : kFarDistance;
  return accepted;
}

namespace {

int64_t march_level_set(View<const float> phi, View<const float> speed, MarchMode mode,
                        View<float> out, View<float> extended, const LevelSetParams& params,
                        FastMarchingWorkspace& workspace, const LevelSetMasks& masks) {
  const Box2 grid = phi.box();
  if (grid.empty()) return 0;
  ARDCELL_CHECK(out.box().contains(grid), "level set marching: output view misses phi's box");
  ARDCELL_CHECK(speed.data() == nullptr || speed.box().contains(grid),
                "level set marching: speed view misses phi's box");
  ARDCELL_CHECK(extended.data() == nullptr || extended.box().contains(grid),
                "level set marching: extension view misses phi's box");
  ARDCELL_CHECK(extended.data() == nullptr || extended.data() != speed.data(),
                "extension_velocities: the extension must not overwrite speed");
  ARDCELL_CHECK(masks.mask.data() == nullptr || masks.mask.box().contains(grid),
                "level set marching: mask view misses phi's box");
  ARDCELL_CHECK(masks.ext_mask.data() == nullptr || masks.ext_mask.box().contains(grid),
                "level set marching: ext_mask view misses phi's box");
  ARDCELL_CHECK(grid.width() <= workspace.size().x && grid.height() <= workspace.size().y,
                "level set marching: workspace smaller than phi");
  ARDCELL_CHECK(params.dx > 0 && params.dy > 0, "level set marching: dx and dy must be > 0");
  ARDCELL_CHECK(params.order == 1 || params.order == 2, "level set marching: order 1 or 2");
  ARDCELL_CHECK(params.narrow >= 0, "level set marching: narrow must be >= 0");
  MarchSetup setup;
  setup.region = grid;
  setup.cell[0] = params.dx;
  setup.cell[1] = params.dy;
  setup.periodic[0] = params.periodic_x;
  setup.periodic[1] = params.periodic_y;
  setup.order = params.order;
  if (params.narrow > 0) setup.stop_beyond = params.narrow;
  setup.mode = mode;
  setup.speed = speed;
  const View<float> extension_channel[1] = {extended};
  if (extended.data() != nullptr) setup.extended = extension_channel;
  FastMarcher marcher(setup, workspace);
  int64_t valued = marcher.freeze_interface(phi, speed, masks);
  // No zero contour: nothing to march from (scikit-fmm raises an error).
  if (valued > 0) valued += marcher.march();
  for (int c = 0; c < marcher.cells(); ++c) {
    const bool reached = valued > 0 && marcher.frozen(c);
    out(marcher.at(c)) = reached ? float(marcher.value(c)) : kFarDistance;
    if (extended.data() != nullptr && !reached) extended(marcher.at(c)) = kFarDistance;
  }
  return valued;
}

}  // namespace

int64_t signed_distance(View<const float> phi, View<float> distance, const LevelSetParams& params,
                        FastMarchingWorkspace& workspace, const LevelSetMasks& masks) {
  return march_level_set(phi, {}, MarchMode::kDistance, distance, {}, params, workspace, masks);
}

int64_t travel_time(View<const float> phi, View<const float> speed, View<float> time,
                    const LevelSetParams& params, FastMarchingWorkspace& workspace,
                    const LevelSetMasks& masks) {
  ARDCELL_CHECK(speed.data() != nullptr, "travel_time: speed is required");
  return march_level_set(phi, speed, MarchMode::kTravelTime, time, {}, params, workspace, masks);
}

int64_t extension_velocities(View<const float> phi, View<const float> speed, View<float> distance,
                             View<float> extended, const LevelSetParams& params,
                             FastMarchingWorkspace& workspace, const LevelSetMasks& masks) {
  ARDCELL_CHECK(speed.data() != nullptr && extended.data() != nullptr,
                "extension_velocities: speed and extended are required");
  return march_level_set(phi, speed, MarchMode::kDistance, distance, extended, params, workspace,
                         masks);
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
