#include "drivers/display_sdl.h"

#include <SDL.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>

#include "drivers/glyph_atlas_sdl.h"

namespace ardcell {

static_assert(sizeof(SDL_Rect) == 4 * sizeof(int));

std::unique_ptr<SdlDisplay> SdlDisplay::open(const DisplayOptions& options, Int2 image_size,
                                             Status& error) {
  // No X and no Wayland: a bare console, so draw straight to the screen through KMS/DRM.
  if (!std::getenv("DISPLAY") && !std::getenv("WAYLAND_DISPLAY") && !std::getenv("SDL_VIDEODRIVER"))
    SDL_SetHint(SDL_HINT_VIDEODRIVER, "kmsdrm");
  SDL_SetHint(SDL_HINT_RENDER_SCALE_QUALITY, "0");
  SDL_SetHint(SDL_HINT_NO_SIGNAL_HANDLERS, "1");
  SDL_SetHint(SDL_HINT_VIDEO_X11_NET_WM_BYPASS_COMPOSITOR, "0");
  if (SDL_InitSubSystem(SDL_INIT_VIDEO) != 0) {
    error = Status::error(std::string("display: cannot start SDL video (") + SDL_GetError() +
                          "); expected X11, Wayland or a KMS/DRM console");
    return nullptr;
  }
  std::unique_ptr<SdlDisplay> d(new SdlDisplay());
  d->driver_ = SDL_GetCurrentVideoDriver() ? SDL_GetCurrentVideoDriver() : "?";
  const int displays = SDL_GetNumVideoDisplays();
  if (options.display < 0 || options.display >= displays) {
    error = Status::error("display: --display " + std::to_string(options.display) +
                          ": no such display; expected 0.." + std::to_string(displays - 1));
    SDL_QuitSubSystem(SDL_INIT_VIDEO);
    return nullptr;
  }
  SDL_DisplayMode mode{};
  if (SDL_GetDesktopDisplayMode(options.display, &mode) == 0) d->refresh_hz_ = mode.refresh_rate;
  int scale = options.scale;
  if (scale <= 0) {
    const int sw = mode.w > 0 ? mode.w : 1024, sh = mode.h > 0 ? mode.h : 768;
    scale = std::max(1, std::min(sw * 8 / 10 / std::max(1, image_size.x),
                                 sh * 8 / 10 / std::max(1, image_size.y)));
  }
  Uint32 flags = SDL_WINDOW_RESIZABLE | SDL_WINDOW_ALLOW_HIGHDPI;
  if (options.fullscreen) flags |= SDL_WINDOW_FULLSCREEN_DESKTOP;
  d->fullscreen_ = options.fullscreen;
  d->window_ =
      SDL_CreateWindow(options.title.c_str(), int(SDL_WINDOWPOS_CENTERED_DISPLAY(options.display)),
                       int(SDL_WINDOWPOS_CENTERED_DISPLAY(options.display)), image_size.x * scale,
                       image_size.y * scale, flags);
  if (!d->window_) {
    error = Status::error(std::string("display: cannot open a window (") + SDL_GetError() + ")");
    return nullptr;
  }
  const Uint32 vsync = options.vsync ? SDL_RENDERER_PRESENTVSYNC : 0;
  d->renderer_ = SDL_CreateRenderer(d->window_, -1, SDL_RENDERER_ACCELERATED | vsync);
  if (!d->renderer_) d->renderer_ = SDL_CreateRenderer(d->window_, -1, SDL_RENDERER_SOFTWARE);
  if (!d->renderer_) {
    error = Status::error(std::string("display: no renderer (") + SDL_GetError() + ")");
    return nullptr;
  }
  SDL_SetRenderDrawBlendMode(d->renderer_, SDL_BLENDMODE_BLEND);
  d->hud_font_ = std::make_unique<SdlGlyphAtlas>();
  d->ensure_texture(image_size.x, image_size.y);
  if (!d->texture_) {
    error = Status::error(std::string("display: cannot create a texture (") + SDL_GetError() + ")");
    return nullptr;
  }
  SDL_ShowCursor(options.fullscreen ? SDL_DISABLE : SDL_ENABLE);
  d->prepare_hud_font();
  error = Status::ok();
  return d;
}

SdlDisplay::~SdlDisplay() {
  hud_font_.reset();
  if (texture_) SDL_DestroyTexture(texture_);
  if (renderer_) SDL_DestroyRenderer(renderer_);
  if (window_) SDL_DestroyWindow(window_);
  // The video subsystem stays up: shutting it down unloads X11/D-Bus helper modules whose
  // small per-process allocations then show up as leaks with no symbol to suppress.
}

Int2 SdlDisplay::window_size() const {
  int w = 0, h = 0;
  SDL_GetRendererOutputSize(renderer_, &w, &h);
  return {w, h};
}

void SdlDisplay::ensure_texture(int w, int h) {
  if (texture_ && w == tex_w_ && h == tex_h_) return;
  if (texture_) SDL_DestroyTexture(texture_);
  texture_ = SDL_CreateTexture(renderer_, SDL_PIXELFORMAT_RGB24, SDL_TEXTUREACCESS_STREAMING, w, h);
  tex_w_ = w;
  tex_h_ = h;
  update_layout();
}

void SdlDisplay::update_layout() {
  const Int2 win = window_size();
  if (tex_w_ <= 0 || tex_h_ <= 0 || win.x <= 0 || win.y <= 0) return;
  // Largest integer scale that fits; a fractional one when the window is smaller than the grid.
  const int s = std::min(win.x / tex_w_, win.y / tex_h_);
  if (s >= 1) {
    dst_w_ = tex_w_ * s;
    dst_h_ = tex_h_ * s;
  } else {
    const double f = std::min(double(win.x) / tex_w_, double(win.y) / tex_h_);
    dst_w_ = std::max(1, int(tex_w_ * f));
    dst_h_ = std::max(1, int(tex_h_ * f));
  }
  dst_x_ = (win.x - dst_w_) / 2;
  dst_y_ = (win.y - dst_h_) / 2;
}

bool SdlDisplay::to_canvas(float wx, float wy, float& x, float& y) const {
  if (dst_w_ <= 0 || dst_h_ <= 0) return false;
  // Window coordinates may be in points while the renderer works in pixels (HiDPI).
  int ww = 0, wh = 0;
  SDL_GetWindowSize(window_, &ww, &wh);
  const Int2 out = window_size();
  const float sx = ww > 0 ? float(out.x) / float(ww) : 1.0f;
  const float sy = wh > 0 ? float(out.y) / float(wh) : 1.0f;
  x = (wx * sx - float(dst_x_)) / float(dst_w_);
  y = (wy * sy - float(dst_y_)) / float(dst_h_);
  return true;
}

void SdlDisplay::poll(StrokeRing& input, CommandQueue& commands) {
  SDL_Event e;
  auto command = [&](LiveCommandKind k, double v = 0) { commands.push(LiveCommand::make(k, v)); };
  while (SDL_PollEvent(&e)) {
    switch (e.type) {
      case SDL_QUIT:
        command(LiveCommandKind::kQuit);
        break;
      case SDL_WINDOWEVENT:
        if (e.window.event == SDL_WINDOWEVENT_SIZE_CHANGED) update_layout();
        break;
      case SDL_KEYDOWN: {
        if (e.key.repeat) break;
        const SDL_Keycode k = e.key.keysym.sym;
        if (k == SDLK_ESCAPE || k == SDLK_q)
          command(LiveCommandKind::kQuit);
        else if (k == SDLK_SPACE)
          command(LiveCommandKind::kTogglePause);
        else if (k == SDLK_r)
          command(LiveCommandKind::kReset);
        else if (k == SDLK_RIGHT || k == SDLK_n || k == SDLK_PAGEDOWN)
          command(LiveCommandKind::kNextPreset);
        else if (k == SDLK_LEFT || k == SDLK_p || k == SDLK_PAGEUP)
          command(LiveCommandKind::kPrevPreset);
        else if (k == SDLK_m)
          command(LiveCommandKind::kNextMode);
        else if (k >= SDLK_1 && k <= SDLK_5)
          command(LiveCommandKind::kSetMode, double(k - SDLK_1));
        else if (k == SDLK_s || k == SDLK_F12)
          command(LiveCommandKind::kScreenshot);
        else if (k == SDLK_v)
          command(LiveCommandKind::kToggleRecord);
        else if (k == SDLK_h || k == SDLK_F1)
          command(LiveCommandKind::kToggleHud);
        else if (k == SDLK_f || k == SDLK_F11) {
          fullscreen_ = !fullscreen_;
          SDL_SetWindowFullscreen(window_, fullscreen_ ? SDL_WINDOW_FULLSCREEN_DESKTOP : 0);
          update_layout();
        }
        command(LiveCommandKind::kInputActivity);
        break;
      }
      case SDL_MOUSEBUTTONDOWN:
      case SDL_MOUSEBUTTONUP:
      case SDL_MOUSEMOTION: {
        // Touch also arrives as synthetic mouse events; the finger events below handle it.
        const Uint32 which = e.type == SDL_MOUSEMOTION ? e.motion.which : e.button.which;
        if (which == SDL_TOUCH_MOUSEID) break;
        if (e.type == SDL_MOUSEBUTTONDOWN) {
          mouse_down_ = true;
          erasing_ = e.button.button == SDL_BUTTON_RIGHT;
        } else if (e.type == SDL_MOUSEBUTTONUP) {
          mouse_down_ = false;
        }
        const int mx = e.type == SDL_MOUSEMOTION ? e.motion.x : e.button.x;
        const int my = e.type == SDL_MOUSEMOTION ? e.motion.y : e.button.y;
        StrokeSample s;
        if (!to_canvas(float(mx), float(my), s.x, s.y)) break;
        s.time = double(e.common.timestamp) * 1e-3;
        s.pressure = mouse_down_ ? 1.0f : 0.0f;
        s.buttons = mouse_down_ ? uint32_t(kButtonTip) : 0u;
        s.in_range = true;
        s.eraser = mouse_down_ && erasing_;
        input.push(s);
        break;
      }
      case SDL_FINGERDOWN:
      case SDL_FINGERMOTION:
      case SDL_FINGERUP: {
        const Int2 out = window_size();
        int ww = 0, wh = 0;
        SDL_GetWindowSize(window_, &ww, &wh);
        StrokeSample s;
        if (!to_canvas(e.tfinger.x * float(ww), e.tfinger.y * float(wh), s.x, s.y)) break;
        (void)out;
        s.time = double(e.common.timestamp) * 1e-3;
        const bool down = e.type != SDL_FINGERUP;
        // Devices without pressure report 0 or 1; treat a touch as full pressure then.
        s.pressure = down ? (e.tfinger.pressure > 0 ? e.tfinger.pressure : 1.0f) : 0.0f;
        s.buttons = down ? uint32_t(kButtonTip) : 0u;
        s.in_range = down;
        input.push(s);
        break;
      }
      default:
        break;
    }
  }
}

void SdlDisplay::draw(const HudInfo* hud) {
  SDL_SetRenderDrawColor(renderer_, 0, 0, 0, 255);
  SDL_RenderClear(renderer_);
  const SDL_Rect dst{dst_x_, dst_y_, dst_w_, dst_h_};
  SDL_RenderCopy(renderer_, texture_, nullptr, &dst);
  if (hud) draw_hud(*hud);
}

void SdlDisplay::present(const ImageRgb8& frame, const HudInfo* hud) {
  if (frame.empty()) return;
  ensure_texture(frame.width, frame.height);
  SDL_UpdateTexture(texture_, nullptr, frame.rgb.data(), frame.width * 3);
  hud_shown_ = hud != nullptr;
  if (hud) last_hud_ = *hud;
  draw(hud);
  SDL_RenderPresent(renderer_);
}

bool SdlDisplay::read_back(ImageRgb8& out) {
  // The back buffer is undefined after a present: draw the last frame again, then read it.
  draw(hud_shown_ ? &last_hud_ : nullptr);
  const Int2 size = window_size();
  out.resize(size.x, size.y);
  return SDL_RenderReadPixels(renderer_, nullptr, SDL_PIXELFORMAT_RGB24, out.rgb.data(),
                              size.x * 3) == 0;
}

void SdlDisplay::prepare_hud_font() {
  if (!hud_notice_.empty()) return;  // no font: said once, not tried again every frame
  // Text about 1/30 of the window's height, narrow enough for ~48 characters a line (DejaVu
  // Sans Mono advances 0.6 of its size), 9 to 32 pixels; a new size only on a resize.
  const Int2 win = window_size();
  const int pixels = std::clamp(std::min(win.y / 30, (win.x - 16) / 29), 9, 32);
  std::string error;
  if (!hud_font_->prepare(renderer_, pixels, error))
    hud_notice_ = "HUD: " + error + "; the HUD shows no text";
}

void SdlDisplay::draw_hud(const HudInfo& hud) {
  char lines[4][192];  // room for a 63-character preset and back-end name on one line
  int n = 0;
  std::snprintf(lines[n++], sizeof lines[0], "%.1f fps  p50 %.2f ms  p99 %.2f ms  missed %lld",
                hud.fps, hud.p50_ms, hud.p99_ms, static_cast<long long>(hud.misses));
  std::snprintf(lines[n++], sizeof lines[0], "%s  [%s]  sweeps %d  RD %.0f%%", hud.preset.data(),
                hud.backend.data(), hud.sweeps, hud.rd_scale * 100);
  if (hud.paused || hud.recording || hud.attract)
    std::snprintf(lines[n++], sizeof lines[0], "%s%s%s", hud.paused ? "PAUSED  " : "",
                  hud.recording ? "REC  " : "", hud.attract ? "ATTRACT" : "");
  if (hud.message[0]) std::snprintf(lines[n++], sizeof lines[0], "%s", hud.message.data());
  prepare_hud_font();
  const int line_h = std::max(1, hud_font_->line_height());
  const int pad = std::max(4, line_h / 4);
  int width = 0;
  for (int i = 0; i < n; ++i) width = std::max(width, hud_font_->width(lines[i]));
  SDL_SetRenderDrawColor(renderer_, 0, 0, 0, 160);
  const SDL_Rect bg{4, 4, width + 2 * pad, n * line_h + 2 * pad};
  SDL_RenderFillRect(renderer_, &bg);
  for (int i = 0; i < n; ++i)
    hud_font_->draw(renderer_, lines[i], 4 + pad, 4 + pad + i * line_h, {255, 255, 255, 255});
}

}  // namespace ardcell
