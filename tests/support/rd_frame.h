#pragma once
// An RdStepper's frame outside an Engine, as the engine runs it: the stepper's stages in a frame
// plan of their own (host/engine/frame_plan.h), built once the state has its fields (A, B from
// init_state; u, v when the RD is to be advected), run on the serial device.
#include "host/engine/frame_plan.h"
#include "host/engine/rd_step.h"

namespace ardcell {

class RdFrame {
 public:
  RdFrame(RdStepper& rd, SimState& state) : plan_(FramePlanOptions{.grid = state.size}) {
    rd.append_stages(plan_, state);
  }
  void step() { plan_.run(CpuDevice::serial()); }

 private:
  FramePlan plan_;
};

}  // namespace ardcell
