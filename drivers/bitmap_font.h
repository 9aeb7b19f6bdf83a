#pragma once
// A tiny built-in 5x7 bitmap font for the live HUD (no SDL_ttf, no font files): digits,
// upper-case letters (lower case draws as upper case) and the punctuation the HUD uses.
#include <array>
#include <cstdint>
#include <string_view>

namespace ardcell {

inline constexpr int kGlyphWidth = 5, kGlyphHeight = 7, kGlyphAdvance = 6;

// Seven rows, top first; bit 4 is the leftmost column. Unknown characters draw as '?'.
std::array<uint8_t, 7> glyph_rows(char c);

// Calls pixel(x, y) for every lit pixel of `text` drawn with its top-left at (x0, y0), each
// font pixel `scale` screen pixels wide (pixel gets the top-left of that square). Returns the
// width drawn.
template <class F>
int draw_text(std::string_view text, int x0, int y0, int scale, F&& pixel) {
  int x = x0;
  for (char c : text) {
    const auto rows = glyph_rows(c);
    for (int r = 0; r < kGlyphHeight; ++r)
      for (int col = 0; col < kGlyphWidth; ++col)
        if (rows[size_t(r)] & (0x10 >> col)) pixel(x + col * scale, y0 + r * scale);
    x += kGlyphAdvance * scale;
  }
  return x - x0;
}

}  // namespace ardcell
