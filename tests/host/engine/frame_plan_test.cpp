#include "host/engine/frame_plan.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "runtime/block_layout.h"
#include "runtime/dma.h"
#include "runtime/local_store.h"
#include "runtime/thread/thread_backend.h"
#include "tests/support/field_compare.h"
#include "tests/support/in_flight_channel.h"

namespace ardcell {
namespace {

struct SweepParams {
  float a, c;
};

// Stam's Jacobi sweep, written here so the test depends only on the runtime.
void test_sweep(const void* params, View<const float> x, View<const float> rhs, View<float> out,
                Box2 region) {
  const auto& p = *static_cast<const SweepParams*>(params);
  for (int y = region.min.y; y < region.max.y; ++y)
    for (int xx = region.min.x; xx < region.max.x; ++xx)
      out(xx, y) =
          (rhs(xx, y) + p.a * (x(xx - 1, y) + x(xx + 1, y) + x(xx, y - 1) + x(xx, y + 1))) / p.c;
}

// buffers[0] *= 1 + 0.5 sin-ish pattern, in place (per cell).
void test_scale(const void*, std::span<const View<float>> b, Box2 region) {
  for (int y = region.min.y; y < region.max.y; ++y)
    for (int x = region.min.x; x < region.max.x; ++x)
      b[0](x, y) = b[0](x, y) * (1.0f + 0.001f * float((x * 7 + y * 3) % 17));
}

// buffers[1] = central difference of buffers[0] (halo 1).
void test_gradient(const void*, std::span<const View<float>> b, Box2 region) {
  for (int y = region.min.y; y < region.max.y; ++y)
    for (int x = region.min.x; x < region.max.x; ++x)
      b[1](x, y) = 0.5f * (b[0](x + 1, y) - b[0](x - 1, y)) + b[0](x, y - 1) * 0.25f;
}

FieldF pattern(Int2 size, int seed) {
  FieldF f(size, 1);
  for (int y = -1; y <= size.y; ++y)
    for (int x = -1; x <= size.x; ++x)
      f(x, y) = float(((x + 3) * 37 + (y + 5) * 91 + seed * 13) % 101) / 101.0f;
  return f;
}

const SweepParams kParams{0.7f, 1.0f + 4 * 0.7f};

// A pass that scales a in place (halo 0, test_scale), refilling its boundary when asked.
PassDesc scale_pass(FieldF& a, bool refill) {
  PassDesc d;
  d.name = "scale";
  d.buffers = {{&a, &a, 0, false}};
  PassOpDesc scale;
  scale.map = test_scale;
  scale.writes = {0, -1, -1, -1};
  if (refill) {
    scale.fill_buffers = {0, -1, -1, -1};
    scale.fills[0] = BoundaryFill::stam(2);
  }
  d.ops.push_back(scale);
  return d;
}

// x_out = k Jacobi sweeps from x (initial guess) with rhs, in one pass of k sweeps.
void add_blocked_solve(FramePlan& plan, const FieldF& x, const FieldF& rhs, FieldF& out, int k) {
  PassDesc d;
  d.name = "solve";
  d.buffers = {{&x, k % 2 == 0 ? &out : nullptr, k, false},
               {nullptr, k % 2 == 1 ? &out : nullptr, k, false},
               {&rhs, nullptr, k - 1, false}};
  PassOpDesc op;
  op.kind = PassOpDesc::Kind::kJacobi;
  op.params = &kParams;
  op.sweep = test_sweep;
  op.a = 0;
  op.b = 1;
  op.rhs = 2;
  op.sweeps = k;
  op.fill = BoundaryFill::stam(1);
  d.ops.push_back(op);
  plan.add_pass(d);
}

FramePlanOptions small_tiles(Int2 grid, int workers) {
  FramePlanOptions o;
  o.grid = grid;
  o.workers = workers;
  o.local_store_bytes = 512 * 1024;
  o.max_tile_width = 32;  // tiles 32 wide and 11 tall: none divides 127 x 93
  o.max_tile_height = 11;
  return o;
}

TEST(FramePlan, TemporalBlockingWithKSweepsEqualsKGlobalSweepsBitwise) {
  const Int2 grid{127, 93};
  const FieldF x = pattern(grid, 1), rhs = pattern(grid, 2);
  ThreadBackend threads({2, 512 * 1024, false});
  SerialBackend serial;
  for (int k = 1; k <= 20; ++k) {
    // Reference: k global sweeps as k one-sweep serial passes through two fields.
    FieldF ping = x, pong(grid, 1), ref(grid, 1);
    {
      FramePlan one(small_tiles(grid, 1));
      for (int s = 0; s < k; ++s)
        add_blocked_solve(one, s % 2 == 0 ? ping : pong, rhs, s % 2 == 0 ? pong : ping, 1);
      one.run(serial);
      ref = k % 2 == 1 ? pong : ping;
    }
    FieldF out(grid, 1);
    FramePlan blocked(small_tiles(grid, 2));
    add_blocked_solve(blocked, x, rhs, out, k);
    ASSERT_GT(blocked.tiles(0).tiles().size(), 20u);
    blocked.run(threads);
    ASSERT_TRUE(same_cells(out, ref)) << "k = " << k;
  }
}

// The halo exchange overlaps its pass: between the exchange's begin and finish the back end
// is handed only tiles whose reads stay inside the block, and the blocks of a 2x1 layout, each
// on its own thread, still give the whole grid's bits. The channel fills the halos in finish,
// as a message would arrive, while the worker beside the host thread computes those tiles
// (tests/support/in_flight_channel.h).
class OverlapCheckingBackend final : public Backend {
 public:
  OverlapCheckingBackend(Backend& inner, const InFlightChannel& channel, Int2 grid, Box2 block)
      : inner_(inner), channel_(channel), grid_(grid), block_(block) {}
  const char* name() const override { return "overlap-checking"; }
  int workers() const override { return inner_.workers(); }
  void dispatch(const Pass& pass, std::span<const Tile> tiles) override {
    for (const Tile& t : tiles) {
      if (!channel_.in_flight) {
        ++after;
        continue;
      }
      ++during;
      // Cells of the domain outside the block are the neighbour's (no periodic edges here).
      if (!block_.contains(t.core.grown(pass.halo).intersected(box_of_size(grid_))))
        ++reading_halo_during;
    }
    inner_.dispatch(pass, tiles);
  }
  void sync() override { inner_.sync(); }
  void help(HostProgress progress) override { inner_.help(progress); }
  int during = 0, after = 0, reading_halo_during = 0;

 private:
  Backend& inner_;
  const InFlightChannel& channel_;
  Int2 grid_;
  Box2 block_;
};

TEST(FramePlan, InnerTilesComputeWhileTheHalosAreInFlight) {
  const Int2 grid{127, 93};
  constexpr int kSweeps = 4;
  const FieldF x = pattern(grid, 1), rhs = pattern(grid, 2);
  FieldF whole(grid, 1);
  {
    FramePlan plan(small_tiles(grid, 1));
    add_blocked_solve(plan, x, rhs, whole, kSweeps);
    SerialBackend serial;
    plan.run(serial);
  }
  // 1 worker: the host thread computes every inner tile, moving the exchange after each
  // (Backend::help); 2: a second worker beside it, the halos filled while it computes.
  for (int workers : {1, 2}) {
    const BlockLayout layout = BlockLayout::split(grid, {2, 1});
    LocalBlockGroup group(layout, kSweeps);
    std::vector<std::thread> threads;
    std::vector<int> during(2), after(2), reading_halo(2), polls(2);
    std::vector<FieldF> out(2);
    for (int b = 0; b < 2; ++b)
      threads.emplace_back([&, b] {
        const Box2 block = layout.block(b);
        // The block's fields: its own cells and the domain's ring from the whole grid's.
        FieldF bx = FieldF::over(block, kSweeps), brhs = FieldF::over(block, kSweeps);
        const Box2 owned = layout.owned(b);
        for (int y = owned.min.y; y < owned.max.y; ++y)
          for (int i = owned.min.x; i < owned.max.x; ++i) {
            bx(i, y) = x(i, y);
            brhs(i, y) = rhs(i, y);
          }
        out[std::size_t(b)] = FieldF::over(block, kSweeps);
        InFlightChannel channel(group.channel(b));
        FramePlanOptions o = small_tiles(grid, workers);
        o.block = block;
        o.halo = &channel;
        o.field_halo = kSweeps;
        FramePlan plan(o);
        add_blocked_solve(plan, bx, brhs, out[std::size_t(b)], kSweeps);
        ThreadBackend threads_backend({workers, 512 * 1024, false});
        OverlapCheckingBackend checking(threads_backend, channel, grid, block);
        plan.run(checking);
        during[std::size_t(b)] = checking.during;
        after[std::size_t(b)] = checking.after;
        reading_halo[std::size_t(b)] = checking.reading_halo_during;
        polls[std::size_t(b)] = channel.polls;
      });
    for (std::thread& t : threads) t.join();
    for (int b = 0; b < 2; ++b) {
      const std::size_t k = std::size_t(b);
      const std::string what = std::to_string(workers) + " workers, block " + std::to_string(b);
      EXPECT_GT(during[k], 0) << what << ": no tile overlapped the exchange";
      EXPECT_GT(after[k], 0) << what << ": no tile waited for the halos";
      EXPECT_EQ(reading_halo[k], 0) << what;
      if (workers == 1) {
        EXPECT_EQ(polls[k], during[k]) << what;
      }
      const Box2 owned = layout.owned(b);
      for (int y = owned.min.y; y < owned.max.y; ++y)
        for (int i = owned.min.x; i < owned.max.x; ++i)
          ASSERT_EQ(std::memcmp(&out[k](i, y), &whole(i, y), sizeof(float)), 0)
              << what << " cell (" << i << ", " << y << ")";
    }
  }
}

TEST(FramePlan, FusedMapOpsMatchSerialForAnyWorkerCount) {
  const Int2 grid{127, 93};
  const FieldF src = pattern(grid, 3);
  auto build = [&](FramePlan& plan, FieldF& a, FieldF& g) {
    // Pass 1: scale a in place (halo 0), refill its boundary.
    plan.add_pass(scale_pass(a, true));
    // Pass 2: g = gradient(a) (reads halo 1), boundary of g refilled.
    PassDesc p2;
    p2.name = "gradient";
    p2.buffers = {{&a, nullptr, 1, false}, {nullptr, &g, 0, false}};
    PassOpDesc grad;
    grad.map = test_gradient;
    grad.writes = {1, -1, -1, -1};
    grad.fill_buffers = {1, -1, -1, -1};
    grad.fills[0] = BoundaryFill::stam(0);
    p2.ops.push_back(grad);
    plan.add_pass(p2);
  };
  FieldF ref_a = src, ref_g(grid, 1);
  {
    FramePlan plan(small_tiles(grid, 1));
    build(plan, ref_a, ref_g);
    SerialBackend serial;
    for (int f = 0; f < 3; ++f) plan.run(serial);
  }
  for (int workers : {1, 2, 4}) {
    FieldF a = src, g(grid, 1);
    FramePlan plan(small_tiles(grid, workers));
    build(plan, a, g);
    ThreadBackend threads({workers, 512 * 1024, false});
    for (int f = 0; f < 3; ++f) plan.run(threads);
    EXPECT_TRUE(same_cells(a, ref_a)) << workers;
    EXPECT_TRUE(same_cells(g, ref_g)) << workers;
    EXPECT_EQ(plan.runs(), 3);
    EXPECT_GT(plan.pass_seconds(1), 0.0);
  }
}

// Stages run in frame order between passes, after the passes before them have finished (a
// stage reads what they wrote); run(with_rd = false) leaves the rd stages out; every step is
// timed; the stats name each step.
TEST(FramePlan, StagesRunInOrderBetweenPassesAndRdStagesCanBeLeftOut) {
  const Int2 grid{127, 93};
  FieldF a = pattern(grid, 5);
  const FieldF start = a;
  FramePlan plan(small_tiles(grid, 2));
  std::vector<std::string> log;
  log.reserve(64);
  float seen = 0;
  plan.add_stage({"double", [&] {
                    log.push_back("double");
                    for (int y = 0; y < grid.y; ++y)
                      for (int x = 0; x < grid.x; ++x) a(x, y) *= 2.0f;
                  }});
  PassDesc d = scale_pass(a, false);
  d.barrier_after = false;  // the stage after it still sees its result
  plan.add_pass(d);
  plan.add_stage({"read", [&] {
                    log.push_back("read");
                    seen = a(120, 90);
                  }});
  plan.add_stage({"rd", [&] { log.push_back("rd"); }, true});
  ASSERT_EQ(plan.pass_count(), 4);
  EXPECT_TRUE(plan.is_stage(0));
  EXPECT_FALSE(plan.is_stage(1));
  EXPECT_EQ(plan.pass_name(3), "rd");

  ThreadBackend threads({2, 512 * 1024, false});
  plan.run(threads);
  EXPECT_EQ(log, (std::vector<std::string>{"double", "read", "rd"}));
  const float expected = start(120, 90) * 2.0f * (1.0f + 0.001f * float((120 * 7 + 90 * 3) % 17));
  EXPECT_EQ(seen, expected);
  EXPECT_EQ(a(120, 90), expected);
  plan.run(threads, false);
  EXPECT_EQ(log, (std::vector<std::string>{"double", "read", "rd", "double", "read"}));
  EXPECT_EQ(plan.runs(), 2);
  EXPECT_GT(plan.pass_seconds(0), 0.0);
  EXPECT_GT(plan.pass_seconds(1), 0.0);

  char text[2048] = {};
  std::FILE* out = fmemopen(text, sizeof text - 1, "w");
  ASSERT_NE(out, nullptr);
  plan.print_stats(out);
  std::fclose(out);
  EXPECT_NE(std::strstr(text, "double"), nullptr);
  EXPECT_NE(std::strstr(text, "scale"), nullptr);
  EXPECT_NE(std::strstr(text, "rd "), nullptr);
}

TEST(FramePlanDeathTest, JacobiBuffersWithTooSmallAHaloAreRefused) {
  const Int2 grid{64, 64};
  FieldF x(grid, 1), rhs(grid, 1), out(grid, 1);
  FramePlan plan(small_tiles(grid, 1));
  PassDesc d;
  d.name = "bad";
  d.buffers = {{&x, &out, 1, false}, {nullptr, nullptr, 1, false}, {&rhs, nullptr, 0, false}};
  PassOpDesc op;
  op.kind = PassOpDesc::Kind::kJacobi;
  op.sweep = test_sweep;
  op.params = &kParams;
  op.a = 0;
  op.b = 1;
  op.rhs = 2;
  op.sweeps = 2;
  d.ops.push_back(op);
  EXPECT_EXIT(plan.add_pass(d), testing::ExitedWithCode(2),
              "pass 'bad': Jacobi buffers need halo >= sweeps");
}

}  // namespace
}  // namespace ardcell

namespace ardcell {
namespace {

// A put into a field above Dma::kStreamingPutFieldBytes goes out with non-temporal stores: the
// box lands exactly, its neighbours stay untouched, on the edge tile (a box ending at the row's
// end) as on an inner one.
TEST(DmaStreamingPut, LargeFieldPutsExactly) {
  const Int2 n{1100, 1000};
  FieldF field(n, 1);
  ASSERT_GE(field.raw_size() * sizeof(float), Dma::kStreamingPutFieldBytes);
  field.fill(-1.0f);
  LocalStore store(256 * 1024);
  Dma dma;
  for (const Box2 box : {Box2{{31, 10}, {31 + 96, 40}}, Box2{{1055, 500}, {1101, 530}}}) {
    SlotArena arena(store, 0);
    View<float> local = dma.local_box(field, box, arena);
    for (int y = box.min.y; y < box.max.y; ++y)
      for (int x = box.min.x; x < box.max.x; ++x) local(x, y) = float(x * 3 + y * 7);
    dma.put_box(local, field, box, 0);
    dma.wait(0);
    for (int y = box.min.y - 1; y <= box.max.y; ++y)
      for (int x = box.min.x - 1; x <= box.max.x && x <= n.x; ++x)
        ASSERT_EQ(field(x, y), box.contains(Int2{x, y}) ? float(x * 3 + y * 7) : -1.0f)
            << x << "," << y;
  }
}

}  // namespace
}  // namespace ardcell
