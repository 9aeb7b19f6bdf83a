#pragma once
// Grouped bar charts for the benchmark reports (`ardcell bench table1`, `ardcell bench scenes`),
// drawn with PLplot: a title, axis labels, one or more panels side by side, a legend, and
// reference marks (the Cell's published figures) as black ticks across each group.
#include <filesystem>
#include <string>
#include <vector>

#include "host/config/status.h"

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

// True when this build draws charts (PLplot found at configure time, ARDCELL_WITH_PLPLOT).
bool charts_available();

// Writes the chart to `path`: PNG (.png, width x height pixels) or SVG (.svg), under a
// temporary name and renamed. Without PLplot it returns an error saying so.
Status write_bar_chart(const std::filesystem::path& path, const BarChart& chart, int width = 1000,
                       int height = 480);

}  // namespace ardcell
