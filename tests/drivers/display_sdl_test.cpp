#include "drivers/display_sdl.h"

#include <SDL.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "drivers/bitmap_font.h"
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
  int white = 0;
  for (size_t i = 0; i + 2 < with_hud.rgb.size(); i += 3)
    white += with_hud.rgb[i] == 255 && with_hud.rgb[i + 1] == 255 && with_hud.rgb[i + 2] == 255;
  EXPECT_GT(white, 100);
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

TEST(BitmapFont, GlyphsAreTheDotMatrixShapes) {
  // 'L': a left column and a bottom row.
  const auto l = glyph_rows('l');
  for (int r = 0; r < 6; ++r) EXPECT_EQ(l[size_t(r)], 0x10);
  EXPECT_EQ(l[6], 0x1F);
  EXPECT_EQ(glyph_rows('~'), glyph_rows('?'));
  int lit = 0, max_x = 0;
  const int w = draw_text("I", 10, 0, 2, [&](int x, int) {
    ++lit;
    max_x = std::max(max_x, x);
  });
  EXPECT_EQ(lit, 3 + 5 + 3);  // top bar, stem, bottom bar
  EXPECT_EQ(w, kGlyphAdvance * 2);
  EXPECT_EQ(max_x, 10 + 3 * 2);
}

}  // namespace
}  // namespace ardcell
