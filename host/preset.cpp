#include "host/preset.h"

#include <toml++/toml.h>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <type_traits>

#include "host/colormap.h"
#include "host/scene_registry.h"

namespace ardcell {

namespace {

constexpr std::string_view kFluidScenes[] = {"none", "cavity", "obstacle", "ink"};
constexpr std::string_view kSolvers[] = {"jacobi", "rbgs", "iccg", "mg"};
constexpr std::string_view kShows[] = {"dye", "speed", "vorticity", "pressure", "A", "B"};
constexpr std::string_view kColormaps[] = {"gray", "viridis", "magma", "rdbu"};
constexpr std::string_view kModes[] = {"deposit", "orient", "push", "obstacle", "erase"};

template <class T>
void assign_number(T& field, double v) {
  if constexpr (std::is_enum_v<T>)
    field = static_cast<T>(static_cast<int>(v));
  else if constexpr (std::is_same_v<T, bool>)
    field = v != 0.0;
  else
    field = static_cast<T>(v);
}
template <class T>
double read_number(const T& field) {
  if constexpr (std::is_enum_v<T>)
    return double(static_cast<int>(field));
  else
    return double(field);
}

// Index of `value` in a choice list stored as a string (colormap, show, mode).
double choice_index(std::span<const std::string_view> choices, const std::string& value) {
  for (size_t i = 0; i < choices.size(); ++i)
    if (choices[i] == value) return double(i);
  return -1;
}

#define ARD_ACCESS(expr)                                      \
  .get = [](const Preset& p) { return read_number(p.expr); }, \
  .set = [](Preset& p, double v) { assign_number(p.expr, v); }
#define ARD_NUMBER(key_, expr, lo, hi, structural_, help_)                        \
  ParamSpec {                                                                     \
    .key = key_, .kind = ParamKind::kNumber, .min = lo, .max = hi, .choices = {}, \
    .structural = structural_, .help = help_, ARD_ACCESS(expr)                    \
  }
#define ARD_INTEGER(key_, expr, lo, hi, structural_, help_)                        \
  ParamSpec {                                                                      \
    .key = key_, .kind = ParamKind::kInteger, .min = lo, .max = hi, .choices = {}, \
    .structural = structural_, .help = help_, ARD_ACCESS(expr)                     \
  }
#define ARD_BOOL(key_, expr, structural_, help_)                              \
  ParamSpec {                                                                 \
    .key = key_, .kind = ParamKind::kBool, .min = 0, .max = 1, .choices = {}, \
    .structural = structural_, .help = help_, ARD_ACCESS(expr)                \
  }
// A choice stored as an enum (its value is the index in `list`).
#define ARD_ENUM(key_, expr, list, structural_, help_)                                     \
  ParamSpec {                                                                              \
    .key = key_, .kind = ParamKind::kChoice, .min = 0, .max = double(std::size(list) - 1), \
    .choices = list, .structural = structural_, .help = help_, ARD_ACCESS(expr)            \
  }
// A choice stored as a string.
#define ARD_NAMED(key_, expr, list, structural_, help_)                                    \
  ParamSpec {                                                                              \
    .key = key_, .kind = ParamKind::kChoice, .min = 0, .max = double(std::size(list) - 1), \
    .choices = list, .structural = structural_, .help = help_,                             \
    .get = [](const Preset& p) { return choice_index(list, p.expr); },                     \
    .set =                                                                                 \
        [](Preset& p, double v) {                                                          \
          const auto i = size_t(v);                                                        \
          if (i < std::size(list)) p.expr.assign(list[i].data(), list[i].size());          \
        },                                                                                 \
    .text = [](Preset& p) -> std::string& { return p.expr; }                               \
  }
#define ARD_STRING(key_, expr, help_)                                           \
  ParamSpec {                                                                   \
    .key = key_, .kind = ParamKind::kString, .min = 0, .max = 0, .choices = {}, \
    .structural = false, .help = help_, .get = nullptr, .set = nullptr,         \
    .text = [](Preset& p) -> std::string& { return p.expr; }                    \
  }
#define ARD_SOLVER(prefix, member, structural_)                                             \
  ARD_ENUM(prefix ".kind", scene.fluid.member.kind, kSolvers, true,                         \
           "jacobi | rbgs (fixed sweeps) | iccg | mg (multigrid)"),                         \
      ARD_INTEGER(prefix ".iterations", scene.fluid.member.max_iterations, 1, 10000, false, \
                  "sweeps, CG iterations or V-cycles at full quality"),                     \
      ARD_NUMBER(prefix ".tolerance", scene.fluid.member.tolerance, 0, 1, false,            \
                 "relative residual to stop at; 0 runs every iteration")

const ParamSpec kParams[] = {
    ARD_STRING("name", scene.name, "preset name (defaults to the file name)"),
    ARD_STRING("description", scene.description, "one line for listings"),
    ParamSpec{.key = "grid.size",
              .kind = ParamKind::kSize,
              .min = 4,
              .max = 8192,
              .choices = {},
              .structural = true,
              .help = "[nx, ny] cells",
              .size = [](Preset& p) -> Int2& { return p.scene.size; }},
    ARD_NUMBER("grid.domain_width", scene.domain_width, 1e-6, 1e6, true,
               "domain width; h = domain_width / nx"),
    ARD_NUMBER("grid.dt", scene.dt, 1e-9, 100, false, "time step per frame"),
    ARD_INTEGER("grid.steps", scene.default_steps, 1, 1e9, false,
                "frames for `ardcell run` without --steps"),
    ARD_ENUM("fluid.scene", scene.fluid.kind, kFluidScenes, true, "none | cavity | obstacle | ink"),
    ARD_NUMBER("fluid.viscosity", scene.fluid.viscosity, 0, 1e3, false, "kinematic viscosity"),
    ARD_NUMBER("fluid.lid_speed", scene.fluid.lid_speed, -1e3, 1e3, false, "cavity lid speed"),
    ARD_NUMBER("fluid.dye_diffusion", scene.fluid.dye_diffusion, 0, 1e3, false,
               "dye diffusion coefficient"),
    ARD_SOLVER("fluid.viscosity_solver", viscosity_solver, true),
    ARD_SOLVER("fluid.pressure_solver", pressure_solver, true),
    ARD_BOOL("rd.enabled", scene.rd.enabled, true, "run reaction-diffusion"),
    ARD_NAMED("output.show", scene.output.show, kShows, false,
              "field drawn: dye | speed | vorticity | pressure | A | B"),
    ARD_NAMED("output.colormap", scene.output.colormap, kColormaps, false,
              "palette: gray | viridis | magma | rdbu"),
    ARD_BOOL("quality.adaptive", quality.adaptive, false,
             "lower sweeps / RD resolution when a frame would miss"),
    ARD_INTEGER("quality.min_sweeps", quality.min_sweeps, 1, 10000, false,
                "fewest solver sweeps adaptive quality may use"),
    ARD_INTEGER("quality.max_sweeps", quality.max_sweeps, 1, 10000, false,
                "sweeps at full quality (scales every solver's iterations)"),
    ARD_NUMBER("quality.min_rd_scale", quality.min_rd_scale, 0.125, 1, false,
               "lowest RD resolution as a fraction of the grid"),
    ARD_NAMED("input.mode", input.mode, kModes, false,
              "painting mode: deposit | orient | push | obstacle | erase"),
    ARD_NUMBER("input.brush_radius", input.brush_radius, 1e-4, 1, false,
               "brush radius as a fraction of the grid width"),
    ARD_NUMBER("input.strength", input.strength, 0, 1e6, false, "deposit amount / push force"),
    ARD_NUMBER("input.pressure_gamma", input.pressure_gamma, 0.05, 20, false,
               "pressure response: p^gamma"),
};

#undef ARD_ACCESS
#undef ARD_NUMBER
#undef ARD_INTEGER
#undef ARD_BOOL
#undef ARD_ENUM
#undef ARD_NAMED
#undef ARD_STRING
#undef ARD_SOLVER

std::string format_number(double v) {
  char buf[64];
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  std::snprintf(buf, sizeof buf, "%.17g", v);
  std::string s = buf;
  // Shortest form that reads back exactly.
  for (int prec = 1; prec <= 17; ++prec) {
    std::snprintf(buf, sizeof buf, "%.*g", prec, v);
    if (std::strtod(buf, nullptr) == v) {
      s = buf;
      break;
    }
  }
  if (s.find_first_of(".eE") == std::string::npos) s += ".0";
  return s;
}

// For messages: short and readable ("1e-09", "1000", "0.5").
std::string human_number(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.10g", v);
  return buf;
}

std::string quoted(std::string_view s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", c);
      out += buf;
    } else {
      out += c;
    }
  }
  return out + '"';
}

std::string join_choices(std::span<const std::string_view> choices) {
  std::string s;
  for (auto c : choices) {
    if (!s.empty()) s += " | ";
    s += c;
  }
  return s;
}

std::string describe_node(const toml::node& n) {
  if (n.is_string()) return "the string " + quoted(*n.value<std::string>());
  if (n.is_integer()) return "the integer " + std::to_string(*n.value<int64_t>());
  if (n.is_floating_point()) return "the number " + human_number(*n.value<double>());
  if (n.is_boolean()) return *n.value<bool>() ? "true" : "false";
  if (n.is_table()) return "a table";
  if (n.is_array()) return "an array";
  return "a date/time";
}

class PresetParser {
 public:
  PresetParser(std::string_view source, Preset& out) : source_(source), out_(out) {}

  void table(const toml::table& t, const std::string& prefix) {
    for (auto&& [k, node] : t) {
      const std::string key =
          prefix.empty() ? std::string(k.str()) : prefix + "." + std::string(k.str());
      const int line =
          int(k.source().begin.line ? k.source().begin.line : node.source().begin.line);
      const ParamSpec* spec = find_param(key);
      if (!spec) {
        if (node.is_table() && is_section(key)) {
          table(*node.as_table(), key);
          continue;
        }
        error(line, key, unknown_key_hint(key, node.is_table()));
        continue;
      }
      value(*spec, node, line);
    }
  }

  // One value outside a file (`--set key=value`): messages carry no file:line.
  void assign(const ParamSpec& spec, const toml::node& node) { value(spec, node, 0); }

  std::vector<std::string> errors;

 private:
  static bool is_section(const std::string& key) {
    const std::string dotted = key + ".";
    for (const ParamSpec& s : preset_params())
      if (s.key.substr(0, dotted.size()) == dotted) return true;
    return false;
  }

  static std::string unknown_key_hint(const std::string& key, bool is_table) {
    const size_t dot = key.rfind('.');
    const std::string parent = dot == std::string::npos ? "" : key.substr(0, dot);
    std::string known;
    std::vector<std::string> seen;
    for (const ParamSpec& s : preset_params()) {
      std::string_view k = s.key;
      if (!parent.empty()) {
        if (k.substr(0, parent.size() + 1) != parent + ".") continue;
        k.remove_prefix(parent.size() + 1);
      }
      const std::string head(k.substr(0, k.find('.')));
      if (std::find(seen.begin(), seen.end(), head) != seen.end()) continue;
      seen.push_back(head);
      if (!known.empty()) known += ", ";
      known += head;
    }
    return std::string("unknown ") + (is_table ? "table" : "key") + "; expected one of: " + known;
  }

  void error(int line, std::string_view key, const std::string& what) {
    const std::string where =
        source_.empty() ? std::string() : std::string(source_) + ":" + std::to_string(line) + ": ";
    errors.push_back(where + std::string(key) + ": " + what);
  }

  void value(const ParamSpec& spec, const toml::node& node, int line) {
    const std::string expected = "expected " + param_expectation(spec);
    switch (spec.kind) {
      case ParamKind::kNumber: {
        if (!node.is_number())
          return error(line, spec.key, expected + ", got " + describe_node(node));
        const double v = *node.value<double>();
        if (!(v >= spec.min && v <= spec.max))
          return error(line, spec.key, expected + ", got " + human_number(v));
        spec.set(out_, v);
        return;
      }
      case ParamKind::kInteger: {
        if (!node.is_integer())
          return error(line, spec.key, expected + ", got " + describe_node(node));
        const int64_t v = *node.value<int64_t>();
        if (!(double(v) >= spec.min && double(v) <= spec.max))
          return error(line, spec.key, expected + ", got " + std::to_string(v));
        spec.set(out_, double(v));
        return;
      }
      case ParamKind::kBool:
        if (!node.is_boolean())
          return error(line, spec.key, expected + ", got " + describe_node(node));
        spec.set(out_, *node.value<bool>() ? 1.0 : 0.0);
        return;
      case ParamKind::kChoice: {
        if (!node.is_string())
          return error(line, spec.key, expected + ", got " + describe_node(node));
        const std::string s = *node.value<std::string>();
        const double i = choice_index(spec.choices, s);
        if (i < 0) return error(line, spec.key, expected + ", got " + quoted(s));
        spec.set(out_, i);
        return;
      }
      case ParamKind::kString:
        if (!node.is_string())
          return error(line, spec.key, expected + ", got " + describe_node(node));
        spec.text(out_) = *node.value<std::string>();
        return;
      case ParamKind::kSize: {
        const toml::array* a = node.as_array();
        if (!a || a->size() != 2 || !(*a)[0].is_integer() || !(*a)[1].is_integer())
          return error(line, spec.key, expected + ", got " + describe_node(node));
        const int64_t x = *(*a)[0].value<int64_t>(), y = *(*a)[1].value<int64_t>();
        if (!(double(x) >= spec.min && double(x) <= spec.max && double(y) >= spec.min &&
              double(y) <= spec.max))
          return error(line, spec.key,
                       expected + ", got [" + std::to_string(x) + ", " + std::to_string(y) + "]");
        spec.size(out_) = Int2{int(x), int(y)};
        return;
      }
    }
  }

  std::string_view source_;
  Preset& out_;
};

std::string file_stem(std::string_view path) {
  const size_t slash = path.rfind('/');
  if (slash != std::string_view::npos) path.remove_prefix(slash + 1);
  const size_t dot = path.rfind('.');
  if (dot != std::string_view::npos && dot > 0) path = path.substr(0, dot);
  return std::string(path);
}

}  // namespace

std::span<const ParamSpec> preset_params() { return kParams; }

const ParamSpec* find_param(std::string_view key) {
  for (const ParamSpec& s : kParams)
    if (s.key == key) return &s;
  return nullptr;
}

std::string param_expectation(const ParamSpec& spec) {
  switch (spec.kind) {
    case ParamKind::kNumber:
      return "a number in [" + human_number(spec.min) + ", " + human_number(spec.max) + "]";
    case ParamKind::kInteger:
      return "an integer in [" + std::to_string(int64_t(spec.min)) + ", " +
             std::to_string(int64_t(spec.max)) + "]";
    case ParamKind::kBool:
      return "true or false";
    case ParamKind::kChoice:
      return "one of " + join_choices(spec.choices);
    case ParamKind::kString:
      return "a string";
    case ParamKind::kSize:
      return "[nx, ny], two integers in [" + std::to_string(int64_t(spec.min)) + ", " +
             std::to_string(int64_t(spec.max)) + "]";
  }
  return "?";
}

Status parse_preset(std::string_view text, std::string_view source_name, Preset& out) {
  out = Preset{};
  out.source = std::string(source_name);
  toml::table root;
  try {
    root = toml::parse(text, source_name);
  } catch (const toml::parse_error& e) {
    return Status::error(std::string(source_name) + ":" + std::to_string(e.source().begin.line) +
                         ": " + std::string(e.description()));
  }
  PresetParser parser(source_name, out);
  parser.table(root, "");
  // Cross-key checks.
  if (parser.errors.empty() && out.quality.min_sweeps > out.quality.max_sweeps) {
    const auto* n = root.at_path("quality.min_sweeps").node();
    const int line = n ? int(n->source().begin.line) : 0;
    parser.errors.push_back(std::string(source_name) + ":" + std::to_string(line) +
                            ": quality.min_sweeps: expected at most quality.max_sweeps (" +
                            std::to_string(out.quality.max_sweeps) + "), got " +
                            std::to_string(out.quality.min_sweeps));
  }
  if (!parser.errors.empty()) {
    std::string all;
    for (const std::string& e : parser.errors) {
      if (!all.empty()) all += '\n';
      all += e;
    }
    return Status::error(all);
  }
  if (out.scene.name.empty()) out.scene.name = file_stem(source_name);
  return Status::ok();
}

Status load_preset_file(const std::string& path, Preset& out) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return Status::error(path + ": cannot open preset (expected a readable TOML file)");
  std::ostringstream ss;
  ss << in.rdbuf();
  return parse_preset(ss.str(), path, out);
}

Status load_preset(std::string_view name_or_path, Preset& out) {
  const bool is_path = name_or_path.find('/') != std::string_view::npos ||
                       (name_or_path.size() > 5 && name_or_path.ends_with(".toml"));
  if (is_path) return load_preset_file(std::string(name_or_path), out);
  for (const EmbeddedPreset& e : embedded_presets()) {
    if (file_stem(e.file) == name_or_path) {
      Status s = parse_preset(e.text, std::string("presets/") + e.file, out);
      if (s) out.source = "embedded:" + std::string(name_or_path);
      return s;
    }
  }
  if (const SceneEntry* entry = builtin_scenes().find(name_or_path)) {
    out = preset_from_scene(entry->make());
    return Status::ok();
  }
  std::string names;
  for (const std::string& n : preset_names()) names += (names.empty() ? "" : ", ") + n;
  return Status::error("preset '" + std::string(name_or_path) +
                       "': no such file or preset; expected a .toml path or one of: " + names);
}

Preset preset_from_scene(const SceneConfig& scene) {
  Preset p;
  p.scene = scene;
  p.source = "builtin:" + scene.name;
  return p;
}

std::string preset_to_toml(const Preset& preset) {
  std::string out = "# ardcell preset (keys: README \"Live display, presets and kiosk\")\n";
  std::string section;
  Preset& p = const_cast<Preset&>(preset);  // accessors are shared with the setters
  for (const ParamSpec& spec : kParams) {
    const size_t dot = spec.key.rfind('.');
    const std::string table =
        dot == std::string_view::npos ? "" : std::string(spec.key.substr(0, dot));
    const std::string leaf(dot == std::string_view::npos ? spec.key : spec.key.substr(dot + 1));
    if (table != section) {
      out += "\n[" + table + "]\n";
      section = table;
    }
    out += leaf + " = ";
    switch (spec.kind) {
      case ParamKind::kNumber:
        out += format_number(spec.get(p));
        break;
      case ParamKind::kInteger:
        out += std::to_string(int64_t(spec.get(p)));
        break;
      case ParamKind::kBool:
        out += spec.get(p) != 0 ? "true" : "false";
        break;
      case ParamKind::kChoice: {
        const double i = spec.get(p);
        out += i >= 0 && size_t(i) < spec.choices.size() ? quoted(spec.choices[size_t(i)])
                                                         : quoted(spec.text ? spec.text(p) : "");
        break;
      }
      case ParamKind::kString:
        out += quoted(spec.text(p));
        break;
      case ParamKind::kSize: {
        const Int2 s = spec.size(p);
        out += "[" + std::to_string(s.x) + ", " + std::to_string(s.y) + "]";
        break;
      }
    }
    out += '\n';
  }
  return out;
}

std::string preset_difference(const Preset& a, const Preset& b) {
  Preset& pa = const_cast<Preset&>(a);
  Preset& pb = const_cast<Preset&>(b);
  for (const ParamSpec& spec : kParams) {
    std::string va, vb;
    if (spec.kind == ParamKind::kString) {
      va = spec.text(pa);
      vb = spec.text(pb);
    } else if (spec.kind == ParamKind::kSize) {
      va = std::to_string(spec.size(pa).x) + "x" + std::to_string(spec.size(pa).y);
      vb = std::to_string(spec.size(pb).x) + "x" + std::to_string(spec.size(pb).y);
    } else if (spec.kind == ParamKind::kChoice && spec.text) {
      va = spec.text(pa);
      vb = spec.text(pb);
    } else {
      const double x = spec.get(a), y = spec.get(b);
      if (x == y || (std::isnan(x) && std::isnan(y))) continue;
      va = format_number(x);
      vb = format_number(y);
    }
    if (va != vb) return std::string(spec.key) + ": " + va + " vs " + vb;
  }
  return {};
}

bool presets_share_structure(const Preset& a, const Preset& b) {
  Preset& pa = const_cast<Preset&>(a);
  Preset& pb = const_cast<Preset&>(b);
  for (const ParamSpec& spec : kParams) {
    if (!spec.structural) continue;
    if (spec.kind == ParamKind::kSize) {
      if (!(spec.size(pa) == spec.size(pb))) return false;
    } else if (spec.kind == ParamKind::kString) {
      if (spec.text(pa) != spec.text(pb)) return false;
    } else if (spec.get(a) != spec.get(b)) {
      return false;
    }
  }
  return true;
}

Status apply_param_override(SceneConfig& scene, std::string_view assignment) {
  auto trim = [](std::string_view v) {
    while (!v.empty() && (v.front() == ' ' || v.front() == '\t')) v.remove_prefix(1);
    while (!v.empty() && (v.back() == ' ' || v.back() == '\t')) v.remove_suffix(1);
    return v;
  };
  const size_t eq = assignment.find('=');
  if (eq == std::string_view::npos)
    return Status::error("--set " + std::string(assignment) +
                         ": expected key=value, e.g. rd.reaction.f=0.04");
  const std::string key(trim(assignment.substr(0, eq)));
  const std::string_view text = trim(assignment.substr(eq + 1));
  const ParamSpec* spec = find_param(key);
  if (!spec || key.starts_with("quality.") || key.starts_with("input.")) {
    std::string known;
    for (const ParamSpec& s : kParams)
      if (!s.key.starts_with("quality.") && !s.key.starts_with("input.")) {
        if (!known.empty()) known += ", ";
        known += s.key;
      }
    return Status::error("--set " + key + ": unknown scene key; expected one of: " + known);
  }
  if (text.empty())
    return Status::error("--set " + key + ": expected " + param_expectation(*spec) +
                         ", got nothing after '='");
  // The value is TOML; a bare word is a string (choices, names), "256x256" a size.
  std::string value(text);
  if (spec->kind == ParamKind::kSize) {
    const size_t x = value.find('x');
    if (x != std::string::npos && value.front() != '[')
      value = "[" + value.substr(0, x) + ", " + value.substr(x + 1) + "]";
  }
  toml::table doc;
  try {
    doc = toml::parse("v = " + value);
  } catch (const toml::parse_error&) {
    if (spec->kind == ParamKind::kChoice || spec->kind == ParamKind::kString) {
      doc = toml::table{};
      doc.insert("v", std::string(text));
    } else {
      return Status::error("--set " + key + ": expected " + param_expectation(*spec) + ", got '" +
                           std::string(text) + "'");
    }
  }
  Preset edited;
  edited.scene = scene;
  PresetParser parser("", edited);
  parser.assign(*spec, *doc.get("v"));
  if (!parser.errors.empty()) return Status::error("--set " + parser.errors.front());
  scene = std::move(edited.scene);
  return Status::ok();
}

bool set_param(Preset& preset, const ParamSpec& spec, double value, std::string* why) {
  if (!spec.set) {
    if (why) *why = std::string(spec.key) + ": cannot be set live (expected a numeric key)";
    return false;
  }
  if (spec.kind == ParamKind::kInteger || spec.kind == ParamKind::kChoice)
    value = std::round(value);
  if (!(value >= spec.min && value <= spec.max)) {
    if (why)
      *why = std::string(spec.key) + ": expected " + param_expectation(spec) + ", got " +
             human_number(value);
    return false;
  }
  spec.set(preset, value);
  return true;
}

double get_param(const Preset& preset, const ParamSpec& spec) {
  return spec.get ? spec.get(preset) : 0.0;
}

void blend_params(const Preset& from, const Preset& to, double t, Preset& out) {
  t = std::clamp(t, 0.0, 1.0);
  for (const ParamSpec& spec : kParams) {
    if (!spec.set || spec.structural) continue;
    const double a = spec.get(from), b = spec.get(to);
    double v = b;
    if (spec.kind == ParamKind::kNumber)
      v = a + (b - a) * t;
    else if (spec.kind == ParamKind::kInteger)
      v = std::round(a + (b - a) * t);
    else
      v = t >= 0.5 ? b : a;
    if (spec.kind == ParamKind::kChoice && v < 0) continue;
    if (spec.get(out) != v) spec.set(out, v);
  }
}

void apply_quality(const Preset& preset, const QualityLevel& level, SceneConfig& out) {
  const double f = preset.quality.max_sweeps > 0
                       ? std::clamp(double(level.sweeps) / preset.quality.max_sweeps, 0.0, 1.0)
                       : 1.0;
  auto scaled = [f](int iterations) { return std::max(1, int(std::lround(iterations * f))); };
  out.fluid.pressure_solver.max_iterations =
      scaled(preset.scene.fluid.pressure_solver.max_iterations);
  out.fluid.viscosity_solver.max_iterations =
      scaled(preset.scene.fluid.viscosity_solver.max_iterations);
}

std::vector<std::string> preset_names() {
  std::vector<std::string> names;
  for (const EmbeddedPreset& e : embedded_presets()) names.push_back(file_stem(e.file));
  std::sort(names.begin(), names.end());
  for (const SceneEntry& s : builtin_scenes().entries())
    if (std::find(names.begin(), names.end(), s.name) == names.end()) names.push_back(s.name);
  return names;
}

}  // namespace ardcell
