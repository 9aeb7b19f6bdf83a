#pragma once
// Integer 2-vectors and half-open boxes of grid cells. A box's minimum may be negative: cells
// at x < 0 or y < 0 are halo cells, so a kernel reads its neighbours with no special case.
#include <algorithm>
#include <cstdint>
#include <ostream>

namespace ardcell {

struct Int2 {
  int x = 0, y = 0;
  friend constexpr Int2 operator+(Int2 a, Int2 b) { return {a.x + b.x, a.y + b.y}; }
  friend constexpr Int2 operator-(Int2 a, Int2 b) { return {a.x - b.x, a.y - b.y}; }
  friend constexpr Int2 operator*(Int2 a, int s) { return {a.x * s, a.y * s}; }
  friend constexpr bool operator==(Int2, Int2) = default;
  friend std::ostream& operator<<(std::ostream& os, Int2 v) {
    return os << '(' << v.x << ", " << v.y << ')';
  }
};

// Cells {(x, y) : min.x <= x < max.x, min.y <= y < max.y}.
struct Box2 {
  Int2 min, max;

  constexpr int width() const { return max.x - min.x; }
  constexpr int height() const { return max.y - min.y; }
  constexpr Int2 size() const { return {width(), height()}; }
  constexpr bool empty() const { return max.x <= min.x || max.y <= min.y; }
  constexpr int64_t area() const { return empty() ? 0 : int64_t(width()) * height(); }
  constexpr bool contains(Int2 p) const {
    return p.x >= min.x && p.x < max.x && p.y >= min.y && p.y < max.y;
  }
  constexpr bool contains(const Box2& b) const {
    return b.empty() ||
           (b.min.x >= min.x && b.min.y >= min.y && b.max.x <= max.x && b.max.y <= max.y);
  }
  // Grown by n cells on every side (shrunk when n < 0).
  constexpr Box2 grown(int n) const { return {{min.x - n, min.y - n}, {max.x + n, max.y + n}}; }
  constexpr Box2 shifted(Int2 d) const { return {min + d, max + d}; }
  constexpr Box2 intersected(const Box2& b) const {
    return {{std::max(min.x, b.min.x), std::max(min.y, b.min.y)},
            {std::min(max.x, b.max.x), std::min(max.y, b.max.y)}};
  }
  // The smallest box holding both (an empty box adds nothing).
  constexpr Box2 united(const Box2& b) const {
    if (b.empty()) return *this;
    if (empty()) return b;
    return {{std::min(min.x, b.min.x), std::min(min.y, b.min.y)},
            {std::max(max.x, b.max.x), std::max(max.y, b.max.y)}};
  }
  friend constexpr bool operator==(const Box2&, const Box2&) = default;
  friend std::ostream& operator<<(std::ostream& os, const Box2& b) {
    return os << '[' << b.min << ", " << b.max << ')';
  }
};

constexpr Box2 box_of_size(Int2 size) { return {{0, 0}, size}; }

}  // namespace ardcell
