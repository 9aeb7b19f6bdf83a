// libFuzzer target for the preset parser: any input either parses or gives a message that
// starts with the source name; what parses writes back to TOML that parses to the same values.
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "host/scenes/preset.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace ardcell;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  Preset p;
  const Status s = parse_preset(text, "fuzz.toml", p);
  if (!s.is_ok()) {
    if (s.message().rfind("fuzz.toml:", 0) != 0) std::abort();
    return 0;
  }
  Preset back;
  if (!parse_preset(preset_to_toml(p), "fuzz.toml", back).is_ok()) std::abort();
  if (!preset_difference(p, back).empty()) std::abort();
  return 0;
}
