// `ardcell propagator`: seed 003's Fig. 1, the polar plot of the diffusion propagator p_tau(r) of
// a tensor sequence at |r| = radius (kernels/gram_charlier.h), as a PNG, and the directions of
// its lobes - the dominant orientations of the texture that sequence grows.
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "drivers/chart.h"
#include "drivers/cli.h"
#include "host/io/atomic_file.h"
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

int do_propagator(const PropagatorArgs& a, CliContext& ctx) {
  auto usage = [&](const std::string& m) { return cli_usage_error(ctx, "propagator", m); };
  TensorSequence d;
  std::string label;
  if (std::string error = parse_sequence(a.sequence, d, label); !error.empty()) return usage(error);
  if (Status s = check_output_path(a.out, false); !s) return usage("--out " + s.message());
  if (!a.out.ends_with(".png") && !a.out.ends_with(".svg"))
    return usage("--out " + a.out + ": expected a .png or .svg file");

  std::vector<double> p(kSamples);
  propagator_on_circle(d, a.tau, a.radius, p);
  const std::vector<double> maxima = polar_maxima_degrees(p);
  char numbers[64];
  std::snprintf(numbers, sizeof numbers, ", #gt = %g, |r| = %g", a.tau, a.radius);
  // PLplot's text: #gt is tau, #d/#u go down/up a level.
  PolarChart chart{
      .title = "p#d#gt#u(r), " + (label.empty() ? a.sequence : "Table 2 " + label) + numbers,
      .samples = p,
      .positive_label = "p > 0",
      .negative_label = "p < 0, drawn as |p|"};
  if (Status s = write_polar_chart(a.out, chart, a.size); !s) {
    std::fprintf(ctx.err, "ardcell propagator: %s\n", s.message().c_str());
    return kExitFailure;
  }
  std::string list;
  for (double deg : maxima) list += (list.empty() ? "" : ",") + format_degrees(deg);
  double lo = p[0], hi = p[0];
  for (double v : p) lo = std::min(lo, v), hi = std::max(hi, v);
  const bool negative = lo < 0;
  std::fprintf(ctx.out, "maxima_deg=%s lobes=%zu p_min=%.6g p_max=%.6g negative=%s out=%s\n",
               list.empty() ? "none" : list.c_str(), maxima.size(), lo, hi, negative ? "yes" : "no",
               a.out.c_str());
  std::fflush(ctx.out);
  return kExitOk;
}

}  // namespace

void add_propagator_command(CLI::App& app, CliContext& ctx) {
  auto args = std::make_shared<PropagatorArgs>();
  PropagatorArgs& a = *args;
  CLI::App* cmd = app.add_subcommand(
      "propagator",
      "Fig. 1 of seed 003: polar plot of the diffusion propagator of a tensor sequence (PNG or "
      "SVG) and "
      "the directions of its lobes");
  cmd->add_option("sequence", a.sequence,
                  "a Table 2 letter a-f, or components such as xx=1,yy=1,xxxx=1,xxyy=-1,yyyy=1")
      ->required();
  cmd->add_option("--out", a.out, "the chart to write (.png or .svg)")->required();
  cmd->add_option("--tau", a.tau, "diffusion time tau (default 0.1, as in Fig. 1)")
      ->check(finite_range(1e-6, 1e3));
  cmd->add_option("--radius", a.radius, "|r| of the circle sampled (default 1, as in Fig. 1)")
      ->check(finite_range(1e-6, 1e3));
  cmd->add_option("--size", a.size, "image side in pixels (default 512)")
      ->check(CLI::Range(64, 4096));
  cmd->callback([args, &ctx] { ctx.exit_code = do_propagator(*args, ctx); });
}

}  // namespace ardcell
