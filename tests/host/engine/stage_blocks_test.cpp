// Blocks of a scene built of stages: the explicit RD schemes' grid cut into blocks
// (runtime/block_layout.h), each block an Engine whose Device computes its cells and exchanges a
// halo (Device::exchange_halos: one cell before each step with walls; on a periodic grid
// kExplicitBlockSteps cells every that many steps, each step also stepping the halo cells the
// next reads), gives the fields one Engine gives over the whole grid, bit for bit: periodic (seed
// 001, whose whole-grid run takes the temporally blocked kernel; a pattern that crosses the
// periodic edges), Dirichlet and Neumann walls, on even and uneven layouts of a grid no block
// divides, on the serial and threads back ends.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "host/engine/device.h"
#include "host/engine/engine.h"
#include "host/engine/rd_step.h"
#include "host/paint/paint.h"
#include "host/scenes/preset.h"
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
                               const SimState& whole, const std::string& what,
                               const std::function<void(SimState&)>& paint = {},
                               int frames = kFrames) {
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
    if (paint) paint(blocks.back()->state());
  }
  std::vector<std::thread> threads;
  for (auto& e : blocks)
    threads.emplace_back([&e, frames] {
      for (int i = 0; i < frames; ++i) e->step();
    });
  for (std::thread& t : threads) t.join();
  const std::string where = what + " " + std::to_string(parts.x) + "x" + std::to_string(parts.y);
  for (int b = 0; b < layout.count(); ++b) {
    const SimState& s = blocks[std::size_t(b)]->state();
    EXPECT_EQ(s.step, frames) << where;
    // Every field the state saves (u, v, p, dye, A, B, theta0), over the cells the block owns:
    // its box, and the domain's ghost ring along its walls.
    int fields = 0;
    whole.for_each_field([&](std::string_view name, const FieldF& w) {
      const FieldF* f = const_cast<SimState&>(s).field(name);
      ASSERT_TRUE(f && !f->empty()) << where << " block " << b << ": no " << name;
      EXPECT_EQ(f->interior(), layout.block(b)) << where << " block " << b << ": " << name;
      EXPECT_TRUE(same_cells_in(*f, w, layout.owned(b))) << where << " block " << b << ": " << name;
      ++fields;
    });
    EXPECT_GE(fields, 2) << where;
  }
}

constexpr Int2 kEveryLayout[] = {{1, 1}, {2, 1}, {1, 2}, {2, 2}, {3, 1}};

void check_scene(const SceneConfig& scene, const std::string& what,
                 std::span<const Int2> layouts = kEveryLayout) {
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
  for (Int2 parts : layouts)
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

SceneConfig builtin_at(const char* name, Int2 size) {
  SceneConfig scene = builtin_scenes().find(name)->make();
  scene.size = size;
  return scene;
}

// Seed 000's implicit scheme: per-cell reactions, the conductivity from A's gradient across the
// blocks' edges, and the diffusion solved on the gathered grid (ICCG's triangular solves).
TEST(StageBlocks, ImplicitAnisotropicDirichletEqualsOneEngineBitwise) {
  const SceneConfig scene = builtin_at("space-cookie-5", {127, 93});
  ASSERT_NE(scene.rd.anisotropy.kind, AnisotropyKind::kIsotropic);
  ASSERT_EQ(scene.rd.boundary, BoundaryKind::kDirichlet);
  check_scene(scene, "space-cookie-5");
}

TEST(StageBlocks, ImplicitPeriodicEqualsOneEngineBitwise) {
  const SceneConfig scene = builtin_at("turing-spots", {127, 93});
  ASSERT_EQ(scene.rd.boundary, BoundaryKind::kPeriodic);
  ASSERT_EQ(block_support(scene).halo, 1);
  check_scene(scene, "turing-spots");
  // Anisotropic: A's gradient across the periodic edges comes from the exchange.
  SceneConfig lobes = builtin_at("space-cookie-5", {127, 93});
  lobes.rd.boundary = BoundaryKind::kPeriodic;
  check_scene(lobes, "space-cookie-5, periodic");
}

// A pen stroke of steps + 1 samples from cell `from`, `step` cells apart (y up), tip down.
std::vector<StrokeSample> straight_stroke(Int2 grid, std::array<double, 2> from,
                                          std::array<double, 2> step, int steps) {
  std::vector<StrokeSample> stroke;
  for (int k = 0; k <= steps; ++k) {
    StrokeSample p;
    p.time = 0.01 * k;
    p.x = float((from[0] + step[0] * k) / grid.x);
    p.y = float(1 - (from[1] + step[1] * k) / grid.y);
    p.pressure = 1;
    p.buttons = kButtonTip;
    p.in_range = true;
    stroke.push_back(p);
  }
  return stroke;
}

// Strokes painted into every block (a stroke reaches every rank): orientation sources and
// obstacles are recorded over the whole grid, so each block's theta0 and the mask its gathered
// solves cut out are the whole grid's.
TEST(StageBlocks, OrientationAndObstacleStrokesOnBlocksEqualOneEngine) {
  const SceneConfig scene = builtin_at("space-cookie-5", {127, 93});
  // Across the middle of the grid, through every 2x2 block.
  std::vector<StrokeSample> stroke = straight_stroke(scene.size, {20, 15}, {4, 3}, 20);
  const auto paint = [&](SimState& s) {
    PaintConfig orient;
    orient.mode = PaintMode::kOrient;
    Painter orienter(scene.size, orient);
    orienter.apply(stroke, s);
    orienter.update_theta0(s);
    PaintConfig obstacle;
    obstacle.mode = PaintMode::kObstacle;
    obstacle.radius = 2;
    Painter wall(scene.size, obstacle);
    for (StrokeSample& p : stroke) p.x += 0.05f;  // beside the orientation stroke
    wall.apply(stroke, s);
    for (StrokeSample& p : stroke) p.x -= 0.05f;
  };
  Engine whole(scene, options(EngineOptions::Backend::kSerial, 1));
  paint(whole.state());
  ASSERT_FALSE(whole.state().obstacle.empty());
  Engine plain(scene, options(EngineOptions::Backend::kSerial, 1));
  for (int i = 0; i < kFrames; ++i) {
    whole.step();
    plain.step();
  }
  EXPECT_FALSE(same_cells(whole.state().A, plain.state().A)) << "the strokes changed nothing";
  for (Int2 parts : {Int2{2, 1}, Int2{2, 2}})
    expect_blocks_equal_whole(scene, parts, options(EngineOptions::Backend::kSerial, 1),
                              whole.state(), "space-cookie-5 painted", paint);
}

// A fluid scene's blocks gather the fluid (host/engine/fluid_step.h) and the RD's back-trace:
// strokes that push the velocity and deposit dye and chemicals into the blocks, MacCormack's
// limited correction of A and B on the gathered grid, a periodic fluid, and two workers a block.
TEST(StageBlocks, FluidScenesPaintedAndVariedEqualOneEngineBitwise) {
  SceneConfig scene = builtin_at("cavity-gray-scott", {61, 47});
  // Across the cuts of every layout below.
  const std::vector<StrokeSample> stroke = straight_stroke(scene.size, {10, 8}, {2.5, 2}, 16);
  const auto paint = [&](SimState& s) {
    for (PaintMode mode : {PaintMode::kPush, PaintMode::kDeposit}) {
      PaintConfig c;
      c.mode = mode;
      c.radius = 3;
      Painter painter(scene.size, c);
      painter.apply(stroke, s);
    }
  };
  Engine whole(scene, options(EngineOptions::Backend::kSerial, 1));
  paint(whole.state());
  Engine plain(scene, options(EngineOptions::Backend::kSerial, 1));
  for (int i = 0; i < kFrames; ++i) {
    whole.step();
    plain.step();
  }
  EXPECT_FALSE(same_cells(whole.state().u, plain.state().u)) << "the push changed nothing";
  EXPECT_FALSE(same_cells(whole.state().dye, plain.state().dye)) << "the dye changed nothing";
  for (Int2 parts : {Int2{2, 1}, Int2{2, 2}})
    expect_blocks_equal_whole(scene, parts, options(EngineOptions::Backend::kSerial, 1),
                              whole.state(), "cavity-gray-scott painted", paint);

  SceneConfig maccormack = scene;  // A and B corrected by MacCormack on the gathered grid
  maccormack.fluid.advection = AdvectionScheme::kMacCormack;
  SceneConfig periodic = builtin_at("ink", {61, 47});  // the fluid wraps; the layout does not
  periodic.fluid.walls = FluidWalls::kPeriodic;
  for (const auto& [variant, what] : {std::pair{maccormack, "cavity-gray-scott maccormack"},
                                      std::pair{periodic, "ink periodic"}}) {
    Engine one(variant, options(EngineOptions::Backend::kSerial, 1));
    for (int i = 0; i < kFrames; ++i) one.step();
    expect_blocks_equal_whole(variant, {3, 1}, options(EngineOptions::Backend::kSerial, 1),
                              one.state(), what);
    expect_blocks_equal_whole(variant, {2, 2}, options(EngineOptions::Backend::kThreads, 2),
                              one.state(), std::string(what) + ", threads (2 workers a block)");
  }
}

TEST(StageBlocks, SecondOrderSchemesAndEverySolverEqualOneEngineBitwise) {
  SceneConfig sbdf = builtin_at("space-cookie-5", {127, 93});
  sbdf.rd.scheme = RdScheme::kSbdf2;
  sbdf.rd.diffusion_solver.kind = SolverKind::kRedBlackGaussSeidel;
  check_scene(sbdf, "space-cookie-5, sbdf2, rbgs");
  SceneConfig cn = builtin_at("turing-spots", {127, 93});
  cn.rd.scheme = RdScheme::kCrankNicolsonAm2;
  cn.rd.diffusion_solver.kind = SolverKind::kMultigrid;
  check_scene(cn, "turing-spots, crank-nicolson-am2, mg");
  SceneConfig jacobi = builtin_at("turing-spots", {127, 93});
  jacobi.rd.diffusion_solver.kind = SolverKind::kJacobi;
  jacobi.rd.diffusion_solver.tolerance = 0;
  check_scene(jacobi, "turing-spots, jacobi");
}

// The real-time settings (`--realtime-solvers`: Jacobi sweeps, the reaction's table) let a block's
// implicit diffusion sweep its own cells, exchanging the iterate between sweeps: a scene without a
// fluid then computes only its blocks (no gather), with one engine's bits. The second-order
// schemes and a Dirichlet value ride the same sweeps; with a fluid (which still runs on the
// gathered grid) and with an obstacle (whose solid cells keep the diffusion on the gathered grid)
// the bits hold too.
TEST(StageBlocks, RealtimeSolversSweepTheirBlocksBitwise) {
  constexpr Int2 kLayouts[] = {{1, 2}, {3, 1}, {2, 2}};
  const auto realtime = [](const char* name) {
    Preset preset = preset_from_scene(builtin_at(name, {47, 41}));
    use_realtime_solvers(preset);
    return preset.scene;
  };
  for (const char* name : {"space-cookie-5", "turing-spots", "meinhardt-spots", "fig3-orient"}) {
    const SceneConfig scene = realtime(name);
    ASSERT_EQ(scene.rd.diffusion_solver.kind, SolverKind::kJacobi) << name;
    EXPECT_TRUE(rd_block_sweeps(scene)) << name;
    EXPECT_FALSE(block_support(scene).gathers) << name;
    check_scene(scene, std::string(name) + ", real-time solvers", kLayouts);
  }
  SceneConfig cn = realtime("turing-spots");
  cn.rd.scheme = RdScheme::kCrankNicolsonAm2;
  check_scene(cn, "turing-spots, crank-nicolson-am2, jacobi", kLayouts);
  SceneConfig sbdf = realtime("space-cookie-5");
  sbdf.rd.scheme = RdScheme::kSbdf2;
  sbdf.rd.boundary_a = 0.25f;
  check_scene(sbdf, "space-cookie-5, sbdf2, jacobi, a Dirichlet value", kLayouts);
  // Red-black Gauss-Seidel sweeps the blocks too, unless the grid wraps an odd number of cells
  // (then it solves on the gathered grid): the same bits either way.
  SceneConfig rbgs = builtin_at("turing-spots", {48, 40});
  rbgs.rd.diffusion_solver = {SolverKind::kRedBlackGaussSeidel, 10, 0.0};
  EXPECT_TRUE(rd_block_sweeps(rbgs));
  check_scene(rbgs, "turing-spots, rbgs, 48 x 40", kLayouts);
  rbgs.size = {47, 41};
  EXPECT_FALSE(rd_block_sweeps(rbgs));
  check_scene(rbgs, "turing-spots, rbgs, 47 x 41", kLayouts);
  const SceneConfig fluid = realtime("cavity-gray-scott");
  EXPECT_TRUE(rd_block_sweeps(fluid));
  check_scene(fluid, "cavity-gray-scott, real-time solvers", kLayouts);
  const SceneConfig obstacle = realtime("obstacle-ard-gray-scott");
  EXPECT_FALSE(rd_block_sweeps(obstacle));
  check_scene(obstacle, "obstacle-ard-gray-scott, real-time solvers", kLayouts);
}

// The schemes whose kernels read the whole grid (seed 003's generalized operators, which wrap
// their indices; their FFT and BiCGSTAB solves; ETDRK4's FFT) run on the gathered grid.
TEST(StageBlocks, GatheredSchemesEqualOneEngineBitwise) {
  // Every block computes the whole grid: a smaller one, and the layouts along each axis.
  const Int2 size{63, 45};
  constexpr Int2 kLayouts[] = {{2, 1}, {1, 2}};
  check_scene(builtin_at("pearson", size), "pearson (etdrk4)", kLayouts);
  check_scene(builtin_at("mcgraw-gray-scott-map", size), "mcgraw-gray-scott-map (FFT, F/k map)",
              kLayouts);
  check_scene(builtin_at("mcgraw-turing-radial", size),
              "mcgraw-turing-radial (tensor field, BiCGSTAB)", kLayouts);
  SceneConfig vortex = builtin_at("mcgraw-turing-vortex", size);
  ASSERT_EQ(vortex.rd.scheme, RdScheme::kExplicit);
  vortex.rd.steps_per_frame = 10;  // of 100: each a gather on every block
  check_scene(vortex, "mcgraw-turing-vortex (explicit tensor field)", kLayouts);
  vortex.rd.generalized.field = TensorFieldKind::kUniform;
  check_scene(vortex, "explicit generalized steps", kLayouts);
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
// ops that compute a block's cells from its cells and halo, and those that run on the gathered
// grid; the whole grid's device runs all.
TEST(StageBlocks, ABlocksDeviceSaysWhichOpsItRuns) {
  LoneBlock block(periodic_scene(), 0);
  const Device& on_block = block.engine.device();
  ASSERT_TRUE(on_block.on_block());
  for (DeviceOp op :
       {DeviceOp::kExplicitRd, DeviceOp::kFillBoundary, DeviceOp::kCopy,
        DeviceOp::kReactionImplicit, DeviceOp::kAddSplat, DeviceOp::kImplicitDiffusion,
        DeviceOp::kGeneralizedRd, DeviceOp::kPeriodicSolve, DeviceOp::kEtdrk4,
        DeviceOp::kAdvectScalar, DeviceOp::kMacCormack})
    EXPECT_TRUE(on_block.supports(op)) << device_op_name(op);
  // The fluid's own ops run on its gathered grid's device (host/engine/fluid_step.h).
  for (DeviceOp op : {DeviceOp::kRange, DeviceOp::kSolve, DeviceOp::kGrayScott9Steps,
                      DeviceOp::kAdvectScalarMac, DeviceOp::kPressureRhs, DeviceOp::kRestoreMass})
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
// orientation stroke gives its theta0 the whole grid's theta0 on its cells (each block's painter
// extends the orientation over the whole grid) instead of writing past the block.
TEST(StageBlocks, PaintingABlockStaysInIt) {
  const SceneConfig scene = builtin_at("space-cookie-5", {127, 93});
  LoneBlock block(scene, 0);
  Engine whole(scene, options(EngineOptions::Backend::kSerial, 1));
  SimState& s = block.engine.state();
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
  orient.orient_deposits = false;
  Painter block_orienter(scene.size, orient), whole_orienter(scene.size, orient);
  const FieldF before = s.theta0;
  block_orienter.apply(stroke, s);
  whole_orienter.apply(stroke, whole.state());
  EXPECT_TRUE(block_orienter.update_theta0(s));
  EXPECT_TRUE(whole_orienter.update_theta0(whole.state()));
  EXPECT_EQ(s.theta0.interior(), block.layout.block(0));
  EXPECT_FALSE(same_cells(s.theta0, before));
  EXPECT_TRUE(same_cells_in(s.theta0, whole.state().theta0, block.layout.block(0)));
}

TEST(StageBlocks, EveryBuiltinSceneRunsAsBlocks) {
  for (const SceneEntry& e : builtin_scenes().entries()) {
    const SceneConfig scene = e.make();
    const BlockSupport support = block_support(scene);
    EXPECT_EQ(support.problem, "") << e.name;
    // A fluid's stages run on the gathered grid: every block computes the whole fluid.
    if (scene.fluid.kind != FluidSceneKind::kNone && scene.fluid.kind != FluidSceneKind::kTable1) {
      EXPECT_TRUE(support.gathers) << e.name;
    }
  }
  EXPECT_FALSE(block_support(builtin_scenes().find("seed001")->make()).gathers);
  // Chemicals that wrap while a fluid carries them: the gathered back-trace would read ghosts
  // that wrap on one process's grid only.
  SceneConfig wrapping = builtin_scenes().find("cavity-gray-scott")->make();
  wrapping.rd.boundary = BoundaryKind::kPeriodic;
  EXPECT_EQ(block_support(wrapping).problem.find("rd.boundary: "), 0u);
  wrapping.rd.advect = false;
  EXPECT_EQ(block_support(wrapping).problem, "");
}

// Every built-in scene of stages (all but the table1 scenes' tile passes, tested with their
// plan), as it ships but on an awkward grid: 2, 3 and 4 blocks (1x2, 3x1, 2x2: uneven splits)
// give one engine's fields after 30 frames, the fluid's included.
std::vector<std::string> stage_scene_names() {
  std::vector<std::string> names;
  for (const SceneEntry& e : builtin_scenes().entries())
    if (e.make().fluid.kind != FluidSceneKind::kTable1) names.push_back(e.name);
  return names;
}

class EveryScene : public testing::TestWithParam<std::string> {};

TEST_P(EveryScene, BlocksEqualOneEngineBitwise) {
  constexpr int kSceneFrames = 30;
  SceneConfig scene = builtin_at(GetParam().c_str(), {47, 41});
  // mcgraw-turing-vortex's 100 steps a frame each meet the other blocks (a gather): 10 suffice;
  // mcgraw-turing-radial's each solve BiCGSTAB on the gathered grid (GatheredSchemes runs more).
  scene.rd.steps_per_frame = std::min(scene.rd.steps_per_frame, 10);
  if (scene.rd.generalized.field != TensorFieldKind::kUniform &&
      scene.rd.scheme != RdScheme::kExplicit)
    scene.rd.steps_per_frame = std::min(scene.rd.steps_per_frame, 2);
  ASSERT_EQ(block_support(scene).problem, "");
  Engine whole(scene, options(EngineOptions::Backend::kSerial, 1));
  for (int i = 0; i < kSceneFrames; ++i) whole.step();
  for (Int2 parts : {Int2{1, 2}, Int2{3, 1}, Int2{2, 2}})
    expect_blocks_equal_whole(scene, parts, options(EngineOptions::Backend::kSerial, 1),
                              whole.state(), GetParam(), {}, kSceneFrames);
}

INSTANTIATE_TEST_SUITE_P(Builtin, EveryScene, testing::ValuesIn(stage_scene_names()),
                         [](const testing::TestParamInfo<std::string>& info) {
                           std::string name = info.param;
                           for (char& c : name)
                             if (c == '-') c = '_';
                           return name;
                         });

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
