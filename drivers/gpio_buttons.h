#pragma once
// Kiosk buttons: a GPIO configuration (chip, line offsets, actions), the debounce that turns
// raw edges into presses, and the thread that feeds presses to the live loop as commands. The
// edges come from an event source: libgpiod (drivers/gpio_gpiod.h) on a real board, a
// simulated source in tests; both drive the same ButtonHandler.
//
//   chip = "gpiochip0"     # name, path or number as gpiodetect shows it
//   debounce_ms = 30
//   [[button]]
//   line = 17              # line offset on the chip
//   action = "next"        # next | previous | reset | pause
//   active_low = true      # pressed = low (button to ground, pull-up on)
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "host/config/status.h"
#include "host/live/live_loop.h"

namespace ardcell {

enum class ButtonAction : uint8_t { kNextPreset, kPrevPreset, kReset, kPause };

struct GpioButton {
  unsigned line = 0;
  ButtonAction action = ButtonAction::kNextPreset;
  bool active_low = true;
};

struct GpioConfig {
  std::string chip = "gpiochip0";
  int debounce_ms = 30;
  std::vector<GpioButton> buttons;
};

// Parses the TOML above; errors name the file, line and key, like presets.
Status parse_gpio_config(std::string_view text, std::string_view source, GpioConfig& out);
Status load_gpio_config(const std::string& path, GpioConfig& out);

struct GpioEdge {
  unsigned line = 0;
  bool rising = false;
  int64_t time_ns = 0;  // kernel timestamp of the edge
};

// Where edges come from. wait() blocks up to timeout_ms; returns the number of edges written,
// 0 on timeout, -1 when the source is closed or failed for good.
class GpioEventSource {
 public:
  virtual ~GpioEventSource() = default;
  virtual int wait(std::span<GpioEdge> out, int timeout_ms) = 0;
  virtual std::string describe() const = 0;
};

// Edges pushed by a test (or any other program part) instead of a chip.
class SimulatedGpioSource final : public GpioEventSource {
 public:
  void push(const GpioEdge& e);
  void close();
  int wait(std::span<GpioEdge> out, int timeout_ms) override;
  std::string describe() const override { return "simulated GPIO"; }

 private:
  std::mutex mutex_;
  std::condition_variable cv_;
  std::deque<GpioEdge> edges_;
  bool closed_ = false;
};

// Debounce: an edge counts only when the line has been quiet for debounce_ms since the last
// edge that counted; a press is the edge into the active level from released. Each press
// becomes one command.
class ButtonHandler {
 public:
  ButtonHandler(const GpioConfig& config, CommandQueue& commands);
  // Returns true when the edge produced a command.
  bool on_edge(const GpioEdge& edge);
  int64_t presses() const { return presses_; }
  int64_t bounces() const { return bounces_; }

 private:
  struct LineState {
    unsigned line;
    ButtonAction action;
    bool active_low;
    bool pressed = false;
    int64_t last_ns = INT64_MIN / 2;
  };
  std::vector<LineState> lines_;
  int64_t debounce_ns_;
  CommandQueue& commands_;
  int64_t presses_ = 0, bounces_ = 0;
};

LiveCommand command_for(ButtonAction action);

// Reads a source on its own thread and hands edges to a ButtonHandler.
class GpioButtons {
 public:
  GpioButtons(std::unique_ptr<GpioEventSource> source, const GpioConfig& config,
              CommandQueue& commands);
  ~GpioButtons();  // stops the thread
  const ButtonHandler& handler() const { return handler_; }

 private:
  std::unique_ptr<GpioEventSource> source_;
  ButtonHandler handler_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace ardcell
