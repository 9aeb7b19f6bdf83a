// Blocks: the Table 1 scene's grid cut into blocks (runtime/block_layout.h), each block an
// Engine of its own on its own thread whose frame plan exchanges halos with the others, gives
// the fields one Engine gives over the whole grid, bit for bit, on every schedule, for even and
// uneven layouts of a grid no block divides.
#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "host/engine/engine.h"
#include "host/engine/table1_plan.h"
#include "host/scenes/scene_registry.h"
#include "runtime/block_layout.h"
#include "tests/support/field_compare.h"

namespace ardcell {
namespace {

constexpr int kFrames = 6;

SceneConfig awkward_scene() {
  SceneConfig scene = builtin_scenes().find("table1-ard")->make();
  scene.size = {127, 93};
  return scene;
}

EngineOptions options(PlanSchedule s) {
  EngineOptions o;
  o.backend = s == PlanSchedule::kSerial ? EngineOptions::Backend::kSerial
                                         : EngineOptions::Backend::kThreads;
  o.workers = 1;
  o.plan.schedule = s;
  o.plan.local_store_bytes = 1024 * 1024;
  return o;
}

void run_blocks(PlanSchedule schedule, Int2 parts, const SimState& whole, int frames) {
  const SceneConfig scene = awkward_scene();
  const BlockLayout layout = BlockLayout::split(scene.size, parts);
  LocalBlockGroup group(layout, table1_block_halo(scene));
  std::vector<std::unique_ptr<Engine>> blocks;
  for (int b = 0; b < layout.count(); ++b) {
    EngineOptions o = options(schedule);
    o.plan.block = layout.block(b);
    o.plan.halo = &group.channel(b);
    blocks.push_back(std::make_unique<Engine>(scene, o));
  }
  std::vector<std::thread> threads;
  for (auto& e : blocks)
    threads.emplace_back([&e, frames] {
      for (int i = 0; i < frames; ++i) e->step();
    });
  for (std::thread& t : threads) t.join();
  const std::string what = std::string(plan_schedule_name(schedule)) + " " +
                           std::to_string(parts.x) + "x" + std::to_string(parts.y);
  for (int b = 0; b < layout.count(); ++b) {
    const SimState& s = blocks[std::size_t(b)]->state();
    const Box2 owned = layout.owned(b);
    EXPECT_TRUE(same_cells_in(s.u, whole.u, owned)) << what << " block " << b << ": u";
    EXPECT_TRUE(same_cells_in(s.v, whole.v, owned)) << what << " block " << b << ": v";
    EXPECT_TRUE(same_cells_in(s.dye, whole.dye, owned)) << what << " block " << b << ": dye";
    EXPECT_TRUE(same_cells_in(s.A, whole.A, owned)) << what << " block " << b << ": A";
    EXPECT_TRUE(same_cells_in(s.B, whole.B, owned)) << what << " block " << b << ": B";
  }
}

TEST(Table1Blocks, BlocksOnThreadsEqualOneEngineBitwise) {
  for (PlanSchedule s : {PlanSchedule::kSerial, PlanSchedule::kStream, PlanSchedule::kBlocked}) {
    Engine whole(awkward_scene(), options(s));
    for (int i = 0; i < kFrames; ++i) whole.step();
    // The run is not trivial: the fluid moved and the chemicals reacted.
    EXPECT_NE(whole.state().u(31, 23), 0.0f);
    EXPECT_GT(whole.state().B(47, 35), 0.0f);
    // 1x1: one block with the deep halo of the others (the fields laid out differently).
    for (Int2 parts : {Int2{1, 1}, Int2{2, 1}, Int2{1, 2}, Int2{2, 2}, Int2{3, 1}})
      run_blocks(s, parts, whole.state(), kFrames);
  }
}

TEST(Table1Blocks, TheExchangeIsAStepOfThePlan) {
  const SceneConfig scene = awkward_scene();
  const BlockLayout layout = BlockLayout::split(scene.size, {2, 1});
  LocalBlockGroup group(layout, table1_block_halo(scene));
  EngineOptions o = options(PlanSchedule::kBlocked);
  o.plan.block = layout.block(0);
  o.plan.halo = &group.channel(0);
  Engine e(scene, o);
  const FramePlan& plan = e.plan();
  // Blocked: the first pass diffuses u from the scene's u, read with a halo of 20: u is
  // exchanged before it, and nothing else (v is read by the next pass, exchanged there).
  ASSERT_EQ(plan.pass_name(0), "diffuse:u");
  EXPECT_EQ(plan.exchanges_before(0), 1);
  ASSERT_EQ(plan.pass_name(1), "diffuse:v");
  EXPECT_EQ(plan.exchanges_before(1), 1);
}

// A block of a scene with nothing to run (no fluid, no RD), and a block on OpenCL, are refused
// with one line.
TEST(Table1Blocks, ABlockOfNothingOrOnOpenClIsRefused) {
  SceneConfig scene = builtin_scenes().find("cavity")->make();
  const BlockLayout layout = BlockLayout::split(scene.size, {2, 1});
  LocalBlockGroup group(layout, 4);
  EngineOptions o;
  o.plan.block = layout.block(0);
  o.plan.halo = &group.channel(0);
  o.backend = EngineOptions::Backend::kOpenCl;
  EXPECT_THROW(Engine(scene, o), std::invalid_argument);
  SceneConfig nothing = builtin_scenes().find("seed001")->make();
  nothing.size = scene.size;
  nothing.rd.enabled = false;
  o.backend = EngineOptions::Backend::kSerial;
  EXPECT_THROW(Engine(nothing, o), std::invalid_argument);
}

}  // namespace
}  // namespace ardcell
