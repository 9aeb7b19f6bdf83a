#pragma once
// RowExecutor: runs a kernel over the rows of a grid on a Backend, as an in-place pass: the
// rows [0, rows) are cut into bands (tiles spanning whole rows), the back end's workers run the
// bands on the fields in main memory (no local-store copy: on a CPU the bands stream through
// the caches), and the call returns when every band is done (dispatch + sync). The kernel is
// any callable f(y0, y1) that writes only rows [y0, y1) of its outputs, so the result is the
// same bits for any number of workers and any banding. A kernel that needs scratch of its own
// takes f(y0, y1, worker), worker in [0, workers()): bands run by one worker run one at a time.
//
// Reductions combine per-row partials in row order: sum_rows() hands the kernel a slot per row
// and adds the slots from row 0 up, so a dot product or a norm gives the same bits on 1, 2, 3 or
// 4 workers, and on the serial back end.
//
// Grids of fewer than kMinParallelCells cells run on the calling thread: dispatching them costs
// more than they do (the coarse levels of a multigrid cycle). Nothing here allocates once the
// partials buffer has grown to the largest grid reduced (reserve_rows).
#include <cstddef>
#include <span>
#include <type_traits>
#include <vector>

#include "runtime/backend.h"

namespace ardcell {

class RowExecutor {
 public:
  static constexpr int kMaxBands = 64;
  static constexpr long kMinParallelCells = 8192;
  static constexpr int kMinRowsPerBand = 4;

  explicit RowExecutor(Backend& backend);
  RowExecutor(const RowExecutor&) = delete;
  RowExecutor& operator=(const RowExecutor&) = delete;

  // The serial executor (whole grid on the calling thread, one per thread): the default of
  // every solver.
  static RowExecutor& serial();

  Backend& backend() const { return *backend_; }
  int workers() const { return backend_->workers(); }

  // Runs f(y0, y1) (or f(y0, y1, worker)) over bands covering [0, rows); `cells_per_row`
  // decides whether the grid is worth dispatching. Returns when done.
  template <class F>
  void for_rows(int rows, int cells_per_row, const F& f) {
    if (rows <= 0) return;
    if (!parallel(rows, cells_per_row)) {
      call<F>(&f, 0, rows, 0);
      return;
    }
    run_bands(rows, &call<F>, &f);
  }

  // Runs f(i) for i in [0, count), independent tasks (the A and B solves of a frame), one per
  // worker where there are several. A task must not use this executor itself.
  template <class F>
  void for_tasks(int count, const F& f) {
    if (count <= 0) return;
    if (backend_->workers() < 2 || count < 2) {
      for (int i = 0; i < count; ++i) f(i);
      return;
    }
    const auto rows = [&](int y0, int y1) {
      for (int i = y0; i < y1; ++i) f(i);
    };
    run_bands(count, &call<decltype(rows)>, &rows, 1);
  }

  // Runs f(y0, y1, partials) where the kernel stores one partial per row y in partials[y];
  // returns the sum of partials[0..rows) in row order.
  template <class F>
  double sum_rows(int rows, int cells_per_row, const F& f) {
    if (rows <= 0) return 0.0;
    reserve_rows(rows);
    double* partials = partials_.data();
    for_rows(rows, cells_per_row, [&](int y0, int y1) { f(y0, y1, partials); });
    double total = 0.0;
    for (int y = 0; y < rows; ++y) total += partials[y];
    return total;
  }

  // Grows the per-row partials and row slots to at least `rows` (call at set-up so frames do not
  // allocate).
  void reserve_rows(int rows);
  // Scratch of kMaxRowSlots doubles per row for reductions that need several partials per row
  // (sum, min and max): slot k of row y is at rows_scratch(rows, k)[y].
  double* rows_scratch(int rows, int slot);
  static constexpr int kMaxRowSlots = 4;

 private:
  using Trampoline = void (*)(const void* f, int y0, int y1, int worker);
  template <class F>
  static void call(const void* f, int y0, int y1, int worker) {
    if constexpr (std::is_invocable_v<const F&, int, int, int>)
      (*static_cast<const F*>(f))(y0, y1, worker);
    else
      (*static_cast<const F*>(f))(y0, y1);
  }
  bool parallel(int rows, int cells_per_row) const {
    return backend_->workers() > 1 && rows >= 2 * kMinRowsPerBand &&
           long(rows) * long(cells_per_row) >= kMinParallelCells;
  }
  void run_bands(int rows, Trampoline fn, const void* f, int rows_per_band = kMinRowsPerBand);

  struct Program {
    Trampoline fn = nullptr;
    const void* f = nullptr;
    int rows = 0;
  };
  static void run_whole(const void* program);
  static void compute(const void* program, const Tile& tile, int slot, WorkerContext& ctx);

  Backend* backend_;
  Program program_;
  Pass pass_;
  Tile tiles_[kMaxBands];
  std::vector<double> partials_;
  std::vector<double> slots_;
};

}  // namespace ardcell
