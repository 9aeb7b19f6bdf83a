#include "drivers/glyph_atlas_sdl.h"

#include <SDL_ttf.h>

#include <algorithm>
#include <memory>

#ifndef ARDCELL_HUD_FONT
#define ARDCELL_HUD_FONT ""
#endif

namespace ardcell {

std::string_view hud_font_path() { return ARDCELL_HUD_FONT; }

SdlGlyphAtlas::~SdlGlyphAtlas() { release(); }

void SdlGlyphAtlas::release() {
  if (texture_) SDL_DestroyTexture(texture_);
  texture_ = nullptr;
  pixel_height_ = line_height_ = 0;
}

bool SdlGlyphAtlas::prepare(SDL_Renderer* renderer, int pixel_height, std::string& error) {
  if (texture_ && pixel_height == pixel_height_) return true;
  release();
  const std::string path(hud_font_path());
  if (path.empty()) {
    error = "no HUD font found when ardcell was built (install fonts-dejavu-core and reconfigure)";
    return false;
  }
  if (!TTF_WasInit() && TTF_Init() != 0) {
    error = std::string("cannot start SDL2_ttf (") + TTF_GetError() + ")";
    return false;
  }
  // The font is needed only while the glyphs are rendered; TTF stays initialised for a resize.
  std::unique_ptr<TTF_Font, void (*)(TTF_Font*)> font(TTF_OpenFont(path.c_str(), pixel_height),
                                                      TTF_CloseFont);
  if (!font) {
    error = "HUD font " + path + ": " + TTF_GetError() + " (expected fonts-dejavu-core)";
    return false;
  }
  TTF_SetFontHinting(font.get(), TTF_HINTING_LIGHT);
  const int height = TTF_FontHeight(font.get());
  // One row of cells, each as wide as its glyph's advance (a monospace font: all alike).
  int total = 0;
  for (char c = kFirst; c <= kLast; ++c) {
    int advance = 0;
    TTF_GlyphMetrics(font.get(), Uint16(c), nullptr, nullptr, nullptr, nullptr, &advance);
    glyphs_[std::size_t(c - kFirst)] = {total, 0, std::max(1, advance), height};
    total += std::max(1, advance);
  }
  std::unique_ptr<SDL_Surface, void (*)(SDL_Surface*)> atlas(
      SDL_CreateRGBSurfaceWithFormat(0, total, height, 32, SDL_PIXELFORMAT_ARGB8888),
      SDL_FreeSurface);
  if (!atlas) {
    error = std::string("HUD glyphs: ") + SDL_GetError();
    return false;
  }
  SDL_FillRect(atlas.get(), nullptr, SDL_MapRGBA(atlas->format, 255, 255, 255, 0));
  const SDL_Color white{255, 255, 255, 255};
  for (char c = kFirst + 1; c <= kLast; ++c) {
    const char text[2] = {c, '\0'};
    std::unique_ptr<SDL_Surface, void (*)(SDL_Surface*)> glyph(
        TTF_RenderText_Blended(font.get(), text, white), SDL_FreeSurface);
    if (!glyph) continue;  // a glyph the font lacks stays blank
    SDL_SetSurfaceBlendMode(glyph.get(), SDL_BLENDMODE_NONE);
    SDL_Rect dst = glyphs_[std::size_t(c - kFirst)];
    dst.w = std::min(dst.w, glyph->w);
    dst.h = std::min(dst.h, glyph->h);
    SDL_Rect src{0, 0, dst.w, dst.h};
    SDL_BlitSurface(glyph.get(), &src, atlas.get(), &dst);
  }
  texture_ = SDL_CreateTextureFromSurface(renderer, atlas.get());
  if (!texture_) {
    error = std::string("HUD glyph texture: ") + SDL_GetError();
    return false;
  }
  SDL_SetTextureBlendMode(texture_, SDL_BLENDMODE_BLEND);
  pixel_height_ = pixel_height;
  line_height_ = height;
  return true;
}

int SdlGlyphAtlas::width(std::string_view text) const {
  int w = 0;
  for (char c : text) w += glyphs_[std::size_t(index(c))].w;
  return w;
}

int SdlGlyphAtlas::draw(SDL_Renderer* renderer, std::string_view text, int x, int y,
                        SDL_Color colour) const {
  if (!texture_) return 0;
  SDL_SetTextureColorMod(texture_, colour.r, colour.g, colour.b);
  SDL_SetTextureAlphaMod(texture_, colour.a);
  const int x0 = x;
  for (char c : text) {
    const SDL_Rect& src = glyphs_[std::size_t(index(c))];
    const SDL_Rect dst{x, y, src.w, src.h};
    if (c != ' ') SDL_RenderCopy(renderer, texture_, &src, &dst);
    x += src.w;
  }
  return x - x0;
}

}  // namespace ardcell
