#pragma once
// A field on a patched surface drawn into an RGB image on the CPU, without a GPU or a display:
// the fixed-camera PNGs (docs, tests, a quick look after `ardcell surface`) and the frames of a
// real-time loop (`ardcell live`: the mouse turns the view and paints on the cell under it).
//
// The method: the limit surface's cell-corner grid (limit_vertex) as two triangles a cell, each
// corner coloured as the PLY colours it (the mean of its four cells, ghosts included) and shaded
// by its normal against a light at the eye (0.25 ambient + 0.75 |n . l|, so both sides of an open
// mesh show), filled with a depth buffer. Orthographic: the camera looks at the centre of the
// surface's bounding box from the direction (azimuth, elevation) in degrees (azimuth from +x
// towards +y, elevation above the xy plane, +z up). A pick buffer beside the depth buffer records
// which cell each pixel shows.
//
// Evaluating the limit surface is the expensive part and does not depend on the view or the
// field, so SurfaceRenderer does it once; a frame projects, colours and shades each corner once
// (patch by patch on the executor's workers), then fills, into buffers sized on the first frame
// of a given size (no allocation after that). The fill: corners snapped to 1/256 pixel; a
// triangle covers the pixel centres where its three integer edge functions, stepped exactly from
// pixel to pixel, are >= 0 (triangles sharing an edge leave no crack between them); depth (float,
// larger is nearer) and colour interpolate the corners' with the barycentric weights. On a closed
// piece of surface (no boundary edge) the triangles facing away are skipped: wherever one covers
// a pixel, a triangle of the same piece facing the camera covers it nearer (which winding faces
// the camera, an outward or an inward piece, comes from the sign of the piece's volume; a piece
// is taken not to be folded inside out anywhere, where the nearest triangle would face away),
// so the picture is the same, up to rounding along the outline, for about half the fill. An open
// piece, or one enclosing next to no volume, draws every triangle. The image is filled in bands of
// rows: a band clears only its rows (depth and pick only across the columns the last frame drew in
// them) and skips the patches whose screen rows miss it, and a pixel sees the triangles in the same
// order in any band, so any number of workers draws the same image.
#include <array>
#include <cstdint>
#include <vector>

#include "host/io/surface_ply.h"
#include "host/render/image.h"
#include "host/surface/limit_surface.h"
#include "host/surface/patch_grid.h"
#include "runtime/row_executor.h"

namespace ardcell {

// Fit of the surface in the image:
//   kOutline - its projected outline fills 90% of the image's smaller side (the fixed-camera
//              PNGs: as large as the view allows, but the scale changes as the view turns);
//   kSphere  - its bounding sphere (centre of the bounding box, radius to the farthest vertex)
//              fills 90% of it, so the scale does not change as the view turns (live).
enum class SurfaceFit : uint8_t { kOutline, kSphere };

struct SurfaceView {
  int width = 800, height = 600;
  double azimuth_deg = 35, elevation_deg = 25;
  Rgb8 background{20, 20, 24};
  SurfaceFit fit = SurfaceFit::kOutline;
};

// The camera of `view` in the mesh's coordinates: `eye` the unit direction from the surface
// towards the camera, (cos el cos az, cos el sin az, sin el); `right` and `up` span the screen,
// right = -eye x z normalised (0, 1, 0 when looking straight up or down), up = right x -eye
// (the image's rows grow downwards). What the renderer draws with, so that a stroke on the screen
// (host/surface/surface_simulation.h) maps to the mesh as drawn.
struct CameraAxes {
  std::array<double, 3> right, up, eye;
};
CameraAxes camera_axes(const SurfaceView& view);

class SurfaceRenderer {
 public:
  // Evaluates the limit surface at every cell corner of `grid` (positions and normals:
  // limit_vertex) once. Keeps a reference to `grid` (each render refreshes the ghosts of its
  // field copy through it and indexes cells with it), which must outlive the renderer; keeps
  // nothing of `surface`.
  SurfaceRenderer(const LimitSurface& surface, const PatchGrid& grid);
  SurfaceRenderer(const LimitSurface&, PatchGrid&&) = delete;  // it would dangle

  // Draws `field` (cells of the grid) into `out`, resized to the view's size. Its ghosts are
  // refreshed in an internal copy: the caller's field is not written. Allocates nothing once
  // `out` and the internal buffers have the view's size (a second call with the same size).
  void render(const PatchField& field, const SurfaceColours& colours, const SurfaceView& view,
              ImageRgb8& out);

  // The cell drawn at pixel (x, y) of the last render: its index into a PatchField
  // (PatchGrid::index(p, i, j)), or -1 for the background, outside the image or before the first
  // render. The cell is the one whose (i, j) square holds the rasterised point: both triangles of
  // a cell belong to it.
  long cell_at(int x, int y) const;
  // The kSphere fit's bounding sphere: the bounding box's centre to the farthest vertex.
  double radius() const { return radius_; }
  // Where a render runs (the corners patch by patch, then bands of image rows; the serial
  // executor by default): the same image for any number of workers. `executor` must outlive the
  // renderer.
  void set_executor(RowExecutor& executor) { executor_ = &executor; }

 private:
  struct Vertex {
    double x[3], n[3];  // limit position and unit normal
  };
  // A projected corner: screen position in 1/256 pixel, depth (larger is nearer) and its shaded
  // colour.
  struct Corner {
    int32_t x, y;
    float depth, r, g, b;
  };

  const PatchGrid& grid_;
  std::vector<Vertex> vertices_;  // patch by patch, (n + 1) x (n + 1) corners, row j major
  // Per patch: the sign of the screen area of the triangles that face away on its closed piece
  // (+1 or -1: skipped), or 0 on an open piece or one enclosing next to no volume (all drawn).
  std::vector<int8_t> cull_sign_;
  double centre_[3] = {0, 0, 0};                // of the bounding box
  double radius_ = 0;                           // centre to the farthest vertex
  PatchField field_;                            // the field with its ghosts refreshed
  RowExecutor* executor_ = nullptr;             // null: the calling thread's serial executor
  std::vector<Corner> corners_;                 // vertices_ projected for the current frame
  std::vector<std::array<int, 2>> patch_rows_;  // each patch's first and last pixel row
  std::vector<float> depth_;                    // per pixel, of the nearest triangle so far
  std::vector<int32_t> pick_;                   // per pixel, its cell or -1
  // Per row, the columns [x0, x1) holding depth and pick written since the row's last clear.
  std::vector<std::array<int, 2>> drawn_;
  std::vector<uint8_t> background_row_;  // a row of the background colour
  int width_ = 0, height_ = 0;           // of depth_ and pick_
};

// The fixed-camera PNG: SurfaceRenderer(surface, grid).render(...) into a new image.
ImageRgb8 render_surface(const LimitSurface& surface, const PatchGrid& grid,
                         const PatchField& field, const SurfaceColours& colours,
                         const SurfaceView& view);

}  // namespace ardcell
