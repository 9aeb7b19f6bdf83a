#include "host/adaptive_quality.h"

#include <algorithm>
#include <cmath>

namespace ardcell {

namespace {
QualityBounds sanitized(QualityBounds b) {
  b.max_sweeps = std::max(1, b.max_sweeps);
  b.min_sweeps = std::clamp(b.min_sweeps, 1, b.max_sweeps);
  if (!(b.min_rd_scale > 0.0) || b.min_rd_scale > 1.0) b.min_rd_scale = 1.0;
  return b;
}
}  // namespace

AdaptiveQuality::AdaptiveQuality(const QualityBounds& bounds, AdaptiveQualitySettings settings)
    : bounds_(sanitized(bounds)), settings_(settings) {
  restore_full();
}

void AdaptiveQuality::restore_full() {
  level_ = {bounds_.max_sweeps, 1.0};
  calm_frames_ = 0;
}

void AdaptiveQuality::set_bounds(const QualityBounds& bounds) {
  bounds_ = sanitized(bounds);
  if (!bounds_.adaptive) {
    restore_full();
    return;
  }
  level_.sweeps = std::clamp(level_.sweeps, bounds_.min_sweeps, bounds_.max_sweeps);
  level_.rd_scale = std::clamp(level_.rd_scale, bounds_.min_rd_scale, 1.0);
}

bool AdaptiveQuality::update(int64_t work_ns, int64_t period_ns) {
  if (!bounds_.adaptive || period_ns <= 0) return false;
  const double load = double(work_ns) / double(period_ns);
  const QualityLevel before = level_;
  if (load > settings_.high_water) {
    calm_frames_ = 0;
    if (level_.sweeps > bounds_.min_sweeps) {
      const int lowered = int(std::floor(level_.sweeps * settings_.sweep_step));
      level_.sweeps =
          std::clamp(std::min(lowered, level_.sweeps - 1), bounds_.min_sweeps, bounds_.max_sweeps);
    } else if (level_.rd_scale > bounds_.min_rd_scale) {
      level_.rd_scale = std::max(bounds_.min_rd_scale, level_.rd_scale * settings_.rd_scale_step);
    }
    if (!(level_ == before)) ++lowered_;
  } else if (load < settings_.low_water) {
    if (++calm_frames_ >= settings_.raise_after) {
      calm_frames_ = 0;
      // Resolution comes back first: it was the last thing given up.
      if (level_.rd_scale < 1.0) {
        level_.rd_scale = std::min(1.0, level_.rd_scale / settings_.rd_scale_step);
        if (level_.rd_scale > 0.999) level_.rd_scale = 1.0;
      } else if (level_.sweeps < bounds_.max_sweeps) {
        const int raised = int(std::ceil(level_.sweeps / settings_.sweep_step));
        level_.sweeps =
            std::clamp(std::max(raised, level_.sweeps + 1), bounds_.min_sweeps, bounds_.max_sweeps);
      }
      if (!(level_ == before)) ++raised_;
    }
  } else {
    calm_frames_ = 0;
  }
  return !(level_ == before);
}

}  // namespace ardcell
