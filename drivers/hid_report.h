#pragma once
// Decoding of raw HID input reports by report ID and bit offset (drivers/hid_descriptor.h),
// and of a pen's report into a StrokeSample.
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "drivers/hid_descriptor.h"
#include "host/paint/stroke.h"

namespace ardcell {

// Reads `bit_size` (1..32) bits at `bit_offset` of payload, LSB first; sign-extends when
// is_signed. False when the bits lie outside the payload.
bool hid_extract(std::span<const uint8_t> payload, uint32_t bit_offset, uint32_t bit_size,
                 bool is_signed, int64_t& value);

struct HidDecodedValue {
  const HidField* field = nullptr;
  uint32_t usage = 0;  // for Array elements: the usage the index selects (0 for "none")
  int64_t value = 0;
};

struct HidDecodedReport {
  uint8_t report_id = 0;
  std::vector<HidDecodedValue> values;  // reused between calls: no allocation once warm
};

// Splits raw input reports (report ID in byte 0 when the descriptor uses IDs) into values.
// Errors (one line): empty report, unknown report ID, report shorter than the descriptor says.
// Longer reports are accepted and the extra bytes ignored (USB devices often pad).
class HidReportDecoder {
 public:
  explicit HidReportDecoder(const HidDescriptor& descriptor) : d_(descriptor) {}
  bool decode(std::span<const uint8_t> raw, HidDecodedReport& out, std::string& error) const;
  const HidDescriptor& descriptor() const { return d_; }

 private:
  const HidDescriptor& d_;
};

// A pen's state as the device reports it, in logical units.
struct HidPenState {
  bool tip = false, in_range = false, barrel = false, secondary = false;
  bool invert = false, eraser = false;
  uint32_t other_buttons = 0;  // bit k = other_buttons[k] of the layout
  int64_t x = 0, y = 0, pressure = 0, x_tilt = 0, y_tilt = 0;
};

// Decodes the pen's fields from a raw report of its report ID. False with `error` when the
// report has another ID or is too short.
bool decode_pen(const HidPenLayout& pen, bool uses_report_ids, std::span<const uint8_t> raw,
                HidPenState& out, std::string& error);

// Maps a decoded pen state onto a sample: X/Y and pressure normalized by their logical ranges,
// tilt in degrees (physical units when the descriptor gives degrees, otherwise the logical
// value, which is degrees on every known pen), eraser = Invert or Eraser, in_range = In Range
// (or tip when the pen has no In Range), buttons from Tip, Barrel, Secondary and the others.
StrokeSample pen_state_to_sample(const HidPenLayout& pen, const HidPenState& state, double time);

}  // namespace ardcell
