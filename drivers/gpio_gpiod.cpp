#include "drivers/gpio_gpiod.h"

#include <gpiod.h>

#include <cerrno>
#include <cstring>

namespace ardcell {

namespace {

class GpiodSource final : public GpioEventSource {
 public:
  ~GpiodSource() override {
    if (chip_) gpiod_chip_close(chip_);  // releases the requested lines too
  }
  int wait(std::span<GpioEdge> out, int timeout_ms) override {
    timespec ts{timeout_ms / 1000, long(timeout_ms % 1000) * 1'000'000};
    gpiod_line_bulk ready;
    gpiod_line_bulk_init(&ready);
    const int r = gpiod_line_event_wait_bulk(&bulk_, &ts, &ready);
    if (r < 0) return -1;
    if (r == 0) return 0;
    int n = 0;
    for (unsigned i = 0; i < gpiod_line_bulk_num_lines(&ready) && size_t(n) < out.size(); ++i) {
      gpiod_line* line = gpiod_line_bulk_get_line(&ready, i);
      gpiod_line_event ev;
      if (gpiod_line_event_read(line, &ev) != 0) continue;
      out[size_t(n++)] = {gpiod_line_offset(line), ev.event_type == GPIOD_LINE_EVENT_RISING_EDGE,
                          int64_t(ev.ts.tv_sec) * 1'000'000'000 + ev.ts.tv_nsec};
    }
    return n;
  }
  std::string describe() const override { return "GPIO " + name_; }

  gpiod_chip* chip_ = nullptr;
  gpiod_line_bulk bulk_;
  std::string name_;
};

}  // namespace

std::unique_ptr<GpioEventSource> open_gpiod_source(const GpioConfig& config, Status& error) {
  auto src = std::make_unique<GpiodSource>();
  src->name_ = config.chip;
  src->chip_ = gpiod_chip_open_lookup(config.chip.c_str());
  if (!src->chip_) {
    error = Status::error("gpio: " + config.chip + ": no such GPIO chip (" + std::strerror(errno) +
                          "); expected a chip from gpiodetect; buttons are off");
    return nullptr;
  }
  gpiod_line_bulk_init(&src->bulk_);
  for (const GpioButton& b : config.buttons) {
    gpiod_line* line = gpiod_chip_get_line(src->chip_, b.line);
    const int flags = b.active_low ? GPIOD_LINE_REQUEST_FLAG_BIAS_PULL_UP : 0;
    if (!line || gpiod_line_request_both_edges_events_flags(line, "ardcell", flags) != 0) {
      error = Status::error("gpio: " + config.chip + " line " + std::to_string(b.line) +
                            ": cannot request edge events (" + std::strerror(errno) +
                            "); expected a free input line; buttons are off");
      return nullptr;
    }
    gpiod_line_bulk_add(&src->bulk_, line);
  }
  error = Status::ok();
  return src;
}

}  // namespace ardcell
