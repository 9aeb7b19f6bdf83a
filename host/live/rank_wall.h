#pragma once
// The video wall over Open MPI (`mpirun -np N ardcell live PRESET --wall WxH`,
// host/live/live_wall.h): screen b is rank b and shows block b of the layout (less the bezel),
// which is also what its engine runs on a split wall; a mirrored wall's engines run the whole
// grid. The input of a frame goes to every rank in one all-gather, the range in an all-reduce,
// the present waits on a barrier, a screenshot is gathered on rank 0, and a mirrored wall's
// fingerprints are all-gathered and screen 0's state broadcast.
#include <vector>

#include "host/live/live_wall.h"
#include "runtime/mpi/mpi_world.h"

namespace ardcell {

class RankWall final : public LiveWall {
 public:
  // bezel_cells: the cells hidden across each gap between screens (wall_view). Every view must
  // keep at least one cell (the caller checks). mirrored: every screen's engine runs the whole
  // grid (otherwise block b of `layout`).
  RankWall(const BlockLayout& layout, int bezel_cells, const MpiWorld& world, bool mirrored);

  int screens() const override { return layout_.count(); }
  int screen() const override { return world_.rank(); }
  Int2 grid() const override { return layout_.domain(); }
  Box2 block() const override {
    return mirrored_ ? box_of_size(layout_.domain()) : layout_.block(world_.rank());
  }
  Box2 view() const override { return views_[std::size_t(world_.rank())]; }
  bool mirrored() const override { return mirrored_; }
  std::span<const WallInput> share(const WallInput& mine) override;
  void agree_range(float& lo, float& hi) override { world_.min_max(lo, hi); }
  void before_present() override { world_.barrier(); }
  bool gather_image(const ImageRgb8& mine, ImageRgb8& wall) override;
  int first_drifted(std::uint64_t fingerprint) override;
  void send_state(SimState& state) override;
  bool regrid(Int2 grid) override;

 private:
  template <class T>
  void send_cells(Field<T>& f);

  BlockLayout layout_;
  const MpiWorld& world_;
  int bezel_cells_;
  bool mirrored_;
  std::vector<std::uint64_t> fingerprints_;
  std::vector<unsigned char> staging_;  // a field's interior on its way from screen 0
  std::vector<Box2> views_;
  std::vector<WallInput> all_;  // every screen's input of the frame
  std::vector<unsigned char> bytes_;
  std::vector<int> counts_;
};

}  // namespace ardcell
