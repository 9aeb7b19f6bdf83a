#include "host/run/rank_stepper.h"

#include <utility>

namespace ardcell {

RankStepper::RankStepper(Engine& engine, const BlockLayout& layout, MpiWorld& world, int64_t every,
                         const std::atomic<bool>* signal, StrokePlayback* playback)
    : engine_(engine),
      world_(world),
      gather_(layout, world),
      every_(every),
      signal_(signal),
      playback_(playback) {
  const SimState& s = std::as_const(engine_).state();
  whole_.size = s.size;
  whole_.h = s.h;
  whole_.dt = s.dt;
  if (world_.rank() == 0)
    s.for_each_field(
        [&](std::string_view name, const FieldF&) { *whole_.field(name) = FieldF(s.size, 1); });
  gather();
}

void RankStepper::step() {
  if (playback_) playback_->before_step(engine_.state(), engine_.state().time);
  engine_.step();
  ++steps_;
  if (world_.any(signal_ && signal_->load(std::memory_order_relaxed)))
    stop_.store(true, std::memory_order_relaxed);
  if (every_ > 0 && steps_ % every_ == 0) gather();
}

void RankStepper::gather() {
  const SimState& s = std::as_const(engine_).state();
  s.for_each_field([&](std::string_view name, const FieldF& f) {
    FieldF* whole = world_.rank() == 0 ? whole_.field(name) : nullptr;
    // A field made since (theta0 by a table1 scene's first orientation stroke, on every rank).
    if (whole && whole->empty()) *whole = FieldF(s.size, 1);
    gather_.gather(f, whole);
  });
  // Every rank paints the whole grid's obstacle mask (host/paint/paint.h): rank 0's is the grid's.
  if (world_.rank() == 0) whole_.obstacle = s.obstacle;
  whole_.time = s.time;
  whole_.rd_time = s.rd_time;
  whole_.step = s.step;
  whole_.dt = s.dt;
}

Status load_state_into_block(const std::filesystem::path& dir, const SavedStateMeta& meta,
                             Engine& engine) {
  SimState& s = engine.state();
  SimState whole;
  whole.size = s.size;
  s.for_each_field(
      [&](std::string_view name, const FieldF&) { *whole.field(name) = FieldF(s.size, 1); });
  if (Status st = load_state_fields(dir, meta, whole); !st) return st;
  s.for_each_field([&](std::string_view name, FieldF& f) {
    copy_box<float>(std::as_const(*whole.field(name)).view(), f.view(), f.interior());
  });
  s.time = whole.time;
  s.rd_time = whole.rd_time;
  s.step = whole.step;
  return Status::ok();
}

}  // namespace ardcell
