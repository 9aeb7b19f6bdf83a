#pragma once
// GPIO buttons through libgpiod 1.6: the chip and lines of a GpioConfig requested for both
// edges (pull-up on active-low lines), read as GpioEdges with the kernel's timestamps.
#include <memory>

#include "drivers/gpio_buttons.h"

namespace ardcell {

// Opens the chip and requests every button line. nullptr with `error` set (one line naming the
// chip or line and what was expected) when there is no such chip or a line is busy.
std::unique_ptr<GpioEventSource> open_gpiod_source(const GpioConfig& config, Status& error);

}  // namespace ardcell
