#pragma once
// A field on a patched surface as a texture atlas and a UV-mapped OBJ of the limit surface, so
// that Blender or MeshLab show it as a texture (seed 004's output for artists):
//   the atlas  - one tile of (N+2) x (N+2) texels a patch, row-major from the top-left, `columns`
//                tiles a row: the patch's N x N cells and, around them, its ghost ring (filled by
//                the exchange), so bilinear filtering across a patch edge blends the right cells;
//                texel (i, j) of tile p is cell (i - 1, j - 1), j growing downwards in the image;
//   the mesh   - per patch an (N+1) x (N+1) grid of vertices at the cell corners on the limit
//                surface, with normals and texture coordinates at the matching texel corners;
//                N x N quads a patch; `mtllib` names the material file, whose `map_Kd` names
//                the atlas.
// The files are written through AtomicFile (each complete or not there at all).
#include <filesystem>
#include <string>

#include "host/config/status.h"
#include "host/io/surface_ply.h"
#include "host/render/image.h"
#include "host/surface/limit_surface.h"
#include "host/surface/patch_grid.h"

namespace ardcell {

struct AtlasLayout {
  int n = 0;        // cells a patch side
  int columns = 0;  // tiles a row
  int rows = 0;
  int tile() const { return n + 2; }
  int width() const { return columns * tile(); }
  int height() const { return rows * tile(); }
  // Top-left texel of patch p's tile.
  int tile_x(int p) const { return (p % columns) * tile(); }
  int tile_y(int p) const { return (p / columns) * tile(); }
};

// ceil(sqrt(patches)) tiles a row.
AtlasLayout atlas_layout(int patches, int n);

// The atlas image of `field` (its ghost ring exchanged first), colour-mapped as the PLY is.
ImageRgb8 surface_atlas_image(const PatchGrid& grid, PatchField field, const AtlasLayout& layout,
                              const SurfaceColours& colours);

// The OBJ (positions, normals, texture coordinates into `layout`, quads) and its material file,
// which names `atlas_png` (a path relative to the OBJ's folder, as written into map_Kd).
Status write_surface_obj(const std::filesystem::path& obj_path,
                         const std::filesystem::path& mtl_path, const std::string& atlas_png,
                         const LimitSurface& surface, const AtlasLayout& layout);

}  // namespace ardcell
