#pragma once
// The processes of one mpirun that share a grid: `ardcell run --ranks WxH` and `ardcell live
// --wall WxH`. Each rank runs one block of the grid (runtime/block_layout.h) on an Engine whose
// frame plan exchanges halos with the other ranks (runtime/mpi/mpi_world.h). Every rank makes the
// same checks, so that bad input ends every rank alike; only rank 0 speaks.
#include <memory>
#include <optional>
#include <string>

#include "drivers/cli.h"
#include "host/config/scene_config.h"
#include "host/engine/engine.h"
#include "runtime/block_layout.h"
#if defined(ARDCELL_WITH_MPI)
#include "runtime/mpi/mpi_world.h"
#endif

namespace ardcell {

#if defined(ARDCELL_WITH_MPI)
struct RankJob {
  Int2 parts{};
  std::unique_ptr<MpiWorld> world;
  std::optional<BlockLayout> layout;
  std::unique_ptr<MpiHaloChannel> channel;
};

// Parses `text` (WxH) given to `flag`, starts MPI and checks that the job has W * H processes;
// ranks other than 0 then write nothing (ctx's out and err go to /dev/null). "" or the usage
// line.
std::string start_rank_job(const std::string& flag, const std::string& text, CliContext& ctx,
                           RankJob& job);
// Cuts the scene's grid into the job's blocks (the scenes block_support() accepts,
// host/engine/engine.h), checks that each block holds its halo, makes the halo channel and points
// options.plan at this rank's block. "" or the usage line.
std::string split_rank_job(const std::string& flag, const std::string& text,
                           const SceneConfig& scene, RankJob& job, EngineOptions& options);
#endif

}  // namespace ardcell
