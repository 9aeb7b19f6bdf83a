#include "runtime/row_executor.h"

#include <algorithm>

#include "runtime/check.h"

namespace ardcell {

RowExecutor::RowExecutor(Backend& backend) : backend_(&backend) {
  pass_.name = "rows";
  pass_.program = &program_;
  pass_.run_whole = &RowExecutor::run_whole;
  pass_.compute = &RowExecutor::compute;
}

RowExecutor& RowExecutor::serial() {
  // One per thread: its reduction partials are scratch, and two threads may reduce at once.
  static thread_local SerialBackend backend;
  static thread_local RowExecutor executor(backend);
  return executor;
}

void RowExecutor::reserve_rows(int rows) {
  if (partials_.size() < std::size_t(rows)) partials_.resize(std::size_t(rows));
  if (slots_.size() < std::size_t(rows) * kMaxRowSlots)
    slots_.resize(std::size_t(rows) * kMaxRowSlots);
}

double* RowExecutor::rows_scratch(int rows, int slot) {
  ARDCELL_CHECK(slot >= 0 && slot < kMaxRowSlots, "RowExecutor: row slot out of range");
  const std::size_t need = std::size_t(rows) * kMaxRowSlots;
  if (slots_.size() < need) slots_.resize(need);
  return slots_.data() + std::size_t(slot) * std::size_t(rows);
}

void RowExecutor::run_bands(int rows, Trampoline fn, const void* f, int rows_per_band) {
  // Several bands per worker, so that a worker held up by the OS costs a band, not a share.
  const int bands =
      std::clamp(std::min(4 * backend_->workers(), rows / rows_per_band), 1, kMaxBands);
  for (int b = 0; b < bands; ++b) {
    const int y0 = int(long(rows) * b / bands), y1 = int(long(rows) * (b + 1) / bands);
    tiles_[b] = Tile{Box2{{0, y0}, {1, y1}}, 0};
  }
  program_ = Program{fn, f, rows};
  backend_->dispatch(pass_, std::span<const Tile>(tiles_, std::size_t(bands)));
  backend_->sync();
}

void RowExecutor::run_whole(const void* program) {
  const auto& p = *static_cast<const Program*>(program);
  p.fn(p.f, 0, p.rows, 0);
}

void RowExecutor::compute(const void* program, const Tile& tile, int, WorkerContext& ctx) {
  const auto& p = *static_cast<const Program*>(program);
  p.fn(p.f, tile.core.min.y, tile.core.max.y, ctx.worker);
}

}  // namespace ardcell
