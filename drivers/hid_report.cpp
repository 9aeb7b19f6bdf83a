#include "drivers/hid_report.h"

#include <algorithm>
#include <cmath>

namespace ardcell {

bool hid_extract(std::span<const uint8_t> payload, uint32_t bit_offset, uint32_t bit_size,
                 bool is_signed, int64_t& value) {
  if (bit_size == 0 || bit_size > 32) return false;
  const uint64_t end = uint64_t(bit_offset) + bit_size;
  if (end > uint64_t(payload.size()) * 8) return false;
  uint64_t v = 0;
  const uint32_t first = bit_offset / 8, last = uint32_t((end - 1) / 8);
  for (uint32_t b = last + 1; b-- > first;) v = (v << 8) | payload[b];
  v >>= (bit_offset % 8);
  v &= (bit_size == 64 ? ~0ull : ((1ull << bit_size) - 1));
  if (is_signed && bit_size < 64 && (v >> (bit_size - 1)) & 1) {
    value = int64_t(v) - int64_t(1ull << bit_size);
  } else {
    value = int64_t(v);
  }
  return true;
}

namespace {

bool split(const HidDescriptor& d, std::span<const uint8_t> raw, uint8_t& id,
           std::span<const uint8_t>& payload, const HidReportInfo*& info, std::string& error) {
  if (raw.empty()) {
    error = "empty report";
    return false;
  }
  id = d.uses_report_ids ? raw[0] : 0;
  info = d.find_report(HidReportType::input, id);
  if (!info) {
    error = "unknown input report ID " + std::to_string(id);
    return false;
  }
  const uint32_t want = info->byte_length(d.uses_report_ids);
  if (raw.size() < want) {
    error = "report " + std::to_string(id) + " has " + std::to_string(raw.size()) +
            " bytes; the descriptor says " + std::to_string(want);
    return false;
  }
  payload = raw.subspan(d.uses_report_ids ? 1 : 0);
  return true;
}

}  // namespace

bool HidReportDecoder::decode(std::span<const uint8_t> raw, HidDecodedReport& out,
                              std::string& error) const {
  uint8_t id = 0;
  std::span<const uint8_t> payload;
  const HidReportInfo* info = nullptr;
  if (!split(d_, raw, id, payload, info, error)) return false;
  out.report_id = id;
  out.values.clear();
  for (const HidField& f : d_.fields) {
    if (f.type != HidReportType::input || f.report_id != id) continue;
    if (f.bit_size > 32) continue;  // opaque vendor blobs: nothing numeric to show
    for (uint32_t k = 0; k < f.count; ++k) {
      int64_t v = 0;
      if (!hid_extract(payload, f.bit_offset + k * f.bit_size, f.bit_size, f.is_signed(), v)) {
        error = "report " + std::to_string(id) + ": field outside the report";
        return false;
      }
      uint32_t usage = f.usage;
      if (f.is_array()) {
        // An array element holds an index into the usage range; values outside the logical
        // range mean "no usage" (e.g. 0 for no key pressed).
        const bool in_range = v >= f.logical_min && v <= f.logical_max;
        const int64_t u = int64_t(f.usage_min) + (v - f.logical_min);
        usage = in_range && u <= int64_t(f.usage_max) ? uint32_t(u) : 0;
      }
      out.values.push_back({&f, usage, v});
    }
  }
  return true;
}

bool decode_pen(const HidPenLayout& pen, bool uses_report_ids, std::span<const uint8_t> raw,
                HidPenState& out, std::string& error) {
  if (raw.empty()) {
    error = "empty report";
    return false;
  }
  const uint8_t id = uses_report_ids ? raw[0] : 0;
  if (id != pen.report_id) {
    error = "report ID " + std::to_string(id) + " is not the pen's (" +
            std::to_string(pen.report_id) + ")";
    return false;
  }
  const std::span<const uint8_t> payload = raw.subspan(uses_report_ids ? 1 : 0);
  bool ok = true;
  auto read = [&](const std::optional<HidField>& f, int64_t fallback) -> int64_t {
    if (!f) return fallback;
    int64_t v = 0;
    if (!hid_extract(payload, f->bit_offset, f->bit_size, f->is_signed(), v)) {
      ok = false;
      return fallback;
    }
    return v;
  };
  HidPenState s;
  s.x = read(pen.x, 0);
  s.y = read(pen.y, 0);
  s.pressure = read(pen.pressure, 0);
  s.x_tilt = read(pen.x_tilt, 0);
  s.y_tilt = read(pen.y_tilt, 0);
  s.tip = read(pen.tip, 0) != 0;
  s.in_range = read(pen.in_range, 0) != 0;
  s.barrel = read(pen.barrel, 0) != 0;
  s.secondary = read(pen.secondary, 0) != 0;
  s.invert = read(pen.invert, 0) != 0;
  s.eraser = read(pen.eraser, 0) != 0;
  for (std::size_t k = 0; k < pen.other_buttons.size() && k < 32; ++k)
    if (read(pen.other_buttons[k], 0)) s.other_buttons |= 1u << k;
  if (!ok) {
    error = "report " + std::to_string(id) + " has " + std::to_string(raw.size()) +
            " bytes, too short for the pen's fields";
    return false;
  }
  out = s;
  return true;
}

namespace {

float normalized(const std::optional<HidField>& f, int64_t v) {
  if (!f || f->logical_max <= f->logical_min) return 0.f;
  const double t = double(v - f->logical_min) / double(f->logical_max - f->logical_min);
  return float(std::clamp(t, 0.0, 1.0));
}

float degrees(const std::optional<HidField>& f, int64_t v) {
  if (!f) return 0.f;
  // Unit 0x14: English Rotation (degrees); 0x12: SI Rotation (radians).
  const uint32_t system_and_rotation = f->unit & 0xff;
  const bool physical = (system_and_rotation == 0x14 || system_and_rotation == 0x12) &&
                        f->logical_max > f->logical_min;
  if (!physical) return float(v);
  const double t = double(v - f->logical_min) / double(f->logical_max - f->logical_min);
  double value = (f->physical_min + t * double(f->physical_max - f->physical_min)) *
                 std::pow(10.0, f->unit_exponent);
  if (system_and_rotation == 0x12) value *= 180.0 / 3.14159265358979323846;
  return float(value);
}

}  // namespace

StrokeSample pen_state_to_sample(const HidPenLayout& pen, const HidPenState& state, double time) {
  StrokeSample s;
  s.time = time;
  s.x = normalized(pen.x, state.x);
  s.y = normalized(pen.y, state.y);
  s.pressure = pen.pressure ? normalized(pen.pressure, state.pressure) : (state.tip ? 1.f : 0.f);
  s.tilt_x = degrees(pen.x_tilt, state.x_tilt);
  s.tilt_y = degrees(pen.y_tilt, state.y_tilt);
  if (state.tip) s.buttons |= kButtonTip;
  if (state.barrel) s.buttons |= kButtonBarrel;
  if (state.secondary) s.buttons |= kButtonSecondary;
  if (state.other_buttons) s.buttons |= kButtonThird;
  s.in_range = pen.in_range ? state.in_range : state.tip;
  s.eraser = state.invert || state.eraser;
  return s;
}

}  // namespace ardcell
