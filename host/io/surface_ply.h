#pragma once
// A field on a patched surface as a PLY mesh of the limit surface (MeshLab, Blender, ParaView
// open it): per patch an (N+1) x (N+1) grid of vertices at the cell corners, evaluated on the
// limit surface, with their normals and the field as vertex colours; N x N quads a patch.
// Binary little-endian; written through AtomicFile (complete or not there at all).
//
// A corner's value is the mean of the four cells around it (ghost cells included, so the two
// patches along an edge give its vertices the same colour).
#include <filesystem>

#include "host/config/status.h"
#include "host/render/colormap.h"
#include "host/surface/limit_surface.h"
#include "host/surface/patch_grid.h"

namespace ardcell {

// How a field value is drawn (the PLY, the atlas and the render share it).
struct SurfaceColours {
  Colormap colormap = Colormap::kMagma;
  double lo = 0, hi = 1;  // the field values drawn at the colormap's ends

  Rgb8 colour(double value) const {
    const double span = hi > lo ? hi - lo : 1.0;
    return colormap_at(colormap_lut(colormap), float((value - lo) / span));
  }
};

Status write_surface_ply(const std::filesystem::path& path, const LimitSurface& surface,
                         const PatchGrid& grid, PatchField field, const SurfaceColours& options);

}  // namespace ardcell
