#pragma once
// Coarse-to-fine texture synthesis (seed 003, Results: "3 grid discretizations (64, 128, 256),
// 20000 iterations at each level"): run a periodic reaction-diffusion scene at the first level's
// size, then at each next size start a fresh Engine of the same scene, replace its A and B by
// the previous level's, prolonged with periodic bilinear interpolation, and continue. Everything
// else (fluid, theta0, parameters) is the scene's at that size. The coarse levels lay the
// pattern out cheaply; the fine ones sharpen it. The scene must be periodic (rd.boundary), so
// that the prolongation wraps and the texture tiles.
#include <atomic>
#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

#include "host/config/scene_config.h"
#include "host/config/status.h"
#include "host/engine/engine.h"

namespace ardcell {

// The smallest level side: the 5x5 stencils and their halo 2 need room to wrap.
inline constexpr int kMinTextureSide = 8;

// "64,128,256": square sides, strictly increasing, each in [kMinTextureSide, kMaxGridSide].
// Errors name `flag` ("--levels 64,32: expected increasing sides, 32 follows 64").
Status parse_texture_levels(std::string_view text, std::vector<int>& out,
                            std::string_view flag = "--levels");
// start, 2 start, 4 start, ... while below final_side, then final_side (start >= final_side:
// the final side alone).
std::vector<int> doubling_levels(int start, int final_side);
// "64,128,256"
std::string format_levels(const std::vector<int>& levels);

// Why `scene` cannot make a texture ("" when it can): RD on, periodic RD boundary.
Status check_texture_scene(const SceneConfig& scene);
// The scene at one level: `scene` with grid.size side x side, range-checked as --size is
// (host/run/offline_run.h apply_overrides).
Status texture_level_scene(const SceneConfig& scene, int side, SceneConfig& out);

// Periodic, cell-centred bilinear prolongation of the interior of `coarse` onto the interior
// of `fine` (any sizes): fine cell x sits at (x + 0.5) * nc / nf - 0.5 in coarse cells
// ((x + 0.5) / 2 - 0.5 for a doubling), read with wrap-around. Halos are not touched.
void prolong_periodic(const FieldF& coarse, FieldF& fine);

struct TextureOptions {
  std::vector<int> levels;       // sides, increasing
  int64_t frames_per_level = 0;  // Engine frames at each level
  EngineOptions engine;
  std::FILE* progress = nullptr;            // a terminal: one progress bar per level
  const std::atomic<bool>* stop = nullptr;  // set asynchronously (a signal): end early
};

struct TextureResult {
  SimState state;       // the last level's state (A and B; the rest as the scene has them)
  int levels_done = 0;  // levels that ran all their frames
  int64_t frames = 0;   // frames run over all levels
  double step_seconds = 0;
  bool stopped_early = false;  // options.stop ended it: the state is not a finished texture
};

// Runs the levels. A level's Engine that cannot be made (memory, a parameter) is an error
// naming the level.
Status synthesize_texture(const SceneConfig& scene, const TextureOptions& options,
                          TextureResult& result);

}  // namespace ardcell
