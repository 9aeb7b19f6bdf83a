// libFuzzer target: HID report descriptor parsing, then decoding of the remaining bytes as
// input reports (generic and pen). Input: [descriptor length (2 bytes LE)] [descriptor]
// [reports...], each report prefixed by its length byte. Seeds: the refdata descriptors
// (tests/fuzz/corpus/hid_fuzz/*.bin: each refdata R: line in this layout, followed by its E:
// lines as reports).
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include "drivers/hid_descriptor.h"
#include "drivers/hid_recorder.h"
#include "drivers/hid_report.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace ardcell;
  if (size < 2) return 0;
  const std::size_t dlen = std::min<std::size_t>(size - 2, std::size_t(data[0] | (data[1] << 8)));
  const std::span<const uint8_t> bytes(data + 2, size - 2);
  HidDescriptor d;
  std::string error;
  if (!parse_hid_descriptor(bytes.first(dlen), d, error)) return 0;
  const std::vector<HidPenLayout> pens = find_pens(d);
  HidReportDecoder decoder(d);
  HidDecodedReport report;
  std::span<const uint8_t> rest = bytes.subspan(dlen);
  while (!rest.empty()) {
    const std::size_t n = std::min<std::size_t>(rest[0], rest.size() - 1);
    const std::span<const uint8_t> raw = rest.subspan(1, n);
    decoder.decode(raw, report, error);
    for (const HidPenLayout& pen : pens) {
      HidPenState s;
      if (decode_pen(pen, d.uses_report_ids, raw, s, error)) pen_state_to_sample(pen, s, 0.0);
    }
    rest = rest.subspan(1 + n);
  }
  // The text format too: the same bytes as a hid-recorder file.
  HidRecording rec;
  parse_hid_recording(std::string(reinterpret_cast<const char*>(data), size), rec, error);
  return 0;
}
