#pragma once
// Blocks: a domain of cells cut into boxes, each with its own fields (runtime/field.h, interior
// the block's box in global coordinates, a halo deep enough for the passes that read across its
// edges), and the halo exchange that fills those halos from the blocks that own the cells - the
// unit one frame plan runs on (host/engine/frame_plan.h), as PETSc's DMDA or AMReX's BoxArray
// cut a grid for MPI ranks. Here the blocks of one process run side by side on threads
// (LocalBlockGroup); the exchange is written as copies between boxes so that a transport
// between processes moves the same boxes.
//
// Ownership: a block owns its interior and, where it touches a non-periodic domain edge, the
// domain's ghost ring on that side (the cells its boundary fills write). The halo cells of a
// block are filled from their owners; along a periodic axis from the cell one domain width away
// (the ring there is nobody's: it is the far side's cells). Halo cells beyond the ring of a
// non-periodic edge are left alone: nobody reads them.
#include <array>
#include <barrier>
#include <cstddef>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "runtime/box.h"
#include "runtime/field.h"

namespace ardcell {

class BlockLayout {
 public:
  // Cuts `domain` into parts.x by parts.y blocks, row-major (block (i, j) is index j * parts.x +
  // i), sizes along each axis differing by at most one cell, the first ones the larger. Throws
  // std::invalid_argument (one line) when a block would be empty.
  static BlockLayout split(Int2 domain, Int2 parts, bool periodic_x = false,
                           bool periodic_y = false);

  Int2 domain() const { return domain_; }
  Int2 parts() const { return parts_; }
  int count() const { return int(blocks_.size()); }
  const Box2& block(int b) const { return blocks_[std::size_t(b)]; }
  bool periodic_x() const { return periodic_x_; }
  bool periodic_y() const { return periodic_y_; }
  // The cells block b writes: its box, grown by the ring on non-periodic domain edges.
  Box2 owned(int b) const;

 private:
  Int2 domain_{}, parts_{};
  bool periodic_x_ = false, periodic_y_ = false;
  std::vector<Box2> blocks_;
};

// "2x1" (x parts by y parts, each >= 1) into out; false when the text is not of that form.
bool parse_block_parts(std::string_view text, Int2& out);

// One rectangle of a block's halo: its cells (global coordinates of the receiving block) read
// the source block's cells at box.shifted(shift) (shift: 0, or a domain width across a
// periodic edge).
struct HaloCopy {
  int src_block = 0;
  Box2 box;
  Int2 shift;
};

// Copies `box` (inside copy.box) of a halo copy: dst's cells there from src's at box + shift.
void copy_halo_cells(const FieldF& src, const HaloCopy& copy, const Box2& box, FieldF& dst);

class HaloExchange {
 public:
  HaloExchange() = default;
  // The copies that fill each block's halo of `width` cells. width must not exceed the domain
  // along a periodic axis.
  HaloExchange(const BlockLayout& layout, int width);

  int width() const { return width_; }
  int count() const { return int(blocks_.size()); }
  // The layout's periodic axes: which domain edges the halos wrap across.
  bool periodic_x() const { return periodic_x_; }
  bool periodic_y() const { return periodic_y_; }
  const Box2& block(int b) const { return blocks_[std::size_t(b)]; }
  // Block b's cells and the domain's ghost ring along its walled edges (BlockLayout::owned).
  const Box2& owned(int b) const { return owned_[std::size_t(b)]; }
  std::span<const HaloCopy> copies_into(int block) const;
  // copy's cells within `depth` of the receiving block (depth <= width).
  Box2 within(const HaloCopy& copy, int block, int depth) const {
    return copy.box.intersected(this->block(block).grown(depth));
  }
  // Whether a fill of `block` writes any cell of `box`.
  bool fills_any(int block, const Box2& box) const;
  // Halo cells one fill of `block` moves (bytes: times sizeof(float)).
  std::size_t cells_into(int block) const;
  // Fills block b's halo, `depth` cells deep (<= width): fields[i] is block i's field (interior
  // layout.block(i), halo >= width). Reads only the other blocks' owned cells and writes only
  // b's halo, so every block may fill at once while no block writes its cells.
  void fill(std::span<FieldF* const> fields, int block, int depth) const;

 private:
  int width_ = 0;
  bool periodic_x_ = false, periodic_y_ = false;
  std::vector<Box2> blocks_, owned_;
  std::vector<HaloCopy> copies_;
  std::vector<std::size_t> first_;  // copies_into(b) = copies_[first_[b], first_[b + 1])
};

// A field of one exchange and how deep around the block its halo is filled (<= the width).
struct HaloField {
  FieldF* field = nullptr;
  int depth = 0;
};

// What a frame plan's exchange step calls (host/engine/frame_plan.h): fills the halos of this
// block's fields from the other blocks' copies of the same fields, in two halves so that work
// which reads no halo cell runs while the halos are in flight. Collective: every block of the
// group calls begin and finish for the same fields in the same order.
class HaloChannel {
 public:
  virtual ~HaloChannel() = default;
  virtual int block() const = 0;
  // The halo width the channel fills.
  virtual int width() const = 0;
  // Whether its layout wraps along x and y (BlockLayout::periodic_x, periodic_y).
  virtual bool periodic_x() const = 0;
  virtual bool periodic_y() const = 0;
  // Whether the exchange writes any cell of `box` (work that reads no such cell may run while
  // an exchange is in flight).
  virtual bool fills_any(const Box2& box) const = 0;
  // Starts filling the halo cells within each field's depth of the block. Returns once the
  // fields' own cells have been read: until finish() returns, the caller may read and write
  // the fields' own cells but no halo cell within the depths.
  virtual void begin(std::span<const HaloField> fields) = 0;
  // Lets the messages of the exchange in flight move, without waiting (a channel whose
  // transport has no progress thread of its own needs its owner to call in now and then).
  virtual void progress() {}
  // Returns when the halos begin() started are filled.
  virtual void finish() = 0;
  // Copies every block's owned cells (its box, and the domain's ghost ring along its walled
  // edges: HaloExchange::owned) of `field`, this block's copy of one field, into `whole` (a field
  // whose interior is the whole domain, halo >= 1), on every block: a step that needs the whole
  // grid (a global solve, a back-trace) runs on the gathered grid, ghosts as the blocks filled
  // them. Collective, like begin and finish, and not while an exchange is in flight.
  virtual void gather_all(const FieldF& field, FieldF& whole) = 0;
  // Adds every block's `values` (at most kMaxSums of them), block by block in block order, and
  // leaves the totals in `values` on every block: the same bits on each, so that blocks which
  // decide by a norm (a solve's stopping rule) decide alike. (Not the row-order sums of one
  // process's grid, which a block holding part of a row cannot form: equal to rounding.)
  // Collective, like begin and finish, and not while an exchange is in flight.
  static constexpr std::size_t kMaxSums = 4;
  virtual void sum(std::span<double> values) = 0;
  // begin and finish of one field.
  void exchange(FieldF& field, int depth) {
    const HaloField f{&field, depth};
    begin({&f, 1});
    finish();
  }
};

// The blocks of one layout run side by side in one process, one thread each: begin publishes
// each block's fields, waits for all, copies, and waits again before anyone writes (so finish
// has nothing left to do).
class LocalBlockGroup {
 public:
  LocalBlockGroup(const BlockLayout& layout, int width);
  HaloChannel& channel(int block) { return channels_[std::size_t(block)]; }

 private:
  class Channel : public HaloChannel {
   public:
    Channel(LocalBlockGroup* group, int block) : group_(group), block_(block) {}
    int block() const override { return block_; }
    int width() const override { return group_->exchange_.width(); }
    bool periodic_x() const override { return group_->exchange_.periodic_x(); }
    bool periodic_y() const override { return group_->exchange_.periodic_y(); }
    bool fills_any(const Box2& box) const override {
      return group_->exchange_.fills_any(block_, box);
    }
    void begin(std::span<const HaloField> fields) override;
    void finish() override {}
    void gather_all(const FieldF& field, FieldF& whole) override;
    void sum(std::span<double> values) override;

   private:
    LocalBlockGroup* group_;
    int block_;
  };
  HaloExchange exchange_;
  std::vector<FieldF*> posted_;
  std::vector<std::array<double, HaloChannel::kMaxSums>> sums_;  // each block's, for sum()
  std::barrier<> barrier_;
  std::vector<Channel> channels_;
};

}  // namespace ardcell
