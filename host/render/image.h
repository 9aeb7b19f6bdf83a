#pragma once
// ImageRgb8: a frame as packed 8-bit RGB, row 0 at the top. The caller owns it and sizes it
// once (resize), so rendering frames in a loop allocates nothing.
#include <cstdint>
#include <vector>

namespace ardcell {

struct ImageRgb8 {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;  // width * height * 3 bytes, row-major from the top

  void resize(int w, int h) {
    width = w;
    height = h;
    rgb.assign(std::size_t(w) * std::size_t(h) * 3, 0);
  }
  uint8_t* row(int y) { return rgb.data() + std::size_t(y) * std::size_t(width) * 3; }
  const uint8_t* row(int y) const { return rgb.data() + std::size_t(y) * std::size_t(width) * 3; }
  bool empty() const { return width <= 0 || height <= 0; }
};

}  // namespace ardcell
