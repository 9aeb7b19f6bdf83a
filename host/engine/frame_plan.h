#pragma once
// FramePlan: the PPE side of the offload runtime. Built once per scene (as a Taskflow graph is
// built once and run every frame): an ordered list of the frame's steps, each either
//   a PASS  - a fused group of kernels that run on a tile while it sits in a worker's local
//             store, with the barrier between passes (the Table 1 scenes' frame), or
//   a STAGE - a step that runs as ops of a Device (host/engine/device.h) on the device's
//             fields (the whole grid, or a block whose halos its ops exchange: DeviceBlock),
//             each op in bands of rows on the CPU workers or as its OpenCL twin: what the other
//             scenes' solvers are made of (FluidStep, RdStepper append their stages).
// run() then replays it every frame on any Backend (or Device) without allocating, and times
// each step.
//
// A pass declares BUFFERS and OPS:
//   buffer - a local array covering the tile's written box grown by `halo` (runtime/tile_plan.h).
//            It may be fetched from a field (src), written back to a field (dst, the written
//            box only), both, or neither (scratch). A `gather` buffer is not copied at all: ops
//            read the whole src field in main memory (semi-Lagrangian advection, whose reach
//            depends on the velocity).
//   op     - kMap: a kernel over the op's region (the tile's core grown by `reach`, clipped to
//            the interior), then boundary fills of the buffers it wrote;
//            kJacobi: `sweeps` sweeps ping-ponging between buffers a and b with right-hand side
//            rhs, each followed by its boundary fill; sweep s computes the core grown by
//            (sweeps - s + extra_reach), so the last one leaves the core (grown by extra_reach)
//            exact: ghost-zone temporal blocking, bit-for-bit k global sweeps. The result is in
//            a (sweeps even) or b.
// On the serial back end the same ops run once over whole fields (the reference): each buffer
// is then a whole field (its dst, or its src when read only, or a scratch field of the plan).
// On a Device that keeps its own fields (OpenCL), run(Device&) replays that whole-field form
// with each op's device twin (`device` / `device_sweeps`: the op as Device ops,
// host/engine/device.h); an op without one runs on the CPU on whole fields, its pass's fields
// moving to the host and back, and says so once on stderr.
//
// A plan may run one BLOCK of a larger grid (runtime/block_layout.h: a block of a LocalBlockGroup
// on its own thread, or an MPI rank): its fields cover the block with a halo deep enough for
// the passes' halos, and the plan inserts the halo exchange as a step of its own before each
// pass that reads a field's halo after the field was last written (a gather reads all of it).
// The exchange overlaps the pass: once it has begun (the fields' own cells sent), the tiles
// whose reads hold no cell the exchange writes are handed to the back end while the halos are
// in flight, the others after they have arrived (on a back end that runs tiles; the serial
// reference waits first). A threads back end whose host thread is a worker computes them on
// every worker, the host moving the messages between its tiles (Backend::help).
// Boundary conditions still apply on the domain's edges only; a block's other edges are like a
// tile's: sweeps shrink there, so the blocks together give the bits one block gives. Advection
// back-traces must stay inside the block's halo (the fields' halo bounds the CFL number).
//
// Per-pass timings accumulate in fixed arrays (no allocation), printable with print_stats.
#include <array>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "runtime/backend.h"
#include "runtime/block_layout.h"
#include "runtime/boundary.h"
#include "runtime/field.h"
#include "runtime/tile_plan.h"

namespace ardcell {

// A kernel adapter: buffers[i] is the i-th buffer of the pass (a local copy or a whole field),
// indexed in global coordinates; region is where it must write.
using MapKernel = void (*)(const void* params, std::span<const View<float>> buffers, Box2 region);
// One Jacobi sweep: out = f(x, rhs) over region (reads x with halo 1, rhs with halo 0).
using SweepKernel = void (*)(const void* params, View<const float> x, View<const float> rhs,
                             View<float> out, Box2 region);

class Device;
// The op's twin on a Device, over whole fields: fields[i] is the i-th buffer's whole field; a
// map twin covers the interior (its fills follow), a sweep twin runs `sweeps` sweeps with their
// fills, the result in a (sweeps even) or b.
using DeviceMapKernel = void (*)(const void* params, Device& device,
                                 std::span<FieldF* const> fields);
using DeviceSweepKernel = void (*)(const void* params, Device& device, const FieldF& rhs, FieldF& a,
                                   FieldF& b, int sweeps, const BoundaryFill& fill);

struct PassBufferDesc {
  const FieldF* src = nullptr;  // fetched from here (null: not fetched)
  FieldF* dst = nullptr;        // written box put here (null: not written back)
  int halo = 0;                 // cells around the written box held in store
  bool gather = false;          // read src in place (whole field), no copy
};

struct PassOpDesc {
  enum class Kind : uint8_t { kMap, kJacobi };
  Kind kind = Kind::kMap;
  const void* params = nullptr;
  // kMap
  MapKernel map = nullptr;
  DeviceMapKernel device = nullptr;  // null: runs on the CPU under run(Device&)
  int reach = 0;
  std::array<int8_t, 4> writes{-1, -1, -1, -1};        // buffers the kernel writes
  std::array<int8_t, 4> fill_buffers{-1, -1, -1, -1};  // buffers refilled after the op
  std::array<BoundaryFill, 4> fills{};
  // kJacobi
  SweepKernel sweep = nullptr;
  DeviceSweepKernel device_sweeps = nullptr;
  int8_t a = -1, b = -1, rhs = -1;
  int sweeps = 1;
  int extra_reach =
      0;  // cells beyond the core still exact after the last sweep (a later op's halo)
  BoundaryFill fill{};
};

struct PassDesc {
  std::string name;
  std::vector<PassBufferDesc> buffers;
  std::vector<PassOpDesc> ops;
  bool barrier_after = true;
};

// A stage (see above): `run` issues the stage's Device ops on the calling thread; it holds the
// fields it works on. Stages of the reaction-diffusion (rd) can be left out of a frame (a
// caller that steps the RD elsewhere: the live display's coarser RD grid).
struct StageDesc {
  std::string name;
  std::function<void()> run;
  bool rd = false;
};

struct FramePlanOptions {
  Int2 grid{};
  Box2 block{};                 // the cells this plan computes (empty: the whole grid)
  HaloChannel* halo = nullptr;  // fills the block's halos from the other blocks (null: one block)
  int field_halo = 1;           // of the block's fields: at least the passes' halos when exchanging
  std::size_t local_store_bytes = machine_local_store_bytes();
  int workers = 1;         // tiles are cut so that each worker gets several
  int max_tile_width = 0;  // caps for tests (0: as large as the store allows)
  int max_tile_height = 0;
};

// How a scene built as a plan runs (host/engine/table1_plan.h):
//   serial  - the whole-grid reference, every pass one loop over whole fields;
//   stream  - every solver sweep one pass of tiles through the local stores;
//   blocked - ghost-zone temporal blocking, several sweeps per tile load.
enum class PlanSchedule : uint8_t { kSerial, kStream, kBlocked };
// "serial", "stream", "blocked"; false when unknown.
bool parse_plan_schedule(std::string_view name, PlanSchedule& out);
std::string_view plan_schedule_name(PlanSchedule s);

struct PlanOptions {
  PlanSchedule schedule = PlanSchedule::kBlocked;
  // Per worker, both double-buffer slots: two of the machine's L2 caches by default;
  // kSpeLocalStoreBytes for the Cell-faithful comparison.
  std::size_t local_store_bytes = machine_local_store_bytes();
  int sweeps_per_residency = 0;  // blocked: sweeps per tile load (0: a whole solve)
  int max_tile_width = 0;        // test hooks: cap tile sizes to force awkward tilings
  int max_tile_height = 0;
  // One block of a decomposed grid and the channel of its halo exchange (none: the whole grid).
  Box2 block{};
  HaloChannel* halo = nullptr;
};

class FramePlan {
 public:
  static constexpr int kMaxPasses = 256;
  static constexpr int kMaxBuffers = 16;

  explicit FramePlan(const FramePlanOptions& options);
  ~FramePlan();
  FramePlan(const FramePlan&) = delete;
  FramePlan& operator=(const FramePlan&) = delete;

  // Adds a pass at the end of the frame; returns its index. Checks the description (buffer
  // indices, halos large enough for the ops' reach) and cuts its tiles.
  int add_pass(PassDesc desc);
  // Adds a stage at the end of the frame; returns its index (stages and passes share one
  // numbering). A stage exchanges through its Device, not the plan: a plan whose passes
  // exchange (options.halo) refuses it.
  int add_stage(StageDesc desc);
  // Runs every step in order (one frame): passes on `backend`, stages as they are; without
  // `with_rd`, the rd stages are left out. No allocation (an MPI halo channel's buffers grow in
  // the first frame).
  void run(Backend& backend, bool with_rd = true);
  // The same frame on `device`'s own fields: passes whole-field, op by op (queued on a device
  // that queues: their times are then the host's time to queue them). No allocation once every
  // field has its device copy.
  void run(Device& device, bool with_rd = true);

  // Steps: passes and stages, in frame order.
  int pass_count() const { return int(passes_.size()); }
  bool is_stage(int i) const;
  const Pass& pass(int i) const;
  const TilePlan& tiles(int i) const;
  std::string_view pass_name(int i) const;
  const FramePlanOptions& options() const { return options_; }
  // Fields whose halos the exchange step fills before pass i (block plans; 0 otherwise).
  int exchanges_before(int i) const;

  // Timings: seconds spent in each step over all run() calls, and the number of runs.
  double pass_seconds(int i) const { return double(pass_ns_[std::size_t(i)]) * 1e-9; }
  std::int64_t runs() const { return runs_; }
  void reset_stats();
  // One line per step: name, tiles, halo, sweeps, exchanges (a stage: "-"), mean ms per frame,
  // share of the frame.
  void print_stats(std::FILE* out) const;

 private:
  struct PassProgram;
  struct StepClock;
  FramePlanOptions options_;
  std::vector<std::unique_ptr<PassProgram>> passes_;
  // While building: fields whose halos are current, and how deep.
  std::vector<HaloField> exchanged_;
  std::array<std::int64_t, kMaxPasses> pass_ns_{};
  std::int64_t runs_ = 0;
};

}  // namespace ardcell
