// The live loop over EngineSimulations on OpenCL (PoCL in CI) against the same loop over the
// CPU back end: presets set to fixed-sweep solvers (tolerance 0), a parameter change, strokes
// and preset switches under the running loop, a fluid preset whose pressure solver (ICCG) runs
// on the CPU with one line saying so. Norm: max |cl - cpu| / max |cpu| over the interior of
// the field shown, <= 1e-5 every frame.
#if defined(ARDCELL_WITH_OPENCL)
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>

#include "host/engine/engine.h"
#include "host/engine/opencl_device.h"
#include "host/live/live_engine.h"
#include "host/scenes/preset.h"
#include "tests/support/field_compare.h"
#include "tests/support/opencl_test_device.h"

namespace ardcell {
namespace {

constexpr double kTolerance = 1e-5;

using Device = TestOpenClDevice;
Device* device() { return test_opencl_device(); }

class NoDisplay final : public LiveDisplay {
 public:
  void poll(StrokeRing&, CommandQueue&) override {}
  void present(const ImageRgb8&, const HudInfo*) override {}
};

struct Fixture {
  std::filesystem::path dir;
  Fixture() {
    dir = std::filesystem::temp_directory_path() /
          ("ardcell_live_opencl_test_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
  }
  ~Fixture() { std::filesystem::remove_all(dir); }
  // A built-in preset at an awkward small grid (same cell size), edited, written as TOML.
  std::string preset(const std::string& builtin, Int2 grid,
                     const std::function<void(Preset&)>& edit) {
    Preset p;
    EXPECT_TRUE(load_preset(builtin, p).is_ok()) << builtin;
    p.scene.domain_width = p.scene.domain_width / p.scene.size.x * grid.x;
    p.scene.size = grid;
    p.quality.adaptive = false;
    edit(p);
    const std::filesystem::path path = dir / (builtin + ".toml");
    std::ofstream(path) << preset_to_toml(p);
    return path.string();
  }
};

LiveOptions options() {
  LiveOptions o;
  o.fps = 0;  // unpaced
  o.adaptive = false;
  o.crossfade_frames = 4;
  o.log = nullptr;
  return o;
}

const FieldF& shown(const LiveLoop& loop) {
  const SimState& s = loop.simulation().state();
  return loop.preset().scene.output.show == "B" ? s.B : s.A;
}

bool finite(const FieldF& f) {
  for (int y = 0; y < f.ny(); ++y)
    for (int x = 0; x < f.nx(); ++x)
      if (!std::isfinite(f(x, y))) return false;
  return true;
}

// The live simulations of the test program's OpenCL device.
SimulationFactory on_opencl() {
  EngineOptions o;
  o.backend = EngineOptions::Backend::kOpenCl;
  o.opencl = test_opencl_device()->ctx.get();
  return engine_simulations(o);
}

StrokeSample pen(float x, float y, bool down) {
  StrokeSample s;
  s.x = x;
  s.y = y;
  s.pressure = 0.8f;
  s.buttons = down ? uint32_t(kButtonTip) : 0u;
  s.in_range = true;
  return s;
}

TEST(LiveOpenCl, SwitchesParametersAndPresetsUnderTheLoopLikeTheCpu) {
  Device* dev = device();
  if (!dev) GTEST_SKIP() << "no OpenCL device (no ICD or no platform)";
  Fixture fx;
  const Int2 grid{29, 23};
  const std::string pearson = fx.preset("pearson", grid, [](Preset& p) {
    p.scene.rd.diffusion_solver = {SolverKind::kJacobi, 8, 0.0};
  });
  const std::string turing = fx.preset("turing-spots", grid, [](Preset& p) {
    p.scene.rd.diffusion_solver = {SolverKind::kRedBlackGaussSeidel, 4, 0.0};
  });
  const std::string fluid = fx.preset("cavity-gray-scott", {16, 16}, [](Preset& p) {
    p.scene.fluid.pressure_solver = {SolverKind::kIccg, 2, 0.0};
    p.scene.fluid.viscosity_solver = {SolverKind::kJacobi, 4, 0.0};
    p.scene.rd.diffusion_solver = {SolverKind::kMultigrid, 2, 0.0};
  });

  const int builds = dev->ctx->build_count();
  NoDisplay cl_display, cpu_display;
  LiveLoop on_device(options(), on_opencl(), cl_display);
  LiveLoop on_cpu(options(), make_engine_simulation, cpu_display);
  ASSERT_TRUE(on_device.start(pearson).is_ok());
  ASSERT_TRUE(on_cpu.start(pearson).is_ok());
  EXPECT_EQ(on_device.simulation().backend(), "opencl");

  double worst = 0;
  int64_t compared = 0;
  auto frames = [&](int n, const char* what) {
    for (int i = 0; i < n; ++i) {
      on_device.run_frame();
      on_cpu.run_frame();
      ASSERT_TRUE(finite(shown(on_device))) << what << " frame " << i;
      const double e = max_relative_error(shown(on_device), shown(on_cpu));
      EXPECT_LE(e, kTolerance) << what << " frame " << i;
      worst = std::max(worst, e);
      ++compared;
    }
  };
  auto both = [&](const LiveCommand& c) {
    on_device.commands().push(c);
    on_cpu.commands().push(c);
  };
  // The switch is built on each loop's worker: it lands in the frame that queued it or, once
  // built, in the next one; either way each loop steps its new simulation exactly once here.
  auto select = [&](const std::string& path) {
    both(LiveCommand::with_text(LiveCommandKind::kSelectPreset, path));
    for (LiveLoop* loop : {&on_device, &on_cpu}) {
      loop->run_frame();
      if (loop->switch_pending()) {
        loop->wait_for_switch();
        loop->run_frame();
      }
    }
  };

  frames(8, "pearson");
  // A slider (non-structural: kernel arguments only), faded in over the crossfade.
  const ParamSpec* feed = find_param("rd.reaction.f");
  ASSERT_NE(feed, nullptr);
  both(LiveCommand::make(LiveCommandKind::kSetParam, 0.03, int(feed - preset_params().data())));
  frames(8, "pearson, F changed");
  EXPECT_DOUBLE_EQ(on_device.preset().scene.rd.reaction.F, 0.03f);
  // A stroke: painted on the host mirror, uploaded.
  for (int i = 0; i <= 6; ++i) {
    const StrokeSample s = pen(0.2f + 0.1f * float(i), 0.5f, i < 6);
    on_device.input().push(s);
    on_cpu.input().push(s);
  }
  frames(6, "pearson, painted");
  // A structural switch (other model and solver): a new engine on the same context.
  select(turing);
  frames(10, "turing-spots");
  EXPECT_EQ(on_device.simulation().backend(), "opencl");
  // A fluid preset (its ICCG pressure solve on the device) whose implicit diffusion the device
  // does not run: that one op on the CPU, with one line naming the setting (each engine says
  // it once).
  testing::internal::CaptureStderr();
  select(fluid);
  frames(3, "cavity-gray-scott");
  const std::string said = testing::internal::GetCapturedStderr();
  EXPECT_EQ(on_device.simulation().backend(), "opencl");
  EXPECT_EQ(said,
            "ardcell: opencl: implicit diffusion runs on the CPU (mg: OpenCL runs iccg, or fixed "
            "jacobi or rbgs sweeps (tolerance 0))\n");
  // And back to a preset with no fallback.
  select(pearson);
  frames(6, "pearson again");
  EXPECT_EQ(on_device.simulation().backend(), "opencl");

  EXPECT_EQ(dev->ctx->build_count(), builds);  // no program built by any switch
  EXPECT_EQ(on_device.preset_errors(), 0);
  std::printf("live OpenCL vs CPU: %lld frames, worst relative error %.2e\n",
              static_cast<long long>(compared), worst);
}

// An orient stroke (theta0, spread by fast marching, and seed dabs of A and B) reaches the
// device: the anisotropic space cookie follows the CPU's over the first 2 frames (beyond them
// the device's atan2 / cos ulps grow, see engine_opencl_parity_test) and differs clearly from
// the unpainted preset.
TEST(LiveOpenCl, OrientStrokeReachesTheDevice) {
  Device* dev = device();
  if (!dev) GTEST_SKIP() << "no OpenCL device (no ICD or no platform)";
  Fixture fx;
  const std::string cookie = fx.preset("space-cookie-5", {25, 19}, [](Preset& p) {
    p.scene.rd.diffusion_solver = {SolverKind::kJacobi, 8, 0.0};
    p.input.mode = "orient";
  });
  NoDisplay d1, d2;
  LiveLoop on_device(options(), on_opencl(), d1);
  LiveLoop on_cpu(options(), make_engine_simulation, d2);
  ASSERT_TRUE(on_device.start(cookie).is_ok());
  ASSERT_TRUE(on_cpu.start(cookie).is_ok());
  for (int i = 0; i <= 8; ++i) {
    const StrokeSample s = pen(0.5f + 0.04f * float(i), 0.2f + 0.07f * float(i), i < 8);
    on_device.input().push(s);
    on_cpu.input().push(s);
  }
  on_device.run_frame();
  on_cpu.run_frame();
  const SimState& cl = on_device.simulation().state();
  const SimState& cpu = on_cpu.simulation().state();
  EXPECT_EQ(max_relative_error(cl.theta0, cpu.theta0), 0.0);
  double spread = 0;
  for (int y = 0; y < cpu.size.y; ++y)
    for (int x = 0; x < cpu.size.x; ++x)
      spread = std::max(spread, std::abs(double(cpu.theta0(x, y))));
  EXPECT_GT(spread, 0.1);  // the stroke did orient the grid
  EXPECT_LE(max_relative_error(shown(on_device), shown(on_cpu)), kTolerance);
  // The same preset unpainted: the stroke changed the device's frame clearly.
  LiveLoop plain(options(), make_engine_simulation, d2);
  ASSERT_TRUE(plain.start(cookie).is_ok());
  plain.run_frame();
  EXPECT_GT(max_relative_error(shown(on_device), shown(plain)), 0.1);
  on_device.run_frame();
  on_cpu.run_frame();
  EXPECT_LE(max_relative_error(shown(on_device), shown(on_cpu)), kTolerance);
}

// The live display brings only the field it shows to the host: a steady frame of a fluid preset
// on OpenCL (real-time solvers, nothing painted) downloads the dye alone, or u and v for speed,
// and uploads nothing.
TEST(LiveOpenCl, AFrameDownloadsOnlyTheShownField) {
  Device* dev = device();
  if (!dev) GTEST_SKIP() << "no OpenCL device (no ICD or no platform)";
  Fixture fx;
  const Int2 grid{31, 27};
  for (const char* show : {"dye", "speed", "B"}) {
    const std::string path = fx.preset("cavity-gray-scott", grid, [&](Preset& p) {
      p.scene.fluid.pressure_solver = {SolverKind::kJacobi, 6, 0.0};
      p.scene.fluid.viscosity_solver = {SolverKind::kJacobi, 4, 0.0};
      p.scene.rd.diffusion_solver = {SolverKind::kRedBlackGaussSeidel, 3, 0.0};
      p.scene.output.show = show;
    });
    NoDisplay display;
    LiveLoop loop(options(), on_opencl(), display);
    ASSERT_TRUE(loop.start(path).is_ok());
    for (int i = 0; i < 2; ++i) loop.run_frame();
    const Engine& engine = static_cast<const EngineSimulation&>(loop.simulation()).engine();
    const auto& cl = static_cast<const OpenClDevice&>(engine.device());
    const std::int64_t up = cl.uploaded_bytes(), down = cl.downloaded_bytes();
    constexpr int kFrames = 4;
    for (int i = 0; i < kFrames; ++i) loop.run_frame();
    // A field's whole allocation (halo and row padding) moves.
    const std::int64_t field_bytes = std::int64_t(engine.state({}).dye.raw_size() * sizeof(float));
    const int fields = std::string_view(show) == "speed" ? 2 : 1;
    EXPECT_EQ(cl.uploaded_bytes(), up) << show;
    EXPECT_EQ(cl.downloaded_bytes() - down, kFrames * fields * field_bytes) << show;
  }
}

}  // namespace
}  // namespace ardcell
#endif
