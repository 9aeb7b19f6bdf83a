#include "host/run/offline_run.h"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <fstream>
#include <memory>
#include <new>
#include <stdexcept>
#include <string>

#include "host/scenes/preset.h"

namespace ardcell {
namespace {

using Clock = std::chrono::steady_clock;

bool parse_positive(std::string_view s, int& out) {
  if (s.empty()) return false;
  int64_t v = 0;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || ptr != s.data() + s.size()) return false;
  if (v < 1 || v > kMaxGridSide) return false;
  out = int(v);
  return true;
}

uint64_t read_number_file(const char* path) {
  std::ifstream in(path);
  std::string text;
  if (!(in >> text) || text == "max") return 0;
  return std::strtoull(text.c_str(), nullptr, 10);
}

std::string human_bytes(double b) {
  const char* units[] = {"B", "KiB", "MiB", "GiB", "TiB", "PiB"};
  int u = 0;
  while (b >= 1024 && u < 5) {
    b /= 1024;
    ++u;
  }
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f %s", b, units[u]);
  return buf;
}

void draw_progress(std::FILE* out, int64_t done, int64_t total, double ms_per_frame) {
  constexpr int kWidth = 30;
  const double f = total > 0 ? double(done) / double(total) : 1.0;
  const int filled = int(f * kWidth);
  char bar[kWidth + 1];
  for (int i = 0; i < kWidth; ++i) bar[i] = i < filled ? '#' : '.';
  bar[kWidth] = '\0';
  const double eta = ms_per_frame * double(total - done) / 1e3;
  std::fprintf(out, "\r[%s] %3d%% %lld/%lld  %.2f ms/frame  ETA %dm%02ds\033[K", bar, int(f * 100),
               static_cast<long long>(done), static_cast<long long>(total), ms_per_frame,
               int(eta) / 60, int(eta) % 60);
  std::fflush(out);
}

}  // namespace

Status parse_grid_size(const std::string& text, Int2& out) {
  auto bad = [&] {
    return Status::error("--size '" + text + "': expected N or WxH with positive integers up to " +
                         std::to_string(kMaxGridSide));
  };
  const std::size_t x = text.find_first_of("xX");
  int w = 0, h = 0;
  if (x == std::string::npos) {
    if (!parse_positive(text, w)) return bad();
    h = w;
  } else if (!parse_positive(std::string_view(text).substr(0, x), w) ||
             !parse_positive(std::string_view(text).substr(x + 1), h)) {
    return bad();
  }
  out = {w, h};
  return Status::ok();
}

Status apply_overrides(const SceneOverrides& o, SceneConfig& scene) {
  // Each flag goes through the range of the preset key it stands for (host/scenes/preset.h).
  Preset p;
  p.scene = scene;
  if (o.size) {
    const std::string flag =
        "--size " + std::to_string(o.size->x) + "x" + std::to_string(o.size->y) + ": a side of";
    if (Status s = check_flag_param("grid.size", std::min(o.size->x, o.size->y), flag); !s)
      return s;
    if (Status s = check_flag_param("grid.size", std::max(o.size->x, o.size->y), flag); !s)
      return s;
    p.scene.size = *o.size;
  }
  if (o.dt)
    if (Status s = set_flag_param(p, "grid.dt", *o.dt, "--dt"); !s) return s;
  if (o.reynolds) {
    if (!(std::isfinite(*o.reynolds) && *o.reynolds > 0))
      return Status::error("--re " + std::to_string(*o.reynolds) +
                           ": expected a positive Reynolds number");
    if (p.scene.fluid.kind == FluidSceneKind::kNone)
      return Status::error("--re: scene '" + scene.name +
                           "' has no fluid (expected a scene with a fluid)");
    FluidConfig fluid = p.scene.fluid;
    set_reynolds_number(fluid, *o.reynolds, p.scene.domain_width);
    char flag[96];
    std::snprintf(flag, sizeof flag, "--re %g gives a viscosity of", *o.reynolds);
    if (Status s = set_flag_param(p, "fluid.viscosity", fluid.viscosity, flag); !s) return s;
  }
  if (o.sweeps)
    if (Status s = check_flag_param("fluid.pressure_solver.iterations", *o.sweeps, "--sweeps"); !s)
      return s;
  if (o.solver || o.sweeps) {
    const SolverKind kind = o.solver ? *o.solver : p.scene.fluid.pressure_solver.kind;
    const int sweeps = o.sweeps ? *o.sweeps : p.scene.fluid.pressure_solver.max_iterations;
    set_fluid_solver(p.scene.fluid, kind, sweeps);
    // The Table 1 plan runs one sweep count for every solve, the RD's included.
    if (p.scene.fluid.kind == FluidSceneKind::kTable1 && p.scene.rd.enabled)
      p.scene.rd.diffusion_solver.max_iterations = sweeps;
  }
  scene = std::move(p.scene);
  return Status::ok();
}

uint64_t estimated_bytes_for_grid(const SceneConfig& scene) {
  // Per cell: the state's float fields, the fluid's scratch (previous velocity, divergence,
  // solver vectors, multigrid or ICCG levels) and the RD's, with halo and padding headroom;
  // plus the RGB frame.
  const uint64_t cells = uint64_t(scene.size.x) * uint64_t(scene.size.y);
  const uint64_t per_cell = 64 * sizeof(float) + (scene.rd.enabled ? 32 * sizeof(float) : 0) + 3;
  return cells * per_cell + (16u << 20);
}

uint64_t available_memory_bytes() {
  uint64_t avail = 0;
  {
    std::ifstream in("/proc/meminfo");
    std::string key;
    uint64_t kb = 0;
    std::string unit;
    while (in >> key >> kb >> unit)
      if (key == "MemAvailable:") {
        avail = kb * 1024;
        break;
      }
  }
  if (avail == 0) {
    const long pages = ::sysconf(_SC_AVPHYS_PAGES), page = ::sysconf(_SC_PAGESIZE);
    if (pages > 0 && page > 0) avail = uint64_t(pages) * uint64_t(page);
  }
  const uint64_t limit = read_number_file("/sys/fs/cgroup/memory.max");
  const uint64_t used = read_number_file("/sys/fs/cgroup/memory.current");
  if (limit > 0 && limit > used && (avail == 0 || limit - used < avail)) avail = limit - used;
  rlimit rl{};
  if (::getrlimit(RLIMIT_AS, &rl) == 0 && rl.rlim_cur != RLIM_INFINITY &&
      (avail == 0 || uint64_t(rl.rlim_cur) < avail))
    avail = rl.rlim_cur;
  return avail;
}

Status check_memory_for_grid(const SceneConfig& scene) {
  const uint64_t need = estimated_bytes_for_grid(scene);
  const uint64_t have = available_memory_bytes();
  if (have > 0 && need > have)
    return Status::error("--size " + std::to_string(scene.size.x) + "x" +
                         std::to_string(scene.size.y) + ": needs about " +
                         human_bytes(double(need)) + " but only " + human_bytes(double(have)) +
                         " of memory is available (expected a smaller grid)");
  return Status::ok();
}

Status make_engine(const SceneConfig& scene, const EngineOptions& options,
                   std::unique_ptr<Engine>& out) {
  try {
    out = std::make_unique<Engine>(scene, options);
  } catch (const std::invalid_argument& e) {
    return Status::error(e.what());
  } catch (const std::bad_alloc&) {
    return Status::error("--size " + std::to_string(scene.size.x) + "x" +
                         std::to_string(scene.size.y) +
                         ": out of memory (expected a smaller grid)");
  }
  return Status::ok();
}

Status run_offline(Engine& engine, const OfflineRunOptions& options,
                   std::span<FrameSink* const> sinks, OfflineRunSummary& summary) {
  EngineStepper stepper(engine);
  return run_offline(stepper, options, sinks, summary);
}

Status run_offline(OfflineStepper& stepper, const OfflineRunOptions& options,
                   std::span<FrameSink* const> sinks, OfflineRunSummary& summary) {
  summary = {};
  const Int2 size = stepper.frame_state().size;
  summary.cells = int64_t(size.x) * size.y;
  ImageRgb8 image;
  if (options.every > 0 && !sinks.empty()) image.resize(size.x, size.y);

  Clock::time_point last_draw = Clock::now();
  for (int64_t i = 1; i <= options.steps; ++i) {
    if (options.stop && options.stop->load(std::memory_order_relaxed)) {
      summary.stopped_early = true;
      break;
    }
    const Clock::time_point t0 = Clock::now();
    stepper.step();
    const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    summary.step_seconds += seconds;
    if (i <= int64_t(options.frame_seconds.size()))
      options.frame_seconds[std::size_t(i - 1)] = seconds;
    summary.steps = i;
    if (options.observer)
      if (Status s = options.observer->after_step(i); !s) return s;

    if (!image.empty() && i % options.every == 0) {
      const SimState& state = stepper.frame_state();
      const RenderStats stats = render_frame(state, options.render, image);
      summary.non_finite_cells = stats.non_finite;
      const FrameInfo info{summary.frames_written, state.step, state.time};
      for (FrameSink* sink : sinks)
        if (Status s = sink->write(image, info); !s) return s;
      ++summary.frames_written;
    }
    if (options.progress) {
      const Clock::time_point now = Clock::now();
      if (now - last_draw > std::chrono::milliseconds(100) || i == options.steps) {
        draw_progress(options.progress, i, options.steps, summary.ms_per_frame());
        last_draw = now;
      }
    }
  }
  if (options.progress) {
    std::fputs("\r\033[K", options.progress);
    std::fflush(options.progress);
  }
  return Status::ok();
}

FrameTimeStats frame_time_stats(std::span<double> seconds) {
  FrameTimeStats st;
  st.frames = int64_t(seconds.size());
  if (seconds.empty()) return st;
  std::sort(seconds.begin(), seconds.end());
  double sum = 0;
  for (double s : seconds) sum += s;
  // Nearest-rank percentiles.
  const auto rank = [&](double q) {
    const std::size_t r = std::size_t(std::ceil(q * double(seconds.size())));
    return seconds[std::min(seconds.size() - 1, r == 0 ? 0 : r - 1)];
  };
  st.mean_ms = 1e3 * sum / double(seconds.size());
  st.p50_ms = 1e3 * rank(0.50);
  st.p99_ms = 1e3 * rank(0.99);
  st.max_ms = 1e3 * seconds.back();
  return st;
}

std::string format_frame_time_stats(const FrameTimeStats& s) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "frame ms: mean=%.3f p50=%.3f p99=%.3f max=%.3f (%lld frames)",
                s.mean_ms, s.p50_ms, s.p99_ms, s.max_ms, static_cast<long long>(s.frames));
  return buf;
}

std::string format_summary(const OfflineRunSummary& s, const std::string& out) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "frames=%lld ms/frame=%.3f cells/s=%.4g images=%lld",
                static_cast<long long>(s.steps), s.ms_per_frame(), s.cells_per_second(),
                static_cast<long long>(s.frames_written));
  return std::string(buf) + " out=" + out;
}

}  // namespace ardcell
