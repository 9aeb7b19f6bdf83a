// Every event of the real Kamvas 13 Gen 3 recording (../shared/refdata/hid) decodes to the
// values the device sent. The expected values below were read by hand off each E: line with
// the layout of hid_descriptor_test.cpp (pen report 0x0a: byte 1 bits Tip, Barrel, Secondary
// Tip, Invert, Eraser, Eraser, In Range; X = bytes 2-3, Y = 4-5, pressure = 6-7, little endian;
// X/Y tilt = bytes 8, 9 signed), and agree with the author's label on each line.
#include "drivers/hid_report.h"

#include <gtest/gtest.h>

#include "drivers/hid_descriptor.h"
#include "drivers/hid_recorder.h"

namespace ardcell {
namespace {

struct Kamvas : ::testing::Test {
  void SetUp() override {
    std::string error;
    ASSERT_TRUE(
        read_hid_recording(std::string(ARDCELL_SHARED_DIR) +
                               "/refdata/hid/huion_kamvas13gen3_GS1333_firmware_pen.hid.txt",
                           rec, error))
        << error;
    ASSERT_TRUE(parse_hid_descriptor(rec.descriptor, desc, error)) << error;
    pens = find_pens(desc);
    ASSERT_EQ(pens.size(), 1u);
  }
  HidRecording rec;
  HidDescriptor desc;
  std::vector<HidPenLayout> pens;
};

struct PenExpect {
  bool tip, barrel, secondary, invert, in_range;
  int x, y, pressure, tilt_x, tilt_y;
};
struct KeyExpect {
  unsigned modifiers;  // bit k = usage 0xE0 + k
  int key;             // keyboard usage of the first array byte, 0 = none
};
struct Expect {
  bool pen;
  PenExpect p;
  KeyExpect k;
};

constexpr Expect P(bool tip, bool barrel, bool sec, bool inv, bool in_range, int x, int y, int p,
                   int tx, int ty) {
  return {true, {tip, barrel, sec, inv, in_range, x, y, p, tx, ty}, {}};
}
constexpr Expect K(unsigned mods, int key) { return {false, {}, {mods, key}}; }

// clang-format off
const Expect kExpected[] = {
    P(0, 1, 0, 0, 1, 10332, 10823, 0, -10, 60),     // c2 5c 28 47 2a 00 00 f6 3c  Barrel switch
    P(0, 0, 1, 0, 1, 10212, 10749, 0, -13, 56),     // c4 ...  Secondary barrel (declared 0x43)
    P(0, 0, 0, 1, 1, 10135, 10591, 0, -14, 51),     // c8 ...  Third switch (declared Invert)
    P(0, 0, 0, 0, 1, 0, 0, 0, 0, 2),                // c0 00.. Top-left
    P(0, 0, 0, 0, 0, 0, 0, 0, 0, 2),                // 00 00.. then out of range
    K(0, 0), K(0, 0),                               // wheel button releases
    P(0, 0, 0, 0, 1, 19434, 16392, 0, -60, 26),     // c0 ea 4b 08 40 .. c4 1a  Min X tilt
    K(0, 0x05),                                     // 03 00 05  Button 1 press
    P(0, 0, 0, 0, 1, 13479, 17049, 0, 60, -12),     // c0 a7 34 99 42 .. 3c f4  Max X tilt
    K(0, 0),
    P(0, 0, 0, 0, 1, 32767, 32767, 0, 0, 0),        // c0 ff 7f ff 7f  Bottom-right
    P(0, 0, 0, 0, 0, 32767, 32767, 0, 0, 0),        // 00 ff 7f ff 7f  then out of range
    P(1, 0, 0, 0, 1, 15486, 12562, 16383, 3, -3),   // c1 7e 3c 12 31 ff 3f 03 fd  max pressure
    K(0x05, 0x11), K(0, 0),                         // 03 05 11  Button 2: LCtrl+LAlt, 0x11
    K(0x01, 0x16), K(0, 0),                         // 03 01 16  Button 3: LCtrl, 0x16
    P(0, 0, 0, 0, 1, 12825, 22539, 0, 0, 60),       // c0 19 32 0b 58 .. 00 3c  Max Y tilt
    K(0, 0x2c), K(0, 0),                            // Button 4
    K(0x05, 0x1d), K(0, 0),                         // Button 5
    P(1, 0, 0, 0, 1, 15086, 12958, 181, 6, -10),    // c1 ee 3a 9e 32 b5 00 06 f6  low pressure
    P(0, 0, 0, 0, 1, 16517, 28297, 0, 23, -60),     // c0 85 40 89 6e .. 17 c4  Min Y tilt
};
// clang-format on

TEST_F(Kamvas, EveryEventDecodesToWhatTheDeviceSent) {
  ASSERT_EQ(rec.events.size(), std::size(kExpected));
  HidReportDecoder decoder(desc);
  HidDecodedReport report;
  for (std::size_t i = 0; i < rec.events.size(); ++i) {
    SCOPED_TRACE("event " + std::to_string(i) + " (" + rec.events[i].comment + ")");
    const std::vector<uint8_t>& raw = rec.events[i].data;
    const Expect& e = kExpected[i];
    std::string error;
    ASSERT_TRUE(decoder.decode(raw, report, error)) << error;
    if (e.pen) {
      EXPECT_EQ(report.report_id, 0x0a);
      HidPenState s;
      ASSERT_TRUE(decode_pen(pens[0], desc.uses_report_ids, raw, s, error)) << error;
      EXPECT_EQ(s.tip, e.p.tip);
      EXPECT_EQ(s.barrel, e.p.barrel);
      EXPECT_EQ(s.secondary, e.p.secondary);
      EXPECT_EQ(s.invert, e.p.invert);
      EXPECT_FALSE(s.eraser);
      EXPECT_EQ(s.in_range, e.p.in_range);
      EXPECT_EQ(s.x, e.p.x);
      EXPECT_EQ(s.y, e.p.y);
      EXPECT_EQ(s.pressure, e.p.pressure);
      EXPECT_EQ(s.x_tilt, e.p.tilt_x);
      EXPECT_EQ(s.y_tilt, e.p.tilt_y);
      // The generic decoder gives the same numbers, field by field.
      for (const HidDecodedValue& v : report.values) {
        if (v.usage == hid::kX && v.field->bit_offset == pens[0].x->bit_offset) {
          EXPECT_EQ(v.value, e.p.x);
        }
        if (v.usage == hid::kXTilt) {
          EXPECT_EQ(v.value, e.p.tilt_x);
        }
      }
    } else {
      EXPECT_EQ(report.report_id, 0x03);
      unsigned mods = 0;
      int key = 0;
      bool seen_key = false;
      for (const HidDecodedValue& v : report.values) {
        if (v.field->is_array()) {
          // First key slot; keyboard usage 0 is "no key".
          if (!seen_key) key = int(v.usage & 0xffff);
          seen_key = true;
        } else if ((v.usage >> 16) == 0x07 && v.value) {
          mods |= 1u << ((v.usage & 0xffff) - 0xe0);
        }
      }
      EXPECT_EQ(mods, e.k.modifiers);
      EXPECT_EQ(key, e.k.key);
      HidPenState s;
      EXPECT_FALSE(decode_pen(pens[0], true, raw, s, error));  // not the pen's report
    }
  }
}

TEST_F(Kamvas, LabelsAgreeWithDecodedValues) {
  // The author's labels: tilt extremes are the declared range's +-60 used by the device,
  // "max pressure" is the logical maximum 0x3fff, "out of range" clears In Range.
  for (const HidEvent& ev : rec.events) {
    if (ev.data[0] != 0x0a) continue;
    HidPenState s;
    std::string error;
    ASSERT_TRUE(decode_pen(pens[0], true, ev.data, s, error));
    const std::string& c = ev.comment;
    if (c.find("Min X Tilt") != std::string::npos) {
      EXPECT_EQ(s.x_tilt, -60);
    }
    if (c.find("Max X tilt") != std::string::npos) {
      EXPECT_EQ(s.x_tilt, 60);
    }
    if (c.find("Max Y Tilt") != std::string::npos) {
      EXPECT_EQ(s.y_tilt, 60);
    }
    if (c.find("Min Y tilt") != std::string::npos) {
      EXPECT_EQ(s.y_tilt, -60);
    }
    if (c.find("Tip switch") != std::string::npos) {
      EXPECT_TRUE(s.tip);
    }
    if (c.find("Barrel switch") != std::string::npos && c.find("Secondary") == std::string::npos) {
      EXPECT_TRUE(s.barrel);
    }
    if (c.find("Bottom-right") != std::string::npos) {
      EXPECT_EQ(s.x, pens[0].x->logical_max);
      EXPECT_EQ(s.y, pens[0].y->logical_max);
    }
  }
}

TEST_F(Kamvas, PenStatesBecomeStrokeSamples) {
  const HidEvent& max_pressure = rec.events[13];
  HidPenState s;
  std::string error;
  ASSERT_TRUE(decode_pen(pens[0], true, max_pressure.data, s, error));
  const StrokeSample sample = pen_state_to_sample(pens[0], s, max_pressure.time);
  EXPECT_DOUBLE_EQ(sample.time, 242.077160);
  EXPECT_FLOAT_EQ(sample.x, float(15486.0 / 32767.0));
  EXPECT_FLOAT_EQ(sample.y, float(12562.0 / 32767.0));
  EXPECT_FLOAT_EQ(sample.pressure, 1.0f);
  EXPECT_FLOAT_EQ(sample.tilt_x, 3.0f);  // tilt has no rotation unit: logical = degrees
  EXPECT_FLOAT_EQ(sample.tilt_y, -3.0f);
  EXPECT_EQ(sample.buttons, uint32_t(kButtonTip));
  EXPECT_TRUE(sample.in_range);
  EXPECT_FALSE(sample.eraser);

  // Third switch: the descriptor calls it Invert, which means the eraser end.
  ASSERT_TRUE(decode_pen(pens[0], true, rec.events[2].data, s, error));
  EXPECT_TRUE(pen_state_to_sample(pens[0], s, 0).eraser);
  ASSERT_TRUE(decode_pen(pens[0], true, rec.events[0].data, s, error));
  EXPECT_EQ(pen_state_to_sample(pens[0], s, 0).buttons, uint32_t(kButtonBarrel));
  ASSERT_TRUE(decode_pen(pens[0], true, rec.events[4].data, s, error));
  EXPECT_FALSE(pen_state_to_sample(pens[0], s, 0).in_range);
}

TEST_F(Kamvas, MalformedReportsGiveErrors) {
  HidReportDecoder decoder(desc);
  HidDecodedReport report;
  std::string error;
  EXPECT_FALSE(decoder.decode({}, report, error));
  EXPECT_NE(error.find("empty"), std::string::npos);
  const uint8_t unknown[] = {0x07, 0, 0, 0};
  EXPECT_FALSE(decoder.decode(unknown, report, error));
  EXPECT_NE(error.find("unknown input report ID 7"), std::string::npos) << error;
  const std::vector<uint8_t>& pen = rec.events[0].data;
  for (std::size_t n = 1; n < pen.size(); ++n) {
    EXPECT_FALSE(decoder.decode(std::span(pen).first(n), report, error)) << n;
    EXPECT_NE(error.find("the descriptor says 10"), std::string::npos) << error;
    HidPenState s;
    EXPECT_FALSE(decode_pen(pens[0], true, std::span(pen).first(n), s, error)) << n;
  }
  // Longer than declared (USB padding): decoded, extra bytes ignored.
  std::vector<uint8_t> padded = pen;
  padded.resize(16, 0xee);
  ASSERT_TRUE(decoder.decode(padded, report, error)) << error;
  HidPenState s;
  ASSERT_TRUE(decode_pen(pens[0], true, padded, s, error));
  EXPECT_EQ(s.x, 10332);
}

TEST(HidExtract, BitsAcrossBytesAndSigns) {
  const uint8_t b[] = {0b10110100, 0b01101011, 0xff};
  int64_t v = 0;
  ASSERT_TRUE(hid_extract(b, 2, 3, false, v));
  EXPECT_EQ(v, 0b101);
  ASSERT_TRUE(hid_extract(b, 6, 4, false, v));  // bits 6,7 of byte 0 then 0,1 of byte 1
  EXPECT_EQ(v, 0b1110);
  ASSERT_TRUE(hid_extract(b, 6, 4, true, v));
  EXPECT_EQ(v, 0b1110 - 16);
  ASSERT_TRUE(hid_extract(b, 16, 8, true, v));
  EXPECT_EQ(v, -1);
  EXPECT_FALSE(hid_extract(b, 20, 8, false, v));  // runs past the end
  EXPECT_FALSE(hid_extract(b, 0, 33, false, v));
  EXPECT_FALSE(hid_extract(b, 0, 0, false, v));
}

}  // namespace
}  // namespace ardcell
