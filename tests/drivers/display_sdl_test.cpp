#include "drivers/display_sdl.h"

#include <SDL.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <vector>

#include "drivers/glyph_atlas_sdl.h"
#include "host/engine/engine.h"
#include "host/live/live_engine.h"

// Sanitizer builds: SDL keeps D-Bus/X11 helper allocations for the life of the process.
extern "C" const char* __lsan_default_options() {
  return "suppressions=" ARDCELL_SOURCE_DIR "/scripts/lsan.supp";
}

namespace ardcell {
namespace {

// The test runner runs ctest under xvfb-run; without any display there is nothing to test.
bool have_display() { return std::getenv("DISPLAY") || std::getenv("WAYLAND_DISPLAY"); }

std::string small_preset() {
  const auto path = std::filesystem::temp_directory_path() /
                    ("ardcell_display_test_" + std::to_string(::getpid()) + ".toml");
  std::ofstream(path) << "name = \"small cavity\"\n[grid]\nsize = [48, 32]\ndt = 0.01\n"
                         "[fluid]\nscene = \"cavity\"\nviscosity = 0.01\n[quality]\n"
                         "adaptive = false\n";
  return path.string();
}

TEST(SdlDisplay, WindowShowsExactlyTheHeadlessRender) {
  if (!have_display()) GTEST_SKIP() << "no X or Wayland display";
  const std::string preset_path = small_preset();
  Status error = Status::ok();
  auto display = SdlDisplay::open({.vsync = false, .scale = 1}, {48, 32}, error);
  ASSERT_NE(display, nullptr) << error.message();
  LiveOptions o;
  o.fps = 0;
  o.max_frames = 12;
  o.log = nullptr;
  LiveLoop loop(o, make_engine_simulation, *display);
  ASSERT_TRUE(loop.start(preset_path).is_ok());
  ASSERT_TRUE(loop.run().is_ok());
  ImageRgb8 window;
  ASSERT_TRUE(display->read_back(window));
  ASSERT_EQ(window.width, 48);
  ASSERT_EQ(window.height, 32);

  // The same frames without a window.
  Preset p;
  ASSERT_TRUE(load_preset(preset_path, p).is_ok());
  Engine engine(p.scene);
  for (int i = 0; i < 12; ++i) engine.step();
  ImageRgb8 headless;
  headless.resize(48, 32);
  render_state(engine.state(), p.scene.output, headless);
  EXPECT_EQ(window.rgb, headless.rgb);
  EXPECT_EQ(window.rgb, loop.image().rgb);
  std::filesystem::remove(preset_path);
}

TEST(SdlDisplay, HudDrawsTextOverTheFrame) {
  if (!have_display()) GTEST_SKIP() << "no X or Wayland display";
  Status error = Status::ok();
  auto display = SdlDisplay::open({.vsync = false, .scale = 4}, {64, 48}, error);
  ASSERT_NE(display, nullptr) << error.message();
  ImageRgb8 frame;
  frame.resize(64, 48);  // black
  HudInfo hud;
  hud.fps = 60;
  std::snprintf(hud.preset.data(), hud.preset.size(), "cavity");
  display->present(frame, nullptr);
  ImageRgb8 plain, with_hud;
  ASSERT_TRUE(display->read_back(plain));
  display->present(frame, &hud);
  ASSERT_TRUE(display->read_back(with_hud));
  // White (anti-aliased) text on the HUD's dark box, in the window's top-left corner only.
  int white = 0, below = 0;
  for (int y = 0; y < with_hud.height; ++y)
    for (int x = 0; x < with_hud.width; ++x) {
      const uint8_t* p = with_hud.row(y) + 3 * x;
      if (p[0] >= 200 && p[1] >= 200 && p[2] >= 200) (y < with_hud.height / 2 ? white : below)++;
    }
  EXPECT_GT(white, 100);
  EXPECT_EQ(below, 0);
  EXPECT_EQ(display->hud_notice(), "");
  for (uint8_t v : plain.rgb) ASSERT_EQ(v, 0);
}

TEST(SdlDisplay, MouseAndKeysBecomeStrokesAndCommands) {
  if (!have_display()) GTEST_SKIP() << "no X or Wayland display";
  Status error = Status::ok();
  auto display = SdlDisplay::open({.vsync = false, .scale = 2}, {50, 40}, error);
  ASSERT_NE(display, nullptr) << error.message();
  StrokeRing ring(64);
  CommandQueue commands;
  display->poll(ring, commands);  // drain window-manager events
  StrokeSample drop;
  while (ring.pop(drop)) {
  }
  LiveCommand c;
  while (commands.pop(c)) {
  }
  SDL_Event e{};
  e.type = SDL_MOUSEBUTTONDOWN;
  e.button.button = SDL_BUTTON_LEFT;
  e.button.x = 25;
  e.button.y = 60;
  SDL_PushEvent(&e);
  SDL_Event k{};
  k.type = SDL_KEYDOWN;
  k.key.keysym.sym = SDLK_SPACE;
  SDL_PushEvent(&k);
  display->poll(ring, commands);
  StrokeSample s;
  ASSERT_TRUE(ring.pop(s));
  EXPECT_TRUE(s.touching());
  EXPECT_FLOAT_EQ(s.x, 0.25f);  // 25 px of a 100 px wide canvas
  EXPECT_FLOAT_EQ(s.y, 0.75f);
  ASSERT_TRUE(commands.pop(c));
  EXPECT_EQ(c.kind, LiveCommandKind::kTogglePause);
}

TEST(SdlGlyphAtlas, TextIsTheFontsGlyphsAtItsAdvance) {
  if (!have_display()) GTEST_SKIP() << "no X or Wayland display";
  ASSERT_FALSE(hud_font_path().empty()) << "built without a HUD font";
  ASSERT_EQ(SDL_InitSubSystem(SDL_INIT_VIDEO), 0) << SDL_GetError();
  std::unique_ptr<SDL_Window, void (*)(SDL_Window*)> window(
      SDL_CreateWindow("atlas", 0, 0, 200, 60, SDL_WINDOW_HIDDEN), SDL_DestroyWindow);
  ASSERT_NE(window, nullptr) << SDL_GetError();
  std::unique_ptr<SDL_Renderer, void (*)(SDL_Renderer*)> owned(
      SDL_CreateRenderer(window.get(), -1, SDL_RENDERER_SOFTWARE), SDL_DestroyRenderer);
  ASSERT_NE(owned, nullptr) << SDL_GetError();
  SDL_Renderer* renderer = owned.get();
  SdlGlyphAtlas atlas;
  std::string why;
  ASSERT_TRUE(atlas.prepare(renderer, 16, why)) << why;
  EXPECT_GE(atlas.line_height(), 16);
  EXPECT_LE(atlas.line_height(), 24);
  // A monospace font: every glyph advances alike; outside ASCII draws as '?'.
  const int one = atlas.width("M");
  EXPECT_GT(one, 4);
  EXPECT_EQ(atlas.width("iiii"), 4 * one);
  EXPECT_EQ(atlas.width("\xc3\xa9"), atlas.width("??"));
  // Drawn: lit pixels only inside the text's box, and more of them for "MMMM" than for "....".
  auto lit_in = [&](const char* text, int& outside) {
    SDL_SetRenderDrawColor(renderer, 0, 0, 0, 255);
    SDL_RenderClear(renderer);
    const int w = atlas.draw(renderer, text, 10, 5, {255, 255, 255, 255});
    EXPECT_EQ(w, atlas.width(text));
    int ww = 0, wh = 0;
    SDL_GetRendererOutputSize(renderer, &ww, &wh);
    std::vector<uint8_t> px(size_t(ww) * size_t(wh) * 3);
    EXPECT_EQ(SDL_RenderReadPixels(renderer, nullptr, SDL_PIXELFORMAT_RGB24, px.data(), ww * 3), 0);
    int lit = 0;
    outside = 0;
    for (int y = 0; y < wh; ++y)
      for (int x = 0; x < ww; ++x)
        if (px[(size_t(y) * size_t(ww) + size_t(x)) * 3] > 128) {
          const bool in = x >= 10 && x < 10 + w && y >= 5 && y < 5 + atlas.line_height();
          (in ? lit : outside) += 1;
        }
    return lit;
  };
  int outside = 0;
  const int heavy = lit_in("MMMM", outside);
  EXPECT_EQ(outside, 0);
  const int light = lit_in("....", outside);
  EXPECT_EQ(outside, 0);
  EXPECT_GT(light, 0);
  EXPECT_GT(heavy, 3 * light);
}

}  // namespace
}  // namespace ardcell
