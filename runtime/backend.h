#pragma once
// The one small interface every back end implements (serial, threads, OpenCL), and the two
// things it is handed: a Pass (what to run) and Tiles (where). A back end knows no equations:
// the host builds Passes (host/engine/frame_plan.h) and the back end runs them over tiles.
//
// A Pass carries three ways to run it, one per kind of back end:
//   run_whole       - the serial reference: the whole grid at once, no tiling, no local store;
//   fetch + compute - the Cell-style tile program: fetch(tile, slot) issues the DMA gets of a
//                     tile into double-buffer `slot` of the worker's LocalStore; compute(tile,
//                     slot) waits for them, runs the kernels on the local copies and issues the
//                     puts. A worker calls fetch for tile i+1 before compute for tile i, so the
//                     next tile streams in while the current one computes. fetch is null for an
//                     in-place pass (runtime/row_executor.h): compute works on the fields in
//                     main memory and tiles are claimed one at a time;
//   kernel_id       - for back ends that compile kernels themselves (OpenCL): the host's id of
//                     the fused kernel group; `program` points at the host's description of it.
// Passes dispatched between two sync() calls must be independent (no pass reads what another
// of them writes); sync() is the barrier.
#include <cstdint>
#include <span>

#include "runtime/box.h"

namespace ardcell {

class LocalStore;
class Dma;

// A rectangle of cells a pass writes (core), and how far around it the pass reads (halo).
struct Tile {
  Box2 core;
  int halo = 0;
  friend constexpr bool operator==(const Tile&, const Tile&) = default;
};

// What a tile program may use on the worker that runs it.
struct WorkerContext {
  int worker = 0;  // 0 .. workers()-1
  LocalStore* store = nullptr;
  Dma* dma = nullptr;
};

struct Pass {
  const char* name = "";
  int kernel_id = -1;             // host-defined id of the fused kernel group (OpenCL dispatch)
  int halo = 0;                   // cells read around each tile's core
  int sweeps = 1;                 // sweeps run per residency (temporal blocking)
  const void* program = nullptr;  // host data handed back to the callbacks below
  void (*run_whole)(const void* program) = nullptr;
  void (*fetch)(const void* program, const Tile& tile, int slot, WorkerContext& ctx) = nullptr;
  void (*compute)(const void* program, const Tile& tile, int slot, WorkerContext& ctx) = nullptr;
};

// What the calling thread does between the tiles it computes in Backend::help.
struct HostProgress {
  void (*poll)(void* user) = nullptr;
  void* user = nullptr;
};

class Backend {
 public:
  virtual ~Backend() = default;
  virtual const char* name() const = 0;
  // Number of workers (accelerator queues); 1 for serial.
  virtual int workers() const = 0;
  // Starts `pass` over `tiles` (a tiling back end) or over the whole grid (serial). May return
  // before the work is done: the pass and the tiles must outlive the next sync().
  virtual void dispatch(const Pass& pass, std::span<const Tile> tiles) = 0;
  // Returns when every dispatched pass has finished and its results are in the fields.
  virtual void sync() = 0;
  // When the calling thread is one of the back end's workers (the threads back end's host):
  // runs its part of what was dispatched since the last sync() now, calling progress.poll
  // between tiles, so that it can drive other work (an MPI exchange) while it computes. sync()
  // still waits for the other workers. Nothing to do by default.
  virtual void help(HostProgress /*progress*/) {}
  // Whether dispatch runs exactly the tiles it is given (so a pass may be dispatched in parts:
  // the tiles that read no halo while a halo exchange is in flight, then the rest), not the
  // whole grid whatever the tiles.
  virtual bool runs_tiles() const { return true; }
};

// The whole-grid reference: dispatch runs pass.run_whole at once on the calling thread.
class SerialBackend final : public Backend {
 public:
  const char* name() const override { return "serial"; }
  int workers() const override { return 1; }
  void dispatch(const Pass& pass, std::span<const Tile> tiles) override;
  void sync() override {}
  bool runs_tiles() const override { return false; }
};

}  // namespace ardcell
