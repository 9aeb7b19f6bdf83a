#pragma once
// The live HUD's text: printable ASCII of a TrueType font (DejaVu Sans Mono Bold from Debian's
// fonts-dejavu-core, found at configure time) rendered once by SDL2_ttf into one texture, then
// drawn a glyph at a time with SDL_RenderCopy, so a frame's HUD allocates nothing.
#include <SDL.h>

#include <array>
#include <string>
#include <string_view>

namespace ardcell {

class SdlGlyphAtlas {
 public:
  SdlGlyphAtlas() = default;
  SdlGlyphAtlas(const SdlGlyphAtlas&) = delete;
  SdlGlyphAtlas& operator=(const SdlGlyphAtlas&) = delete;
  ~SdlGlyphAtlas();

  // Renders the glyphs at `pixel_height` for `renderer` (again only when the height changed).
  // False with `error` (one line) when the font or the texture cannot be made.
  bool prepare(SDL_Renderer* renderer, int pixel_height, std::string& error);
  bool ready() const { return texture_ != nullptr; }
  int line_height() const { return line_height_; }

  // Width in pixels of `text` (characters outside printable ASCII count as '?').
  int width(std::string_view text) const;
  // Draws `text` in `colour` with its top-left at (x, y). Returns the width drawn.
  int draw(SDL_Renderer* renderer, std::string_view text, int x, int y, SDL_Color colour) const;

 private:
  static constexpr char kFirst = ' ', kLast = '~';
  static int index(char c) { return (c >= kFirst && c <= kLast ? c : '?') - kFirst; }
  void release();

  SDL_Texture* texture_ = nullptr;
  int pixel_height_ = 0, line_height_ = 0;
  std::array<SDL_Rect, kLast - kFirst + 1> glyphs_{};  // each glyph's cell in the texture
};

// The font file the HUD uses (ARDCELL_HUD_FONT).
std::string_view hud_font_path();

}  // namespace ardcell
