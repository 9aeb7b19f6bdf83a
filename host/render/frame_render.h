#pragma once
// Field -> RGB8 image for frames (PNG, video, the live display). One pixel per cell, the
// grid's y axis pointing up (row 0 of the image is the top row y = ny - 1). Non-finite values
// are drawn in kNonFiniteRgb and counted, obstacle cells in kObstacleRgb. render_frame writes
// into a caller-owned image and allocates nothing.
#include <cmath>
#include <cstdint>
#include <span>
#include <string_view>

#include "host/config/sim_state.h"
#include "host/render/colormap.h"
#include "host/render/image.h"

namespace ardcell {

enum class FrameField : uint8_t { kDye, kSpeed, kVorticity, kPressure, kA, kB };

// "dye", "speed", "vorticity", "pressure", "A", "B"; false when unknown.
bool parse_frame_field(std::string_view name, FrameField& out);
std::string_view frame_field_name(FrameField field);
std::string_view frame_field_names();  // "dye|speed|vorticity|pressure|A|B"
// Whether `state` holds what the field is drawn from (speed and vorticity need u and v) over
// `cells` (empty: the whole grid; a block of a decomposed grid holds its own). Looks at the
// fields' boxes only, not their values.
bool frame_field_available(const SimState& state, FrameField field, Box2 cells = {});
// The SimState fields the field is drawn from, by their SimState::for_each_field names ("u" and
// "v" for speed and vorticity): what a device must bring to the host to draw it.
std::span<const std::string_view> frame_field_inputs(FrameField field);
// The field `show` names when `state` holds it, else the first of dye, B, A, speed it holds (an
// RD-only scene has no dye).
FrameField shown_frame_field(const SimState& state, std::string_view show, Box2 cells = {});

// How values map to [0, 1] before the colormap.
enum class RangeMode : uint8_t {
  kFixed,          // [lo, hi] as given
  kAuto,           // [min, max] of the finite values of this frame
  kAutoFromZero,   // [0, max] (magnitudes such as speed)
  kAutoSymmetric,  // [-m, m] with m = max |value| (signed fields: 0 at the map's centre)
};

struct RenderSettings {
  FrameField field = FrameField::kDye;
  Colormap colormap = Colormap::kViridis;
  RangeMode range = RangeMode::kFixed;
  float lo = 0.0f, hi = 1.0f;  // for kFixed
};

// The usual settings for a field: dye, A and B fixed [0, 1]; speed [0, max]; vorticity
// symmetric with the diverging map; pressure [min, max].
RenderSettings default_render_settings(FrameField field);

inline constexpr Rgb8 kObstacleRgb{96, 96, 96};

struct RenderStats {
  float lo = 0, hi = 0;    // the value range that was mapped to the colormap's ends
  int64_t non_finite = 0;  // cells that were NaN or +-inf
};

// The value drawn at cell (x, y) (speed and vorticity derived from u, v; vorticity by
// central differences, one-sided at the grid's border, so no ghost cell is read).
float frame_field_value(const SimState& state, FrameField field, int x, int y);

// The least and greatest finite value of the field over `cells` (solid cells left out) and its
// largest magnitude; lo > hi when none is finite.
struct FieldValueRange {
  float lo = INFINITY, hi = -INFINITY, abs_max = 0.0f;
};
FieldValueRange frame_value_range(const SimState& state, FrameField field, Box2 cells);
// What an automatic range mode maps to the colormap's ends, from the field's values.
void range_limits(RangeMode mode, const FieldValueRange& values, float& lo, float& hi);

// Renders the cells `cells` of `state` (empty: the whole grid) into `image`, which must already
// be as wide and high as they are: the top row is the highest y.
RenderStats render_frame(const SimState& state, const RenderSettings& settings, ImageRgb8& image,
                         Box2 cells = {});

}  // namespace ardcell
