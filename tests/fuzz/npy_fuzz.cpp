// libFuzzer target for the .npy reader of saved states (host/io/npy.h parse_npy, the bytes of a
// whole file in memory): any input either parses to an array whose data is exactly ny x nx
// floats within the side limits, or gives a message naming the file; what parses reads back
// the same from npy_header + its data. Seeds: tests/fuzz/corpus/npy_fuzz/ (files --save-state
// writes, and broken headers).
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <span>
#include <string>

#include "host/io/npy.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace ardcell;
  NpyArray a;
  const Status s = parse_npy(std::span<const uint8_t>(data, size), "fuzz.npy", a);
  if (!s.is_ok()) {
    if (s.message().rfind("fuzz.npy", 0) != 0) std::abort();
    return 0;
  }
  if (a.ny < 1 || a.nx < 1 || a.ny > kNpyMaxSide || a.nx > kNpyMaxSide) std::abort();
  if (a.data.size() != std::size_t(a.ny) * std::size_t(a.nx)) std::abort();
  std::string again = npy_header(a.ny, a.nx);
  const std::size_t header = again.size();
  again.resize(header + a.data.size() * sizeof(float));
  std::memcpy(again.data() + header, a.data.data(), a.data.size() * sizeof(float));
  NpyArray b;
  if (!parse_npy(
           std::span<const uint8_t>(reinterpret_cast<const uint8_t*>(again.data()), again.size()),
           "again.npy", b)
           .is_ok())
    std::abort();
  if (b.ny != a.ny || b.nx != a.nx ||
      std::memcmp(a.data.data(), b.data.data(), a.data.size() * sizeof(float)) != 0)
    std::abort();
  return 0;
}
