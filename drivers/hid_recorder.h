#pragma once
// The hid-recorder text format (hid-tools / libevdev's hid-recorder):
//   # comment
//   D: 0                                  device index (accepted, ignored)
//   R: <size> <hex bytes...>              report descriptor
//   N: <name>
//   P: <physical path>                    (optional)
//   I: <bus> <vendor> <product>           hex
//   E: <seconds.micros> <size> <hex bytes...>   one input report
// One device per file. Comments directly before an E: line are kept with that event.
#include <cstdint>
#include <string>
#include <vector>

namespace ardcell {

struct HidEvent {
  double time = 0;  // seconds
  std::vector<uint8_t> data;
  std::string comment;  // the "# ..." lines just before it, joined by '\n', without "# "
};

struct HidRecording {
  std::vector<uint8_t> descriptor;
  std::string name;
  std::string phys;
  uint32_t bus = 0, vendor = 0, product = 0;
  std::vector<HidEvent> events;
};

// Parses the text; false with one line `error` naming the line number and what was expected
// ("2: E: bad timestamp ..."; read_hid_recording puts the path before it: "pen.txt:2: ...").
bool parse_hid_recording(const std::string& text, HidRecording& out, std::string& error);
bool read_hid_recording(const std::string& path, HidRecording& out, std::string& error);
std::string format_hid_recording(const HidRecording& rec);
// One E: line (no newline).
std::string format_hid_event(const HidEvent& e);
// Writes atomically (host/io/atomic_file.h: a temporary sibling, fsynced, then renamed), so the
// file is the whole recording or absent, never half-written.
bool write_hid_recording(const std::string& path, const HidRecording& rec, std::string& error);

}  // namespace ardcell
