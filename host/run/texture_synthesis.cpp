#include "host/run/texture_synthesis.h"

#include <charconv>
#include <cmath>
#include <memory>
#include <utility>

#include "host/run/offline_run.h"

namespace ardcell {

Status parse_texture_levels(std::string_view text, std::vector<int>& out, std::string_view flag) {
  const std::string what = std::string(flag) + " " + std::string(text);
  std::vector<int> levels;
  std::size_t begin = 0;
  while (true) {
    const std::size_t comma = text.find(',', begin);
    const std::string_view item = text.substr(
        begin, comma == std::string_view::npos ? std::string_view::npos : comma - begin);
    int64_t side = 0;
    const auto [ptr, ec] = std::from_chars(item.data(), item.data() + item.size(), side);
    if (item.empty() || ec != std::errc() || ptr != item.data() + item.size())
      return Status::error(what + ": '" + std::string(item) +
                           "' is not a whole number (expected sides like 64,128,256)");
    if (side < kMinTextureSide || side > kMaxGridSide)
      return Status::error(what + ": side " + std::string(item) + " is out of range (expected " +
                           std::to_string(kMinTextureSide) + ".." + std::to_string(kMaxGridSide) +
                           ")");
    if (!levels.empty() && side <= levels.back())
      return Status::error(what + ": " + std::string(item) + " follows " +
                           std::to_string(levels.back()) + " (expected increasing sides)");
    levels.push_back(int(side));
    if (comma == std::string_view::npos) break;
    begin = comma + 1;
  }
  out = std::move(levels);
  return Status::ok();
}

std::vector<int> doubling_levels(int start, int final_side) {
  std::vector<int> out;
  for (int64_t side = start; side < final_side; side *= 2) out.push_back(int(side));
  out.push_back(final_side);
  return out;
}

std::string format_levels(const std::vector<int>& levels) {
  std::string out;
  for (int side : levels) {
    // Appended piece by piece: GCC 12 warns (-Wrestrict, a false positive) on the chain.
    if (!out.empty()) out += ',';
    out += std::to_string(side);
  }
  return out;
}

Status check_texture_scene(const SceneConfig& scene) {
  if (!scene.rd.enabled)
    return Status::error("texture needs a reaction-diffusion preset: rd.enabled = true, got false");
  if (scene.rd.boundary != BoundaryKind::kPeriodic)
    return Status::error(std::string("texture needs a periodic preset: rd.boundary = periodic, "
                                     "got ") +
                         (scene.rd.boundary == BoundaryKind::kNeumann ? "neumann" : "dirichlet"));
  return Status::ok();
}

Status texture_level_scene(const SceneConfig& scene, int side, SceneConfig& out) {
  SceneConfig s = scene;
  SceneOverrides o;
  o.size = Int2{side, side};
  if (Status st = apply_overrides(o, s); !st) return st;
  out = std::move(s);
  return Status::ok();
}

void prolong_periodic(const FieldF& coarse, FieldF& fine) {
  const int cx = coarse.nx(), cy = coarse.ny(), fx = fine.nx(), fy = fine.ny();
  if (cx <= 0 || cy <= 0 || fx <= 0 || fy <= 0) return;
  // The coarse position of a fine cell centre, split into the lower neighbour (wrapped into
  // [0, n)) and the weight of the upper one.
  auto locate = [](int i, int nf, int nc, int& lo, int& hi, double& w) {
    const double p = (double(i) + 0.5) * double(nc) / double(nf) - 0.5;
    const double f = std::floor(p);
    w = p - f;
    lo = ((int(f) % nc) + nc) % nc;
    hi = (lo + 1) % nc;
  };
  for (int y = 0; y < fy; ++y) {
    int y0, y1;
    double wy;
    locate(y, fy, cy, y0, y1, wy);
    const float* r0 = coarse.row(y0);
    const float* r1 = coarse.row(y1);
    float* out = fine.row(y);
    for (int x = 0; x < fx; ++x) {
      int x0, x1;
      double wx;
      locate(x, fx, cx, x0, x1, wx);
      const double bottom = (1 - wx) * double(r0[x0]) + wx * double(r0[x1]);
      const double top = (1 - wx) * double(r1[x0]) + wx * double(r1[x1]);
      out[x] = float((1 - wy) * bottom + wy * top);
    }
  }
}

Status synthesize_texture(const SceneConfig& scene, const TextureOptions& options,
                          TextureResult& result) {
  result = {};
  if (Status s = check_texture_scene(scene); !s) return s;
  if (options.levels.empty()) return Status::error("texture: no levels (expected one or more)");
  FieldF a, b;  // the previous level's chemicals, kept across the rebuild
  SimState carried;
  for (std::size_t i = 0; i < options.levels.size(); ++i) {
    const int side = options.levels[i];
    const std::string where = "level " + std::to_string(i + 1) + " (" + std::to_string(side) + "x" +
                              std::to_string(side) + ")";
    SceneConfig level;
    if (Status s = texture_level_scene(scene, side, level); !s)
      return Status::error(where + ": " + s.message());
    std::unique_ptr<Engine> engine;
    if (Status s = make_engine(level, options.engine, engine); !s)
      return Status::error(where + ": " + s.message());
    if (i > 0) {
      SimState& state = engine->state();
      prolong_periodic(a, state.A);
      prolong_periodic(b, state.B);
      // The clock goes on: time-dependent sources see one continuous run.
      state.time = carried.time;
      state.rd_time = carried.rd_time;
      state.step = carried.step;
    }
    OfflineRunOptions run;
    run.steps = options.frames_per_level;
    run.progress = options.progress;
    run.stop = options.stop;
    OfflineRunSummary summary;
    if (Status s = run_offline(*engine, run, {}, summary); !s)
      return Status::error(where + ": " + s.message());
    result.frames += summary.steps;
    result.step_seconds += summary.step_seconds;
    const SimState& state = std::as_const(*engine).state();
    if (summary.stopped_early) {
      result.stopped_early = true;
      result.state = state;
      return Status::ok();
    }
    ++result.levels_done;
    if (i + 1 == options.levels.size()) {
      result.state = state;
      break;
    }
    a = state.A;
    b = state.B;
    carried.time = state.time;
    carried.rd_time = state.rd_time;
    carried.step = state.step;
  }
  return Status::ok();
}

}  // namespace ardcell
