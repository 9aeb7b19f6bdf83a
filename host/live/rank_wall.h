#pragma once
// The video wall over Open MPI (`mpirun -np N ardcell live PRESET --wall WxH`,
// host/live/live_wall.h): screen b is rank b and shows block b of the layout the ranks' engines
// run (runtime/block_layout.h); the input of a frame goes to every rank in one all-gather, the
// range in an all-reduce, the present waits on a barrier, and a screenshot is gathered on rank 0.
#include <vector>

#include "host/live/live_wall.h"
#include "runtime/mpi/mpi_world.h"

namespace ardcell {

class RankWall final : public LiveWall {
 public:
  // bezel_cells: the cells hidden across each gap between screens (wall_view). Every view must
  // keep at least one cell (the caller checks).
  RankWall(const BlockLayout& layout, int bezel_cells, const MpiWorld& world);

  int screens() const override { return layout_.count(); }
  int screen() const override { return world_.rank(); }
  Int2 grid() const override { return layout_.domain(); }
  Box2 block() const override { return layout_.block(world_.rank()); }
  Box2 view() const override { return views_[std::size_t(world_.rank())]; }
  std::span<const WallInput> share(const WallInput& mine) override;
  void agree_range(float& lo, float& hi) override { world_.min_max(lo, hi); }
  void before_present() override { world_.barrier(); }
  bool gather_image(const ImageRgb8& mine, ImageRgb8& wall) override;

 private:
  BlockLayout layout_;
  const MpiWorld& world_;
  std::vector<Box2> views_;
  std::vector<WallInput> all_;  // every screen's input of the frame
  std::vector<unsigned char> bytes_;
  std::vector<int> counts_;
};

}  // namespace ardcell
