#include "host/engine/frame_plan.h"

#include <algorithm>
#include <cstdlib>

#include "host/engine/device.h"
#include "runtime/check.h"
#include "runtime/dma.h"
#include "runtime/local_store.h"

namespace ardcell {
namespace {

[[noreturn]] void bad_pass(const std::string& name, const char* why) {
  std::fprintf(stderr, "ardcell: frame plan pass '%s': %s\n", name.c_str(), why);
  std::exit(2);
}

Box2 grow_clip(const Box2& core, int reach, Int2 grid) {
  return core.grown(reach).intersected(box_of_size(grid));
}

// A field and how many cells deep around the block its halo is (to be) current.
HaloField* find(std::vector<HaloField>& list, const FieldF* f) {
  for (HaloField& e : list)
    if (e.field == f) return &e;
  return nullptr;
}

}  // namespace

struct FramePlan::PassProgram {
  PassDesc desc;
  // A stage instead of a pass (desc holds its name only).
  std::function<void()> stage;
  bool rd = false;
  Int2 grid;
  int field_halo = 1;
  Tile block;  // the whole-field form's one tile: the plan's block
  TilePlan plan;
  // Fields whose halos the plan's exchange step fills before the pass (block plans), and how
  // deep; the pass's tiles reordered for it: first the `inner_tiles` that read no cell of those
  // halos (they run while the exchange is in flight), then the rest.
  std::vector<HaloField> exchange;
  std::vector<Tile> exchange_order;
  std::size_t inner_tiles = 0;
  Pass pass;
  int nbuf = 0;
  std::array<bool, kMaxBuffers> written{};
  // Serial reference: the whole field each buffer maps to, and the copies made at pass start.
  std::array<FieldF*, kMaxBuffers> whole{};
  std::array<const FieldF*, kMaxBuffers> copy_from{};
  std::vector<std::unique_ptr<FieldF>> scratch;
  // run(Device&): ops without a device twin that said so already.
  mutable std::array<bool, 16> said_cpu{};

  Box2 buffer_box(const Tile& t, int i) const {
    return plan.written_box(t)
        .grown(desc.buffers[std::size_t(i)].halo)
        .intersected(plan.readable());
  }

  // Lays the buffers out in `slot` (the same layout every time for a tile), fetching when asked.
  void layout(const Tile& t, int slot, WorkerContext& ctx, View<float>* views, bool fetch) const {
    SlotArena arena(*ctx.store, slot);
    for (int i = 0; i < nbuf; ++i) {
      const PassBufferDesc& b = desc.buffers[std::size_t(i)];
      if (b.gather) {
        views[i] = const_cast<FieldF*>(b.src)->view();
      } else if (fetch && b.src) {
        views[i] = ctx.dma->get_box(*b.src, buffer_box(t, i), arena, slot);
      } else {
        views[i] = ctx.dma->local_box(plan.block().min.x - field_halo, buffer_box(t, i), arena);
      }
    }
  }

  // On a tile, or on the whole block (tile = block: the whole-field form).
  void run_ops(std::span<const View<float>> views, const Tile& tile) const {
    for (const PassOpDesc& op : desc.ops) run_op(op, views, tile);
  }

  void run_op(const PassOpDesc& op, std::span<const View<float>> views, const Tile& tile) const {
    if (op.kind == PassOpDesc::Kind::kMap) {
      const Box2 region = grow_clip(tile.core, op.reach, grid);
      op.map(op.params, views, region);
      for (int j = 0; j < 4 && op.fill_buffers[std::size_t(j)] >= 0; ++j) {
        const View<float>& v = views[std::size_t(op.fill_buffers[std::size_t(j)])];
        fill_boundary(v.crop(region.grown(1).intersected(v.box())), grid, op.fills[std::size_t(j)]);
      }
    } else {
      int cur = op.a, other = op.b;
      for (int s = 1; s <= op.sweeps; ++s) {
        const Box2 region = plan.sweep_region(tile, op.sweeps + op.extra_reach, s);
        const View<float>& out = views[std::size_t(other)];
        op.sweep(op.params, views[std::size_t(cur)], views[std::size_t(op.rhs)], out, region);
        fill_boundary(out.crop(region.grown(1).intersected(out.box())), grid, op.fill);
        std::swap(cur, other);
      }
    }
  }

  static void run_whole(const void* self) {
    const auto& p = *static_cast<const PassProgram*>(self);
    std::array<View<float>, kMaxBuffers> views;
    for (int i = 0; i < p.nbuf; ++i) {
      if (p.copy_from[std::size_t(i)])
        copy_box<float>(p.copy_from[std::size_t(i)]->view(), p.whole[std::size_t(i)]->view(),
                        p.whole[std::size_t(i)]->with_halo());
      views[std::size_t(i)] = p.whole[std::size_t(i)]->view();
    }
    p.run_ops(std::span<const View<float>>(views.data(), std::size_t(p.nbuf)), p.block);
  }

  // The whole-field form on a Device: each op's twin, or the CPU op with the pass's fields
  // brought to the host and handed back.
  void run_on(Device& device) const {
    std::span<FieldF* const> fields(whole.data(), std::size_t(nbuf));
    for (int i = 0; i < nbuf; ++i)
      if (copy_from[std::size_t(i)])
        device.copy(*copy_from[std::size_t(i)], *whole[std::size_t(i)]);
    for (std::size_t o = 0; o < desc.ops.size(); ++o) {
      const PassOpDesc& op = desc.ops[o];
      const bool twin =
          op.kind == PassOpDesc::Kind::kMap ? op.device != nullptr : op.device_sweeps != nullptr;
      if (!twin) {
        if (o < said_cpu.size() && !said_cpu[o]) {
          said_cpu[o] = true;
          std::fprintf(stderr,
                       "ardcell: %s: frame plan pass '%s' op %zu runs on the CPU (no %s twin)\n",
                       device.name(), desc.name.c_str(), o, device.name());
        }
        for (FieldF* f : fields) device.sync_to_host(*f);
        std::array<View<float>, kMaxBuffers> views;
        for (int i = 0; i < nbuf; ++i) views[std::size_t(i)] = whole[std::size_t(i)]->view();
        run_op(op, std::span<const View<float>>(views.data(), std::size_t(nbuf)), block);
        for (FieldF* f : fields) device.host_wrote(*f);
        continue;
      }
      if (op.kind == PassOpDesc::Kind::kMap) {
        op.device(op.params, device, fields);
        for (int j = 0; j < 4 && op.fill_buffers[std::size_t(j)] >= 0; ++j)
          device.fill_boundary(*whole[std::size_t(op.fill_buffers[std::size_t(j)])],
                               op.fills[std::size_t(j)]);
      } else {
        op.device_sweeps(op.params, device, *whole[std::size_t(op.rhs)], *whole[std::size_t(op.a)],
                         *whole[std::size_t(op.b)], op.sweeps, op.fill);
      }
    }
  }

  static void fetch(const void* self, const Tile& t, int slot, WorkerContext& ctx) {
    const auto& p = *static_cast<const PassProgram*>(self);
    ctx.dma->wait(slot);  // the slot's previous puts have left the store
    std::array<View<float>, kMaxBuffers> views;
    p.layout(t, slot, ctx, views.data(), true);
  }

  static void compute(const void* self, const Tile& t, int slot, WorkerContext& ctx) {
    const auto& p = *static_cast<const PassProgram*>(self);
    std::array<View<float>, kMaxBuffers> views;
    p.layout(t, slot, ctx, views.data(), false);
    ctx.dma->wait(slot);
    p.run_ops(std::span<const View<float>>(views.data(), std::size_t(p.nbuf)), t);
    const Box2 written = p.plan.written_box(t);
    for (int i = 0; i < p.nbuf; ++i)
      if (FieldF* dst = p.desc.buffers[std::size_t(i)].dst)
        ctx.dma->put_box(views[std::size_t(i)], *dst, written, slot);
  }
};

FramePlan::FramePlan(const FramePlanOptions& options) : options_(options) {
  ARDCELL_CHECK(options.grid.x > 0 && options.grid.y > 0, "FramePlan needs a non-empty grid");
  if (options_.block.empty()) options_.block = box_of_size(options.grid);
  ARDCELL_CHECK(box_of_size(options.grid).contains(options_.block),
                "FramePlan: the block lies outside the grid");
  ARDCELL_CHECK(!options_.halo || options_.halo->width() <= options_.field_halo,
                "FramePlan: the halo exchange is wider than the fields' halo");
}

FramePlan::~FramePlan() = default;

int FramePlan::add_pass(PassDesc desc) {
  ARDCELL_CHECK(int(passes_.size()) < kMaxPasses, "FramePlan: too many passes");
  auto p = std::make_unique<PassProgram>();
  p->grid = options_.grid;
  p->field_halo = options_.field_halo;
  p->block = Tile{options_.block, 0};
  p->nbuf = int(desc.buffers.size());
  if (p->nbuf > kMaxBuffers) bad_pass(desc.name, "more than 16 buffers");
  const auto valid = [&](int i) { return i >= 0 && i < p->nbuf; };
  int max_sweeps = 1;
  for (const PassOpDesc& op : desc.ops) {
    if (op.kind == PassOpDesc::Kind::kMap) {
      if (!op.map) bad_pass(desc.name, "map op without a kernel");
      for (int j = 0; j < 4; ++j) {
        const int f = op.fill_buffers[std::size_t(j)];
        if (f >= 0 && !valid(f)) bad_pass(desc.name, "fill of a buffer that does not exist");
        if (f >= 0) p->written[std::size_t(f)] = true;
      }
    } else {
      if (!op.sweep || !valid(op.a) || !valid(op.b) || !valid(op.rhs) || op.sweeps < 1)
        bad_pass(desc.name, "Jacobi op needs a kernel, buffers a, b, rhs and sweeps >= 1");
      const auto& ba = desc.buffers[std::size_t(op.a)];
      const auto& bb = desc.buffers[std::size_t(op.b)];
      const auto& br = desc.buffers[std::size_t(op.rhs)];
      const int k = op.sweeps + op.extra_reach;
      if (ba.halo < k || bb.halo < k || br.halo < k - 1)
        bad_pass(desc.name, "Jacobi buffers need halo >= sweeps (rhs: sweeps - 1)");
      // One sweep only reads a: the whole-field form can then read its field in place.
      if (op.sweeps >= 2) p->written[std::size_t(op.a)] = true;
      p->written[std::size_t(op.b)] = true;
      max_sweeps = std::max(max_sweeps, op.sweeps);
    }
  }
  for (const PassOpDesc& op : desc.ops)
    if (op.kind == PassOpDesc::Kind::kMap)
      for (int8_t w : op.writes) {
        if (w >= 0 && !valid(w)) bad_pass(desc.name, "write to a buffer that does not exist");
        if (w >= 0) p->written[std::size_t(w)] = true;
      }
  // Serial mapping of buffers onto whole fields.
  int max_halo = 0;
  std::vector<int> halos;
  for (int i = 0; i < p->nbuf; ++i) {
    const PassBufferDesc& b = desc.buffers[std::size_t(i)];
    if (b.gather && (!b.src || b.dst)) bad_pass(desc.name, "a gather buffer is read-only");
    if (!b.gather) {
      halos.push_back(b.halo);
      max_halo = std::max(max_halo, b.halo);
    }
    for (const FieldF* f : {b.src, static_cast<const FieldF*>(b.dst)})
      if (f && (f->interior() != options_.block || f->halo() != options_.field_halo))
        bad_pass(desc.name, "buffer field box or halo differs from the plan's block");
    // A block's buffers reach past the block into its fields' halo (sweeps shrink there).
    if (options_.halo && b.halo > options_.field_halo)
      bad_pass(desc.name, "a buffer's halo is deeper than the block's fields hold");
    // Across a block edge a buffer's halo comes from the exchange (a gather reads all of it,
    // as far as the back-trace reaches).
    if (options_.halo && b.src && (b.gather || b.halo > 0)) {
      if (b.halo > options_.halo->width())
        bad_pass(desc.name, "a buffer's halo is wider than the plan's halo exchange");
      FieldF* src = const_cast<FieldF*>(b.src);
      const int depth = b.gather ? options_.halo->width() : b.halo;
      const HaloField* current = find(exchanged_, src);
      if (!current || current->depth < depth) {
        if (HaloField* e = find(p->exchange, src))
          e->depth = std::max(e->depth, depth);
        else
          p->exchange.push_back({src, depth});
      }
    }
    const bool written = p->written[std::size_t(i)] || b.dst;
    if (b.gather || (b.src && !written)) {
      p->whole[std::size_t(i)] = const_cast<FieldF*>(b.src);
    } else if (b.dst) {
      p->whole[std::size_t(i)] = b.dst;
      if (b.src && b.src != b.dst) p->copy_from[std::size_t(i)] = b.src;
    } else {
      p->scratch.push_back(
          std::make_unique<FieldF>(FieldF::over(options_.block, options_.field_halo)));
      p->whole[std::size_t(i)] = p->scratch.back().get();
      p->copy_from[std::size_t(i)] = b.src;
    }
  }
  // Halos stay current until the field is written again.
  for (const HaloField& e : p->exchange) {
    if (HaloField* current = find(exchanged_, e.field))
      current->depth = e.depth;
    else
      exchanged_.push_back(e);
  }
  for (const PassBufferDesc& b : desc.buffers)
    if (b.dst) std::erase_if(exchanged_, [&](const HaloField& e) { return e.field == b.dst; });
  TilePlanRequest r;
  r.grid = options_.grid;
  r.block = options_.block;
  r.field_halo = options_.field_halo;
  r.halo = max_halo;
  r.buffer_halos = halos;
  r.store_bytes = options_.local_store_bytes;
  r.min_tiles = options_.workers > 1 ? 4 * options_.workers : 1;
  r.max_width = options_.max_tile_width;
  r.max_height = options_.max_tile_height;
  p->plan = TilePlan::make(r);
  if (!p->exchange.empty()) {
    // A tile whose core grown by the deepest exchanged halo holds no cell the exchange writes
    // reads none of the exchanged halos (a gather's reach is the exchange's depth).
    int reach = 0;
    for (const HaloField& e : p->exchange) reach = std::max(reach, e.depth);
    const auto inner = [&](const Tile& t) {
      return !options_.halo->fills_any(t.core.grown(reach));
    };
    for (const Tile& t : p->plan.tiles())
      if (inner(t)) p->exchange_order.push_back(t);
    p->inner_tiles = p->exchange_order.size();
    for (const Tile& t : p->plan.tiles())
      if (!inner(t)) p->exchange_order.push_back(t);
  }
  p->desc = std::move(desc);
  p->pass.name = p->desc.name.c_str();
  p->pass.kernel_id = int(passes_.size());
  p->pass.halo = max_halo;
  p->pass.sweeps = max_sweeps;
  p->pass.program = p.get();
  p->pass.run_whole = &PassProgram::run_whole;
  p->pass.fetch = &PassProgram::fetch;
  p->pass.compute = &PassProgram::compute;
  passes_.push_back(std::move(p));
  return int(passes_.size()) - 1;
}

const Pass& FramePlan::pass(int i) const { return passes_.at(std::size_t(i))->pass; }
const TilePlan& FramePlan::tiles(int i) const { return passes_.at(std::size_t(i))->plan; }
std::string_view FramePlan::pass_name(int i) const { return passes_.at(std::size_t(i))->desc.name; }
int FramePlan::exchanges_before(int i) const {
  return int(passes_.at(std::size_t(i))->exchange.size());
}

int FramePlan::add_stage(StageDesc desc) {
  ARDCELL_CHECK(int(passes_.size()) < kMaxPasses, "FramePlan: too many steps");
  ARDCELL_CHECK(desc.run != nullptr, "FramePlan: a stage needs its run function");
  ARDCELL_CHECK(!options_.halo, "FramePlan: a stage works on whole fields, not in a block plan");
  auto p = std::make_unique<PassProgram>();
  p->grid = options_.grid;
  p->desc.name = std::move(desc.name);
  p->stage = std::move(desc.run);
  p->rd = desc.rd;
  p->pass.name = p->desc.name.c_str();
  p->pass.kernel_id = int(passes_.size());
  passes_.push_back(std::move(p));
  return int(passes_.size()) - 1;
}

bool FramePlan::is_stage(int i) const { return passes_.at(std::size_t(i))->stage != nullptr; }

// Charges the time since the last charge to step i.
struct FramePlan::StepClock {
  std::array<std::int64_t, kMaxPasses>& ns;
  std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
  void operator()(std::size_t i) {
    const auto now = std::chrono::steady_clock::now();
    ns[i] += std::chrono::duration_cast<std::chrono::nanoseconds>(now - start).count();
    start = now;
  }
};

void FramePlan::run(Backend& backend, bool with_rd) {
  StepClock charge{pass_ns_};
  bool synced = true;
  std::size_t unsynced = 0;  // the last pass dispatched without a barrier
  for (std::size_t i = 0; i < passes_.size(); ++i) {
    const PassProgram& p = *passes_[i];
    if (p.stage) {
      if (p.rd && !with_rd) continue;
      if (!synced) {
        backend.sync();
        synced = true;
        charge(unsynced);
      }
      p.stage();
      charge(i);
      continue;
    }
    if (!p.exchange.empty()) {
      // The exchange step: once the fields' cells are final (barrier), their halos are sent;
      // the tiles that read none of them compute meanwhile, the rest after they arrive.
      if (!synced) backend.sync();
      const std::span<const Tile> tiles = p.exchange_order;
      const std::size_t inner = backend.runs_tiles() ? p.inner_tiles : 0;
      options_.halo->begin(p.exchange);
      if (inner > 0) {
        backend.dispatch(p.pass, tiles.first(inner));
        // The host thread's own part of those tiles (when it is a worker), moving the
        // messages between them.
        backend.help(
            {[](void* halo) { static_cast<HaloChannel*>(halo)->progress(); }, options_.halo});
      }
      options_.halo->finish();
      if (inner < tiles.size()) backend.dispatch(p.pass, tiles.subspan(inner));
    } else {
      backend.dispatch(p.pass, p.plan.tiles());
    }
    if (p.desc.barrier_after) {
      backend.sync();
      synced = true;
      charge(i);
    } else {
      synced = false;
      unsynced = i;
    }
  }
  if (!synced) {
    backend.sync();
    charge(unsynced);
  }
  ++runs_;
}

void FramePlan::run(Device& device, bool with_rd) {
  ARDCELL_CHECK(!options_.halo, "FramePlan: a block plan runs on a back end, not a device");
  StepClock charge{pass_ns_};
  for (std::size_t i = 0; i < passes_.size(); ++i) {
    const PassProgram& p = *passes_[i];
    if (p.stage) {
      if (p.rd && !with_rd) continue;
      p.stage();
    } else {
      p.run_on(device);
    }
    charge(i);
  }
  ++runs_;
}

void FramePlan::reset_stats() {
  pass_ns_.fill(0);
  runs_ = 0;
}

void FramePlan::print_stats(std::FILE* out) const {
  std::int64_t total = 0;
  for (std::size_t i = 0; i < passes_.size(); ++i) total += pass_ns_[i];
  const double runs = runs_ > 0 ? double(runs_) : 1.0;
  std::fprintf(out, "%-28s %6s %5s %6s %4s %10s %6s\n", "step", "tiles", "halo", "sweeps", "xchg",
               "ms/frame", "share");
  for (std::size_t i = 0; i < passes_.size(); ++i) {
    const PassProgram& p = *passes_[i];
    const double ms = double(pass_ns_[i]) * 1e-6 / runs;
    const double share = total > 0 ? 100.0 * double(pass_ns_[i]) / double(total) : 0.0;
    if (p.stage)
      std::fprintf(out, "%-28s %6s %5s %6s %4s %10.3f %5.1f%%\n", p.desc.name.c_str(), "-", "-",
                   "-", "-", ms, share);
    else
      std::fprintf(out, "%-28s %6zu %5d %6d %4zu %10.3f %5.1f%%\n", p.desc.name.c_str(),
                   p.plan.tiles().size(), p.pass.halo, p.pass.sweeps, p.exchange.size(), ms, share);
  }
}

bool parse_plan_schedule(std::string_view name, PlanSchedule& out) {
  if (name == "serial")
    out = PlanSchedule::kSerial;
  else if (name == "stream")
    out = PlanSchedule::kStream;
  else if (name == "blocked")
    out = PlanSchedule::kBlocked;
  else
    return false;
  return true;
}

std::string_view plan_schedule_name(PlanSchedule s) {
  switch (s) {
    case PlanSchedule::kSerial:
      return "serial";
    case PlanSchedule::kStream:
      return "stream";
    case PlanSchedule::kBlocked:
      return "blocked";
  }
  return "?";
}

}  // namespace ardcell
