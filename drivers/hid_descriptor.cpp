#include "drivers/hid_descriptor.h"

#include <algorithm>
#include <cstdio>

namespace ardcell {

namespace {

constexpr int kMaxDepth = 64;
constexpr uint32_t kMaxReportSize = 256;     // bits per element (Linux' limit)
constexpr uint32_t kMaxReportCount = 12288;  // elements per main item (Linux' HID_MAX_USAGES)
constexpr uint32_t kMaxReportBits = 8192 * 8;
constexpr std::size_t kMaxFields = 65536;

struct Globals {
  uint16_t usage_page = 0;
  bool has_usage_page = false;
  int64_t logical_min = 0, logical_max = 0;
  int64_t physical_min = 0, physical_max = 0;
  int8_t unit_exponent = 0;
  uint32_t unit = 0;
  uint32_t report_size = 0;
  uint8_t report_id = 0;
  uint32_t report_count = 0;
  // Raw maxima, reinterpreted as signed or unsigned once the minimum is known (as Linux does).
  uint32_t logical_max_raw = 0, physical_max_raw = 0;
  int logical_max_size = 0, physical_max_size = 0;
};

// A usage range [min, max]; `explicit_page` when the item carried a 4-byte extended usage.
struct UsageRange {
  uint32_t min = 0, max = 0;
  bool explicit_page = false;
};

struct Locals {
  std::vector<UsageRange> usages;
  bool have_min = false;
  uint32_t pending_min = 0;
  bool pending_min_explicit = false;
  void clear() {
    usages.clear();
    have_min = false;
  }
};

int64_t sign_extend(uint32_t v, int bytes) {
  switch (bytes) {
    case 1:
      return int8_t(v);
    case 2:
      return int16_t(v);
    case 4:
      return int32_t(v);
    default:
      return 0;
  }
}

int64_t resolve_max(uint32_t raw, int size, int64_t min) {
  return min < 0 ? sign_extend(raw, size) : int64_t(raw);
}

std::string at(std::size_t offset, const std::string& why) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "byte %zu: ", offset);
  return buf + why;
}

uint32_t resolve_usage(uint32_t u, bool explicit_page, uint16_t page) {
  return explicit_page ? u : hid_usage(page, uint16_t(u));
}

}  // namespace

const HidReportInfo* HidDescriptor::find_report(HidReportType type, uint8_t id) const {
  for (const HidReportInfo& r : reports)
    if (r.type == type && r.id == id) return &r;
  return nullptr;
}

const HidField* HidDescriptor::find_field(HidReportType type, uint8_t id, uint32_t usage) const {
  for (const HidField& f : fields)
    if (f.type == type && f.report_id == id && !f.is_array() && f.usage == usage) return &f;
  return nullptr;
}

uint32_t HidDescriptor::application_usage(const HidField& f) const {
  if (f.collection < 0) return 0;
  const int app = collections[std::size_t(f.collection)].application;
  return app < 0 ? 0 : collections[std::size_t(app)].usage;
}

bool parse_hid_descriptor(std::span<const uint8_t> bytes, HidDescriptor& out, std::string& error) {
  HidDescriptor d;
  Globals g;
  Locals l;
  std::vector<Globals> global_stack;
  std::vector<int> collection_stack;

  std::size_t i = 0;
  while (i < bytes.size()) {
    const std::size_t item_at = i;
    const uint8_t prefix = bytes[i++];
    if (prefix == 0xFE) {  // long item: size, tag, data; defines nothing we use
      if (i + 2 > bytes.size()) {
        error = at(item_at, "truncated long item");
        return false;
      }
      const std::size_t size = bytes[i];
      i += 2;
      if (i + size > bytes.size()) {
        error = at(item_at, "truncated long item data");
        return false;
      }
      i += size;
      continue;
    }
    const int size = (prefix & 3) == 3 ? 4 : (prefix & 3);
    const int type = (prefix >> 2) & 3;
    const int tag = prefix >> 4;
    if (i + std::size_t(size) > bytes.size()) {
      error = at(
          item_at, "item 0x" +
                       [&] {
                         char b[8];
                         std::snprintf(b, sizeof b, "%02x", prefix);
                         return std::string(b);
                       }() +
                       " needs " + std::to_string(size) + " data bytes but the descriptor ends");
      return false;
    }
    uint32_t udata = 0;
    for (int k = 0; k < size; ++k) udata |= uint32_t(bytes[i + std::size_t(k)]) << (8 * k);
    const int64_t sdata = sign_extend(udata, size);
    i += std::size_t(size);

    if (type == 0) {  // main
      if (tag == 8 || tag == 9 || tag == 11) {
        const HidReportType rtype = tag == 8   ? HidReportType::input
                                    : tag == 9 ? HidReportType::output
                                               : HidReportType::feature;
        if (g.report_size > kMaxReportSize) {
          error = at(item_at, "Report Size " + std::to_string(g.report_size) + " exceeds " +
                                  std::to_string(kMaxReportSize) + " bits");
          return false;
        }
        if (g.report_count > kMaxReportCount) {
          error = at(item_at, "Report Count " + std::to_string(g.report_count) + " exceeds " +
                                  std::to_string(kMaxReportCount));
          return false;
        }
        auto rep = std::find_if(d.reports.begin(), d.reports.end(), [&](const HidReportInfo& r) {
          return r.type == rtype && r.id == g.report_id;
        });
        if (rep == d.reports.end()) {
          d.reports.push_back({rtype, g.report_id, 0});
          rep = d.reports.end() - 1;
        }
        const uint32_t bits = g.report_size * g.report_count;
        if (rep->bit_length + bits > kMaxReportBits) {
          error = at(item_at, "report " + std::to_string(g.report_id) + " longer than " +
                                  std::to_string(kMaxReportBits / 8) + " bytes");
          return false;
        }
        const uint32_t flags = udata;
        const bool constant = flags & kHidConstant;
        if (!constant && bits > 0) {
          if (!g.has_usage_page &&
              std::none_of(l.usages.begin(), l.usages.end(),
                           [](const UsageRange& u) { return u.explicit_page; })) {
            error = at(item_at, "data item before any Usage Page");
            return false;
          }
          if (d.fields.size() + g.report_count > kMaxFields) {
            error = at(item_at, "too many fields");
            return false;
          }
          HidField f;
          f.type = rtype;
          f.report_id = g.report_id;
          f.bit_size = g.report_size;
          f.flags = flags;
          f.logical_min = g.logical_min;
          f.logical_max = resolve_max(g.logical_max_raw, g.logical_max_size, g.logical_min);
          f.physical_min = g.physical_min;
          f.physical_max = resolve_max(g.physical_max_raw, g.physical_max_size, g.physical_min);
          if (f.physical_min == 0 && f.physical_max == 0) {
            f.physical_min = f.logical_min;
            f.physical_max = f.logical_max;
          }
          f.unit_exponent = g.unit_exponent;
          f.unit = g.unit;
          f.collection = collection_stack.empty() ? -1 : collection_stack.back();
          if (flags & kHidVariable) {
            // Element k takes the k-th usage of the expanded list; the last one repeats.
            std::size_t range = 0;
            uint32_t next = l.usages.empty() ? 0 : l.usages[0].min;
            for (uint32_t k = 0; k < g.report_count; ++k) {
              uint32_t u = 0;
              if (!l.usages.empty()) {
                const UsageRange& r = l.usages[range];
                u = resolve_usage(next, r.explicit_page, g.usage_page);
                if (next < r.max) {
                  ++next;
                } else if (range + 1 < l.usages.size()) {
                  ++range;
                  next = l.usages[range].min;
                }
              }
              f.usage = f.usage_min = f.usage_max = u;
              f.bit_offset = rep->bit_length + k * g.report_size;
              d.fields.push_back(f);
            }
          } else {
            f.count = g.report_count;
            if (!l.usages.empty()) {
              f.usage_min =
                  resolve_usage(l.usages.front().min, l.usages.front().explicit_page, g.usage_page);
              f.usage_max =
                  resolve_usage(l.usages.back().max, l.usages.back().explicit_page, g.usage_page);
            }
            f.usage = f.usage_min;
            f.bit_offset = rep->bit_length;
            d.fields.push_back(f);
          }
        }
        rep->bit_length += bits;
        l.clear();
      } else if (tag == 10) {  // Collection
        if (collection_stack.size() >= std::size_t(kMaxDepth)) {
          error = at(item_at, "collections nested deeper than " + std::to_string(kMaxDepth));
          return false;
        }
        HidCollection c;
        c.type = uint8_t(udata);
        if (!l.usages.empty())
          c.usage = resolve_usage(l.usages[0].min, l.usages[0].explicit_page, g.usage_page);
        c.parent = collection_stack.empty() ? -1 : collection_stack.back();
        const int index = int(d.collections.size());
        c.application = c.type == 1     ? index
                        : c.parent >= 0 ? d.collections[std::size_t(c.parent)].application
                                        : -1;
        d.collections.push_back(c);
        collection_stack.push_back(index);
        l.clear();
      } else if (tag == 12) {  // End Collection
        if (collection_stack.empty()) {
          error = at(item_at, "End Collection without an open collection");
          return false;
        }
        collection_stack.pop_back();
        l.clear();
      } else {
        error = at(item_at, "unknown main item tag " + std::to_string(tag));
        return false;
      }
    } else if (type == 1) {  // global
      switch (tag) {
        case 0:
          g.usage_page = uint16_t(udata);
          g.has_usage_page = true;
          break;
        case 1:
          g.logical_min = sdata;
          break;
        case 2:
          g.logical_max_raw = udata;
          g.logical_max_size = size;
          break;
        case 3:
          g.physical_min = sdata;
          break;
        case 4:
          g.physical_max_raw = udata;
          g.physical_max_size = size;
          break;
        case 5:
          // A 1-byte exponent 0..15 is a 4-bit two's complement nibble (0x0d = -3).
          g.unit_exponent = (size == 1 && udata <= 15)
                                ? int8_t(udata >= 8 ? int(udata) - 16 : int(udata))
                                : int8_t(sdata);
          break;
        case 6:
          g.unit = udata;
          break;
        case 7:
          g.report_size = udata;
          break;
        case 8:
          if (udata == 0 || udata > 255) {
            error = at(item_at, "Report ID " + std::to_string(udata) + " (expected 1..255)");
            return false;
          }
          g.report_id = uint8_t(udata);
          d.uses_report_ids = true;
          break;
        case 9:
          g.report_count = udata;
          break;
        case 10:
          if (global_stack.size() >= std::size_t(kMaxDepth)) {
            error = at(item_at, "Push nested deeper than " + std::to_string(kMaxDepth));
            return false;
          }
          global_stack.push_back(g);
          break;
        case 11:
          if (global_stack.empty()) {
            error = at(item_at, "Pop without a matching Push");
            return false;
          }
          g = global_stack.back();
          global_stack.pop_back();
          break;
        default:
          error = at(item_at, "unknown global item tag " + std::to_string(tag));
          return false;
      }
    } else if (type == 2) {  // local
      const bool extended = size == 4;
      switch (tag) {
        case 0:
          l.usages.push_back({udata, udata, extended});
          break;
        case 1:
          l.have_min = true;
          l.pending_min = udata;
          l.pending_min_explicit = extended;
          break;
        case 2:
          if (!l.have_min) {
            error = at(item_at, "Usage Maximum without a Usage Minimum");
            return false;
          }
          if (udata < l.pending_min) {
            error = at(item_at, "Usage Maximum below Usage Minimum");
            return false;
          }
          if (extended != l.pending_min_explicit) {
            error = at(item_at, "Usage Minimum and Maximum of different sizes");
            return false;
          }
          l.usages.push_back({l.pending_min, udata, extended});
          l.have_min = false;
          break;
        default:
          break;  // designators, strings, delimiters: nothing to map
      }
    } else {
      error = at(item_at, "reserved item type");
      return false;
    }
  }
  if (!collection_stack.empty()) {
    error = "descriptor ends with " + std::to_string(collection_stack.size()) +
            " collection(s) still open";
    return false;
  }
  if (!global_stack.empty()) {
    error = "descriptor ends with " + std::to_string(global_stack.size()) + " unmatched Push";
    return false;
  }
  // Without any Application collection (some tablets open their pen as a top-level Physical
  // collection), each top-level collection stands for the application, as Linux maps them.
  const bool any_application = std::any_of(d.collections.begin(), d.collections.end(),
                                           [](const HidCollection& c) { return c.type == 1; });
  if (!any_application)
    for (HidCollection& c : d.collections)
      c.application = c.parent < 0 ? int(&c - d.collections.data())
                                   : d.collections[std::size_t(c.parent)].application;
  out = std::move(d);
  return true;
}

std::vector<HidPenLayout> find_pens(const HidDescriptor& d) {
  auto is_pen_field = [&](const HidField& f) {
    if (f.collection < 0) return false;
    const uint32_t app = d.application_usage(f);
    if (app >> 16 != hid::kPageDigitizer) return false;
    if (app == hid::kDigitizer || app == hid::kPen || app == hid_usage(0x0D, 0x03)) return true;
    for (int c = f.collection; c >= 0; c = d.collections[std::size_t(c)].parent)
      if (d.collections[std::size_t(c)].usage == hid::kStylus) return true;
    return false;
  };
  std::vector<HidPenLayout> pens;
  for (const HidReportInfo& r : d.reports) {
    if (r.type != HidReportType::input) continue;
    HidPenLayout pen;
    pen.report_id = r.id;
    for (const HidField& f : d.fields) {
      if (f.type != HidReportType::input || f.report_id != r.id || f.is_array() || !is_pen_field(f))
        continue;
      pen.application_usage = d.application_usage(f);
      auto take = [&](std::optional<HidField>& slot) {
        if (!slot) slot = f;
        return true;
      };
      switch (f.usage) {
        case hid::kX:
          take(pen.x);
          break;
        case hid::kY:
          take(pen.y);
          break;
        case hid::kTipPressure:
          take(pen.pressure);
          break;
        case hid::kXTilt:
          take(pen.x_tilt);
          break;
        case hid::kYTilt:
          take(pen.y_tilt);
          break;
        case hid::kTipSwitch:
          take(pen.tip);
          break;
        case hid::kInRange:
          take(pen.in_range);
          break;
        case hid::kBarrelSwitch:
          take(pen.barrel);
          break;
        case hid::kSecondaryBarrelSwitch:
        case hid::kSecondaryTipSwitch:
          take(pen.secondary);
          break;
        case hid::kInvert:
          take(pen.invert);
          break;
        case hid::kEraser:
          take(pen.eraser);
          break;
        default:
          if (f.usage >> 16 == hid::kPageButton && f.bit_size == 1) pen.other_buttons.push_back(f);
          break;
      }
    }
    if (pen.x && pen.y) pens.push_back(std::move(pen));
  }
  return pens;
}

std::string hid_usage_name(uint32_t usage) {
  struct Name {
    uint32_t usage;
    const char* name;
  };
  static const Name names[] = {
      {hid::kX, "Generic Desktop/X"},
      {hid::kY, "Generic Desktop/Y"},
      {hid_usage(0x01, 0x02), "Generic Desktop/Mouse"},
      {hid_usage(0x01, 0x06), "Generic Desktop/Keyboard"},
      {hid::kDigitizer, "Digitizer/Digitizer"},
      {hid::kPen, "Digitizer/Pen"},
      {hid_usage(0x0D, 0x04), "Digitizer/Touch Screen"},
      {hid::kStylus, "Digitizer/Stylus"},
      {hid_usage(0x0D, 0x22), "Digitizer/Finger"},
      {hid::kTipPressure, "Digitizer/Tip Pressure"},
      {hid::kInRange, "Digitizer/In Range"},
      {hid::kInvert, "Digitizer/Invert"},
      {hid::kXTilt, "Digitizer/X Tilt"},
      {hid::kYTilt, "Digitizer/Y Tilt"},
      {hid::kTipSwitch, "Digitizer/Tip Switch"},
      {hid::kSecondaryTipSwitch, "Digitizer/Secondary Tip Switch"},
      {hid::kBarrelSwitch, "Digitizer/Barrel Switch"},
      {hid::kEraser, "Digitizer/Eraser"},
      {hid_usage(0x0D, 0x51), "Digitizer/Contact Identifier"},
      {hid_usage(0x0D, 0x54), "Digitizer/Contact Count"},
      {hid_usage(0x0D, 0x55), "Digitizer/Contact Count Maximum"},
      {hid_usage(0x0D, 0x56), "Digitizer/Scan Time"},
      {hid::kSecondaryBarrelSwitch, "Digitizer/Secondary Barrel Switch"},
  };
  for (const Name& n : names)
    if (n.usage == usage) return n.name;
  char buf[32];
  if (usage >> 16 == hid::kPageButton) {
    std::snprintf(buf, sizeof buf, "Button/%u", usage & 0xffff);
  } else {
    std::snprintf(buf, sizeof buf, "0x%04x/0x%04x", usage >> 16, usage & 0xffff);
  }
  return buf;
}

}  // namespace ardcell
