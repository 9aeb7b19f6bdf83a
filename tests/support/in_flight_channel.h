#pragma once
// A HaloChannel whose exchange arrives only when finish() is called, as a message may: between
// begin and finish the halo cells stay as they were, so work that reads them too early shows.
// It wraps another block's channel (LocalBlockGroup), which does the copies in finish().
#include <span>
#include <vector>

#include "runtime/block_layout.h"

namespace ardcell {

class InFlightChannel final : public HaloChannel {
 public:
  explicit InFlightChannel(HaloChannel& inner) : inner_(inner) {}
  int block() const override { return inner_.block(); }
  int width() const override { return inner_.width(); }
  bool periodic_x() const override { return inner_.periodic_x(); }
  bool periodic_y() const override { return inner_.periodic_y(); }
  bool fills_any(const Box2& box) const override { return inner_.fills_any(box); }
  void begin(std::span<const HaloField> fields) override {
    fields_.assign(fields.begin(), fields.end());
    in_flight = true;
    ++begun;
  }
  void progress() override { polls += in_flight; }  // only polls that can move a message
  void gather_all(const FieldF& field, FieldF& whole) override { inner_.gather_all(field, whole); }
  void sum(std::span<double> values) override { inner_.sum(values); }
  void finish() override {
    inner_.begin(fields_);  // reads the blocks' own cells, writes this block's halos
    inner_.finish();
    in_flight = false;
  }
  bool in_flight = false;
  int polls = 0;  // progress() calls while an exchange was in flight
  int begun = 0;  // exchanges begun

 private:
  HaloChannel& inner_;
  std::vector<HaloField> fields_;
};

}  // namespace ardcell
