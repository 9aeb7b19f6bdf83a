#pragma once
// Generic HID report descriptor parser (USB HID 1.11, section 6.2.2) and the mapping of a pen
// digitizer (usage page 0x0D) onto stroke samples. No per-vendor tables: everything comes from
// the descriptor the device sends.
//
// Bit offsets count from the first byte AFTER the report ID (as in the HID spec and Linux):
// when a descriptor uses report IDs, byte 0 of a raw report is the ID and field bit b lives in
// raw byte 1 + b / 8, bit b % 8 (little-endian, LSB first).
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace ardcell {

// A usage with its page: (page << 16) | id, as in 4-byte "extended" usages.
constexpr uint32_t hid_usage(uint16_t page, uint16_t id) { return (uint32_t(page) << 16) | id; }

namespace hid {
inline constexpr uint16_t kPageGenericDesktop = 0x01;
inline constexpr uint16_t kPageButton = 0x09;
inline constexpr uint16_t kPageDigitizer = 0x0D;
inline constexpr uint32_t kX = hid_usage(0x01, 0x30);
inline constexpr uint32_t kY = hid_usage(0x01, 0x31);
inline constexpr uint32_t kDigitizer = hid_usage(0x0D, 0x01);
inline constexpr uint32_t kPen = hid_usage(0x0D, 0x02);
inline constexpr uint32_t kStylus = hid_usage(0x0D, 0x20);
inline constexpr uint32_t kTipPressure = hid_usage(0x0D, 0x30);
inline constexpr uint32_t kInRange = hid_usage(0x0D, 0x32);
inline constexpr uint32_t kInvert = hid_usage(0x0D, 0x3C);
inline constexpr uint32_t kXTilt = hid_usage(0x0D, 0x3D);
inline constexpr uint32_t kYTilt = hid_usage(0x0D, 0x3E);
inline constexpr uint32_t kTipSwitch = hid_usage(0x0D, 0x42);
inline constexpr uint32_t kSecondaryTipSwitch = hid_usage(0x0D, 0x43);
inline constexpr uint32_t kBarrelSwitch = hid_usage(0x0D, 0x44);
inline constexpr uint32_t kEraser = hid_usage(0x0D, 0x45);
inline constexpr uint32_t kSecondaryBarrelSwitch = hid_usage(0x0D, 0x5A);
}  // namespace hid

enum class HidReportType : uint8_t { input, output, feature };

// Main item data bits (HID 1.11, 6.2.2.5).
enum HidMainFlags : uint32_t {
  kHidConstant = 1u << 0,
  kHidVariable = 1u << 1,
  kHidRelative = 1u << 2,
  kHidWrap = 1u << 3,
  kHidNonLinear = 1u << 4,
  kHidNoPreferred = 1u << 5,
  kHidNullState = 1u << 6,
  kHidVolatile = 1u << 7,
  kHidBufferedBytes = 1u << 8,
};

struct HidCollection {
  uint8_t type = 0;      // 0 physical, 1 application, 2 logical, ...
  uint32_t usage = 0;    // page << 16 | id (0 when the collection has no usage)
  int parent = -1;       // index into HidDescriptor::collections, -1 at top level
  int application = -1;  // index of the enclosing application collection (itself if one); in a
                         // descriptor with none, the top-level collection (as Linux maps it)
};

// One data field of a report. A Variable main item yields one field per report-count element
// (each with its own usage, the last usage repeating); an Array item yields one field with
// count > 1 whose elements hold usage indices in [usage_min, usage_max]. Constant items
// (padding) yield no field but take their bits.
struct HidField {
  HidReportType type = HidReportType::input;
  uint8_t report_id = 0;
  uint32_t usage = 0;  // Variable fields; Array fields: usage_min
  uint32_t usage_min = 0, usage_max = 0;
  uint32_t bit_offset = 0;  // from the first byte after the report ID
  uint32_t bit_size = 0;
  uint32_t count = 1;  // > 1 only for Array fields
  uint32_t flags = 0;  // HidMainFlags
  int64_t logical_min = 0, logical_max = 0;
  int64_t physical_min = 0, physical_max = 0;  // equal to logical when both were 0 (HID 6.2.2.7)
  int8_t unit_exponent = 0;
  uint32_t unit = 0;
  int collection = -1;  // innermost collection
  bool is_signed() const { return logical_min < 0; }
  bool is_array() const { return (flags & kHidVariable) == 0; }
};

struct HidReportInfo {
  HidReportType type = HidReportType::input;
  uint8_t id = 0;
  uint32_t bit_length = 0;  // without the report ID byte
  // Bytes of a raw report: the ID byte (when the descriptor uses IDs) + ceil(bits / 8).
  uint32_t byte_length(bool with_id) const { return (with_id ? 1 : 0) + (bit_length + 7) / 8; }
};

struct HidDescriptor {
  std::vector<HidCollection> collections;
  std::vector<HidField> fields;
  std::vector<HidReportInfo> reports;
  bool uses_report_ids = false;

  const HidReportInfo* find_report(HidReportType type, uint8_t id) const;
  // The first field of that usage in that report, or nullptr.
  const HidField* find_field(HidReportType type, uint8_t id, uint32_t usage) const;
  // The usage of the application collection around a field (0 if none).
  uint32_t application_usage(const HidField& f) const;
};

// Parses a descriptor. False with `error` (one line: byte offset, what was wrong) on malformed
// input: truncated items, unbalanced collections or Push/Pop, report size/count out of range,
// main items before a usage page, reports over 8 KiB, more than 64 nested levels.
bool parse_hid_descriptor(std::span<const uint8_t> bytes, HidDescriptor& out, std::string& error);

// Where a pen's values live in the input reports of one digitizer application collection.
struct HidPenLayout {
  uint8_t report_id = 0;
  uint32_t application_usage = 0;
  std::optional<HidField> x, y, pressure, x_tilt, y_tilt;
  std::optional<HidField> tip, in_range, barrel, secondary, invert, eraser;
  std::vector<HidField> other_buttons;  // any further 1-bit switch of the pen
};

// Every pen found: input reports in an application collection of usage page 0x0D (Pen,
// Digitizer, ...) that carry X and Y. Mouse-like or keyboard collections are ignored.
std::vector<HidPenLayout> find_pens(const HidDescriptor& d);

// A readable name for a usage ("Digitizer/Tip Pressure", "Generic Desktop/X", "0xff00/0x00c5").
std::string hid_usage_name(uint32_t usage);

}  // namespace ardcell
