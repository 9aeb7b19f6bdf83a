#pragma once
// The live window (SDL2): a window or fullscreen on a chosen display, vsync, SDL's KMS/DRM
// video driver when there is no X or Wayland (a kiosk needs no desktop). Each frame is
// uploaded to a streaming texture and drawn scaled with its aspect kept (nearest neighbour);
// the HUD's text comes from a glyph atlas (drivers/glyph_atlas_sdl.h). Mouse and touch become
// stroke samples (pressure where the device reports it); keys become live-loop commands:
//   Esc/Q quit   Space pause   R reset   Right/N/PgDn next preset   Left/P/PgUp previous
//   M next painting mode   1-5 mode (deposit orient push obstacle erase)   S/F12 screenshot
//   V start/stop recording   H/F1 HUD   F/F11 fullscreen
#include <array>
#include <memory>
#include <string>

#include "host/live/live_loop.h"

struct SDL_Window;
struct SDL_Renderer;
struct SDL_Texture;

namespace ardcell {

class SdlGlyphAtlas;

struct DisplayOptions {
  int display = 0;  // --display N
  bool fullscreen = false;
  bool vsync = true;
  int scale = 0;  // window pixels per cell; 0: the largest that fits ~80% of the screen
  std::string title = "ardcell";
};

class SdlDisplay final : public LiveDisplay {
 public:
  // nullptr with `error` set (one line: the driver, the display, what was expected).
  static std::unique_ptr<SdlDisplay> open(const DisplayOptions& options, Int2 image_size,
                                          Status& error);
  ~SdlDisplay() override;

  void poll(StrokeRing& input, CommandQueue& commands) override;
  void present(const ImageRgb8& frame, const HudInfo* hud) override;
  // The window's pixels as last drawn (frame and HUD), read from the renderer.
  bool read_back(ImageRgb8& out) override;

  // The display's refresh rate in Hz (0 when unknown): the default --fps.
  double refresh_rate() const { return refresh_hz_; }
  std::string_view driver() const { return driver_; }
  Int2 window_size() const;
  // Empty, or the one line saying why the HUD shows no text (no font).
  const std::string& hud_notice() const { return hud_notice_; }

 private:
  SdlDisplay() = default;
  void draw(const HudInfo* hud);
  void draw_hud(const HudInfo& hud);
  void prepare_hud_font();
  void update_layout();
  bool to_canvas(float wx, float wy, float& x, float& y) const;
  void ensure_texture(int w, int h);

  SDL_Window* window_ = nullptr;
  SDL_Renderer* renderer_ = nullptr;
  SDL_Texture* texture_ = nullptr;
  int tex_w_ = 0, tex_h_ = 0;
  int dst_x_ = 0, dst_y_ = 0, dst_w_ = 0, dst_h_ = 0;
  double refresh_hz_ = 0;
  std::string driver_;
  bool fullscreen_ = false;
  bool mouse_down_ = false;
  bool erasing_ = false;
  bool hud_shown_ = false;
  HudInfo last_hud_{};
  std::unique_ptr<SdlGlyphAtlas> hud_font_;
  std::string hud_notice_;
};

}  // namespace ardcell
