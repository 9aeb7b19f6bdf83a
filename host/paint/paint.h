#pragma once
// Painting with strokes (Kim & Lin section 6, Fig. 3). A Painter turns stroke samples
// (host/paint/stroke.h) into changes of the simulation state, in one of several modes that can be
// switched at any time:
//   deposit   chemicals A/B (and dye) blended towards deposit values under the brush (Fig. 3 top)
//   orient    the stroke tangent is rasterised as an orientation source; update_theta0() then
//             spreads it over the whole grid by fast marching extension (Fig. 3 bottom)
//   push      the fluid velocity under the brush is blended towards the stroke direction
//   obstacle  solid cells under the brush
//   erase     everything above under the brush back to its background
// The eraser end of a pen (StrokeSample::eraser) erases the current mode's layer. Pressure
// sets the brush radius (min_radius .. radius) and strength. A stroke starts at the first
// sample with the tip down: nothing joins it to where the pen was lifted (no jump).
//
// Coordinates: sample (x, y) in [0, 1], y from the top, maps to grid cell coordinates
// (x * nx, (1 - y) * ny) (the grid's y axis points up, as the frame renderer draws it).
// theta0 = theta_scale * (stroke tangent angle in grid coordinates) + theta_offset; with the
// defaults (-1, -pi) Eqn 16's single lobe (peak at theta + theta0 = 0) points opposite to the
// stroke, as in Fig. 3 bottom.
#include <algorithm>
#include <cstdint>
#include <span>
#include <string_view>

#include "host/config/scene_config.h"
#include "host/config/sim_state.h"
#include "host/paint/stroke.h"
#include "kernels/fast_marching.h"

namespace ardcell {

// The brush's soft edge, the weight of a cell at distance d from its centre: full inside half the
// radius r, falling to 0 at the rim (the blends of every mode, and painting on surfaces).
inline double brush_falloff(double d, double r) { return std::min(1.0, 2.0 * (1.0 - d / r)); }

enum class PaintMode : uint8_t { kDeposit, kOrient, kPush, kObstacle, kErase };
inline constexpr int kPaintModeCount = 5;

// "deposit", "orient", "push", "obstacle", "erase".
std::string_view paint_mode_name(PaintMode m);
bool parse_paint_mode(std::string_view name, PaintMode& out);

struct PaintConfig {
  PaintMode mode = PaintMode::kDeposit;
  float radius = 4.0f;      // brush radius in cells at full pressure
  float min_radius = 1.0f;  // at zero pressure
  float strength = 1.0f;    // blend factor at full pressure (clamped to 1 per sample)
  bool pressure_sets_strength = true;
  // deposit: what the brush blends towards; erase: the background restored.
  float deposit_a = 0.5f, deposit_b = 0.25f, deposit_dye = 1.0f;
  float background_a = 1.0f, background_b = 0.0f;
  // push: target speed along the stroke, in domain widths per second.
  float push_speed = 0.5f;
  // orient: theta0 = theta_scale * angle + theta_offset (see above).
  float theta_scale = -1.0f;
  float theta_offset = -3.14159265f;
  // orient strokes also deposit the chemicals (the stroke seeds the pattern it steers).
  bool orient_deposits = true;
  // When > 0, orient strokes deposit separate dabs (discs of the brush, blended at `strength`
  // whatever the pressure) whose centres are this many brush radii apart along the stroke,
  // instead of a continuous line.
  // A continuous line seeds stripes parallel to the stroke, which a lobe along the stroke
  // leaves standing; separate dabs each grow into a stripe across the stroke that the lobe
  // carries along it (Fig. 3 bottom).
  float orient_dab_spacing = 0.0f;
  // Coarsening of the orientation extension: 0 = automatic (about 128 coarse cells across).
  int orient_coarsening = 0;
};

// The Painter defaults for a scene: orient mode with the lobe opposite to the stroke when the
// scene's RD uses a single cosine lobe (Fig. 3 bottom), deposit otherwise; deposit and
// background values from the scene's RD; orient strokes deposit full-strength dabs 3.2 brush
// radii apart. (`ardcell run --strokes` starts from these.)
PaintConfig paint_config_for(const SceneConfig& scene);

class Painter {
 public:
  // Allocates everything it will need for a grid of `grid` cells.
  explicit Painter(Int2 grid, const PaintConfig& config = {});

  const PaintConfig& config() const { return config_; }
  // Any field may change at any time (the orientation extender is rebuilt only when
  // orient_coarsening changes, which allocates).
  void set_config(const PaintConfig& config);
  void set_mode(PaintMode mode) { config_.mode = mode; }
  PaintMode mode() const { return config_.mode; }

  // Paints samples into state (whose size must be the painter's grid). No allocation but the
  // obstacle mask's on its first stroke. A state whose fields cover one block of the grid (a
  // rank of `ardcell run --ranks`) gets the chemicals, dye and velocity of its block's cells;
  // the orientation sources and the obstacle mask are whole-grid and painted over the whole
  // grid on every block. Every block painted by the same samples gives the whole grid's painting.
  void apply(std::span<const StrokeSample> samples, SimState& state);
  void apply(const StrokeSample& sample, SimState& state) { apply({&sample, 1}, state); }

  // When orientation sources changed since the last call: theta0 over the whole grid from
  // them (fast marching extension); returns true if theta0 was written. A theta0 over a block
  // (a rank, a split wall's screen) gets the whole grid's theta0 on its cells (extended into a
  // whole-grid scratch, allocated on the first such call).
  bool update_theta0(SimState& state);
  // Forgets every orientation source (theta0 itself is left as it is).
  void clear_orientation();

  bool pen_down() const { return down_; }
  // Where a stroke stands between samples: several pens (the screens of a video wall) paint
  // through one painter by swapping their strokes in and out around apply().
  struct Stroke {
    bool down = false;
    double last_x = 0, last_y = 0, arc = 0, next_dab = 0;
  };
  Stroke stroke() const { return {down_, last_x_, last_y_, arc_, next_dab_}; }
  void set_stroke(const Stroke& s) {
    down_ = s.down;
    last_x_ = s.last_x;
    last_y_ = s.last_y;
    arc_ = s.arc;
    next_dab_ = s.next_dab;
  }
  // The rasterised orientation sources: weight > 0 under orient strokes, and their direction.
  const FieldF& orientation_weight() const { return weight_; }
  const FieldF& orientation_cos() const { return dir_cos_; }
  const FieldF& orientation_sin() const { return dir_sin_; }
  int coarsening() const { return extender_.coarsening(); }

 private:
  void segment(double x0, double y0, double x1, double y1, float pressure, bool eraser,
               SimState& s);
  // Blends A/B towards the deposit values with factor k at cell (x, y).
  void deposit_chemicals(int x, int y, float k, SimState& s) const;
  // Orient-mode dabs whose arc-length positions fall on this segment.
  void orient_dabs(double x0, double y0, double ux, double uy, double len, double r, double k_base,
                   SimState& s);
  int auto_coarsening() const;

  Int2 grid_;
  Box2 cells_;  // the cells the painted state holds (its block; the grid otherwise)
  PaintConfig config_;
  FieldF weight_, dir_cos_, dir_sin_;  // whole grid, on a block too
  FieldF block_theta0_;                // update_theta0's whole-grid scratch on a block
  OrientationExtender extender_;
  bool orientation_dirty_ = false;
  bool down_ = false;
  double last_x_ = 0, last_y_ = 0;  // grid coordinates of the previous sample of this stroke
  double arc_ = 0;                  // length of this stroke so far (cells), for the dabs
  double next_dab_ = 0;             // arc length of this stroke's next dab
};

}  // namespace ardcell
