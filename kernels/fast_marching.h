#pragma once
// Sethian's fast marching method (PNAS 1996) for the Eikonal equation |grad T| F = 1: T is the
// arrival time of a front that starts on an interface and moves along its normal at speed F > 0
// (F = 1: T is the distance). First- or second-order upwind differences, binary heap. Also the
// extension velocities of Adalsteinsson & Sethian (J. Comput. Phys. 148, 1999): a value given
// on the interface carried outward so that grad f . grad T = 0 (constant along the
// characteristics, i.e. along the normals).
//
// One marcher behind two entry points:
// - The level-set entry point (signed_distance, travel_time, extension_velocities) follows
//   scikit-fmm's conventions (skfmm.distance / travel_time / extension_velocities, 2D):
//   * the interface is the zero contour of phi. A cell whose phi is 0 is on it (T = 0); a cell
//     whose phi changes sign towards an axis neighbour gets, per axis, the distance to the
//     crossing found by linear interpolation, d_a = dx_a phi / (phi - phi_n) (the nearer of
//     the two neighbours), and T = 1 / sqrt(sum_a 1 / d_a^2). These cells are frozen; the rest
//     is marched from them.
//   * signed_distance is negative where phi < 0. travel_time is |distance| / speed on the
//     interface cells and solves |grad T| speed = 1 beyond (always >= 0); cells whose speed is
//     below the double epsilon are masked, as scikit-fmm does.
//   * dx and dy are the cell sizes along x and y (scikit-fmm's dx = (dy, dx) for an array
//     indexed [y][x]); order 1 or 2 (scikit-fmm's default is 2); periodic per axis.
//   * mask (optional, nonzero = masked): masked cells take no part; they and every cell they
//     cut off from the interface (and, with narrow > 0, every cell beyond |T| > narrow) get
//     kFarDistance in every output, where scikit-fmm returns a masked entry.
//   * extension_velocities extends `speed` from the interface: an interface cell takes the
//     distance-weighted mean over its axes of the speed linearly interpolated at each crossing,
//     sum_a (f_a / d_a^2) / sum_a (1 / d_a^2); where ext_mask (optional, nonzero = excluded)
//     marks a cell, the value on the other side of that crossing is taken instead.
//   * A grid with one row is scikit-fmm's 1D case.
//   Differences from scikit-fmm, none of which changes one of its published values: where a
//   cell's distance quadratic has no real root scikit-fmm leaves the cell as it was, here it
//   takes the smallest one-axis solution (scikit-fmm's own fallback for travel times); a
//   second-order stencil pairs a neighbour with the cell beyond that same neighbour only; an
//   extension value uses, per axis, the frozen neighbour nearest the interface on either side
//   of it (scikit-fmm's choice flips on the positive side) and, with no usable weight, the
//   plain mean of its frozen neighbours (scikit-fmm: an error); masked cells are never
//   neighbours, periodic or not.
// - The stroke entry point (fast_marching) takes unsigned distances at caller-chosen source
//   cells instead of phi: the painting code's orientation (Kim & Lin section 6: stroke
//   orientations spread this way set theta0, extended as (cos, sin) and taken back with atan2
//   so nothing tears at 0 / 2 pi).
//
// Distances and times are marched in double (workspace) and written as float.
//
// Unlike the local stencil kernels this is a global sweep: it reads and writes every cell of
// its region (no halo beyond it); cells outside the region are never touched.
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

// Scratch for one grid size: heap, back pointers, cell states, marched values. Allocated once;
// marching allocates nothing.
class FastMarchingWorkspace {
 public:
  FastMarchingWorkspace() = default;
  explicit FastMarchingWorkspace(Int2 size);
  Int2 size() const { return size_; }

 private:
  friend class FastMarcher;
  Int2 size_{};
  std::vector<int32_t> heap_;      // cell indices, ordered by |value_|
  std::vector<int32_t> heap_pos_;  // cell -> index in heap_, -1 when not in the heap
  std::vector<int32_t> batch_;     // cells frozen together (tied values)
  std::vector<uint8_t> state_;     // far, trial, frozen, masked
  std::vector<int8_t> side_;       // sign of phi (+1 everywhere for the stroke entry point)
  std::vector<double> value_;      // signed distance or travel time
};

// Stroke entry point: marches over `region` (whose size must fit the workspace) from source
// cells whose unsigned distance the caller gives.
// Second order needs source cells at least two cells deep on each side of the interface: the
// distance is unsigned, so a one-cell band would let a second-order stencil reach across it.
// Extension values use first-order upwind weights (a convex combination of known neighbours).
// distance: on entry, the distance (>= 0) of each source cell to the interface, kFarDistance
//   at every other cell; on exit, the distance everywhere (up to max_distance).
// values: extension channels (any number, each a view containing region); on entry defined at
//   the source cells, on exit extended to every reached cell.
// Returns the number of cells accepted (sources not counted).
int64_t fast_marching(View<float> distance, std::span<const View<float>> values, const Box2& region,
                      const FastMarchingParams& params, FastMarchingWorkspace& workspace);

// Level-set entry point (scikit-fmm's conventions, see the top of this file).
struct LevelSetParams {
  double dx = 1.0;  // cell size along x (> 0)
  double dy = 1.0;  // cell size along y (> 0)
  int order = 2;    // 1 or 2
  bool periodic_x = false, periodic_y = false;
  // > 0: marching stops once |T| passes narrow (scikit-fmm's narrow band); 0: no limit.
  double narrow = 0.0;
};

// Optional cell masks (nonzero = set); a default-constructed view means none. Each one given
// must contain phi's box.
struct LevelSetMasks {
  View<const uint8_t> mask;      // cells that take no part (scikit-fmm's masked phi)
  View<const uint8_t> ext_mask;  // extension_velocities only: speeds not to interpolate from
};

// The grid is phi's box; every view must contain it and the workspace must fit its size.
// Each returns the number of cells given a value; 0 when phi has no zero contour (scikit-fmm's
// "no zero level set" error), every output then kFarDistance.
int64_t signed_distance(View<const float> phi, View<float> distance, const LevelSetParams& params,
                        FastMarchingWorkspace& workspace, const LevelSetMasks& masks = {});
int64_t travel_time(View<const float> phi, View<const float> speed, View<float> time,
                    const LevelSetParams& params, FastMarchingWorkspace& workspace,
                    const LevelSetMasks& masks = {});
// distance: the signed distance; extended: speed extended from the interface (must not be the
// memory of speed).
int64_t extension_velocities(View<const float> phi, View<const float> speed, View<float> distance,
                             View<float> extended, const LevelSetParams& params,
                             FastMarchingWorkspace& workspace, const LevelSetMasks& masks = {});

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
