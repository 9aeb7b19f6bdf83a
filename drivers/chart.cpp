#include "drivers/chart.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <numbers>
#include <vector>

#include "drivers/png_writer.h"
#include "host/io/atomic_file.h"
#include "host/render/image.h"

#if ARDCELL_WITH_PLPLOT
#include <plplot.h>
#endif

namespace ardcell {

#if !ARDCELL_WITH_PLPLOT

bool charts_available() { return false; }

static Status not_drawn(const std::filesystem::path& path) {
  return Status::error(path.string() +
                       ": not drawn (built without PLplot: install libplplot-dev "
                       "and reconfigure)");
}

Status write_bar_chart(const std::filesystem::path& path, const BarChart&, int, int) {
  return not_drawn(path);
}

Status write_polar_chart(const std::filesystem::path& path, const PolarChart&, int) {
  return not_drawn(path);
}

#else

namespace {

// Colour map 0: 0 background, 1 ink, 2 grid, 3.. the series (light to dark pairs cycle).
constexpr int kInk = 1, kGrid = 2, kFirstSeries = 3;
constexpr Rgb8 kBarPalette[] = {{255, 255, 255}, {30, 30, 30},    {215, 215, 215}, {40, 110, 190},
                                {40, 150, 60},   {200, 90, 50},   {130, 60, 180},  {190, 150, 20},
                                {90, 170, 200},  {120, 120, 120}, {220, 120, 170}, {60, 60, 140}};
constexpr int kSeriesColours = int(std::size(kBarPalette)) - kFirstSeries;

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

// Draws one page with `draw` into `path` (.png or .svg), whole or not at all.
template <class Draw>
Status write_page(const std::filesystem::path& path, int width, int height,
                  std::span<const Rgb8> palette, Draw&& draw) {
  auto start_stream = [&] {
    PLINT stream = 0;
    plmkstrm(&stream);
    plscmap0n(16);
    for (int i = 0; i < int(palette.size()); ++i)
      plscol0(i, palette[std::size_t(i)].r, palette[std::size_t(i)].g, palette[std::size_t(i)].b);
    plfontld(1);
  };
  if (path.extension() == ".svg") {
    // The SVG driver writes the file itself: a temporary name beside it, then a rename.
    const std::filesystem::path tmp = temporary_sibling(path);
    start_stream();
    plsdev("svg");
    plsfnam(tmp.c_str());
    plspage(0, 0, width, height, 0, 0);
    plinit();
    draw();
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
  draw();
  plend1();
  return write_png(path, image);
}

// Polar plot colour map 0.
constexpr int kPolarAxis = 1, kPolarGrid = 2, kPolarPositive = 3, kPolarNegative = 4;
constexpr Rgb8 kPolarPalette[] = {
    {255, 255, 255}, {90, 90, 90}, {210, 210, 210}, kPolarPositiveRgb, kPolarNegativeRgb};

void polyline(const std::vector<PLFLT>& x, const std::vector<PLFLT>& y) {
  plline(PLINT(x.size()), x.data(), y.data());
}

void draw_polar(const PolarChart& c, int size) {
  const double pi = std::numbers::pi;
  const double text = std::clamp(size / 350.0, 0.8, 3.0);
  // A square viewport on the square page, the title above it.
  pladv(0);
  plvpor(0.05, 0.95, 0.02, 0.92);
  plwind(-1.32, 1.32, -1.22, 1.42);
  plwidth(std::max(1.0, size / 512.0));
  plcol0(kPolarGrid);
  std::vector<PLFLT> x, y;
  for (int ring = 1; ring <= 4; ++ring) {
    x.clear(), y.clear();
    for (int k = 0; k <= 240; ++k) {
      x.push_back(0.25 * ring * std::cos(2 * pi * k / 240));
      y.push_back(0.25 * ring * std::sin(2 * pi * k / 240));
    }
    polyline(x, y);
  }
  for (int deg = 30; deg < 180; deg += 30) {
    if (deg == 90) continue;
    const double a = deg * pi / 180;
    pljoin(-std::cos(a), -std::sin(a), std::cos(a), std::sin(a));
  }
  plcol0(kPolarAxis);
  pljoin(-1.05, 0, 1.05, 0);
  pljoin(0, -1.05, 0, 1.05);
  plschr(0, text);
  plptex(1.08, -0.025, 1, 0, 0, "0#uo");
  plptex(0, 1.08, 1, 0, 0.5, "90#uo");
  plptex(-1.08, -0.025, 1, 0, 1, "180#uo");
  plptex(0, -1.14, 1, 0, 0.5, "270#uo");
  plschr(0, 1.1 * text);
  plmtex("t", 1.2, 0.5, 0.5, c.title.c_str());

  double scale = 0;
  bool negative = false;
  for (double v : c.samples)
    if (std::isfinite(v)) scale = std::max(scale, std::abs(v)), negative |= v < 0;
  const std::size_t n = c.samples.size();
  // The legend in the lower left corner.
  plschr(0, 0.9 * text);
  auto legend = [&](int colour, double at, const std::string& label) {
    plcol0(colour);
    plwidth(2 * std::max(1.0, size / 256.0));
    pljoin(-1.28, at, -1.16, at);
    plptex(-1.12, at - 0.02, 1, 0, 0, label.c_str());
  };
  legend(kPolarPositive, negative ? -1.06 : -1.16, c.positive_label);
  if (negative) legend(kPolarNegative, -1.16, c.negative_label);
  if (!(scale > 0) || n < 2) return;

  // The curve, one segment per pair of samples; where the sign changes it passes the centre.
  plwidth(2 * std::max(1.0, size / 256.0));
  auto point = [&](std::size_t k, double& px, double& py) {
    const double theta = 2 * pi * double(k % n) / double(n), r = std::abs(c.samples[k % n]) / scale;
    px = r * std::cos(theta), py = r * std::sin(theta);
  };
  for (std::size_t k = 0; k < n; ++k) {
    const double v0 = c.samples[k], v1 = c.samples[(k + 1) % n];
    if (!std::isfinite(v0) || !std::isfinite(v1)) continue;
    double x0, y0, x1, y1;
    point(k, x0, y0);
    point(k + 1, x1, y1);
    plcol0(v0 < 0 ? kPolarNegative : kPolarPositive);
    if ((v0 < 0) == (v1 < 0)) {
      pljoin(x0, y0, x1, y1);
      continue;
    }
    pljoin(x0, y0, 0, 0);
    plcol0(v1 < 0 ? kPolarNegative : kPolarPositive);
    pljoin(0, 0, x1, y1);
  }
}

}  // namespace

bool charts_available() { return true; }

Status write_bar_chart(const std::filesystem::path& path, const BarChart& chart, int width,
                       int height) {
  if (width < 200 || height < 150 || width > 8192 || height > 8192)
    return Status::error(path.string() + ": chart size " + std::to_string(width) + "x" +
                         std::to_string(height) + " (expected 200..8192 x 150..8192)");
  return write_page(path, width, height, kBarPalette, [&] { draw(chart); });
}

Status write_polar_chart(const std::filesystem::path& path, const PolarChart& chart, int size) {
  if (size < 64 || size > 8192)
    return Status::error(path.string() + ": chart size " + std::to_string(size) +
                         " (expected 64..8192)");
  return write_page(path, size, size, kPolarPalette, [&] { draw_polar(chart, size); });
}

#endif

}  // namespace ardcell
