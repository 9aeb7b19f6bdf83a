// Every descriptor of ../shared/refdata/hid parses to the fields, bit offsets and ranges read
// off its bytes by hand (each expectation below names the items it comes from), and malformed
// descriptors give an error, never a crash.
#include "drivers/hid_descriptor.h"

#include <gtest/gtest.h>

#include "drivers/hid_recorder.h"
#include "drivers/hid_report.h"

namespace ardcell {
namespace {

HidDescriptor load(const char* file) {
  HidRecording rec;
  std::string error;
  const std::string path = std::string(ARDCELL_SHARED_DIR) + "/refdata/hid/" + file;
  EXPECT_TRUE(read_hid_recording(path, rec, error)) << error;
  HidDescriptor d;
  EXPECT_TRUE(parse_hid_descriptor(rec.descriptor, d, error)) << error;
  return d;
}

const HidField& field(const HidDescriptor& d, uint8_t id, uint32_t usage) {
  const HidField* f = d.find_field(HidReportType::input, id, usage);
  EXPECT_NE(f, nullptr) << "report " << int(id) << " usage " << hid_usage_name(usage);
  static const HidField none;
  return f ? *f : none;
}

void expect_field(const HidField& f, uint32_t offset, uint32_t size, int64_t lmin, int64_t lmax) {
  EXPECT_EQ(f.bit_offset, offset);
  EXPECT_EQ(f.bit_size, size);
  EXPECT_EQ(f.logical_min, lmin);
  EXPECT_EQ(f.logical_max, lmax);
}

// Kamvas 13 Gen 3 / Kamvas 16 Gen 3, pen report 0x0a (85 0a):
//  09 42 09 44 09 43 09 3c 09 45, 15 00 25 01 75 01 95 06 81 02 -> bits 0..5: Tip, Barrel,
//    Secondary Tip, Invert, Eraser, Eraser (the last usage repeats for the 6th bit)
//  09 32 75 01 95 01 81 02 -> bit 6 In Range; 81 03 -> bit 7 constant
//  05 01 09 30 09 31 55 0d 65 33 26 ff 7f 35 00 46 00 08 75 10 95 02 81 02 -> X at 8, Y at 24,
//    16 bits, logical 0..32767, physical 0..2048, unit 0x33, exponent -3
//  05 0d 09 30 26 ff 3f 75 10 95 01 81 02 -> Tip Pressure at 40, 16 bits, 0..16383
//  09 3d 09 3e 15 a6 25 5a 75 08 95 02 81 02 -> X Tilt at 56, Y Tilt at 64, 8 bits, -90..90
// Report length 72 bits = 9 bytes + ID = 10 (the E: lines of the recording are 10 bytes).
void expect_kamvas_pen(const HidDescriptor& d) {
  EXPECT_TRUE(d.uses_report_ids);
  expect_field(field(d, 0x0a, hid::kTipSwitch), 0, 1, 0, 1);
  expect_field(field(d, 0x0a, hid::kBarrelSwitch), 1, 1, 0, 1);
  expect_field(field(d, 0x0a, hid::kSecondaryTipSwitch), 2, 1, 0, 1);
  expect_field(field(d, 0x0a, hid::kInvert), 3, 1, 0, 1);
  expect_field(field(d, 0x0a, hid::kEraser), 4, 1, 0, 1);
  expect_field(field(d, 0x0a, hid::kInRange), 6, 1, 0, 1);
  const HidField& x = field(d, 0x0a, hid::kX);
  expect_field(x, 8, 16, 0, 32767);
  EXPECT_EQ(x.physical_min, 0);
  EXPECT_EQ(x.physical_max, 2048);
  EXPECT_EQ(x.unit, 0x33u);
  EXPECT_EQ(x.unit_exponent, -3);
  expect_field(field(d, 0x0a, hid::kY), 24, 16, 0, 32767);
  expect_field(field(d, 0x0a, hid::kTipPressure), 40, 16, 0, 16383);
  const HidField& tx = field(d, 0x0a, hid::kXTilt);
  expect_field(tx, 56, 8, -90, 90);
  EXPECT_TRUE(tx.is_signed());
  expect_field(field(d, 0x0a, hid::kYTilt), 64, 8, -90, 90);
  const HidReportInfo* pen = d.find_report(HidReportType::input, 0x0a);
  ASSERT_NE(pen, nullptr);
  EXPECT_EQ(pen->bit_length, 72u);
  EXPECT_EQ(pen->byte_length(true), 10u);

  // Touch report 0x04: per finger 6-bit Contact Id + Tip + pad (8), X 16, Y 16, pressure 16
  // -> 56 bits; two fingers 112; Scan Time 32 (27 ff ff ff 7f: max 0x7fffffff) -> 144;
  // Contact Count 8 -> 152; 8 constant bytes -> 216 bits = 27 bytes + ID = 28.
  const HidReportInfo* touch = d.find_report(HidReportType::input, 0x04);
  ASSERT_NE(touch, nullptr);
  EXPECT_EQ(touch->bit_length, 216u);
  const HidField& scan = field(d, 0x04, hid_usage(0x0D, 0x56));
  expect_field(scan, 112, 32, 0, 0x7fffffff);
  // Second finger's X: 56 + 8 (id, tip, pad) = 64, physical max 0x0c15 = 3093, exponent -2.
  int fingers_x = 0;
  for (const HidField& f : d.fields)
    if (f.report_id == 0x04 && f.usage == hid::kX) {
      EXPECT_EQ(f.bit_offset, fingers_x == 0 ? 8u : 64u);
      EXPECT_EQ(f.physical_max, 3093);
      EXPECT_EQ(f.unit_exponent, -2);
      EXPECT_EQ(f.flags, uint32_t(kHidVariable | kHidNullState));
      ++fingers_x;
    }
  EXPECT_EQ(fingers_x, 2);
  // Feature reports: 5 (Contact Count Maximum, 8 bits, max 10) and 6 (vendor 0xff00/0xc5,
  // 96 00 01: count 256 of 8 bits).
  const HidReportInfo* f5 = d.find_report(HidReportType::feature, 5);
  const HidReportInfo* f6 = d.find_report(HidReportType::feature, 6);
  ASSERT_NE(f5, nullptr);
  ASSERT_NE(f6, nullptr);
  EXPECT_EQ(f5->bit_length, 8u);
  EXPECT_EQ(f6->bit_length, 2048u);
  const HidField* vendor = d.find_field(HidReportType::feature, 6, hid_usage(0xff00, 0xc5));
  ASSERT_NE(vendor, nullptr);
  EXPECT_EQ(vendor->logical_max, 255);  // 26 ff 00: 2-byte 255, not -1

  const std::vector<HidPenLayout> pens = find_pens(d);
  ASSERT_EQ(pens.size(), 1u);  // the touch screen (0x0D/0x04, fingers) is not a pen
  EXPECT_EQ(pens[0].report_id, 0x0a);
  // 09 20 a1 01: the Stylus collection is itself an Application collection inside Pen.
  EXPECT_EQ(pens[0].application_usage, hid::kStylus);
  ASSERT_TRUE(pens[0].x && pens[0].y && pens[0].pressure && pens[0].x_tilt && pens[0].y_tilt);
  ASSERT_TRUE(pens[0].tip && pens[0].barrel && pens[0].secondary && pens[0].invert &&
              pens[0].eraser && pens[0].in_range);
  EXPECT_EQ(pens[0].eraser->bit_offset, 4u);  // the first Eraser bit, not the repeated one
}

TEST(HidDescriptor, Kamvas16Gen3PenAndTouch) {
  const HidDescriptor d = load("huion_kamvas16gen3_GS1563_pen.rdesc.hid.txt");
  expect_kamvas_pen(d);
  EXPECT_EQ(d.find_report(HidReportType::input, 0x03), nullptr);
}

TEST(HidDescriptor, Kamvas13Gen3AddsKeyboard) {
  const HidDescriptor d = load("huion_kamvas13gen3_GS1333_firmware_pen.hid.txt");
  expect_kamvas_pen(d);
  // Keyboard report 3: 05 07 19 e0 29 e7 ... 75 01 95 08 81 02 -> 8 modifier bits E0..E7;
  // 19 00 29 ff 26 ff 00 75 08 95 06 81 00 -> one Array field of 6 bytes, usages 0..255.
  const HidReportInfo* kb = d.find_report(HidReportType::input, 0x03);
  ASSERT_NE(kb, nullptr);
  EXPECT_EQ(kb->bit_length, 56u);  // 7 bytes + ID = the 8-byte E: lines
  expect_field(field(d, 0x03, hid_usage(0x07, 0xe0)), 0, 1, 0, 1);
  expect_field(field(d, 0x03, hid_usage(0x07, 0xe7)), 7, 1, 0, 1);
  const HidField* keys = nullptr;
  for (const HidField& f : d.fields)
    if (f.report_id == 0x03 && f.is_array()) keys = &f;
  ASSERT_NE(keys, nullptr);
  EXPECT_EQ(keys->bit_offset, 8u);
  EXPECT_EQ(keys->count, 6u);
  EXPECT_EQ(keys->usage_min, hid_usage(0x07, 0x00));
  EXPECT_EQ(keys->usage_max, hid_usage(0x07, 0xff));
  EXPECT_EQ(keys->logical_max, 255);
  EXPECT_EQ(d.application_usage(*keys), hid_usage(0x01, 0x06));
}

// H610 Pro, report 7: 09 42 09 44 09 45 09 3c 09 43 09 44 (6 usages), 75 01 95 06 81 02 ->
// Tip 0, Barrel 1, Eraser 2, Invert 3, Secondary Tip 4, Barrel 5; 09 32 ... 81 02 -> In Range
// 6; 81 03 -> pad 7. 05 01 09 30 75 10 95 01 a4 (Push) 55 0d 65 13 35 00 46 10 27
// 27 40 9c 00 00 (4-byte Logical Maximum 40000) 81 02 -> X at 8, 16 bits, 0..40000, physical
// 0..10000 (0x2710), unit 0x13 (inch), exponent -3; 09 31 46 6a 18 26 a8 61 81 02 -> Y at 24,
// 0..25000, physical 0..6250; b4 (Pop) 05 0d 09 30 26 ff 07 46 ff 07 55 00 66 11 e1 75 10
// 81 02 -> Tip Pressure at 40, 0..2047, unit 0xe111, exponent 0. Report: 56 bits (8 bytes).
// Report 9 is a Generic Desktop Mouse collection: not a pen even though it has Tip Pressure.
TEST(HidDescriptor, H610ProFourByteLogicalMaximum) {
  const HidDescriptor d = load("huion_h610pro_pen.rdesc.hid.txt");
  expect_field(field(d, 7, hid::kTipSwitch), 0, 1, 0, 1);
  expect_field(field(d, 7, hid::kBarrelSwitch), 1, 1, 0, 1);
  expect_field(field(d, 7, hid::kEraser), 2, 1, 0, 1);
  expect_field(field(d, 7, hid::kInvert), 3, 1, 0, 1);
  expect_field(field(d, 7, hid::kSecondaryTipSwitch), 4, 1, 0, 1);
  expect_field(field(d, 7, hid::kInRange), 6, 1, 0, 1);
  const HidField& x = field(d, 7, hid::kX);
  expect_field(x, 8, 16, 0, 40000);
  EXPECT_EQ(x.physical_max, 10000);
  EXPECT_EQ(x.unit, 0x13u);
  EXPECT_EQ(x.unit_exponent, -3);
  const HidField& y = field(d, 7, hid::kY);
  expect_field(y, 24, 16, 0, 25000);
  EXPECT_EQ(y.physical_max, 6250);
  const HidField& p = field(d, 7, hid::kTipPressure);
  expect_field(p, 40, 16, 0, 2047);
  EXPECT_EQ(p.unit, 0xe111u);
  EXPECT_EQ(p.unit_exponent, 0);
  EXPECT_EQ(d.find_report(HidReportType::input, 7)->bit_length, 56u);
  // Report 9: 3 buttons + 5 pad, X 8..24 (0..2048), Y, then pressure (flags 0xb2).
  EXPECT_EQ(d.find_report(HidReportType::input, 9)->bit_length, 56u);
  expect_field(field(d, 9, hid_usage(0x09, 1)), 0, 1, 0, 1);
  expect_field(field(d, 9, hid_usage(0x09, 3)), 2, 1, 0, 1);
  expect_field(field(d, 9, hid::kX), 8, 16, 0, 2048);
  EXPECT_EQ(field(d, 9, hid::kTipPressure).flags, 0xb2u);
  const std::vector<HidPenLayout> pens = find_pens(d);
  ASSERT_EQ(pens.size(), 1u);
  EXPECT_EQ(pens[0].report_id, 7);
  EXPECT_FALSE(pens[0].x_tilt.has_value());  // no tilt on this tablet
  EXPECT_EQ(pens[0].eraser->bit_offset, 2u);
  EXPECT_EQ(pens[0].secondary->bit_offset, 4u);
}

// XP-Pen Deco 01 V3, report 7: 09 42 09 44 09 45 09 3c ... 95 04 81 02 -> Tip 0, Barrel 1,
// Eraser 2, Invert 3; 95 01 81 03 -> pad 4; 09 32 95 01 81 02 -> In Range 5; 95 02 81 03 ->
// pad 6..7. 75 10 95 01 35 00 a4 (Push: page 0x0D) 05 01 09 30 65 13 55 0d 46 10 27
// 26 ff 7f 81 02 -> X at 8, 0..32767, physical 0..10000; 09 31 46 6a 18 ... -> Y at 24,
// physical 0..6250; b4 (Pop: page back to 0x0D, unit and exponent back to 0) 09 30 -> Tip
// Pressure (not X!) at 40, 45 00 26 ff 3f 81 42 -> 0..16383 with Null State; 09 3d 15 81 25 7f
// 75 08 -> X Tilt at 56, -127..127; 09 3e -> Y Tilt at 64. Report: 72 bits (10 bytes).
TEST(HidDescriptor, XpPenDeco01V3PushPop) {
  const HidDescriptor d = load("xppen_deco01v3_pen.rdesc.hid.txt");
  expect_field(field(d, 7, hid::kTipSwitch), 0, 1, 0, 1);
  expect_field(field(d, 7, hid::kInvert), 3, 1, 0, 1);
  expect_field(field(d, 7, hid::kInRange), 5, 1, 0, 1);
  const HidField& x = field(d, 7, hid::kX);
  expect_field(x, 8, 16, 0, 32767);
  EXPECT_EQ(x.physical_max, 10000);
  EXPECT_EQ(x.unit_exponent, -3);
  expect_field(field(d, 7, hid::kY), 24, 16, 0, 32767);
  EXPECT_EQ(field(d, 7, hid::kY).physical_max, 6250);
  const HidField& p = field(d, 7, hid::kTipPressure);
  expect_field(p, 40, 16, 0, 16383);
  EXPECT_EQ(p.unit, 0u);
  EXPECT_EQ(p.unit_exponent, 0);
  EXPECT_EQ(p.flags, uint32_t(kHidVariable | kHidNullState));
  expect_field(field(d, 7, hid::kXTilt), 56, 8, -127, 127);
  expect_field(field(d, 7, hid::kYTilt), 64, 8, -127, 127);
  EXPECT_EQ(d.find_report(HidReportType::input, 7)->bit_length, 72u);
  // Only one X in the report: the one after Pop is not Generic Desktop.
  int xs = 0;
  for (const HidField& f : d.fields) xs += f.usage == hid::kX;
  EXPECT_EQ(xs, 1);
  ASSERT_EQ(find_pens(d).size(), 1u);
}

TEST(HidDescriptor, ExtendedUsageCarriesItsOwnPage) {
  // Usage Page Generic Desktop, then a 4-byte usage 0x000D0030 (Digitizer/Tip Pressure).
  const uint8_t bytes[] = {0x05, 0x01, 0x09, 0x02, 0xa1, 0x01, 0x0b, 0x30, 0x00, 0x0d, 0x00, 0x15,
                           0x00, 0x26, 0xff, 0x00, 0x75, 0x08, 0x95, 0x01, 0x81, 0x02, 0xc0};
  HidDescriptor d;
  std::string error;
  ASSERT_TRUE(parse_hid_descriptor(bytes, d, error)) << error;
  ASSERT_EQ(d.fields.size(), 1u);
  EXPECT_EQ(d.fields[0].usage, hid::kTipPressure);
  EXPECT_FALSE(d.uses_report_ids);
}

TEST(HidDescriptor, SignedLogicalMaximumFollowsMinimum) {
  // 15 81 25 ff: min -127, max 0xff read signed = -1; 15 00 25 ff: max 255.
  const uint8_t a[] = {0x05, 0x01, 0x09, 0x30, 0x15, 0x81, 0x25,
                       0xff, 0x75, 0x08, 0x95, 0x01, 0x81, 0x02};
  const uint8_t b[] = {0x05, 0x01, 0x09, 0x30, 0x15, 0x00, 0x25,
                       0xff, 0x75, 0x08, 0x95, 0x01, 0x81, 0x02};
  HidDescriptor d;
  std::string error;
  ASSERT_TRUE(parse_hid_descriptor(a, d, error)) << error;
  EXPECT_EQ(d.fields[0].logical_max, -1);
  ASSERT_TRUE(parse_hid_descriptor(b, d, error)) << error;
  EXPECT_EQ(d.fields[0].logical_max, 255);
}

// A pen opened as a top-level Physical collection with no Application collection anywhere
// (Gaomon 1080 Pro, 256c:0064): Linux maps the top-level collection as the application, so
// must we.
//  05 0d 09 02 a1 00 -> Digitizer / Pen, Collection (Physical)
//  85 07 09 42 09 32 15 00 25 01 75 01 95 02 81 02 -> report 7: Tip bit 0, In Range bit 1
//  95 06 81 03 -> 6 constant bits
//  05 01 09 30 09 31 26 ff 7f 75 10 95 02 81 02 -> X at 8, Y at 24, 0..32767
//  05 0d 09 30 26 ff 1f 75 10 95 01 81 02 c0 -> Tip Pressure at 40, 0..8191
TEST(HidDescriptor, TopLevelPhysicalPenWithoutApplicationIsAPen) {
  std::vector<uint8_t> bytes = {0x05, 0x0d, 0x09, 0x02, 0xa1, 0x00, 0x85, 0x07, 0x09, 0x42, 0x09,
                                0x32, 0x15, 0x00, 0x25, 0x01, 0x75, 0x01, 0x95, 0x02, 0x81, 0x02,
                                0x95, 0x06, 0x81, 0x03, 0x05, 0x01, 0x09, 0x30, 0x09, 0x31, 0x26,
                                0xff, 0x7f, 0x75, 0x10, 0x95, 0x02, 0x81, 0x02, 0x05, 0x0d, 0x09,
                                0x30, 0x26, 0xff, 0x1f, 0x75, 0x10, 0x95, 0x01, 0x81, 0x02, 0xc0};
  HidDescriptor d;
  std::string error;
  ASSERT_TRUE(parse_hid_descriptor(bytes, d, error)) << error;
  const std::vector<HidPenLayout> pens = find_pens(d);
  ASSERT_EQ(pens.size(), 1u);
  EXPECT_EQ(pens[0].report_id, 7);
  EXPECT_EQ(pens[0].application_usage, hid::kPen);
  ASSERT_TRUE(pens[0].x && pens[0].y && pens[0].pressure && pens[0].tip);
  // Tip and in range, x = 0x4000, y = 0x2000, pressure = 0x1000.
  const uint8_t report[] = {0x07, 0x03, 0x00, 0x40, 0x00, 0x20, 0x00, 0x10};
  HidPenState st;
  ASSERT_TRUE(decode_pen(pens[0], d.uses_report_ids, report, st, error)) << error;
  EXPECT_TRUE(st.tip);
  EXPECT_TRUE(st.in_range);
  const StrokeSample sample = pen_state_to_sample(pens[0], st, 0.0);
  EXPECT_NEAR(sample.x, 0x4000 / 32767.0, 1e-4);
  EXPECT_NEAR(sample.y, 0x2000 / 32767.0, 1e-4);
  EXPECT_NEAR(sample.pressure, 0x1000 / 8191.0, 1e-4);

  // The same collection beside an Application collection stays what it is: not a pen.
  bytes.insert(bytes.begin(), {0x05, 0x01, 0x09, 0x02, 0xa1, 0x01, 0xc0});  // empty mouse app
  ASSERT_TRUE(parse_hid_descriptor(bytes, d, error)) << error;
  EXPECT_TRUE(find_pens(d).empty());
}

struct Malformed {
  const char* what;
  std::vector<uint8_t> bytes;
  const char* expect;  // a word the error must contain
};

TEST(HidDescriptor, MalformedGiveOneLineErrors) {
  const Malformed cases[] = {
      {"truncated item", {0x05, 0x0d, 0x26, 0xff}, "descriptor ends"},
      {"unclosed collection", {0x05, 0x0d, 0x09, 0x02, 0xa1, 0x01}, "still open"},
      {"end without collection", {0xc0}, "End Collection"},
      {"pop without push", {0xb4}, "Pop"},
      {"unmatched push", {0xa4}, "Push"},
      {"report id 0", {0x85, 0x00}, "Report ID"},
      {"usage max without min", {0x29, 0x03}, "Usage Minimum"},
      {"data before usage page", {0x09, 0x30, 0x75, 0x08, 0x95, 0x01, 0x81, 0x02}, "Usage Page"},
      {"report size too big",
       {0x05, 0x01, 0x09, 0x30, 0x76, 0x01, 0x01, 0x95, 0x01, 0x81, 0x02},
       "Report Size"},
      {"report count too big",
       {0x05, 0x01, 0x09, 0x30, 0x75, 0x01, 0x97, 0xff, 0xff, 0xff, 0x7f, 0x81, 0x02},
       "Report Count"},
      {"truncated long item", {0xfe, 0x05}, "long item"},
      {"unknown main tag", {0xf0}, "main item"},
  };
  for (const Malformed& m : cases) {
    HidDescriptor d;
    std::string error;
    EXPECT_FALSE(parse_hid_descriptor(m.bytes, d, error)) << m.what;
    EXPECT_NE(error.find(m.expect), std::string::npos) << m.what << ": " << error;
    EXPECT_EQ(error.find('\n'), std::string::npos);
  }
  // Collections nested 100 deep.
  std::vector<uint8_t> deep;
  for (int k = 0; k < 100; ++k) deep.insert(deep.end(), {0xa1, 0x00});
  HidDescriptor d;
  std::string error;
  EXPECT_FALSE(parse_hid_descriptor(deep, d, error));
  EXPECT_NE(error.find("nested"), std::string::npos) << error;
}

TEST(HidDescriptor, EveryTruncationOfTheRealDescriptorsIsHandled) {
  // Each prefix of every real descriptor either parses or fails with a message; never crashes.
  for (const char* file : {"huion_kamvas13gen3_GS1333_firmware_pen.hid.txt",
                           "huion_h610pro_pen.rdesc.hid.txt", "xppen_deco01v3_pen.rdesc.hid.txt"}) {
    HidRecording rec;
    std::string error;
    ASSERT_TRUE(
        read_hid_recording(std::string(ARDCELL_SHARED_DIR) + "/refdata/hid/" + file, rec, error));
    int failures = 0;
    for (std::size_t n = 0; n < rec.descriptor.size(); ++n) {
      HidDescriptor d;
      if (!parse_hid_descriptor(std::span(rec.descriptor).first(n), d, error)) {
        EXPECT_FALSE(error.empty());
        ++failures;
      }
    }
    EXPECT_GT(failures, 0) << file;  // cutting inside a collection must be caught
  }
}

}  // namespace
}  // namespace ardcell
