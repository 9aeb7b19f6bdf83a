#pragma once
// Parameters of the reaction-diffusion half of a scene (Kim & Lin). Plain data, like
// FluidConfig. Owned by the RD solver (host/rd_step.h).
#include <cstdint>

namespace ardcell {

struct RdConfig {
  bool enabled = false;
};

}  // namespace ardcell
