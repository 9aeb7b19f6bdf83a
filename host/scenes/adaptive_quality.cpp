#include "host/scenes/adaptive_quality.h"

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
// Rung r's scale, exactly as rd_scale_ladder computes it.
double rung_scale(int rung, double step) {
  double s = 1.0;
  for (int i = 0; i < rung; ++i) s *= step;
  return s;
}
constexpr double kScaleTolerance = 1e-9;
}  // namespace

std::vector<double> rd_scale_ladder(double min_rd_scale, double step) {
  std::vector<double> ladder{1.0};
  if (!(step > 0.0 && step < 1.0)) return ladder;
  for (int rung = 1; rung < 64; ++rung) {
    const double s = rung_scale(rung, step);
    if (s < min_rd_scale - kScaleTolerance) break;
    ladder.push_back(s);
  }
  return ladder;
}

AdaptiveQuality::AdaptiveQuality(const QualityBounds& bounds, AdaptiveQualitySettings settings)
    : bounds_(sanitized(bounds)), settings_(settings) {
  restore_full();
}

void AdaptiveQuality::restore_full() {
  level_ = {bounds_.max_sweeps, 0, 1.0};
  calm_frames_ = 0;
}

void AdaptiveQuality::set_bounds(const QualityBounds& bounds) {
  bounds_ = sanitized(bounds);
  if (!bounds_.adaptive) {
    restore_full();
    return;
  }
  level_.sweeps = std::clamp(level_.sweeps, bounds_.min_sweeps, bounds_.max_sweeps);
  while (level_.rd_rung > 0 && level_.rd_scale < bounds_.min_rd_scale - kScaleTolerance) {
    --level_.rd_rung;
    level_.rd_scale = rung_scale(level_.rd_rung, settings_.rd_scale_step);
  }
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
    } else if (const double lower = rung_scale(level_.rd_rung + 1, settings_.rd_scale_step);
               settings_.rd_scale_step < 1.0 && lower >= bounds_.min_rd_scale - kScaleTolerance) {
      ++level_.rd_rung;
      level_.rd_scale = lower;
    }
    if (!(level_ == before)) ++lowered_;
  } else if (load < settings_.low_water) {
    if (++calm_frames_ >= settings_.raise_after) {
      calm_frames_ = 0;
      // Resolution comes back first: it was the last thing given up.
      if (level_.rd_rung > 0) {
        --level_.rd_rung;
        level_.rd_scale = rung_scale(level_.rd_rung, settings_.rd_scale_step);
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
