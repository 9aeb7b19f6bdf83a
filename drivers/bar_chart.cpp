#include "drivers/bar_chart.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "drivers/png_writer.h"
#include "host/render/image.h"

#if ARDCELL_WITH_PLPLOT
#include <plplot.h>
#endif

namespace ardcell {

#if !ARDCELL_WITH_PLPLOT

bool charts_available() { return false; }

Status write_bar_chart(const std::filesystem::path& path, const BarChart&, int, int) {
  return Status::error(path.string() +
                       ": not drawn (built without PLplot: install libplplot-dev "
                       "and reconfigure)");
}

#else

namespace {

// Colour map 0: 0 background, 1 ink, 2 grid, 3.. the series (light to dark pairs cycle).
constexpr int kInk = 1, kGrid = 2, kFirstSeries = 3;
constexpr unsigned char kPalette[][3] = {{255, 255, 255}, {30, 30, 30},    {215, 215, 215},
                                         {40, 110, 190},  {40, 150, 60},   {200, 90, 50},
                                         {130, 60, 180},  {190, 150, 20},  {90, 170, 200},
                                         {120, 120, 120}, {220, 120, 170}, {60, 60, 140}};
constexpr int kPaletteSize = int(sizeof kPalette / sizeof kPalette[0]);
constexpr int kSeriesColours = kPaletteSize - kFirstSeries;

bool has_value(double v, bool log_y) { return std::isfinite(v) && (!log_y || v > 0); }

// Solid fills through the software filler: a dense pattern of horizontal lines (the memory
// driver has no hardware fill, and PLplot's default would be a cross-hatch).
void solid_fill(int n, PLFLT* x, PLFLT* y) {
  plpsty(1);
  const PLINT inc[1] = {0}, del[1] = {100};
  plpat(1, inc, del);
  plfill(n, x, y);
}

void fill_rect(double x0, double y0, double x1, double y1) {
  PLFLT x[4] = {x0, x1, x1, x0}, y[4] = {y0, y0, y1, y1};
  solid_fill(4, x, y);
}

void draw(const BarChart& c) {
  const bool log_y = c.log_y;
  const auto ty = [&](double v) { return log_y ? std::log10(v) : v; };
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const BarPanel& p : c.panels) {
    for (const BarSeries& s : p.series)
      for (double v : s.values)
        if (has_value(v, log_y)) lo = std::min(lo, ty(v)), hi = std::max(hi, ty(v));
    for (double v : p.reference)
      if (has_value(v, log_y)) lo = std::min(lo, ty(v)), hi = std::max(hi, ty(v));
  }
  if (!(lo <= hi)) lo = 0, hi = 1;
  if (log_y) {
    lo = std::floor(lo), hi = std::ceil(hi);
    if (hi == lo) hi += 1;
  } else {
    lo = std::min(lo, 0.0), hi = hi + 0.08 * (hi - lo + 1e-12);
  }
  const int groups = std::max<int>(1, int(c.groups.size()));
  const int panels = std::max<int>(1, int(c.panels.size()));
  const double left = 0.08, right = 0.82, gap = 0.07, top = 0.86;
  const double bottom = c.vertical_group_labels ? 0.42 : 0.14;
  const double width = (right - left - gap * (panels - 1)) / panels;

  pladv(0);
  plvpor(0, 1, 0, 1);
  plwind(0, 1, 0, 1);
  plcol0(kInk);
  plschr(0, 1.15);
  plptex(0.5, 0.955, 1, 0, 0.5, c.title.c_str());
  plschr(0, 0.85);
  plptex(0.5 * (left + right), 0.025, 1, 0, 0.5, c.x_label.c_str());
  plptex(0.015, 0.5 * (bottom + top), 0, 1, 0.5, c.y_label.c_str());

  for (int pi = 0; pi < int(c.panels.size()); ++pi) {
    const BarPanel& p = c.panels[std::size_t(pi)];
    const double x0 = left + pi * (width + gap);
    plvpor(x0, x0 + width, bottom, top);
    plwind(-0.5, groups - 0.5, lo, hi);
    plcol0(kGrid);
    plbox("", 0, 0, log_y ? "gl" : "g", 0, 0);
    const int n = std::max<int>(1, int(p.series.size()));
    const double bar = 0.8 / n;
    for (int si = 0; si < int(p.series.size()); ++si) {
      plcol0(kFirstSeries + si % kSeriesColours);
      const std::vector<double>& vs = p.series[std::size_t(si)].values;
      for (int g = 0; g < int(vs.size()) && g < groups; ++g)
        if (has_value(vs[std::size_t(g)], log_y)) {
          const double xb = g - 0.4 + si * bar;
          fill_rect(xb + 0.05 * bar, lo, xb + 0.95 * bar,
                    std::clamp(ty(vs[std::size_t(g)]), lo, hi));
        }
    }
    // Reference marks: bars of ink a few pixels thick across the group.
    plcol0(kInk);
    const double half = 0.005 * (hi - lo);
    for (int g = 0; g < int(p.reference.size()) && g < groups; ++g)
      if (has_value(p.reference[std::size_t(g)], log_y)) {
        const double y = ty(p.reference[std::size_t(g)]);
        fill_rect(g - 0.45, y - half, g + 0.45, y + half);
      }
    plschr(0, 0.8);
    plbox("bc", 0, 0, log_y ? "bcnstvl" : "bcnstv", 0, 0);
    if (c.vertical_group_labels) plschr(0, 0.6);
    for (int g = 0; g < int(c.groups.size()); ++g)
      plmtex(c.vertical_group_labels ? "bv" : "b", c.vertical_group_labels ? 0.5 : 1.3,
             (g + 0.5) / groups, c.vertical_group_labels ? 1.0 : 0.5,
             c.groups[std::size_t(g)].c_str());
    plschr(0, 0.9);
    plmtex("t", 0.8, 0.5, 0.5, p.title.c_str());
  }

  // The legend: the series of the first panel (every panel lists the same), then the marks.
  plvpor(right + 0.02, 0.99, bottom, top);
  plwind(0, 1, 0, 1);
  plschr(0, 0.8);
  double y = 0.97;
  const double step = 0.075;
  if (!c.panels.empty())
    for (int si = 0; si < int(c.panels.front().series.size()); ++si, y -= step) {
      plcol0(kFirstSeries + si % kSeriesColours);
      fill_rect(0.02, y - 0.025, 0.14, y + 0.025);
      plcol0(kInk);
      plptex(0.18, y - 0.012, 1, 0, 0, c.panels.front().series[std::size_t(si)].name.c_str());
    }
  if (!c.reference_label.empty()) {
    plcol0(kInk);
    fill_rect(0.02, y - 0.006, 0.14, y + 0.006);
    plptex(0.18, y - 0.012, 1, 0, 0, c.reference_label.c_str());
  }
}

void start_stream() {
  PLINT stream = 0;
  plmkstrm(&stream);
  plscmap0n(16);
  for (int i = 0; i < kPaletteSize; ++i) plscol0(i, kPalette[i][0], kPalette[i][1], kPalette[i][2]);
  plfontld(1);
}

}  // namespace

bool charts_available() { return true; }

Status write_bar_chart(const std::filesystem::path& path, const BarChart& chart, int width,
                       int height) {
  if (width < 200 || height < 150 || width > 8192 || height > 8192)
    return Status::error(path.string() + ": chart size " + std::to_string(width) + "x" +
                         std::to_string(height) + " (expected 200..8192 x 150..8192)");
  if (path.extension() == ".svg") {
    // The SVG driver writes the file itself: a temporary name beside it, then a rename.
    std::string name(1, '.');  // (appends: GCC 12 warns falsely about "." + string)
    name.append(path.filename().string()).append(".tmp-").append(std::to_string(getpid()));
    const std::filesystem::path tmp = path.parent_path() / name;
    start_stream();
    plsdev("svg");
    plsfnam(tmp.c_str());
    plspage(0, 0, width, height, 0, 0);
    plinit();
    draw(chart);
    plend1();
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    if (ec) {
      std::filesystem::remove(tmp, ec);
      return Status::error(path.string() + ": cannot write the chart");
    }
    return Status::ok();
  }
  if (path.extension() != ".png")
    return Status::error(path.string() + ": chart format (expected .png or .svg)");
  // The memory driver draws into our RGB buffer; libpng writes it.
  ImageRgb8 image;
  image.resize(width, height);
  std::fill(image.rgb.begin(), image.rgb.end(), uint8_t(255));
  start_stream();
  plsdev("mem");
  plsmem(width, height, image.rgb.data());
  plinit();
  draw(chart);
  plend1();
  return write_png(path, image);
}

#endif

}  // namespace ardcell
