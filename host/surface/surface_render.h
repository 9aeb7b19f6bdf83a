#pragma once
// A field on a patched surface drawn into a PNG-ready image from a fixed camera, without a GPU or
// a display (docs, tests, a quick look after `ardcell surface`): the limit surface's cell-corner
// grid (limit_vertex) as two triangles a cell, each corner coloured as the PLY colours it (the
// mean of its four cells, ghosts included) and shaded by its normal against a light at the eye
// (0.25 ambient + 0.75 |n . l|, so both sides of an open mesh show), filled with a depth buffer.
// Orthographic: the camera looks at the centre of the surface's bounding box from the direction
// (azimuth, elevation) in degrees (azimuth from +x towards +y, elevation above the xy plane, +z
// up), and the surface's outline fills 90% of the image's smaller side.
#include "host/io/surface_ply.h"
#include "host/render/image.h"
#include "host/surface/limit_surface.h"
#include "host/surface/patch_grid.h"

namespace ardcell {

struct SurfaceView {
  int width = 800, height = 600;
  double azimuth_deg = 35, elevation_deg = 25;
  Rgb8 background{20, 20, 24};
};

ImageRgb8 render_surface(const LimitSurface& surface, const PatchGrid& grid, PatchField field,
                         const SurfaceColours& colours, const SurfaceView& view);

}  // namespace ardcell
