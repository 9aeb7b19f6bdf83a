#include "runtime/boundary.h"

namespace ardcell {

BoundaryFill BoundaryFill::stam(int b) {
  const EdgeFill copy{EdgeRule::kCopy, 0.0f};
  const EdgeFill negate{EdgeRule::kMirror, 0.0f};
  if (b == 1) return {negate, negate, copy, copy};
  if (b == 2) return {copy, copy, negate, negate};
  return all(copy);
}

BoundaryFill BoundaryFill::no_slip(float lid) {
  const EdgeFill wall{EdgeRule::kMirror, 0.0f};
  return {wall, wall, wall, {EdgeRule::kMirror, lid}};
}

namespace {

bool reads_inner(EdgeRule r) {
  return r == EdgeRule::kCopy || r == EdgeRule::kMirror || r == EdgeRule::kParabolic;
}

// Ghost value from the rule, the nearest interior value and the value one domain away; `k` of
// `n` is the cell's position along the side (the parabolic profile).
inline float ghost_value(const EdgeFill& e, float inner, float wrapped, int k, int n) {
  switch (e.rule) {
    case EdgeRule::kParabolic:
      return 2.0f * (e.value * parabolic_profile(k, n)) - inner;
    case EdgeRule::kCopy:
      return inner;
    case EdgeRule::kFixed:
      return e.value;
    case EdgeRule::kMirror:
      return 2.0f * e.value - inner;
    case EdgeRule::kPeriodic:
      return wrapped;
  }
  return inner;
}

// Fills the vertical ghost column x = ghost_x from interior column inner_x (and wrap_x for
// periodic), rows [y0, y1) clipped to the view.
void fill_column(View<float> f, const EdgeFill& e, int ghost_x, int inner_x, int wrap_x, int y0,
                 int y1, int n_along) {
  const Box2& b = f.box();
  if (ghost_x < b.min.x || ghost_x >= b.max.x) return;
  const bool need_inner = reads_inner(e.rule);
  const bool need_wrap = e.rule == EdgeRule::kPeriodic;
  if (need_inner && (inner_x < b.min.x || inner_x >= b.max.x)) return;
  if (need_wrap && (wrap_x < b.min.x || wrap_x >= b.max.x)) return;
  y0 = std::max(y0, b.min.y);
  y1 = std::min(y1, b.max.y);
  for (int y = y0; y < y1; ++y) {
    float* r = f.row(y);
    r[ghost_x] =
        ghost_value(e, need_inner ? r[inner_x] : 0.0f, need_wrap ? r[wrap_x] : 0.0f, y, n_along);
  }
}

// Fills the horizontal ghost row y = ghost_y from rows inner_y / wrap_y, columns [x0, x1).
void fill_row(View<float> f, const EdgeFill& e, int ghost_y, int inner_y, int wrap_y, int x0,
              int x1, int n_along) {
  const Box2& b = f.box();
  if (ghost_y < b.min.y || ghost_y >= b.max.y) return;
  const bool need_inner = reads_inner(e.rule);
  const bool need_wrap = e.rule == EdgeRule::kPeriodic;
  if (need_inner && (inner_y < b.min.y || inner_y >= b.max.y)) return;
  if (need_wrap && (wrap_y < b.min.y || wrap_y >= b.max.y)) return;
  x0 = std::max(x0, b.min.x);
  x1 = std::min(x1, b.max.x);
  float* g = f.row(ghost_y);
  const float* in = need_inner ? f.row(inner_y) : nullptr;
  const float* wr = need_wrap ? f.row(wrap_y) : nullptr;
  switch (e.rule) {
    case EdgeRule::kCopy:
      for (int x = x0; x < x1; ++x) g[x] = in[x];
      break;
    case EdgeRule::kFixed:
      for (int x = x0; x < x1; ++x) g[x] = e.value;
      break;
    case EdgeRule::kMirror: {
      const float twice = 2.0f * e.value;
      for (int x = x0; x < x1; ++x) g[x] = twice - in[x];
      break;
    }
    case EdgeRule::kPeriodic:
      for (int x = x0; x < x1; ++x) g[x] = wr[x];
      break;
    case EdgeRule::kParabolic:
      for (int x = x0; x < x1; ++x) g[x] = 2.0f * (e.value * parabolic_profile(x, n_along)) - in[x];
      break;
  }
}

void fill_corner(View<float> f, Int2 corner, Int2 along_x, Int2 along_y) {
  const Box2& b = f.box();
  if (!b.contains(corner) || !b.contains(along_x) || !b.contains(along_y)) return;
  f(corner) = 0.5f * (f(along_x) + f(along_y));
}

}  // namespace

void fill_boundary(View<float> f, Int2 n, const BoundaryFill& fill) {
  const bool periodic_x =
      fill.left.rule == EdgeRule::kPeriodic && fill.right.rule == EdgeRule::kPeriodic;
  const bool periodic_y =
      fill.bottom.rule == EdgeRule::kPeriodic && fill.top.rule == EdgeRule::kPeriodic;
  // Edges first (interior rows/columns only), then corners: corners read the edge ghosts.
  fill_column(f, fill.left, -1, 0, n.x - 1, 0, n.y, n.y);
  fill_column(f, fill.right, n.x, n.x - 1, 0, 0, n.y, n.y);
  fill_row(f, fill.bottom, -1, 0, n.y - 1, 0, n.x, n.x);
  fill_row(f, fill.top, n.y, n.y - 1, 0, 0, n.x, n.x);
  if (periodic_x && periodic_y) {
    // Wrap the ghost rows too: the corners become the diagonally opposite interior cells.
    fill_column(f, fill.left, -1, 0, n.x - 1, -1, 0, n.y);
    fill_column(f, fill.left, -1, 0, n.x - 1, n.y, n.y + 1, n.y);
    fill_column(f, fill.right, n.x, n.x - 1, 0, -1, 0, n.y);
    fill_column(f, fill.right, n.x, n.x - 1, 0, n.y, n.y + 1, n.y);
    return;
  }
  fill_corner(f, {-1, -1}, {0, -1}, {-1, 0});
  fill_corner(f, {n.x, -1}, {n.x - 1, -1}, {n.x, 0});
  fill_corner(f, {-1, n.y}, {0, n.y}, {-1, n.y - 1});
  fill_corner(f, {n.x, n.y}, {n.x - 1, n.y}, {n.x, n.y - 1});
}

void set_bnd(View<float> f, Int2 domain, int b) { fill_boundary(f, domain, BoundaryFill::stam(b)); }

void fill_obstacle(View<float> f, View<const uint8_t> solid, Box2 region, ObstacleRule rule) {
  if (region.empty()) return;
  ARDCELL_CHECK(f.box().contains(region.grown(1)) && solid.box().contains(region.grown(1)),
                "fill_obstacle: views must hold the region grown by 1");
  for (int y = region.min.y; y < region.max.y; ++y) {
    const uint8_t* s = solid.row(y);
    const uint8_t* sb = solid.row(y - 1);
    const uint8_t* sa = solid.row(y + 1);
    float* r = f.row(y);
    const float* rb = f.row(y - 1);
    const float* ra = f.row(y + 1);
    for (int x = region.min.x; x < region.max.x; ++x) {
      if (!s[x]) continue;
      if (rule == ObstacleRule::kZero) {
        r[x] = 0.0f;
        continue;
      }
      float sum = 0.0f;
      int count = 0;
      if (!s[x - 1]) sum += r[x - 1], ++count;
      if (!s[x + 1]) sum += r[x + 1], ++count;
      if (!sb[x]) sum += rb[x], ++count;
      if (!sa[x]) sum += ra[x], ++count;
      const float mean = count ? sum / float(count) : 0.0f;
      r[x] = rule == ObstacleRule::kNoSlip ? -mean : mean;
    }
  }
}

}  // namespace ardcell
