#pragma once
// AdaptiveQuality: keeps a live frame inside its deadline by trading accuracy for time. When a
// frame's work comes close to the period (or misses), it lowers the solver sweeps; at the
// preset's minimum sweeps it lowers the RD resolution one rung of a fixed ladder
// (rd_scale_step^rung of the scene's grid, never below min_rd_scale). When there is slack for a
// while, it raises them back, resolution first, never above the preset's bounds. It decides; the
// live loop applies the level on the next frame: sweeps through the solver iterations
// (apply_quality), resolution through LiveSimulation::set_rd_scale, whose preallocated coarser
// RD grids are the ladder's rungs (rd_scale_ladder). Input is never dropped.
#include <cstdint>
#include <vector>

namespace ardcell {

// Bounds from the preset's [quality] table.
struct QualityBounds {
  int min_sweeps = 4;         // solver sweeps/iterations per implicit solve, lowest allowed
  int max_sweeps = 20;        // ... and the preset's full quality
  double min_rd_scale = 1.0;  // RD grid resolution as a fraction of the scene's (0 < s <= 1)
  bool adaptive = true;       // false: always run at max_sweeps and full resolution
};

struct QualityLevel {
  int sweeps = 20;
  int rd_rung = 0;        // 0: full resolution
  double rd_scale = 1.0;  // rd_scale_step^rd_rung
  friend bool operator==(const QualityLevel&, const QualityLevel&) = default;
};

inline constexpr double kRdScaleStep = 0.75;

struct AdaptiveQualitySettings {
  double high_water = 0.85;  // work above this fraction of the period: lower quality
  double low_water = 0.55;   // work below this fraction for `raise_after` frames: raise
  int raise_after = 30;
  double sweep_step = 0.75;             // multiply sweeps by this when lowering
  double rd_scale_step = kRdScaleStep;  // one rung of RD resolution
};

// The RD resolutions a level can take for a floor of min_rd_scale: 1, step, step^2, ... while
// >= min_rd_scale (exactly step^rung, so a simulation can preallocate one grid per rung).
std::vector<double> rd_scale_ladder(double min_rd_scale, double step = kRdScaleStep);

class AdaptiveQuality {
 public:
  explicit AdaptiveQuality(const QualityBounds& bounds, AdaptiveQualitySettings settings = {});

  void set_bounds(const QualityBounds& bounds);  // keeps the level, clamped into the new bounds
  const QualityBounds& bounds() const { return bounds_; }
  const QualityLevel& level() const { return level_; }
  // Back to full quality (preset switch, reset).
  void restore_full();

  // Feeds one frame's work time against the period; returns true when the level changed.
  // period_ns <= 0 (unpaced loop) never changes the level.
  bool update(int64_t work_ns, int64_t period_ns);

  int64_t lowered() const { return lowered_; }
  int64_t raised() const { return raised_; }

 private:
  QualityBounds bounds_;
  AdaptiveQualitySettings settings_;
  QualityLevel level_;
  int calm_frames_ = 0;
  int64_t lowered_ = 0;
  int64_t raised_ = 0;
};

}  // namespace ardcell
