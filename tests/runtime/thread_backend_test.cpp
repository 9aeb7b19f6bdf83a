#include "runtime/thread/thread_backend.h"

#include <gtest/gtest.h>

#include <cstring>

#include "runtime/tile_plan.h"
#include "tests/support/field_compare.h"

namespace ardcell {
namespace {

// A test kernel with a halo of 1: out = in + 0.25 * (sum of 4 neighbours) * in, the kind of
// expression whose float rounding would differ if any cell read a different neighbour.
void blur(View<const float> in, View<float> out, Box2 region) {
  for (int y = region.min.y; y < region.max.y; ++y)
    for (int x = region.min.x; x < region.max.x; ++x)
      out(x, y) =
          in(x, y) + 0.25f * (in(x - 1, y) + in(x + 1, y) + in(x, y - 1) + in(x, y + 1)) * in(x, y);
}

struct BlurProgram {
  const FieldF* in;
  FieldF* out;
  const TilePlan* plan;
};

Pass blur_pass(const BlurProgram& p) {
  Pass pass;
  pass.name = "blur";
  pass.halo = 1;
  pass.program = &p;
  pass.run_whole = [](const void* self) {
    const auto& b = *static_cast<const BlurProgram*>(self);
    blur(b.in->view(), b.out->view(), b.in->interior());
  };
  pass.fetch = [](const void* self, const Tile& t, int slot, WorkerContext& ctx) {
    const auto& b = *static_cast<const BlurProgram*>(self);
    ctx.dma->wait(slot);  // this slot's previous puts have left the store
    SlotArena arena(*ctx.store, slot);
    ctx.dma->get_box(*b.in, b.plan->load_box(t, 1), arena, slot);
  };
  pass.compute = [](const void* self, const Tile& t, int slot, WorkerContext& ctx) {
    const auto& b = *static_cast<const BlurProgram*>(self);
    SlotArena arena(*ctx.store, slot);
    View<float> in = ctx.dma->local_box(*b.in, b.plan->load_box(t, 1), arena);
    View<float> out = ctx.dma->local_box(*b.out, b.plan->written_box(t), arena);
    ctx.dma->wait(slot);
    blur(in, out, t.core);
    ctx.dma->put_box(out, *b.out, t.core.intersected(b.plan->written_box(t)), slot);
  };
  return pass;
}

// Cells of interior + halo equal bit for bit (row padding is not part of a field's value).
FieldF pattern(Int2 size) {
  FieldF f(size, 1);
  for (int y = -1; y <= size.y; ++y)
    for (int x = -1; x <= size.x; ++x) f(x, y) = float((x * 37 + y * 91) % 101) / 101.0f;
  return f;
}

// The core of a tile is line-exact only where the tile plan put it; for cores that do not
// start at x = 0 the plan cut them on lines, and core == written box away from the domain edge.
// Cores at the domain edge start at 0, which is not a line: the put then writes the written box.
Pass blur_pass_written(const BlurProgram& p) {
  Pass pass = blur_pass(p);
  pass.compute = [](const void* self, const Tile& t, int slot, WorkerContext& ctx) {
    const auto& b = *static_cast<const BlurProgram*>(self);
    SlotArena arena(*ctx.store, slot);
    View<float> in = ctx.dma->local_box(*b.in, b.plan->load_box(t, 1), arena);
    const Box2 w = b.plan->written_box(t);
    View<float> out = ctx.dma->local_box(*b.out, w, arena);
    ctx.dma->wait(slot);
    // Cells of the written box outside the core keep what the output field had: the halo
    // of `in` (an identity there) stands in for them in this test.
    for (int y = w.min.y; y < w.max.y; ++y)
      for (int x = w.min.x; x < w.max.x; ++x) out(x, y) = in(x, y);
    blur(in, out, t.core);
    ctx.dma->put_box(out, *b.out, w, slot);
  };
  pass.run_whole = [](const void* self) {
    const auto& b = *static_cast<const BlurProgram*>(self);
    copy_box<float>(b.in->view(), b.out->view(), b.in->with_halo());
    blur(b.in->view(), b.out->view(), b.in->interior());
  };
  return pass;
}

TEST(ThreadBackend, TiledPassEqualsSerialBitwiseForAnyWorkerCount) {
  const Int2 size{127, 93};
  const FieldF in = pattern(size);
  FieldF reference(size, 1);
  TilePlanRequest r;
  r.grid = size;
  r.halo = 1;
  r.fields_with_halo = 1;
  r.fields_core = 1;
  r.store_bytes = 16 * 1024;  // many small tiles
  const TilePlan plan = TilePlan::make(r);
  ASSERT_GT(plan.tiles().size(), 4u);
  {
    BlurProgram p{&in, &reference, &plan};
    SerialBackend serial;
    const Pass pass = blur_pass_written(p);
    serial.dispatch(pass, plan.tiles());
    serial.sync();
  }
  for (int workers : {1, 2, 4}) {
    FieldF out(size, 1);
    BlurProgram p{&in, &out, &plan};
    ThreadBackend backend({workers, 16 * 1024, true});
    EXPECT_EQ(backend.workers(), workers);
    const Pass pass = blur_pass_written(p);
    for (int rep = 0; rep < 3; ++rep) {
      backend.dispatch(pass, plan.tiles());
      backend.sync();
    }
    ASSERT_TRUE(same_cells(out, reference)) << workers << " workers";
    EXPECT_GT(backend.dma_bytes(), 0u);
  }
}

TEST(ThreadBackend, IndependentPassesMayBeQueuedBeforeOneSync) {
  const Int2 size{64, 64};
  const FieldF in = pattern(size);
  FieldF a(size, 1), b(size, 1);
  TilePlanRequest r;
  r.grid = size;
  r.store_bytes = 16 * 1024;
  const TilePlan plan = TilePlan::make(r);
  BlurProgram pa{&in, &a, &plan}, pb{&in, &b, &plan};
  const Pass passa = blur_pass_written(pa), passb = blur_pass_written(pb);
  ThreadBackend backend({2, 16 * 1024, false});
  backend.dispatch(passa, plan.tiles());
  backend.dispatch(passb, plan.tiles());
  backend.sync();
  EXPECT_TRUE(same_cells(a, b));
  EXPECT_NE(a(10, 10), 0.0f);
}

}  // namespace
}  // namespace ardcell
