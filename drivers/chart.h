#pragma once
// Charts drawn with PLplot, written as PNG (the memory driver, then libpng) or SVG:
// - grouped bar charts for the benchmark reports (`ardcell bench table1`, `ardcell bench
//   scenes`): a title, axis labels, panels side by side, a legend, and reference marks (the
//   Cell's published figures) as ink bars across each group;
// - polar plots of a function sampled around a circle (`ardcell propagator`, seed 003's Fig. 1).
// Both go to disk under a temporary name and are renamed, so a chart is whole or absent.
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "host/config/status.h"
#include "host/render/colormap.h"

namespace ardcell {

struct BarSeries {
  std::string name;            // legend text
  std::vector<double> values;  // one per group; NaN or <= 0 (on a log axis): no bar
};

struct BarPanel {
  std::string title;
  std::vector<BarSeries> series;
  std::vector<double> reference;  // one per group (NaN: none), or empty
};

struct BarChart {
  std::string title, x_label, y_label;
  std::string reference_label;      // legend text of the reference marks
  std::vector<std::string> groups;  // x tick labels
  std::vector<BarPanel> panels;
  bool log_y = true;
  bool vertical_group_labels = false;  // long names (presets): written upwards from the axis
};

// The polar curve's colours: where the sampled function is negative its magnitude is drawn at
// the same angle in its own colour, so a negative lobe shows instead of folding into the centre.
inline constexpr Rgb8 kPolarPositiveRgb{20, 70, 170};
inline constexpr Rgb8 kPolarNegativeRgb{210, 40, 40};

struct PolarChart {
  std::string title;
  // samples[k] is the value at theta_k = 2 pi k / samples.size() from the +x axis, counter-
  // clockwise towards +y (up). The curve is r(theta) = |p(theta)| / max |p|; non-finite
  // samples are left out.
  std::span<const double> samples;
  std::string positive_label, negative_label;  // legend; the negative entry only when used
};

// True when this build draws charts (PLplot found at configure time, ARDCELL_WITH_PLPLOT).
bool charts_available();

// Write the chart to `path`: .png (width x height pixels) or .svg. Without PLplot they return an
// error saying so.
Status write_bar_chart(const std::filesystem::path& path, const BarChart& chart, int width = 1000,
                       int height = 480);
Status write_polar_chart(const std::filesystem::path& path, const PolarChart& chart, int size);

}  // namespace ardcell
