// `ardcell propagator`: seed 003's Fig. 1, the polar plot of the diffusion propagator p_tau(r) of
// a tensor sequence at |r| = radius (kernels/gram_charlier.h), as a PNG, and the directions of
// its lobes - the dominant orientations of the texture that sequence grows.
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "drivers/bitmap_font.h"
#include "drivers/cli.h"
#include "drivers/png_writer.h"
#include "host/io/atomic_file.h"
#include "host/render/polar_plot.h"
#include "kernels/generalized_diffusion.h"
#include "kernels/gram_charlier.h"

namespace ardcell {
namespace {

constexpr int kSamples = 720;  // every half degree

struct PropagatorArgs {
  std::string sequence, out;
  double tau = 0.1, radius = 1.0;
  int size = 512;
};

constexpr const char* kKeys = "xx, xy, yy, xxx, xxy, xyy, yyy, xxxx, xxxy, xxyy, xyyy, yyyy";

// The component a key names: its x and y counts (the tensors are symmetric, so "yx" is xy).
double* component_for(TensorSequence& d, const std::string& key) {
  int nx = 0, ny = 0;
  for (char c : key) {
    if (c == 'x' || c == 'X')
      ++nx;
    else if (c == 'y' || c == 'Y')
      ++ny;
    else
      return nullptr;
  }
  if (nx + ny < 2 || nx + ny > 4) return nullptr;
  return &d.component(nx, ny);
}

// A Table 2 letter, or key=value pairs; "" when fine, else the one-line reason.
std::string parse_sequence(const std::string& text, TensorSequence& out, std::string& label) {
  if (text.size() == 1) {
    const char letter = char(std::tolower(static_cast<unsigned char>(text[0])));
    for (const NamedTensorSequence& named : kTable2)
      if (named.name.size() == 1 && named.name[0] == letter) {
        out = named.tensors;
        label = "(" + std::string(1, letter) + ")";
        return "";
      }
  }
  const std::string expected =
      " (expected a Table 2 letter a-f, or key=value pairs such as xx=1,yy=1,xxxx=1 with keys " +
      std::string(kKeys) + ")";
  TensorSequence d;
  std::vector<double*> seen;
  std::size_t begin = 0;
  while (true) {
    const std::size_t comma = text.find(',', begin);
    const std::string item =
        text.substr(begin, comma == std::string::npos ? std::string::npos : comma - begin);
    const std::size_t eq = item.find('=');
    if (eq == std::string::npos)
      return "sequence '" + text + "': '" + item + "' is not key=value" + expected;
    const std::string key = item.substr(0, eq), value = item.substr(eq + 1);
    double* slot = component_for(d, key);
    if (!slot) return "sequence '" + text + "': unknown tensor component '" + key + "'" + expected;
    for (double* s : seen)
      if (s == slot) return "sequence '" + text + "': component '" + key + "' given twice";
    seen.push_back(slot);
    char* end = nullptr;
    const double v = std::strtod(value.c_str(), &end);
    if (value.empty() || end != value.c_str() + value.size() || !std::isfinite(v))
      return "sequence '" + text + "': " + key + "='" + value + "' (expected a finite number)";
    *slot = v;
    if (comma == std::string::npos) break;
    begin = comma + 1;
  }
  // N(0, 2 tau D2) of Eqn 23 needs a positive definite rank-2 part.
  if (!(d.xx > 0 && d.xx * d.yy - d.xy * d.xy > 0))
    return "sequence '" + text +
           "': the rank-2 part must be positive definite (expected xx > 0 and xx*yy - xy^2 > 0)";
  out = d;
  label = "";
  return "";
}

// "45" or "44.7": degrees rounded to a tenth, in [0, 360).
std::string format_degrees(double deg) {
  double r = std::round(deg * 10.0) / 10.0;
  if (r >= 360.0) r -= 360.0;
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f", r);
  std::string s = buf;
  if (s.ends_with(".0")) s.resize(s.size() - 2);
  return s;
}

void draw_label(ImageRgb8& image, const std::string& text, int x, int y, int scale, Rgb8 c) {
  draw_text(text, x, y, scale, [&](int px, int py) {
    for (int dy = 0; dy < scale; ++dy)
      for (int dx = 0; dx < scale; ++dx) {
        const int X = px + dx, Y = py + dy;
        if (X < 0 || Y < 0 || X >= image.width || Y >= image.height) continue;
        uint8_t* p = image.row(Y) + 3 * X;
        p[0] = c.r, p[1] = c.g, p[2] = c.b;
      }
  });
}

int text_width(const std::string& text, int scale) {
  return int(text.size()) * kGlyphAdvance * scale - scale;
}

// The angle labels at the ends of the axes, a title and the colour legend.
void add_labels(ImageRgb8& image, const std::string& title, bool negative) {
  const int scale = std::max(1, image.width / 256);
  const PolarPlotLayout L = polar_plot_layout(image.width);
  const int gap = 4 * scale, h = kGlyphHeight * scale;
  const int cx = int(L.cx), cy = int(L.cy), r = int(L.radius * kPolarAxisReach);
  draw_label(image, "0", cx + r + gap, cy - h / 2, scale, kPolarAxisRgb);
  draw_label(image, "90", cx - text_width("90", scale) / 2, cy - r - gap - h, scale, kPolarAxisRgb);
  draw_label(image, "180", cx - r - gap - text_width("180", scale), cy - h / 2, scale,
             kPolarAxisRgb);
  draw_label(image, "270", cx - text_width("270", scale) / 2, cy + r + gap, scale, kPolarAxisRgb);
  draw_label(image, title, gap, gap, scale, kPolarAxisRgb);
  const int bottom = image.height - gap - h;
  draw_label(image, "POSITIVE", gap, bottom - (negative ? h + gap : 0), scale, kPolarPositiveRgb);
  if (negative) draw_label(image, "NEGATIVE, DRAWN AS -P", gap, bottom, scale, kPolarNegativeRgb);
}

int do_propagator(const PropagatorArgs& a, CliContext& ctx) {
  auto usage = [&](const std::string& m) { return cli_usage_error(ctx, "propagator", m); };
  TensorSequence d;
  std::string label;
  if (std::string error = parse_sequence(a.sequence, d, label); !error.empty()) return usage(error);
  if (Status s = check_output_path(a.out, false); !s) return usage("--out " + s.message());

  std::vector<double> p(kSamples);
  propagator_on_circle(d, a.tau, a.radius, p);
  const std::vector<double> maxima = polar_maxima_degrees(p);
  ImageRgb8 image;
  const PolarPlotInfo info = draw_polar_plot(p, a.size, image);
  char title[96];
  std::snprintf(title, sizeof title, "%s%sTAU=%g R=%g", label.c_str(), label.empty() ? "" : " ",
                a.tau, a.radius);
  add_labels(image, title, info.has_negative);
  if (Status s = write_png(a.out, image); !s) {
    std::fprintf(ctx.err, "ardcell propagator: %s\n", s.message().c_str());
    return kExitFailure;
  }
  std::string list;
  for (double deg : maxima) list += (list.empty() ? "" : ",") + format_degrees(deg);
  double lo = p[0], hi = p[0];
  for (double v : p) lo = std::min(lo, v), hi = std::max(hi, v);
  std::fprintf(ctx.out, "maxima_deg=%s lobes=%zu p_min=%.6g p_max=%.6g negative=%s out=%s\n",
               list.empty() ? "none" : list.c_str(), maxima.size(), lo, hi,
               info.has_negative ? "yes" : "no", a.out.c_str());
  std::fflush(ctx.out);
  return kExitOk;
}

}  // namespace

void add_propagator_command(CLI::App& app, CliContext& ctx) {
  auto args = std::make_shared<PropagatorArgs>();
  PropagatorArgs& a = *args;
  CLI::App* cmd = app.add_subcommand(
      "propagator",
      "Fig. 1 of seed 003: polar plot of the diffusion propagator of a tensor sequence (PNG) and "
      "the directions of its lobes");
  cmd->add_option("sequence", a.sequence,
                  "a Table 2 letter a-f, or components such as xx=1,yy=1,xxxx=1,xxyy=-1,yyyy=1")
      ->required();
  cmd->add_option("--out", a.out, "the PNG to write")->required();
  cmd->add_option("--tau", a.tau, "diffusion time tau (default 0.1, as in Fig. 1)")
      ->check(finite_range(1e-6, 1e3));
  cmd->add_option("--radius", a.radius, "|r| of the circle sampled (default 1, as in Fig. 1)")
      ->check(finite_range(1e-6, 1e3));
  cmd->add_option("--size", a.size, "image side in pixels (default 512)")
      ->check(CLI::Range(64, 4096));
  cmd->callback([args, &ctx] { ctx.exit_code = do_propagator(*args, ctx); });
}

}  // namespace ardcell
