// The hid-recorder text format: the real Kamvas 13 capture parses completely (descriptor,
// name, ids, 25 events with their labels), round-trips exactly, is written atomically, and
// malformed lines give one-line errors with the line number.
#include "drivers/hid_recorder.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace ardcell {
namespace {

const std::string kKamvas =
    std::string(ARDCELL_SHARED_DIR) + "/refdata/hid/huion_kamvas13gen3_GS1333_firmware_pen.hid.txt";

TEST(HidRecorder, ReadsTheKamvas13Capture) {
  HidRecording rec;
  std::string error;
  ASSERT_TRUE(read_hid_recording(kKamvas, rec, error)) << error;
  EXPECT_EQ(rec.descriptor.size(), 368u);
  EXPECT_EQ(rec.descriptor[0], 0x05);
  EXPECT_EQ(rec.descriptor.back(), 0xc0);
  EXPECT_EQ(rec.name, "HUION Huion Tablet_GS1333");
  EXPECT_EQ(rec.bus, 3u);
  EXPECT_EQ(rec.vendor, 0x256cu);
  EXPECT_EQ(rec.product, 0x2008u);
  ASSERT_EQ(rec.events.size(), 25u);
  EXPECT_DOUBLE_EQ(rec.events[0].time, 37.949777);
  EXPECT_EQ(rec.events[0].comment, "Pen: Barrel switch");
  EXPECT_EQ(rec.events[0].data,
            (std::vector<uint8_t>{0x0a, 0xc2, 0x5c, 0x28, 0x47, 0x2a, 0x00, 0x00, 0xf6, 0x3c}));
  EXPECT_EQ(rec.events[5].data.size(), 8u);
  EXPECT_DOUBLE_EQ(rec.events.back().time, 340.888288);
}

TEST(HidRecorder, RoundTripsAndWritesAtomically) {
  HidRecording rec;
  std::string error;
  ASSERT_TRUE(read_hid_recording(kKamvas, rec, error)) << error;
  const std::string text = format_hid_recording(rec);
  HidRecording again;
  ASSERT_TRUE(parse_hid_recording(text, again, error)) << error;
  EXPECT_EQ(again.descriptor, rec.descriptor);
  EXPECT_EQ(again.name, rec.name);
  ASSERT_EQ(again.events.size(), rec.events.size());
  for (std::size_t i = 0; i < rec.events.size(); ++i) {
    EXPECT_EQ(again.events[i].data, rec.events[i].data);
    EXPECT_NEAR(again.events[i].time, rec.events[i].time, 5e-7);
    EXPECT_EQ(again.events[i].comment, rec.events[i].comment);
  }
  EXPECT_EQ(format_hid_event(rec.events[0]), "E: 000037.949777 10 0a c2 5c 28 47 2a 00 00 f6 3c");

  const auto dir = std::filesystem::temp_directory_path() / "ardcell_hid_recorder_test";
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "kamvas.hid.txt").string();
  ASSERT_TRUE(write_hid_recording(path, rec, error)) << error;
  for (const auto& e : std::filesystem::directory_iterator(dir))  // no temporary left
    EXPECT_EQ(e.path().filename(), "kamvas.hid.txt");
  HidRecording back;
  ASSERT_TRUE(read_hid_recording(path, back, error)) << error;
  EXPECT_EQ(back.events.size(), 25u);
  // A folder that does not exist: an error, and nothing written.
  EXPECT_FALSE(write_hid_recording((dir / "no/such/dir/x.txt").string(), rec, error));
  EXPECT_NE(error.find("no/such/dir/x.txt: cannot create file"), std::string::npos) << error;
  std::filesystem::remove_all(dir);
}

TEST(HidRecorder, MalformedLinesNameTheLine) {
  struct Case {
    const char* text;
    const char* expect;
  };
  const Case cases[] = {
      {"N: x\n", "no R: line"},
      {"R: 3 05 0d\n", "1: R: says 3 bytes but has 2"},
      {"R: 2 05 zz\n", "1: R: \"zz\" is not a hex byte"},
      {"R: 1 05\nR: 1 05\n", "2: a second R: line"},
      {"R: 1 05\nI: 3 256c\n", "2: I: expected three hex numbers"},
      {"R: 1 05\nE: 1.0 2 0a\n", "2: E: says 2 bytes but has 1"},
      {"R: 1 05\nE: 2.0 1 0a\nE: 1.0 1 0a\n", "3: E: timestamp goes backwards"},
      {"R: 1 05\nE: abc 1 0a\n", "2: E: bad timestamp"},
      {"R: 1 05\nE: 1.0 0\n", "2: E: an event needs at least one byte"},
      {"R: 1 05\nX: what\n", "2: unknown line kind"},
      {"R: 1 05\nhello\n", "2: expected a line starting"},
  };
  for (const Case& c : cases) {
    HidRecording rec;
    std::string error;
    EXPECT_FALSE(parse_hid_recording(c.text, rec, error)) << c.text;
    EXPECT_EQ(error.rfind(c.expect, 0), 0u) << c.text << " -> " << error;
  }
  HidRecording rec;
  std::string error;
  EXPECT_FALSE(read_hid_recording("/nonexistent/file.hid.txt", rec, error));
  EXPECT_NE(error.find("/nonexistent/file.hid.txt: not found (expected a hid-recorder file)"),
            std::string::npos);
}

}  // namespace
}  // namespace ardcell
