#include "host/paint/paint.h"

#include <algorithm>
#include <cmath>

namespace ardcell {

namespace {

constexpr std::string_view kModeNames[kPaintModeCount] = {"deposit", "orient", "push", "obstacle",
                                                          "erase"};
}  // namespace

std::string_view paint_mode_name(PaintMode m) { return kModeNames[int(m) % kPaintModeCount]; }

bool parse_paint_mode(std::string_view name, PaintMode& out) {
  for (int i = 0; i < kPaintModeCount; ++i)
    if (kModeNames[i] == name) {
      out = PaintMode(i);
      return true;
    }
  return false;
}

PaintConfig paint_config_for(const SceneConfig& scene) {
  PaintConfig c;
  const AnisotropyParams& a = scene.rd.anisotropy;
  c.mode = scene.rd.enabled && a.kind == AnisotropyKind::kCosineLobes && a.lobes == 1
               ? PaintMode::kOrient
               : PaintMode::kDeposit;
  c.background_a = scene.rd.background_a;
  c.background_b = scene.rd.background_b;
  c.deposit_a = scene.rd.seed_a;
  c.deposit_b = scene.rd.seed_b;
  c.radius = std::max(1.5f, float(scene.size.x) / 128.f);
  c.min_radius = std::max(1.0f, c.radius * 0.25f);
  // Orient strokes seed the pattern as separate dabs about two stripe wavelengths apart: each
  // grows into a stripe across the stroke (a continuous line would grow stripes along it).
  c.orient_dab_spacing = 3.2f;
  return c;
}

Painter::Painter(Int2 grid, const PaintConfig& config)
    : grid_(grid),
      cells_(box_of_size(grid)),
      config_(config),
      weight_(grid, 0),
      dir_cos_(grid, 0),
      dir_sin_(grid, 0) {
  extender_ = OrientationExtender(grid, auto_coarsening());
}

int Painter::auto_coarsening() const {
  if (config_.orient_coarsening > 0) return config_.orient_coarsening;
  const int n = std::max(grid_.x, grid_.y);
  return std::clamp(n / 128, 1, 8);
}

void Painter::set_config(const PaintConfig& config) {
  const int before = extender_.coarsening();
  config_ = config;
  if (auto_coarsening() != before) {
    extender_ = OrientationExtender(grid_, auto_coarsening());
    orientation_dirty_ = true;
  }
}

void Painter::clear_orientation() {
  weight_.fill(0);
  dir_cos_.fill(0);
  dir_sin_.fill(0);
  orientation_dirty_ = false;
}

void Painter::apply(std::span<const StrokeSample> samples, SimState& s) {
  ARDCELL_CHECK(s.size == grid_, "Painter: state size differs from the painter's grid");
  cells_ = box_of_size(grid_);
  for (const FieldF* f : {&s.A, &s.B, &s.dye, &s.u})
    if (!f->empty()) {
      cells_ = f->interior();
      break;
    }
  for (const StrokeSample& sample : samples) {
    const bool touching = sample.touching() && sample.in_range;
    if (!touching) {
      down_ = false;
      continue;
    }
    if (!std::isfinite(sample.x) || !std::isfinite(sample.y)) continue;
    const double x = double(sample.x) * grid_.x;
    const double y = (1.0 - double(sample.y)) * grid_.y;
    const float pressure =
        std::clamp(std::isfinite(sample.pressure) ? sample.pressure : 0.f, 0.f, 1.f);
    if (!down_) {
      // Pen-down: the stroke starts here. A dot, never a segment from the last pen-up.
      down_ = true;
      arc_ = next_dab_ = 0;
      segment(x, y, x, y, pressure, sample.eraser, s);
    } else {
      segment(last_x_, last_y_, x, y, pressure, sample.eraser, s);
    }
    last_x_ = x;
    last_y_ = y;
  }
}

void Painter::segment(double x0, double y0, double x1, double y1, float pressure, bool eraser,
                      SimState& s) {
  const PaintConfig& c = config_;
  const double r = c.min_radius + (c.radius - c.min_radius) * double(pressure);
  if (!(r > 0)) return;
  const double k_base =
      std::min(1.0, double(c.strength) * (c.pressure_sets_strength ? double(pressure) : 1.0));
  const double dx = x1 - x0, dy = y1 - y0;
  const double len2 = dx * dx + dy * dy;
  const double len = std::sqrt(len2);
  const double ux = len > 0 ? dx / len : 0, uy = len > 0 ? dy / len : 0;
  const PaintMode mode = c.mode;
  const bool erasing = eraser || c.mode == PaintMode::kErase;
  const bool erase_all = c.mode == PaintMode::kErase;

  // Clip boxes: the state's A, B, dye, u, v hold only cells_ (a block's box), while the
  // orientation sources and the obstacle mask cover the whole grid on every block, so that each
  // block records the same whole-grid strokes (an implicit anisotropic solve gathers them).
  const Box2 grid = box_of_size(grid_);
  const bool whole_grid = mode == PaintMode::kOrient || mode == PaintMode::kObstacle || erase_all;
  const Box2 clip = whole_grid ? grid : cells_;
  const int xa = std::max(clip.min.x, int(std::floor(std::min(x0, x1) - r)));
  const int xb = std::min(clip.max.x - 1, int(std::ceil(std::max(x0, x1) + r)));
  const int ya = std::max(clip.min.y, int(std::floor(std::min(y0, y1) - r)));
  const int yb = std::min(clip.max.y - 1, int(std::ceil(std::max(y0, y1) + r)));
  // True on the whole grid (cells_ is the grid) and in the modes that write only the state:
  // then no per-cell test is needed.
  const bool all_in_cells = cells_.contains(Box2{{xa, ya}, {xb + 1, yb + 1}});
  for (int y = ya; y <= yb; ++y) {
    for (int x = xa; x <= xb; ++x) {
      const double px = x + 0.5, py = y + 0.5;
      double t = len2 > 0 ? ((px - x0) * dx + (py - y0) * dy) / len2 : 0.0;
      t = std::clamp(t, 0.0, 1.0);
      const double d = std::hypot(px - (x0 + t * dx), py - (y0 + t * dy));
      if (d > r) continue;
      const float k = float(k_base * brush_falloff(d, r));
      const bool in_cells = all_in_cells || cells_.contains(Int2{x, y});
      if (erasing) {
        if ((erase_all || mode == PaintMode::kDeposit) && in_cells) {
          if (!s.A.empty()) s.A(x, y) = c.background_a;
          if (!s.B.empty()) s.B(x, y) = c.background_b;
          if (!s.dye.empty()) s.dye(x, y) = 0;
        }
        if (erase_all || mode == PaintMode::kOrient) {
          if (weight_(x, y) > 0) orientation_dirty_ = true;
          weight_(x, y) = 0;
        }
        if ((erase_all || mode == PaintMode::kObstacle) && !s.obstacle.empty())
          s.obstacle(x, y) = 0;
        if (mode == PaintMode::kPush && !s.u.empty() && in_cells) {
          s.u(x, y) *= 1 - k;
          s.v(x, y) *= 1 - k;
        }
        continue;
      }
      switch (mode) {
        case PaintMode::kDeposit:
          deposit_chemicals(x, y, k, s);
          if (!s.dye.empty()) s.dye(x, y) += k * (c.deposit_dye - s.dye(x, y));
          break;
        case PaintMode::kOrient:
          if (c.orient_deposits && !(c.orient_dab_spacing > 0) && in_cells)
            deposit_chemicals(x, y, k, s);
          if (len > 0) {  // a dot has no direction
            weight_(x, y) = 1;
            dir_cos_(x, y) = float(ux);
            dir_sin_(x, y) = float(uy);
            orientation_dirty_ = true;
          }
          break;
        case PaintMode::kPush:
          if (len > 0 && !s.u.empty() && !s.v.empty()) {
            const double w = s.size.x * s.h > 0 ? s.size.x * s.h : 1.0;
            s.u(x, y) += k * (float(ux * c.push_speed * w) - s.u(x, y));
            s.v(x, y) += k * (float(uy * c.push_speed * w) - s.v(x, y));
          }
          break;
        case PaintMode::kObstacle:
          if (s.obstacle.empty()) s.obstacle = Field<uint8_t>(grid_, 1);  // first use only
          s.obstacle(x, y) = 1;
          if (in_cells && !s.u.empty()) s.u(x, y) = 0;
          if (in_cells && !s.v.empty()) s.v(x, y) = 0;
          break;
        case PaintMode::kErase:
          break;
      }
    }
  }
  if (mode == PaintMode::kOrient && !erasing && c.orient_deposits && c.orient_dab_spacing > 0)
    // Dabs are seeds: pressure sets their size, not their strength (weaker ones dissolve).
    orient_dabs(x0, y0, ux, uy, len, r, std::min(1.0, double(c.strength)), s);
}

void Painter::deposit_chemicals(int x, int y, float k, SimState& s) const {
  if (!s.A.empty()) s.A(x, y) += k * (config_.deposit_a - s.A(x, y));
  if (!s.B.empty()) s.B(x, y) += k * (config_.deposit_b - s.B(x, y));
}

void Painter::orient_dabs(double x0, double y0, double ux, double uy, double len, double r,
                          double k_base, SimState& s) {
  const double spacing = std::max(0.5, double(config_.orient_dab_spacing) * r);
  for (; next_dab_ <= arc_ + len; next_dab_ += spacing) {
    const double cx = x0 + (next_dab_ - arc_) * ux, cy = y0 + (next_dab_ - arc_) * uy;
    const int xa = std::max(cells_.min.x, int(std::floor(cx - r)));
    const int xb = std::min(cells_.max.x - 1, int(cx + r));
    const int ya = std::max(cells_.min.y, int(std::floor(cy - r)));
    const int yb = std::min(cells_.max.y - 1, int(cy + r));
    for (int y = ya; y <= yb; ++y)
      for (int x = xa; x <= xb; ++x) {
        const double d = std::hypot(x + 0.5 - cx, y + 0.5 - cy);
        if (d <= r) deposit_chemicals(x, y, float(k_base * brush_falloff(d, r)), s);
      }
  }
  arc_ += len;
}

bool Painter::update_theta0(SimState& s) {
  if (!orientation_dirty_) return false;
  orientation_dirty_ = false;
  if (s.theta0.empty()) s.theta0 = FieldF(grid_, 1);
  if (s.theta0.interior() == box_of_size(grid_))
    return extender_.extend(weight_.view(), dir_cos_.view(), dir_sin_.view(), s.theta0.view(),
                            config_.theta_scale, config_.theta_offset);
  // A block's theta0 (a rank, a split wall's screen): the extension fills the whole grid, and
  // every block must hold the whole grid's theta0 on its cells (an implicit anisotropic solve
  // gathers the blocks), so extend into a whole-grid scratch and keep the block's cells.
  if (block_theta0_.empty()) block_theta0_ = FieldF(grid_, 1);  // first block call only
  if (!extender_.extend(weight_.view(), dir_cos_.view(), dir_sin_.view(), block_theta0_.view(),
                        config_.theta_scale, config_.theta_offset))
    return false;  // no source: theta0 left as it is, as on the whole grid
  copy_box<float>(block_theta0_.view(), s.theta0.view(), s.theta0.interior());
  return true;
}

}  // namespace ardcell
