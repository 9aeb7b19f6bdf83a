#include "host/io/state_io.h"

#include <fcntl.h>
#include <stdio.h>  // renameat2

#include <cerrno>
#include <cmath>
#include <fstream>
#include <sstream>

#include "host/io/atomic_file.h"
#include "host/io/npy.h"
#include "host/io/user_file.h"

namespace ardcell {
namespace {

namespace fs = std::filesystem;

constexpr const char* kFormat = "ardcell-state";
constexpr const char* kFieldNames[] = {"u", "v", "p", "dye", "A", "B", "theta0"};

bool known_field(const std::string& name) {
  for (const char* n : kFieldNames)
    if (name == n) return true;
  return false;
}

// Whether j is a saved state's meta.json: an object whose "format" is ours. Any other type of
// "format" (an array, a number) is not ours either, never an exception (found by
// state_meta_fuzz).
bool is_saved_state_meta(const nlohmann::json& j) {
  if (!j.is_object()) return false;
  const auto format = j.find("format");
  return format != j.end() && format->is_string() && format->get<std::string>() == kFormat;
}

bool is_saved_state_or_empty(const fs::path& dir) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return false;
  if (fs::is_empty(dir, ec)) return true;
  std::string text;
  if (!read_user_file(dir / "meta.json", kMaxTextConfigBytes, "a saved state's meta.json", text))
    return false;
  return is_saved_state_meta(nlohmann::json::parse(text, nullptr, false));
}

// Puts the finished temporary folder in place of dir.
Status install_folder(const fs::path& tmp, const fs::path& dir) {
  if (::rename(tmp.c_str(), dir.c_str()) == 0) return Status::ok();
  if (errno != EEXIST && errno != ENOTEMPTY && errno != EISDIR && errno != ENOTDIR)
    return Status::error(dir.string() + ": cannot create (" + errno_text(errno) + ")");
  if (!is_saved_state_or_empty(dir))
    return Status::error(dir.string() +
                         ": exists and is not an ardcell saved state (expected a new folder, "
                         "an empty one or a previous saved state)");
  // Swap atomically where the file system allows, else move the old one aside first.
  if (::renameat2(AT_FDCWD, tmp.c_str(), AT_FDCWD, dir.c_str(), RENAME_EXCHANGE) == 0) {
    std::error_code ec;
    fs::remove_all(tmp, ec);  // now the previous state
    return Status::ok();
  }
  const fs::path old = temporary_sibling(dir);
  if (::rename(dir.c_str(), old.c_str()) != 0 || ::rename(tmp.c_str(), dir.c_str()) != 0)
    return Status::error(dir.string() + ": cannot replace (" + errno_text(errno) + ")");
  std::error_code ec;
  fs::remove_all(old, ec);
  return Status::ok();
}

template <class T>
bool get_number(const nlohmann::json& j, const char* key, T& out) {
  auto it = j.find(key);
  if (it == j.end() || !it->is_number()) return false;
  if constexpr (std::is_integral_v<T>) {
    if (!it->is_number_integer()) return false;
    out = it->get<T>();
  } else {
    out = it->get<T>();
  }
  return true;
}

}  // namespace

nlohmann::json preset_parameters_to_json(const Preset& preset) {
  nlohmann::json out = nlohmann::json::object();
  Preset& p = const_cast<Preset&>(preset);  // the accessors take a mutable preset; read only
  for (const ParamSpec& spec : preset_params()) {
    const std::string key(spec.key);
    switch (spec.kind) {
      case ParamKind::kNumber:
        out[key] = get_param(preset, spec);
        break;
      case ParamKind::kInteger:
        out[key] = int64_t(std::llround(get_param(preset, spec)));
        break;
      case ParamKind::kBool:
        out[key] = get_param(preset, spec) != 0.0;
        break;
      case ParamKind::kChoice: {
        const double i = get_param(preset, spec);
        if (i >= 0 && std::size_t(i) < spec.choices.size())
          out[key] = std::string(spec.choices[std::size_t(i)]);
        break;
      }
      case ParamKind::kString:
        if (spec.text) out[key] = spec.text(p);
        break;
      case ParamKind::kSize:
        if (spec.size) {
          const Int2 s = spec.size(p);
          out[key] = {s.x, s.y};
        }
        break;
      case ParamKind::kFloats: {
        nlohmann::json a = nlohmann::json::array();
        for (float v : spec.floats(p)) a.push_back(double(v));
        out[key] = a;
        break;
      }
      case ParamKind::kEmitters: {
        nlohmann::json a = nlohmann::json::array();
        for (const FluidEmitter& e : spec.emitters(p))
          a.push_back({{"x", e.x},
                       {"y", e.y},
                       {"radius", e.radius},
                       {"dye_rate", e.dye_rate},
                       {"force_x", e.force_x},
                       {"force_y", e.force_y},
                       {"swirl", e.swirl}});
        out[key] = a;
        break;
      }
    }
  }
  return out;
}

Status apply_preset_parameters(const nlohmann::json& parameters, const std::string& what,
                               Preset& preset) {
  if (!parameters.is_object())
    return Status::error(what + ": \"parameters\" is not an object (expected key: value pairs)");
  for (auto it = parameters.begin(); it != parameters.end(); ++it) {
    const ParamSpec* spec = find_param(it.key());
    if (!spec)
      return Status::error(what + ": unknown parameter '" + it.key() +
                           "' (expected a preset key, see `ardcell live --keys`)");
    const nlohmann::json& v = it.value();
    auto wrong = [&] {
      return Status::error(what + ": parameter '" + it.key() + "' is " + v.dump() + " (expected " +
                           param_expectation(*spec) + ")");
    };
    std::string why;
    switch (spec->kind) {
      case ParamKind::kNumber:
      case ParamKind::kInteger:
        if (!v.is_number() || !set_param(preset, *spec, v.get<double>(), &why)) return wrong();
        break;
      case ParamKind::kBool:
        if (!v.is_boolean() || !set_param(preset, *spec, v.get<bool>() ? 1.0 : 0.0, &why))
          return wrong();
        break;
      case ParamKind::kChoice: {
        if (!v.is_string()) return wrong();
        std::size_t i = 0;
        while (i < spec->choices.size() && spec->choices[i] != v.get<std::string>()) ++i;
        if (i == spec->choices.size() || !set_param(preset, *spec, double(i), &why)) return wrong();
        break;
      }
      case ParamKind::kString:
        if (!v.is_string() || !spec->text) return wrong();
        spec->text(preset) = v.get<std::string>();
        break;
      case ParamKind::kSize:
        if (!v.is_array() || v.size() != 2 || !v[0].is_number_integer() ||
            !v[1].is_number_integer() || !spec->size)
          return wrong();
        spec->size(preset) = Int2{v[0].get<int>(), v[1].get<int>()};
        break;
      case ParamKind::kFloats: {
        const std::span<float> dst = spec->floats(preset);
        if (!v.is_array() || v.size() > dst.size()) return wrong();
        for (std::size_t i = 0; i < dst.size(); ++i) {
          if (i < v.size() && !v[i].is_number()) return wrong();
          dst[i] = i < v.size() ? v[i].get<float>() : float(spec->fill);
        }
        break;
      }
      case ParamKind::kEmitters: {
        if (!v.is_array()) return wrong();
        std::vector<FluidEmitter> list;
        for (const nlohmann::json& e : v) {
          FluidEmitter f;
          if (!e.is_object() || !get_number(e, "x", f.x) || !get_number(e, "y", f.y) ||
              !get_number(e, "radius", f.radius) || !get_number(e, "dye_rate", f.dye_rate) ||
              !get_number(e, "force_x", f.force_x) || !get_number(e, "force_y", f.force_y) ||
              !get_number(e, "swirl", f.swirl))
            return wrong();
          list.push_back(f);
        }
        spec->emitters(preset) = std::move(list);
        break;
      }
    }
  }
  return Status::ok();
}

Status save_state(const fs::path& dir_in, const SimState& state, const SceneConfig& scene) {
  const fs::path dir = dir_in.has_filename() ? dir_in : dir_in.parent_path();
  if (dir.empty()) return Status::error("--save-state: empty folder name");
  std::error_code ec;
  const fs::path parent = dir.parent_path().empty() ? fs::path(".") : dir.parent_path();
  fs::create_directories(parent, ec);
  if (ec) return Status::error(parent.string() + ": cannot create folder (" + ec.message() + ")");
  const fs::path tmp = temporary_sibling(dir);
  if (!fs::create_directory(tmp, ec))
    return Status::error(dir.string() + ": cannot write a saved state here (" +
                         (ec ? ec.message() : std::string("exists")) + ")");
  auto fail = [&](Status s) {
    std::error_code ignored;
    fs::remove_all(tmp, ignored);
    return s;
  };

  nlohmann::json meta;
  meta["format"] = kFormat;
  meta["version"] = kStateFormatVersion;
  meta["ardcell_version"] = ARDCELL_VERSION;
  meta["scene"] = scene.name;
  meta["size"] = {state.size.x, state.size.y};
  meta["h"] = state.h;
  meta["dt"] = state.dt;
  meta["time"] = state.time;
  meta["rd_time"] = state.rd_time;
  meta["step"] = state.step;
  meta["layout"] =
      "float32 little-endian .npy, C order, shape [ny][nx], row y = grid row y "
      "(y up), interior cells only";
  nlohmann::json fields = nlohmann::json::array();
  Status status = Status::ok();
  state.for_each_field([&](std::string_view name, const FieldF& f) {
    if (!status) return;
    if (f.size() != state.size) {
      status = Status::error(std::string(name) + ": field size differs from the state size");
      return;
    }
    status = write_npy(tmp / (std::string(name) + ".npy"), f.view(f.interior()));
    fields.push_back(std::string(name));
  });
  if (!status) return fail(status);
  meta["fields"] = fields;
  meta["parameters"] = preset_parameters_to_json(preset_from_scene(scene));

  AtomicFile file;
  if (Status s = file.open(tmp / "meta.json"); !s) return fail(s);
  const std::string text = meta.dump(2) + "\n";
  file.write(text.data(), text.size());
  if (Status s = file.commit(true); !s) return fail(s);
  if (Status s = install_folder(tmp, dir); !s) return fail(s);
  return Status::ok();
}

Status check_state_destination(const fs::path& dir) {
  std::error_code ec;
  if (fs::exists(dir, ec) && !is_saved_state_or_empty(dir))
    return Status::error(dir.string() +
                         ": exists and is not an ardcell saved state (expected a new folder, "
                         "an empty one or a previous saved state)");
  // The state is written as a temporary sibling and renamed: its folder must be writable.
  fs::path norm = fs::absolute(dir).lexically_normal();
  if (norm.filename().empty()) norm = norm.parent_path();
  if (!fs::exists(norm, ec)) return check_output_path(norm, true);  // its nearest ancestor
  if (Status s = check_output_path(norm.parent_path(), true); !s)
    return Status::error(dir.string() + ": " + s.message());
  return Status::ok();
}

Status read_state_meta(const fs::path& dir, SavedStateMeta& meta) {
  std::error_code ec;
  if (!fs::exists(dir, ec))
    return Status::error(dir.string() +
                         ": saved state not found (expected a folder written by "
                         "--save-state)");
  if (!fs::is_directory(dir, ec))
    return Status::error(dir.string() +
                         ": not a folder (expected a folder written by "
                         "--save-state)");
  const fs::path path = dir / "meta.json";
  const std::string what = path.string();
  std::string text;
  if (Status s = read_user_file(path, kMaxTextConfigBytes, "the saved state's meta.json", text); !s)
    return s;
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    return Status::error(what + ": not valid JSON (byte " + std::to_string(e.byte) + ")");
  } catch (const nlohmann::json::exception&) {
    // A number beyond double (out_of_range 406, e.g. 2e308): found by state_meta_fuzz.
    return Status::error(what + ": not valid JSON (a number out of range)");
  }
  if (!is_saved_state_meta(j))
    return Status::error(what + ": not an ardcell saved state (expected \"format\": \"" + kFormat +
                         "\")");
  int version = 0;
  if (!get_number(j, "version", version) || version != kStateFormatVersion)
    return Status::error(what + ": unsupported version (expected " +
                         std::to_string(kStateFormatVersion) + ")");
  auto bad = [&](const std::string& key, const std::string& expected) {
    return Status::error(what + ": \"" + key + "\" is missing or invalid (expected " + expected +
                         ")");
  };
  SavedStateMeta m;
  if (!j.contains("scene") || !j["scene"].is_string() || j["scene"].get<std::string>().empty())
    return bad("scene", "the scene name");
  m.scene = j["scene"].get<std::string>();
  const nlohmann::json& size = j.value("size", nlohmann::json());
  if (!size.is_array() || size.size() != 2 || !size[0].is_number_integer() ||
      !size[1].is_number_integer() || size[0].get<int64_t>() < 1 || size[1].get<int64_t>() < 1 ||
      size[0].get<int64_t>() > kNpyMaxSide || size[1].get<int64_t>() > kNpyMaxSide)
    return bad("size", "[nx, ny] with positive integers");
  m.size = {size[0].get<int>(), size[1].get<int>()};
  if (!get_number(j, "h", m.h) || !std::isfinite(m.h) || m.h <= 0)
    return bad("h", "a positive number");
  if (!get_number(j, "dt", m.dt) || !std::isfinite(m.dt) || m.dt <= 0)
    return bad("dt", "a positive number");
  if (!get_number(j, "time", m.time) || !std::isfinite(m.time) || m.time < 0)
    return bad("time", "a number >= 0");
  m.rd_time = m.time;
  if (j.contains("rd_time") &&
      (!get_number(j, "rd_time", m.rd_time) || !std::isfinite(m.rd_time) || m.rd_time < 0))
    return bad("rd_time", "a number >= 0");
  if (!get_number(j, "step", m.step) || m.step < 0) return bad("step", "an integer >= 0");
  const nlohmann::json& fields = j.value("fields", nlohmann::json());
  if (!fields.is_array() || fields.empty()) return bad("fields", "a list of field names");
  for (const nlohmann::json& f : fields) {
    if (!f.is_string() || !known_field(f.get<std::string>()))
      return bad("fields", "names among u, v, p, dye, A, B, theta0");
    m.fields.push_back(f.get<std::string>());
  }
  m.parameters = j.value("parameters", nlohmann::json::object());
  if (!m.parameters.is_object()) return bad("parameters", "an object");
  meta = std::move(m);
  return Status::ok();
}

Status saved_state_preset(const fs::path& dir, const SavedStateMeta& meta, Preset& preset,
                          std::string& notice) {
  notice.clear();
  const std::string what = (dir / "meta.json").string();
  // The name comes from a file: shown escaped and short, so it cannot break the line.
  const std::string scene = escaped_prefix(meta.scene, 60);
  Preset p;
  if (!load_builtin_preset(meta.scene, p)) {
    // Without a built-in scene underneath, a missing key would silently take the default of a
    // scene the state was never made from: every key must be there.
    const nlohmann::json every_key = preset_parameters_to_json(Preset{});
    std::vector<std::string> missing;
    for (const auto& [key, value] : every_key.items())
      if (!meta.parameters.contains(key)) missing.push_back(key);
    if (!missing.empty())
      return Status::error(
          what + ": scene '" + scene + "' is not built in and \"parameters\" lacks " +
          missing.front() +
          (missing.size() > 1 ? " and " + std::to_string(missing.size() - 1) + " more keys" : "") +
          " (expected a built-in scene, or every preset key as --save-state writes them)");
    p = Preset{};
    p.scene.name = meta.scene;
    p.source = what;
    notice = "state " + dir.string() + " was saved from scene '" + scene +
             "', which is not built in: resuming from the parameters saved with it";
  }
  if (Status s = apply_preset_parameters(meta.parameters, what, p); !s) {
    notice.clear();
    return s;
  }
  p.scene.size = meta.size;
  preset = std::move(p);
  return Status::ok();
}

Status load_state_fields(const fs::path& dir, const SavedStateMeta& meta, SimState& state) {
  if (meta.size != state.size)
    return Status::error((dir / "meta.json").string() + ": size " + std::to_string(meta.size.x) +
                         "x" + std::to_string(meta.size.y) + " does not match the scene's " +
                         std::to_string(state.size.x) + "x" + std::to_string(state.size.y));
  // Read everything first so that a failure leaves the running state untouched.
  struct Loaded {
    FieldF* field;
    NpyArray array;
  };
  std::vector<Loaded> loaded;
  std::vector<std::string> wanted;
  Status status = Status::ok();
  state.for_each_field([&](std::string_view name, FieldF& f) {
    wanted.emplace_back(name);
    if (!status) return;
    const fs::path path = dir / (std::string(name) + ".npy");
    bool listed = false;
    for (const std::string& n : meta.fields) listed = listed || n == name;
    if (!listed) {
      status = Status::error((dir / "meta.json").string() + ": lists no " + std::string(name) +
                             " field, which the scene needs (expected it in \"fields\")");
      return;
    }
    Loaded l{&f, {}};
    if (Status s = read_npy(path, l.array, &state.size); !s) {
      status = s;
      return;
    }
    if (l.array.ny != state.size.y || l.array.nx != state.size.x) {
      status =
          Status::error(path.string() + ": shape (" + std::to_string(l.array.ny) + ", " +
                        std::to_string(l.array.nx) + ") does not match meta.json (expected (" +
                        std::to_string(state.size.y) + ", " + std::to_string(state.size.x) + "))");
      return;
    }
    for (std::size_t i = 0; i < l.array.data.size(); ++i)
      if (!std::isfinite(l.array.data[i])) {
        status = Status::error(path.string() +
                               ": value at (x=" + std::to_string(i % std::size_t(l.array.nx)) +
                               ", y=" + std::to_string(i / std::size_t(l.array.nx)) +
                               ") is not finite (expected finite numbers)");
        return;
      }
    loaded.push_back(std::move(l));
  });
  if (!status) return status;
  for (const std::string& n : meta.fields) {
    bool needed = false;
    for (const std::string& w : wanted) needed = needed || w == n;
    if (!needed)
      return Status::error((dir / (n + ".npy")).string() + ": the scene has no " + n +
                           " field (expected a state saved from the same scene)");
  }
  for (Loaded& l : loaded)
    for (int y = 0; y < l.array.ny; ++y)
      std::copy_n(l.array.data.data() + std::size_t(y) * l.array.nx, l.array.nx, l.field->row(y));
  state.time = meta.time;
  state.rd_time = meta.rd_time;
  state.step = meta.step;
  return Status::ok();
}

}  // namespace ardcell
