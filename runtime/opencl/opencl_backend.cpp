#include "runtime/opencl/opencl_backend.h"

#include <algorithm>
#include <cstdio>
#include <string>

namespace ardcell {

OpenClBackend::OpenClBackend(std::unique_ptr<OpenClContext> ctx) : ctx_(std::move(ctx)) {
  ARDCELL_CHECK(ctx_ != nullptr, "OpenClBackend needs an open context");
}

int OpenClBackend::workers() const { return std::max(1, int(ctx_->device().compute_units)); }

void OpenClBackend::bind(int kernel_id, Encoder encoder, void* user) {
  ARDCELL_CHECK(kernel_id >= 0 && encoder != nullptr, "OpenClBackend::bind: bad id or encoder");
  if (std::size_t(kernel_id) >= bindings_.size()) bindings_.resize(std::size_t(kernel_id) + 1);
  bindings_[std::size_t(kernel_id)] = Binding{encoder, user};
}

bool OpenClBackend::bound(int kernel_id) const {
  return kernel_id >= 0 && std::size_t(kernel_id) < bindings_.size() &&
         bindings_[std::size_t(kernel_id)].encoder != nullptr;
}

void OpenClBackend::dispatch(const Pass& pass, std::span<const Tile> tiles) {
  // A pass with no OpenCL twin is a broken plan, not bad input: stop with its name.
  if (!bound(pass.kernel_id)) {
    std::fprintf(stderr, "ardcell: OpenCL back end: pass '%s' (kernel %d) has no OpenCL twin\n",
                 pass.name, pass.kernel_id);
    ARDCELL_CHECK(false, "OpenCL dispatch of an unbound pass");
  }
  const Binding& b = bindings_[std::size_t(pass.kernel_id)];
  b.encoder(b.user, *ctx_, pass, tiles);
  ++dispatched_;
}

void OpenClBackend::sync() { ctx_->finish(); }

}  // namespace ardcell
