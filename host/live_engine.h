#pragma once
// The Engine (host/engine.h) as a LiveSimulation: what `ardcell live` runs. Live parameter
// changes reach the engine through Engine::update_parameters(const SceneConfig&); stroke samples
// are painted with a simple brush per painting mode.
#include <memory>

#include "host/live_loop.h"

namespace ardcell {

std::unique_ptr<LiveSimulation> make_engine_simulation(const Preset& preset);

// The brush used for live input: paints `samples` into `state` (deposit, orient, push, erase;
// obstacle marks solid cells where the state has an obstacle mask). Allocates nothing.
void paint_brush(SimState& state, std::span<const StrokeSample> samples, const InputMapping& input,
                 StrokeSample& previous);

}  // namespace ardcell
