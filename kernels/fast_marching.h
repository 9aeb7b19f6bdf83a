#pragma once
// Sethian's fast marching method (PNAS 1996) for the distance to an interface,
// |grad T| = 1 / F with F = 1, first or second order upwind, binary heap; and the extension
// velocities of Adalsteinsson & Sethian (J. Comput. Phys. 148, 1999), which carry values given
// on the interface outward so that grad F . grad T = 0 (constant along the characteristics,
// i.e. along the normals). Kim & Lin section 6: stroke orientations spread this way set theta0,
// extended as (cos, sin) and taken back with atan2 so nothing tears at 0 / 2 pi.
//
// Unlike the local stencil kernels this is a global sweep: it reads and writes every cell of
// `region` (no halo beyond it); cells outside the region are never touched.
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "runtime/box.h"
#include "runtime/field.h"

namespace ardcell {

inline constexpr float kFarDistance = std::numeric_limits<float>::infinity();

struct FastMarchingParams {
  double h = 1.0;  // cell size
  int order = 2;   // 1: first-order upwind; 2: second-order where two upwind cells are known
  // Marching stops once the front passes this distance (a narrow band); cells beyond keep
  // kFarDistance and their extension values are left as they were.
  double max_distance = std::numeric_limits<double>::infinity();
};

// Scratch for one grid size: heap, back pointers, cell states. Allocated once; fast_marching
// allocates nothing.
class FastMarchingWorkspace {
 public:
  FastMarchingWorkspace() = default;
  explicit FastMarchingWorkspace(Int2 size);
  Int2 size() const { return size_; }

 private:
  friend class FastMarcher;
  Int2 size_{};
  std::vector<int32_t> heap_;      // cell indices, ordered by distance
  std::vector<int32_t> heap_pos_;  // cell -> index in heap_, -1 when not in the heap
  std::vector<uint8_t> state_;     // 0 far, 1 trial, 2 known
};

// Marches over `region` (whose size must fit the workspace).
// Second order needs source cells at least two cells deep on each side of the interface: the
// distance is unsigned, so a one-cell band would let a second-order stencil reach across it.
// Extension values use first-order upwind weights (a convex combination of known neighbours).
// distance: on entry, the distance (>= 0) of each source cell to the interface, kFarDistance
//   at every other cell; on exit, the distance everywhere (up to max_distance).
// values: extension channels (any number, each a view containing region); on entry defined at
//   the source cells, on exit extended to every reached cell.
// Returns the number of cells accepted.
int64_t fast_marching(View<float> distance, std::span<const View<float>> values, const Box2& region,
                      const FastMarchingParams& params, FastMarchingWorkspace& workspace);

// Orientation over a whole grid from rasterised strokes, fast enough for a live pen: the
// sources are pooled onto a grid `coarsening` times coarser, (cos, sin) extended there by
// fast marching, bilinearly upsampled and turned back into an angle; source cells keep their
// own angle exactly. coarsening = 1 is the full-grid reference.
class OrientationExtender {
 public:
  OrientationExtender() = default;
  OrientationExtender(Int2 size, int coarsening);
  Int2 size() const { return size_; }
  int coarsening() const { return factor_; }

  // weight > 0 marks a source cell whose direction is (dir_cos, dir_sin) (need not be unit).
  // Writes theta0 in (-pi, pi] for every cell of the grid [0, size). With no source at all,
  // theta0 is left unchanged and false is returned.
  // Written value: scale * angle + offset (e.g. -1 and -pi to turn a stroke angle into Eqn 16's
  // theta0 for a lobe opposite the stroke).
  bool extend(View<const float> weight, View<const float> dir_cos, View<const float> dir_sin,
              View<float> theta0, float scale = 1.f, float offset = 0.f);
  // The same, but only pools and marches; upsample_rows() then fills rows [y0, y1) of theta0
  // (independent row ranges can run on separate threads).
  bool march(View<const float> weight, View<const float> dir_cos, View<const float> dir_sin);
  void upsample_rows(View<const float> weight, View<const float> dir_cos, View<const float> dir_sin,
                     View<float> theta0, int y0, int y1, float scale = 1.f,
                     float offset = 0.f) const;

 private:
  Int2 size_{}, coarse_{};
  int factor_ = 1;
  FieldF dist_, cos_, sin_;
  FastMarchingWorkspace ws_;
};

// atan2 with |error| < 2e-5 rad, a few times faster than std::atan2 (for per-cell angles).
float fast_atan2(float y, float x);

}  // namespace ardcell
