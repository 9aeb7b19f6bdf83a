// Blocks of a scene built of stages: the explicit RD schemes' grid cut into blocks
// (runtime/block_layout.h), each block an Engine whose Device computes its cells and exchanges a
// halo (Device::exchange_halos: one cell before each step with walls; on a periodic grid
// kExplicitBlockSteps cells every that many steps, each step also stepping the halo cells the
// next reads), gives the fields one Engine gives over the whole grid, bit for bit: periodic (seed
// 001, whose whole-grid run takes the temporally blocked kernel; a pattern that crosses the
// periodic edges), Dirichlet and Neumann walls, on even and uneven layouts of a grid no block
// divides, on the serial and threads back ends.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "host/engine/device.h"
#include "host/engine/engine.h"
#include "host/engine/rd_step.h"
#include "host/paint/paint.h"
#include "host/scenes/scene_registry.h"
#include "runtime/block_layout.h"
#include "tests/support/field_compare.h"

namespace ardcell {
namespace {

constexpr int kFrames = 12;

SceneConfig seed001_at(Int2 size) {
  SceneConfig scene = builtin_scenes().find("seed001")->make();
  scene.size = size;
  return scene;
}

// Seed 001 as it ships: explicit 9-point Gray-Scott on a periodic grid.
SceneConfig periodic_scene() { return seed001_at({127, 93}); }

// The 5-point scheme with Dirichlet walls (a step short enough for it).
SceneConfig dirichlet_scene() {
  SceneConfig scene = seed001_at({127, 93});
  scene.rd.scheme = RdScheme::kExplicit5;
  scene.rd.boundary = BoundaryKind::kDirichlet;
  scene.rd.boundary_a = 1.0f;
  scene.rd.boundary_b = 0.0f;
  scene.rd.dt = 0.2;
  return scene;
}

// The generic 9-point kernel (no reaction) with Neumann walls.
SceneConfig neumann_scene() {
  SceneConfig scene = seed001_at({127, 93});
  scene.rd.boundary = BoundaryKind::kNeumann;
  scene.rd.react = false;
  return scene;
}

EngineOptions options(EngineOptions::Backend backend, int workers) {
  EngineOptions o;
  o.backend = backend;
  o.workers = workers;
  return o;
}

// Runs `scene` as parts.x by parts.y blocks, one thread each, and compares every cell each block
// owns with the whole-grid run.
void expect_blocks_equal_whole(const SceneConfig& scene, Int2 parts, const EngineOptions& o,
                               const SimState& whole, const std::string& what) {
  const BlockSupport support = block_support(scene);
  ASSERT_EQ(support.problem, "") << what;
  const BlockLayout layout =
      BlockLayout::split(scene.size, parts, support.periodic_x, support.periodic_y);
  LocalBlockGroup group(layout, support.halo);
  std::vector<std::unique_ptr<Engine>> blocks;
  for (int b = 0; b < layout.count(); ++b) {
    EngineOptions bo = o;
    bo.plan.block = layout.block(b);
    bo.plan.halo = &group.channel(b);
    blocks.push_back(std::make_unique<Engine>(scene, bo));
  }
  std::vector<std::thread> threads;
  for (auto& e : blocks)
    threads.emplace_back([&e] {
      for (int i = 0; i < kFrames; ++i) e->step();
    });
  for (std::thread& t : threads) t.join();
  const std::string where = what + " " + std::to_string(parts.x) + "x" + std::to_string(parts.y);
  for (int b = 0; b < layout.count(); ++b) {
    const SimState& s = blocks[std::size_t(b)]->state();
    EXPECT_EQ(s.A.interior(), layout.block(b)) << where;
    EXPECT_EQ(s.step, kFrames) << where;
    const Box2 owned = layout.owned(b);
    EXPECT_TRUE(same_cells_in(s.A, whole.A, owned)) << where << " block " << b << ": A";
    EXPECT_TRUE(same_cells_in(s.B, whole.B, owned)) << where << " block " << b << ": B";
  }
}

void check_scene(const SceneConfig& scene, const std::string& what) {
  Engine whole(scene, options(EngineOptions::Backend::kSerial, 1));
  const SimState& initial = whole.state();
  const int cx = scene.size.x / 2, cy = scene.size.y / 2;
  const float a0 = initial.A(cx, cy), b0 = initial.B(cx, cy);
  for (int i = 0; i < kFrames; ++i) whole.step();
  const SimState& s = whole.state();
  // The run is not trivial and stays finite: the chemicals moved where the pattern started.
  EXPECT_TRUE(s.A(cx, cy) != a0 || s.B(cx, cy) != b0) << what;
  for (int y = 0; y < scene.size.y; ++y)
    for (int x = 0; x < scene.size.x; ++x)
      ASSERT_TRUE(std::isfinite(s.A(x, y)) && std::isfinite(s.B(x, y))) << what;
  for (Int2 parts : {Int2{1, 1}, Int2{2, 1}, Int2{1, 2}, Int2{2, 2}, Int2{3, 1}})
    expect_blocks_equal_whole(scene, parts, options(EngineOptions::Backend::kSerial, 1), s,
                              what + ", serial");
  expect_blocks_equal_whole(scene, {2, 2}, options(EngineOptions::Backend::kThreads, 2), s,
                            what + ", threads (2 workers a block)");
}

TEST(StageBlocks, PeriodicSeed001EqualsOneEngineBitwise) {
  // The whole grid runs seed 001's temporally blocked kernel on threads; blocks step one step
  // at a time: the same bits.
  check_scene(periodic_scene(), "seed001 periodic");
  Engine blocked(periodic_scene(), options(EngineOptions::Backend::kThreads, 2));
  Engine serial(periodic_scene(), options(EngineOptions::Backend::kSerial, 1));
  for (int i = 0; i < kFrames; ++i) {
    blocked.step();
    serial.step();
  }
  EXPECT_TRUE(same_cells_in(blocked.state().A, serial.state().A, box_of_size({127, 93})));
}

TEST(StageBlocks, DeepHalosCrossThePeriodicEdges) {
  // On 31 x 23 seed 001's square reaches every edge within the 12 frames: the halo cells a
  // block steps come across the wrap, from its neighbours or from itself (1x1, and 2x1 along y).
  SceneConfig scene = seed001_at({31, 23});
  Engine probe(scene, options(EngineOptions::Backend::kSerial, 1));
  for (int i = 0; i < kFrames; ++i) probe.step();
  const SimState& s = probe.state();
  const float background = s.B(0, 0);
  int edge_cells_moved = 0;
  for (int x = 0; x < 31; ++x) edge_cells_moved += s.B(x, 0) != background;
  for (int y = 0; y < 23; ++y) edge_cells_moved += s.B(0, y) != background;
  EXPECT_GT(edge_cells_moved, 10);
  check_scene(scene, "seed001 31x23");
}

TEST(StageBlocks, DeepHalosStepOnlyTheRowsOfTheirColumnsThatCanChange) {
  // On a tall grid the pattern and its tail cover part of the rows of a cut through it, and none
  // of the far edges but the rows next to the halo above and below: the halo columns a block
  // steps are stepped only there, and the rows they held two steps before are overwritten when
  // the background settles.
  check_scene(seed001_at({160, 400}), "seed001 160x400");
  // 6 steps a frame: an exchange for 5, then one a cell deep for the last step, which steps no
  // halo column but must still see what that exchange wrote into column 1.
  SceneConfig six = seed001_at({160, 400});
  six.rd.steps_per_frame = 6;
  check_scene(six, "seed001 160x400, 6 steps a frame");
}

TEST(StageBlocks, DeepHalosServeFramesOfAnyLength) {
  // A block of a periodic grid steps kExplicitBlockSteps steps per exchange: 7 steps a frame
  // are an exchange for 5 and one for 2; blocks 3 and 4 cells wide take their halo from several
  // neighbours.
  SceneConfig scene = periodic_scene();
  scene.rd.steps_per_frame = 7;
  ASSERT_EQ(block_support(scene).halo, kExplicitBlockSteps);
  check_scene(scene, "seed001, 7 steps a frame");
  Engine whole(scene, options(EngineOptions::Backend::kSerial, 1));
  for (int i = 0; i < kFrames; ++i) whole.step();
  expect_blocks_equal_whole(scene, {32, 1}, options(EngineOptions::Backend::kSerial, 1),
                            whole.state(), "seed001, blocks 4 cells wide");
}

TEST(StageBlocks, DirichletFivePointEqualsOneEngineBitwise) {
  check_scene(dirichlet_scene(), "explicit5 dirichlet");
}

TEST(StageBlocks, NeumannNinePointEqualsOneEngineBitwise) {
  check_scene(neumann_scene(), "explicit9 neumann");
}

// Block b of `scene` cut into 2x2, on the serial back end, alone: its group's other blocks are
// never made, so it must not step (an exchange would wait for them for ever).
struct LoneBlock {
  LoneBlock(const SceneConfig& scene, int b)
      : support(block_support(scene)),
        layout(BlockLayout::split(scene.size, {2, 2}, support.periodic_x, support.periodic_y)),
        group(layout, support.halo),
        engine(scene, block_options(b)) {}
  EngineOptions block_options(int b) {
    EngineOptions o = options(EngineOptions::Backend::kSerial, 1);
    o.plan.block = layout.block(b);
    o.plan.halo = &group.channel(b);
    return o;
  }
  BlockSupport support;
  BlockLayout layout;
  LocalBlockGroup group;
  Engine engine;
};

// What a block's device runs (Device::supports, as an OpenCL device says what it runs): the
// ops that compute a block's cells from its cells and halo; the whole grid's device runs all.
TEST(StageBlocks, ABlocksDeviceSaysWhichOpsItRuns) {
  LoneBlock block(periodic_scene(), 0);
  const Device& on_block = block.engine.device();
  ASSERT_TRUE(on_block.on_block());
  for (DeviceOp op : {DeviceOp::kExplicitRd, DeviceOp::kFillBoundary, DeviceOp::kCopy,
                      DeviceOp::kReactionImplicit, DeviceOp::kAddSplat})
    EXPECT_TRUE(on_block.supports(op)) << device_op_name(op);
  for (DeviceOp op : {DeviceOp::kRange, DeviceOp::kSolve, DeviceOp::kGrayScott9Steps,
                      DeviceOp::kAdvectScalar, DeviceOp::kGeneralizedRd, DeviceOp::kPeriodicSolve})
    EXPECT_FALSE(on_block.supports(op)) << device_op_name(op);
  Engine whole(periodic_scene(), options(EngineOptions::Backend::kSerial, 1));
  for (int op = 0; op < int(DeviceOp::kCount); ++op)
    EXPECT_TRUE(whole.device().supports(DeviceOp(op))) << device_op_name(DeviceOp(op));
}

TEST(StageBlocks, ABlockDoesNotDivideItsPattern) {
  // seed001's initial square straddles the 2x2 cut: each block starts with its cells of it.
  const SceneConfig scene = periodic_scene();
  Engine whole(scene, options(EngineOptions::Backend::kSerial, 1));
  LoneBlock block(scene, 3);  // constructing steps nothing
  EXPECT_TRUE(same_cells_in(block.engine.state().A, whole.state().A, block.layout.owned(3)));
  EXPECT_TRUE(same_cells_in(block.engine.state().B, whole.state().B, block.layout.owned(3)));
}

// A stroke painted into a block (a split wall's screen): deposits land in its cells, and an
// orientation stroke leaves its theta0 alone (the extension fills a whole grid; the explicit
// schemes are isotropic) instead of writing past the block.
TEST(StageBlocks, PaintingABlockStaysInIt) {
  const SceneConfig scene = periodic_scene();
  LoneBlock block(scene, 0);
  SimState& s = block.engine.state();
  const FieldF theta0 = s.theta0;
  std::vector<StrokeSample> stroke;
  for (int k = 0; k <= 20; ++k) {  // from (10, 10) across the block's corner to (100, 80)
    StrokeSample p;
    p.time = 0.01 * k;
    p.x = float((10 + 4.5 * k) / scene.size.x);
    p.y = float(1 - (10 + 3.5 * k) / scene.size.y);  // y from the top
    p.pressure = 1;
    p.buttons = kButtonTip;
    p.in_range = true;
    stroke.push_back(p);
  }
  PaintConfig deposit;
  deposit.mode = PaintMode::kDeposit;
  Painter painter(scene.size, deposit);
  painter.apply(stroke, s);
  EXPECT_LT(s.A(10, 10), 0.9f);  // blended towards deposit_a (0.5) from the background (1)
  PaintConfig orient;
  orient.mode = PaintMode::kOrient;
  Painter orienter(scene.size, orient);
  orienter.apply(stroke, s);
  EXPECT_FALSE(orienter.update_theta0(s));
  EXPECT_TRUE(same_cells(s.theta0, theta0));
}

TEST(StageBlocks, ScenesThatRunWholeSayWhy) {
  const BlockSupport implicit = block_support(builtin_scenes().find("space-cookie-5")->make());
  EXPECT_NE(implicit.problem.find("rd.scheme"), std::string::npos) << implicit.problem;
  const BlockSupport fluid = block_support(builtin_scenes().find("cavity-gray-scott")->make());
  EXPECT_NE(fluid.problem.find("fluid.scene"), std::string::npos) << fluid.problem;
  EXPECT_EQ(block_support(builtin_scenes().find("table1-ard")->make()).problem, "");
  EXPECT_EQ(block_support(builtin_scenes().find("seed001")->make()).problem, "");

  // The Engine refuses a block of such a scene with the same line.
  SceneConfig scene = builtin_scenes().find("space-cookie-5")->make();
  scene.size = {64, 64};
  const BlockLayout layout = BlockLayout::split(scene.size, {2, 1});
  LocalBlockGroup group(layout, 1);
  EngineOptions o;
  o.plan.block = layout.block(0);
  o.plan.halo = &group.channel(0);
  try {
    Engine e(scene, o);
    ADD_FAILURE() << "a block of an implicit scheme was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("blocks: rd.scheme"), std::string::npos) << e.what();
  }
}

// A split wall switching presets keeps its layout and channel: a scene whose grid wraps
// otherwise is refused with one line; a walled scene on a channel wider than it needs gives its
// fields the channel's halo.
TEST(StageBlocks, BlocksCutForAnotherScenesGrid) {
  const BlockLayout periodic = BlockLayout::split({127, 93}, {2, 1}, true, true);
  LocalBlockGroup wide(periodic, kExplicitBlockSteps);
  EngineOptions o;
  o.plan.block = periodic.block(0);
  o.plan.halo = &wide.channel(0);
  try {
    Engine e(dirichlet_scene(), o);
    ADD_FAILURE() << "a walled scene ran on blocks of a grid that wraps";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("blocks: rd.boundary"), std::string::npos) << e.what();
  }
  const BlockLayout walled = BlockLayout::split({127, 93}, {2, 1});
  LocalBlockGroup narrow(walled, 1);
  o.plan.block = walled.block(0);
  o.plan.halo = &narrow.channel(0);
  EXPECT_THROW(Engine(periodic_scene(), o), std::invalid_argument);
  LocalBlockGroup walled_wide(walled, kExplicitBlockSteps);
  o.plan.halo = &walled_wide.channel(0);
  Engine e(dirichlet_scene(), o);  // constructing steps nothing
  EXPECT_GE(e.state().A.halo(), kExplicitBlockSteps);
  EXPECT_GE(e.state().B.halo(), kExplicitBlockSteps);
}

}  // namespace
}  // namespace ardcell
