#pragma once
// The OpenCL back end behind runtime/backend.h's interface. A Pass names its fused kernel group
// by kernel_id; the host binds each id once to an encoder that enqueues that group's OpenCL
// kernels over the tiles (the device-side tile walk: work-groups as SPEs, __local memory as the
// local store, async_work_group_copy as the DMA). dispatch() only enqueues - it returns before
// the work is done, as the interface allows - and sync() waits for the queue. workers() is the
// device's compute units (the SPEs a frame plan cuts tiles for).
#include <memory>
#include <span>
#include <vector>

#include "runtime/backend.h"
#include "runtime/opencl/opencl_context.h"

namespace ardcell {

class OpenClBackend final : public Backend {
 public:
  // Enqueues the kernels of `pass` over `tiles` on ctx's queue. `user` is the bound pointer.
  using Encoder = void (*)(void* user, OpenClContext& ctx, const Pass& pass,
                           std::span<const Tile> tiles);

  explicit OpenClBackend(std::unique_ptr<OpenClContext> ctx);
  const char* name() const override { return "opencl"; }
  int workers() const override;
  void dispatch(const Pass& pass, std::span<const Tile> tiles) override;
  void sync() override;

  // Binds kernel_id (>= 0) to an encoder, once, before the first frame (allocates then only).
  void bind(int kernel_id, Encoder encoder, void* user);
  bool bound(int kernel_id) const;
  OpenClContext& context() { return *ctx_; }
  // Passes enqueued since construction (tests, statistics).
  long dispatched() const { return dispatched_; }

 private:
  struct Binding {
    Encoder encoder = nullptr;
    void* user = nullptr;
  };
  std::unique_ptr<OpenClContext> ctx_;
  std::vector<Binding> bindings_;
  long dispatched_ = 0;
};

}  // namespace ardcell
