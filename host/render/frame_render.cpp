#include "host/render/frame_render.h"

#include <algorithm>
#include <cmath>

namespace ardcell {
namespace {

// Reads one field's value at a cell. Vorticity and speed are derived from u and v with
// one-sided differences at the grid's border, so that no ghost cell is read. On a block of a
// decomposed grid, vorticity at an inner edge reads the neighbour's cells in the block's halo:
// as current as the plan's last exchange of u and v (the table1 plans exchange them after their
// last write, for the dye's advection).
class Sampler {
 public:
  Sampler(const SimState& s, FrameField f) : s_(s), f_(f) {}
  float operator()(int x, int y) const {
    switch (f_) {
      case FrameField::kDye:
        return s_.dye(x, y);
      case FrameField::kPressure:
        return s_.p(x, y);
      case FrameField::kA:
        return s_.A(x, y);
      case FrameField::kB:
        return s_.B(x, y);
      case FrameField::kSpeed:
        return std::hypot(s_.u(x, y), s_.v(x, y));
      case FrameField::kVorticity: {
        const int nx = s_.size.x, ny = s_.size.y;
        const int xl = std::max(x - 1, 0), xr = std::min(x + 1, nx - 1);
        const int yl = std::max(y - 1, 0), yr = std::min(y + 1, ny - 1);
        const double h = s_.h > 0 ? s_.h : 1.0;
        const double dvdx = xr > xl ? (double(s_.v(xr, y)) - s_.v(xl, y)) / ((xr - xl) * h) : 0;
        const double dudy = yr > yl ? (double(s_.u(x, yr)) - s_.u(x, yl)) / ((yr - yl) * h) : 0;
        return float(dvdx - dudy);
      }
    }
    return 0.0f;
  }

 private:
  const SimState& s_;
  FrameField f_;
};

bool is_finite(float v) { return std::isfinite(v); }

}  // namespace

bool parse_frame_field(std::string_view name, FrameField& out) {
  if (name == "dye")
    out = FrameField::kDye;
  else if (name == "speed")
    out = FrameField::kSpeed;
  else if (name == "vorticity")
    out = FrameField::kVorticity;
  else if (name == "pressure")
    out = FrameField::kPressure;
  else if (name == "A")
    out = FrameField::kA;
  else if (name == "B")
    out = FrameField::kB;
  else
    return false;
  return true;
}

std::string_view frame_field_name(FrameField field) {
  switch (field) {
    case FrameField::kDye:
      return "dye";
    case FrameField::kSpeed:
      return "speed";
    case FrameField::kVorticity:
      return "vorticity";
    case FrameField::kPressure:
      return "pressure";
    case FrameField::kA:
      return "A";
    case FrameField::kB:
      return "B";
  }
  return "dye";
}

std::string_view frame_field_names() { return "dye|speed|vorticity|pressure|A|B"; }

bool frame_field_available(const SimState& s, FrameField field, Box2 cells) {
  if (cells.empty()) cells = box_of_size(s.size);
  auto sized = [&](const FieldF& f) { return !f.empty() && f.interior().contains(cells); };
  switch (field) {
    case FrameField::kDye:
      return sized(s.dye);
    case FrameField::kPressure:
      return sized(s.p);
    case FrameField::kA:
      return sized(s.A);
    case FrameField::kB:
      return sized(s.B);
    case FrameField::kSpeed:
    case FrameField::kVorticity:
      return sized(s.u) && sized(s.v);
  }
  return false;
}

std::span<const std::string_view> frame_field_inputs(FrameField field) {
  static constexpr std::string_view kDye[] = {"dye"}, kPressure[] = {"p"}, kA[] = {"A"},
                                    kB[] = {"B"}, kVelocity[] = {"u", "v"};
  switch (field) {
    case FrameField::kDye:
      return kDye;
    case FrameField::kPressure:
      return kPressure;
    case FrameField::kA:
      return kA;
    case FrameField::kB:
      return kB;
    case FrameField::kSpeed:
    case FrameField::kVorticity:
      return kVelocity;
  }
  return kDye;
}

FrameField shown_frame_field(const SimState& state, std::string_view show, Box2 cells) {
  FrameField field = FrameField::kDye;
  if (parse_frame_field(show, field) && frame_field_available(state, field, cells)) return field;
  for (FrameField f : {FrameField::kDye, FrameField::kB, FrameField::kA, FrameField::kSpeed})
    if (frame_field_available(state, f, cells)) return f;
  return field;
}

float frame_field_value(const SimState& state, FrameField field, int x, int y) {
  return Sampler(state, field)(x, y);
}

RenderSettings default_render_settings(FrameField field) {
  RenderSettings r;
  r.field = field;
  switch (field) {
    case FrameField::kDye:
    case FrameField::kA:
    case FrameField::kB:
      r.colormap = Colormap::kViridis;
      r.range = RangeMode::kFixed;
      r.lo = 0.0f;
      r.hi = 1.0f;
      break;
    case FrameField::kSpeed:
      r.colormap = Colormap::kMagma;
      r.range = RangeMode::kAutoFromZero;
      break;
    case FrameField::kVorticity:
      r.colormap = Colormap::kRdBu;
      r.range = RangeMode::kAutoSymmetric;
      break;
    case FrameField::kPressure:
      r.colormap = Colormap::kViridis;
      r.range = RangeMode::kAuto;
      break;
  }
  return r;
}

FieldValueRange frame_value_range(const SimState& state, FrameField field, Box2 cells) {
  const Sampler sample(state, field);
  const bool has_obstacle = !state.obstacle.empty() && state.obstacle.interior().contains(cells);
  FieldValueRange r;
  for (int y = cells.min.y; y < cells.max.y; ++y)
    for (int x = cells.min.x; x < cells.max.x; ++x) {
      if (has_obstacle && state.obstacle(x, y) != 0) continue;
      const float v = sample(x, y);
      if (!is_finite(v)) continue;
      r.lo = std::min(r.lo, v);
      r.hi = std::max(r.hi, v);
      r.abs_max = std::max(r.abs_max, std::fabs(v));
    }
  return r;
}

void range_limits(RangeMode mode, const FieldValueRange& values, float& lo, float& hi) {
  float mn = values.lo, mx = values.hi;
  if (mn > mx) mn = mx = 0.0f;  // nothing finite
  switch (mode) {
    case RangeMode::kAuto:
      lo = mn;
      hi = mx;
      break;
    case RangeMode::kAutoFromZero:
      lo = 0.0f;
      hi = std::max(mx, 0.0f);
      break;
    case RangeMode::kAutoSymmetric:
      lo = -values.abs_max;
      hi = values.abs_max;
      break;
    case RangeMode::kFixed:
      break;
  }
}

RenderStats render_frame(const SimState& state, const RenderSettings& settings, ImageRgb8& image,
                         Box2 cells) {
  if (cells.empty()) cells = box_of_size(state.size);
  ARDCELL_CHECK(image.width == cells.width() && image.height == cells.height() &&
                    image.rgb.size() == std::size_t(image.width) * image.height * 3,
                "render_frame: image must be sized to the cells drawn");
  ARDCELL_CHECK(frame_field_available(state, settings.field, cells),
                "render_frame: the state does not hold the field to draw");
  const Sampler sample(state, settings.field);
  const bool has_obstacle = !state.obstacle.empty() && state.obstacle.interior().contains(cells);
  auto solid = [&](int x, int y) { return has_obstacle && state.obstacle(x, y) != 0; };

  RenderStats stats;
  float lo = settings.lo, hi = settings.hi;
  if (settings.range != RangeMode::kFixed)
    range_limits(settings.range, frame_value_range(state, settings.field, cells), lo, hi);
  stats.lo = lo;
  stats.hi = hi;
  const bool flat = !(hi > lo) || !std::isfinite(hi - lo);
  const float flat_t = settings.range == RangeMode::kAutoSymmetric ? 0.5f : 0.0f;
  const float scale = flat ? 0.0f : 1.0f / (hi - lo);

  const std::array<Rgb8, 256>& lut = colormap_lut(settings.colormap);
  for (int py = 0; py < cells.height(); ++py) {
    const int y = cells.max.y - 1 - py;
    uint8_t* out = image.row(py);
    for (int x = cells.min.x; x < cells.max.x; ++x, out += 3) {
      Rgb8 c;
      if (solid(x, y)) {
        c = kObstacleRgb;
      } else {
        const float v = sample(x, y);
        if (!is_finite(v)) {
          ++stats.non_finite;
          c = kNonFiniteRgb;
        } else {
          c = colormap_at(lut, flat ? flat_t : (v - lo) * scale);
        }
      }
      out[0] = c.r;
      out[1] = c.g;
      out[2] = c.b;
    }
  }
  return stats;
}

}  // namespace ardcell
