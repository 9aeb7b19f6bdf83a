#include "host/paint/stroke_io.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "host/io/user_file.h"

namespace ardcell {

namespace {
constexpr double kMaxStrokeCoordinate = 1000;
constexpr double kMaxStrokeTime = 1e9;
}  // namespace

std::string stroke_sample_to_json(const StrokeSample& s) {
  // Fixed key order and plain numbers so that files diff well.
  nlohmann::ordered_json j;
  j["t"] = s.time;
  j["x"] = s.x;
  j["y"] = s.y;
  j["pressure"] = s.pressure;
  j["tilt_x"] = s.tilt_x;
  j["tilt_y"] = s.tilt_y;
  j["buttons"] = s.buttons;
  j["in_range"] = s.in_range;
  j["eraser"] = s.eraser;
  return j.dump();
}

namespace {

bool get_number(const nlohmann::json& j, const char* key, bool required, double& out,
                std::string& error) {
  auto it = j.find(key);
  if (it == j.end()) {
    if (required) error = std::string("missing key \"") + key + "\" (a number)";
    return !required;
  }
  if (!it->is_number()) {
    error = std::string("key \"") + key + "\" must be a number";
    return false;
  }
  out = it->get<double>();
  if (!std::isfinite(out)) {
    error = std::string("key \"") + key + "\" must be finite";
    return false;
  }
  return true;
}

bool get_bool(const nlohmann::json& j, const char* key, bool& out, std::string& error) {
  auto it = j.find(key);
  if (it == j.end()) return true;
  if (!it->is_boolean()) {
    error = std::string("key \"") + key + "\" must be true or false";
    return false;
  }
  out = it->get<bool>();
  return true;
}

}  // namespace

bool stroke_sample_from_json(std::string_view line, StrokeSample& out, std::string& error) {
  nlohmann::json j = nlohmann::json::parse(line, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded() || !j.is_object()) {
    error = "expected one JSON object per line";
    return false;
  }
  StrokeSample s;
  s.in_range = true;
  double t = 0, x = 0, y = 0, p = s.pressure, tx = 0, ty = 0, b = 0;
  if (!get_number(j, "t", true, t, error) || !get_number(j, "x", true, x, error) ||
      !get_number(j, "y", true, y, error) || !get_number(j, "pressure", false, p, error) ||
      !get_number(j, "tilt_x", false, tx, error) || !get_number(j, "tilt_y", false, ty, error) ||
      !get_number(j, "buttons", false, b, error) || !get_bool(j, "in_range", s.in_range, error) ||
      !get_bool(j, "eraser", s.eraser, error))
    return false;
  if (p < 0 || p > 1) {
    error = "key \"pressure\" must be in [0, 1]";
    return false;
  }
  // Off-canvas positions paint nothing, but must stay representable (x * nx as a float).
  if (std::abs(x) > kMaxStrokeCoordinate || std::abs(y) > kMaxStrokeCoordinate) {
    error = "keys \"x\" and \"y\" must be in [-1000, 1000] (0..1 is the canvas)";
    return false;
  }
  if (std::abs(t) > kMaxStrokeTime || std::abs(tx) > 90 || std::abs(ty) > 90) {
    error = "key \"t\" must be in [-1e9, 1e9] seconds and tilts in [-90, 90] degrees";
    return false;
  }
  if (b < 0 || b > 4294967295.0 || b != std::floor(b)) {
    error = "key \"buttons\" must be a non-negative integer (bit 0 = tip)";
    return false;
  }
  s.time = t;
  s.x = float(x);
  s.y = float(y);
  s.pressure = float(p);
  s.tilt_x = float(tx);
  s.tilt_y = float(ty);
  s.buttons = uint32_t(b);
  out = s;
  return true;
}

bool read_stroke_file(const std::string& path, std::vector<StrokeSample>& out, std::string& error) {
  std::string text;
  if (Status s = read_user_file(path, kMaxRecordingBytes, "a stroke file (JSON lines)", text); !s) {
    error = s.message();
    return false;
  }
  std::istringstream in(text);
  std::vector<StrokeSample> samples;
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const auto first = line.find_first_not_of(" \t");
    if (first == std::string::npos || line[first] == '#') continue;
    StrokeSample s;
    std::string why;
    if (!stroke_sample_from_json(line, s, why)) {
      error = path + ":" + std::to_string(number) + ": " + why;
      return false;
    }
    if (!samples.empty() && s.time < samples.back().time) {
      error = path + ":" + std::to_string(number) + ": time " + std::to_string(s.time) +
              " goes backwards (times must not decrease)";
      return false;
    }
    samples.push_back(s);
  }
  if (in.bad()) {
    error = path + ": read error";
    return false;
  }
  out = std::move(samples);
  return true;
}

bool write_stroke_file(const std::string& path, const std::vector<StrokeSample>& samples,
                       std::string& error) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream f(tmp, std::ios::trunc);
    if (!f) {
      error = path + ": cannot write (" + std::strerror(errno) + ")";
      return false;
    }
    for (const StrokeSample& s : samples) f << stroke_sample_to_json(s) << '\n';
    f.flush();
    if (!f) {
      error = path + ": write failed (" + std::strerror(errno) + ")";
      f.close();
      std::remove(tmp.c_str());
      return false;
    }
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    error = path + ": cannot rename the temporary file into place (" + std::strerror(errno) + ")";
    std::remove(tmp.c_str());
    return false;
  }
  return true;
}

}  // namespace ardcell
