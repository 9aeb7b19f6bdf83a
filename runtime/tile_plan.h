#pragma once
// TilePlan: cuts a grid into tiles sized so that every field one pass keeps in a LocalStore,
// double-buffered, fits; rows move as DMA transfers of at most 16 KiB on 128-byte lines.
//
// The tiles cut a BLOCK of the domain (the whole domain by default; runtime/block_layout.h): the
// fields are the block's, over its box with a halo of `field_halo` cells, which a halo exchange
// fills from the neighbouring blocks. x cuts fall on 128-byte lines of the fields' memory
// (x - block.min.x + field_halo a multiple of 32 floats), so every tile's put is line-exact and
// no two tiles write one line. The last tile of a row or column takes what is left (tiles need
// not divide the block). Tiles touching the domain edge also own the domain's ghost ring on that
// side (written_box; one cell, runtime/boundary.h): a kernel there refills the boundary locally
// after each sweep. A pass reads its tiles' cores grown by `halo`, clipped to what the fields
// hold: the block grown by field_halo, and no further than the ring past the domain (load_box).
#include <cstddef>
#include <span>
#include <vector>

#include "runtime/backend.h"
#include "runtime/box.h"
#include "runtime/local_store.h"

namespace ardcell {

struct TilePlanRequest {
  Int2 grid;                 // the domain's interior cells
  Box2 block{};              // the cells to cut, inside the domain (empty: the whole domain)
  int field_halo = 1;        // halo of the block's fields (at least the domain's ghost ring)
  int halo = 1;              // cells read around each core (pass halo, e.g. k for k sweeps)
  int fields_with_halo = 1;  // buffers per tile holding core + halo (inputs, ping-pong)
  int fields_core = 1;       // buffers per tile holding the written box only (outputs)
  // When not empty: one entry per buffer, the halo it holds around the written box; replaces
  // fields_with_halo and fields_core (a pass whose buffers have different halos).
  std::span<const int> buffer_halos;
  std::size_t store_bytes = machine_local_store_bytes();  // both slots together
  int min_tiles = 1;   // at least this many tiles where the grid allows (load balance)
  int max_width = 0;   // cap on core width in cells (0: none); tests use it to force cuts
  int max_height = 0;  // cap on core height in cells (0: none)
};

class TilePlan {
 public:
  TilePlan() = default;
  // Throws std::invalid_argument (one line naming the sizes) when not even one 32-cell-wide row
  // fits the store.
  static TilePlan make(const TilePlanRequest& request);

  Int2 grid() const { return grid_; }
  const Box2& block() const { return block_; }
  int field_halo() const { return field_halo_; }
  int halo() const { return halo_; }
  Int2 tile_size() const { return tile_; }  // nominal core size (edge tiles may differ)
  std::span<const Tile> tiles() const { return tiles_; }
  std::size_t slot_bytes_needed() const { return slot_bytes_needed_; }

  Box2 domain() const { return box_of_size(grid_); }
  // The domain's ghost ring: one cell (none for fields without a halo).
  static int ring(int field_halo) { return field_halo > 0 ? 1 : 0; }
  int ring() const { return ring(field_halo_); }
  // Core grown by the domain's ring on the sides where the tile touches the domain edge.
  Box2 written_box(const Tile& t) const;
  // What the block's fields hold: the block grown by field_halo, no further than the ring.
  Box2 readable() const;
  // Core grown by `halo`, clipped to readable().
  Box2 load_box(const Tile& t, int halo) const;
  // The cells of the interior a k-th in-store sweep can still compute exactly on a tile loaded
  // with `halo`: the interior part of the load box shrunk by `sweep` on the sides facing other
  // tiles or blocks (the domain's own sides do not shrink: the boundary is refilled locally).
  Box2 sweep_region(const Tile& t, int halo, int sweep) const;
  // Worst-case bytes of one tile's buffers in one slot for a core of `size`.
  static std::size_t slot_bytes_for(Int2 size, const TilePlanRequest& request);

 private:
  Int2 grid_{};
  Box2 block_{};
  int field_halo_ = 0;
  int halo_ = 0;
  Int2 tile_{};
  std::size_t slot_bytes_needed_ = 0;
  std::vector<Tile> tiles_;
};

}  // namespace ardcell
