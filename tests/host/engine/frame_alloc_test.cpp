// No heap allocation during a steady-state frame: global operator new is replaced in this
// test program and counted while frames run, on every schedule of the Table 1 plan and on every
// preset on every back end of the engine (the OpenCL one on PoCL: the host side of its frame, which
// only enqueues kernels), the FFT steps on the OpenCL device included, and blocks of a scene of
// stages exchanging their halos.
#include <gtest/gtest.h>

#include <atomic>
#include <barrier>
#include <cstdlib>
#include <memory>
#include <new>
#include <string>
#include <thread>
#include <vector>

#include "host/engine/device.h"
#include "host/engine/engine.h"
#include "host/engine/table1_plan.h"
#include "host/scenes/preset.h"
#include "host/scenes/scene_registry.h"
#include "runtime/block_layout.h"

#include "tests/support/alloc_counter.h"
#if defined(ARDCELL_WITH_OPENCL)
#include "tests/support/opencl_test_device.h"
#endif

namespace ardcell {
namespace {

TEST(FrameAlloc, SteadyStateFramesDoNotAllocate) {
  for (PlanSchedule s : {PlanSchedule::kSerial, PlanSchedule::kStream, PlanSchedule::kBlocked}) {
    for (bool rd : {false, true}) {
      SceneConfig scene = builtin_scenes().find(rd ? "table1-ard" : "table1")->make();
      scene.size = {64, 64};
      EngineOptions o;
      o.workers = 2;
      o.plan.schedule = s;
      Engine w(scene, o);
      w.step();  // first frame: nothing should allocate either, but it is not the steady state
      const long before = g_allocations.load();
      for (int i = 0; i < 5; ++i) w.step();
      EXPECT_EQ(g_allocations.load() - before, 0)
          << plan_schedule_name(s) << (rd ? " ard" : " fluid");
    }
  }
}

TEST(FrameAlloc, EveryPresetOnEveryBackendSteps0Allocations) {
  std::vector<EngineOptions> back_ends = {EngineOptions{EngineOptions::Backend::kSerial, 1},
                                          EngineOptions{EngineOptions::Backend::kThreads, 2}};
#if defined(ARDCELL_WITH_OPENCL)
  if (TestOpenClDevice* device = test_opencl_device())
    back_ends.push_back({EngineOptions::Backend::kOpenCl, 0, device->ctx.get()});
#endif
  for (const std::string& name : preset_names()) {
    Preset preset;
    ASSERT_TRUE(load_preset(name, preset)) << name;
    SceneConfig scene = preset.scene;
    scene.size = {127, 93};  // large enough to be cut into bands of rows
    for (const EngineOptions& options : back_ends) {
      Engine engine(scene, options);
      // The first frame may size scratch (reduction partials), and on OpenCL it must have
      // finished before counting: PoCL compiles each kernel (LLVM, on its own threads) when the
      // first frame's queue reaches it, and with a cold kernel cache - a fresh machine - that
      // ran on into the counted frames.
      engine.step();
      engine.finish();
      const long before = g_allocations.load();
      for (int i = 0; i < 3; ++i) engine.step();
      engine.finish();
      EXPECT_EQ(g_allocations.load() - before, 0) << name << " on " << engine.backend_name();
    }
  }
}

// Blocks of a scene of stages (seed 001, space-cookie-5 whose solves gather the grid or, on its
// real-time settings, sweep the blocks and sum their residuals, and obstacle-ard-gray-scott whose
// fluid and advection run on the gathered grid, as 2x1 blocks on threads, one engine each): the
// halo exchanges, gathers and sums of every frame allocate nothing either.
TEST(FrameAlloc, StageBlocksStep0Allocations) {
  const struct {
    const char* name;
    bool realtime;
  } cases[] = {{"seed001", false},
               {"space-cookie-5", false},
               {"space-cookie-5", true},
               {"obstacle-ard-gray-scott", false}};
  for (const auto& [name, realtime] : cases) {
    Preset preset = preset_from_scene(builtin_scenes().find(name)->make());
    if (realtime) use_realtime_solvers(preset);
    SceneConfig scene = preset.scene;
    scene.size = {127, 93};
    const BlockSupport support = block_support(scene);
    ASSERT_EQ(support.problem, "") << name;
    const BlockLayout layout =
        BlockLayout::split(scene.size, {2, 1}, support.periodic_x, support.periodic_y);
    LocalBlockGroup group(layout, support.halo);
    std::vector<std::unique_ptr<Engine>> blocks;
    for (int b = 0; b < 2; ++b) {
      EngineOptions o{EngineOptions::Backend::kThreads, 2};
      o.plan.block = layout.block(b);
      o.plan.halo = &group.channel(b);
      blocks.push_back(std::make_unique<Engine>(scene, o));
    }
    // Both blocks step together (their exchanges meet); the count covers both threads' frames.
    std::barrier<> sync(2);
    std::thread other([&] {
      blocks[1]->step();
      sync.arrive_and_wait();  // the first frames are done
      sync.arrive_and_wait();  // counting
      for (int i = 0; i < 3; ++i) blocks[1]->step();
      sync.arrive_and_wait();
    });
    blocks[0]->step();
    sync.arrive_and_wait();
    const long before = g_allocations.load();
    sync.arrive_and_wait();
    for (int i = 0; i < 3; ++i) blocks[0]->step();
    sync.arrive_and_wait();
    const long after = g_allocations.load();
    other.join();
    EXPECT_EQ(after - before, 0) << name << (realtime ? " (real-time settings)" : "");
  }
}

// The FFT steps on the OpenCL device (the test above runs them on the CPU: 127 and 31 are prime
// factors the device FFT lacks) at a size it transforms: seed 003's semi-implicit solve
// (mcgraw-turing-d) and ETDRK4 (pearson), each frame several transforms of fft.cl's passes.
TEST(FrameAlloc, FftStepsOnTheOpenClDeviceStep0Allocations) {
#if defined(ARDCELL_WITH_OPENCL)
  TestOpenClDevice* device = test_opencl_device();
  if (!device) GTEST_SKIP() << "no OpenCL device (no ICD or no platform)";
  for (const char* name : {"mcgraw-turing-d", "pearson"}) {
    Preset preset;
    ASSERT_TRUE(load_preset(name, preset)) << name;
    SceneConfig scene = preset.scene;
    scene.size = {64, 48};
    testing::internal::CaptureStderr();  // a fallback line would say the FFT ran on the CPU
    Engine engine(scene, {EngineOptions::Backend::kOpenCl, 0, device->ctx.get()});
    EXPECT_STREQ(engine.backend_name(), "opencl") << name;
    engine.step();
    engine.finish();
    const long before = g_allocations.load();
    for (int i = 0; i < 3; ++i) engine.step();
    engine.finish();
    EXPECT_EQ(g_allocations.load() - before, 0) << name;
    EXPECT_EQ(testing::internal::GetCapturedStderr(), "") << name;
  }
#else
  GTEST_SKIP() << "built without OpenCL";
#endif
}

// The tensor field's BiCGSTAB on the OpenCL device (mcgraw-turing-radial; the test above runs it
// there too, this one also asserts that no line says it fell back to the CPU): its vectors are
// made on the first solve, a frame's solves only enqueue kernels and read row partials.
TEST(FrameAlloc, TensorFieldSolveOnTheOpenClDeviceSteps0Allocations) {
#if defined(ARDCELL_WITH_OPENCL)
  TestOpenClDevice* device = test_opencl_device();
  if (!device) GTEST_SKIP() << "no OpenCL device (no ICD or no platform)";
  Preset preset;
  ASSERT_TRUE(load_preset("mcgraw-turing-radial", preset));
  SceneConfig scene = preset.scene;
  scene.size = {127, 93};
  testing::internal::CaptureStderr();
  Engine engine(scene, {EngineOptions::Backend::kOpenCl, 0, device->ctx.get()});
  EXPECT_STREQ(engine.backend_name(), "opencl");
  engine.step();
  engine.finish();
  const long before = g_allocations.load();
  for (int i = 0; i < 3; ++i) engine.step();
  engine.finish();
  EXPECT_EQ(g_allocations.load() - before, 0);
  const std::string lines = testing::internal::GetCapturedStderr();
  // A device without doubles keeps the CPU solve, with its line.
  if (engine.device().supports(DeviceOp::kTensorFieldSolve)) {
    EXPECT_EQ(lines, "");
  }
#else
  GTEST_SKIP() << "built without OpenCL";
#endif
}

// The second-order RD schemes (pearson alone runs one of them among the presets), on the CPU
// back ends, with anisotropy where the scheme takes it.
TEST(FrameAlloc, EveryRdSchemeSteps0Allocations) {
  Preset preset;
  ASSERT_TRUE(load_preset("pearson", preset));
  for (RdScheme scheme :
       {RdScheme::kImplicit, RdScheme::kCrankNicolsonAm2, RdScheme::kSbdf2, RdScheme::kEtdrk4}) {
    SceneConfig scene = preset.scene;
    scene.size = {127, 93};
    scene.rd.scheme = scheme;
    scene.rd.steps_per_frame = 2;
    if (scheme != RdScheme::kEtdrk4) scene.rd.anisotropy.kind = AnisotropyKind::kWitkinKass;
    for (const EngineOptions& options : {EngineOptions{EngineOptions::Backend::kSerial, 1},
                                         EngineOptions{EngineOptions::Backend::kThreads, 2}}) {
      Engine engine(scene, options);
      engine.step();
      const long before = g_allocations.load();
      for (int i = 0; i < 3; ++i) engine.step();
      EXPECT_EQ(g_allocations.load() - before, 0) << int(scheme) << " on " << engine.backend_name();
    }
  }
}

TEST(FrameAlloc, TheCounterSeesAllocations) {
  const long before = g_allocations.load();
  auto* p = new int(3);
  EXPECT_EQ(g_allocations.load() - before, 1);
  delete p;
}

}  // namespace
}  // namespace ardcell
