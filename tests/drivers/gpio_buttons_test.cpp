#include "drivers/gpio_buttons.h"

#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#ifdef ARDCELL_WITH_GPIOD
#include "drivers/gpio_gpiod.h"
#endif

namespace ardcell {
namespace {

constexpr int64_t kMs = 1'000'000;

GpioConfig two_buttons() {
  GpioConfig c;
  c.debounce_ms = 30;
  c.buttons = {{17, ButtonAction::kNextPreset, true}, {27, ButtonAction::kPause, false}};
  return c;
}

std::vector<LiveCommandKind> drain(CommandQueue& q) {
  std::vector<LiveCommandKind> kinds;
  LiveCommand c;
  while (q.pop(c))
    if (c.kind != LiveCommandKind::kInputActivity) kinds.push_back(c.kind);
  return kinds;
}

TEST(GpioButtons, DebouncedPressesBecomeCommands) {
  CommandQueue q;
  ButtonHandler h(two_buttons(), q);
  // Active-low button on 17: a falling edge presses; bounces within 30 ms are ignored.
  EXPECT_TRUE(h.on_edge({17, false, 1000 * kMs}));
  EXPECT_FALSE(h.on_edge({17, true, 1002 * kMs}));   // bounce
  EXPECT_FALSE(h.on_edge({17, false, 1004 * kMs}));  // bounce
  EXPECT_FALSE(h.on_edge({17, true, 1100 * kMs}));   // release
  EXPECT_TRUE(h.on_edge({17, false, 1200 * kMs}));   // second press
  // Active-high button on 27: rising presses.
  EXPECT_FALSE(h.on_edge({27, false, 1300 * kMs}));  // already released: no change
  EXPECT_TRUE(h.on_edge({27, true, 1400 * kMs}));
  EXPECT_FALSE(h.on_edge({5, false, 1500 * kMs}));  // a line no button uses
  EXPECT_EQ(h.presses(), 3);
  EXPECT_EQ(h.bounces(), 2);
  EXPECT_EQ(drain(q), (std::vector<LiveCommandKind>{LiveCommandKind::kNextPreset,
                                                    LiveCommandKind::kNextPreset,
                                                    LiveCommandKind::kTogglePause}));
}

TEST(GpioButtons, SimulatedSourceDrivesTheSameHandlerOnItsThread) {
  CommandQueue q;
  auto source = std::make_unique<SimulatedGpioSource>();
  SimulatedGpioSource* sim = source.get();
  GpioConfig cfg = two_buttons();
  cfg.buttons.push_back({22, ButtonAction::kReset, true});
  GpioButtons buttons(std::move(source), cfg, q);
  sim->push({22, false, 10 * kMs});
  sim->push({22, true, 11 * kMs});  // bounce
  sim->push({22, true, 100 * kMs});
  sim->push({17, false, 200 * kMs});
  for (int i = 0; i < 500 && buttons.handler().presses() < 2; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  sim->close();
  EXPECT_EQ(drain(q),
            (std::vector<LiveCommandKind>{LiveCommandKind::kReset, LiveCommandKind::kNextPreset}));
}

TEST(GpioButtons, ConfigParsesAndBadConfigsSayWhy) {
  GpioConfig c;
  const Status ok = parse_gpio_config(
      "chip = \"gpiochip1\"\ndebounce_ms = 20\n[[button]]\nline = 4\naction = \"previous\"\n"
      "[[button]]\nline = 5\naction = \"reset\"\nactive_low = false\n",
      "kiosk.toml", c);
  ASSERT_TRUE(ok.is_ok()) << ok.message();
  EXPECT_EQ(c.chip, "gpiochip1");
  EXPECT_EQ(c.debounce_ms, 20);
  ASSERT_EQ(c.buttons.size(), 2u);
  EXPECT_EQ(c.buttons[0].action, ButtonAction::kPrevPreset);
  EXPECT_FALSE(c.buttons[1].active_low);
  const std::pair<const char*, const char*> bad[] = {
      {"[[button]]\nline = 4\naction = \"jump\"\n",
       "g.toml:3: button.action: expected one of next | previous | reset | pause"},
      {"[[button]]\nline = -1\naction = \"next\"\n",
       "g.toml:2: button.line: expected a line offset in [0, 1023]"},
      {"chips = \"x\"\n",
       "g.toml:1: chips: unknown key; expected one of: chip, debounce_ms, button"},
      {"chip = \"x\"\n", "g.toml: no [[button]] tables (expected at least one)"},
  };
  for (const auto& [text, message] : bad) {
    const Status s = parse_gpio_config(text, "g.toml", c);
    EXPECT_EQ(s.message(), message) << text;
  }
}

TEST(GpioButtons, ExampleKioskConfigLoads) {
  GpioConfig c;
  const Status s = load_gpio_config(ARDCELL_SOURCE_DIR "/scripts/kiosk.example.toml", c);
  ASSERT_TRUE(s.is_ok()) << s.message();
  EXPECT_EQ(c.buttons.size(), 4u);
}

#ifdef ARDCELL_WITH_GPIOD
TEST(GpioButtons, MissingChipGivesOneClearLine) {
  GpioConfig cfg = two_buttons();
  cfg.chip = "gpiochip-ardcell-missing";
  Status error = Status::ok();
  auto src = open_gpiod_source(cfg, error);
  EXPECT_EQ(src, nullptr);
  EXPECT_EQ(error.message().rfind("gpio: gpiochip-ardcell-missing: no such GPIO chip", 0), 0u)
      << error.message();
  EXPECT_EQ(error.message().find('\n'), std::string::npos);
}
#endif

}  // namespace
}  // namespace ardcell
