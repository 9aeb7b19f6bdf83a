#include "drivers/cli_ranks.h"

#include <cstdio>
#include <stdexcept>

namespace ardcell {

#if defined(ARDCELL_WITH_MPI)
std::string start_rank_job(const std::string& flag, const std::string& text, CliContext& ctx,
                           RankJob& job) {
  if (!parse_block_parts(text, job.parts))
    return flag + " '" + text + "': expected WxH, the ranks along x by along y (e.g. 2x1)";
  job.world = std::make_unique<MpiWorld>();
  if (job.world->rank() != 0) {
    static std::FILE* const quiet = std::fopen("/dev/null", "w");
    if (quiet) ctx.out = ctx.err = quiet;
  }
  const int n = job.parts.x * job.parts.y;
  if (job.world->size() != n)
    return flag + " " + text + " needs " + std::to_string(n) + " processes (mpirun -np " +
           std::to_string(n) + "); this run has " + std::to_string(job.world->size());
  return "";
}

std::string split_rank_job(const std::string& flag, const std::string& text,
                           const SceneConfig& scene, RankJob& job, EngineOptions& options) {
  const BlockSupport support = block_support(scene);
  if (!support.problem.empty())
    return flag + ": scene '" + scene.name +
           "' runs on one process's whole grid: " + support.problem + " (expected no " + flag + ")";
  try {
    job.layout = BlockLayout::split(scene.size, job.parts, support.periodic_x, support.periodic_y);
  } catch (const std::invalid_argument& e) {
    return flag + " " + text + ": " + e.what();
  }
  const int width = support.halo;
  for (int b = 0; b < job.layout->count(); ++b)
    if (job.layout->block(b).width() < width || job.layout->block(b).height() < width)
      return flag + " " + text + ": a block of " + std::to_string(job.layout->block(b).width()) +
             "x" + std::to_string(job.layout->block(b).height()) +
             " cells is narrower than its halo of " + std::to_string(width) +
             " (expected fewer ranks or a larger --size)";
  job.channel = std::make_unique<MpiHaloChannel>(*job.layout, width, *job.world);
  options.plan.block = job.layout->block(job.world->rank());
  options.plan.halo = job.channel.get();
  return "";
}
#endif

}  // namespace ardcell
