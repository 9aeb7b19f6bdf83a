#pragma once
// `ardcell run --ranks WxH` under mpirun: each rank steps the Engine of its block of the grid
// (PlanOptions::block, the plan's halo exchange through MpiHaloChannel), and rank 0 holds the
// whole state, gathered from the blocks, for the frames, videos and saved states it writes. The
// ranks agree on stopping (a signal reaches them at different frames) after every frame, so
// that every rank runs the same number of frames.
#include <atomic>
#include <cstdint>
#include <filesystem>

#include "host/config/sim_state.h"
#include "host/engine/engine.h"
#include "host/io/state_io.h"
#include "host/run/offline_run.h"
#include "runtime/block_layout.h"
#include "runtime/mpi/mpi_world.h"

namespace ardcell {

class RankStepper final : public OfflineStepper {
 public:
  // `every`: the run loop writes a frame after every `every` steps (0: none); `signal`: set
  // asynchronously on this rank (Ctrl-C); `playback`: strokes every rank reads alike, painted
  // into this rank's block before each step (host/paint/paint.h).
  RankStepper(Engine& engine, const BlockLayout& layout, MpiWorld& world, int64_t every,
              const std::atomic<bool>* signal, StrokePlayback* playback = nullptr);
  // The strokes due, one frame; then whether any rank was asked to stop; then, when a frame is
  // due, the gather.
  void step() override;
  // Rank 0: the whole state as of the last gather (other ranks: its size only).
  const SimState& frame_state() override { return whole_; }
  // Gathers the whole state on rank 0 now (every rank calls it).
  void gather();
  // Set on every rank once any rank's signal was seen: the run loop's stop flag.
  const std::atomic<bool>* stop() const { return &stop_; }

 private:
  Engine& engine_;
  MpiWorld& world_;
  BlockGather gather_;
  int64_t every_ = 0, steps_ = 0;
  const std::atomic<bool>* signal_;
  StrokePlayback* playback_;
  std::atomic<bool> stop_{false};
  SimState whole_;
};

// Loads a saved state of the whole grid into the block of each rank's engine (every rank reads
// the files): the cells of its block, the time and the step.
Status load_state_into_block(const std::filesystem::path& dir, const SavedStateMeta& meta,
                             Engine& engine);

}  // namespace ardcell
