#include "host/surface/surface_render.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

namespace ardcell {
namespace {

using Vec3 = std::array<double, 3>;

Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec3 normalized(Vec3 a) {
  const double len = std::sqrt(dot(a, a));
  if (len > 0)
    for (double& c : a) c /= len;
  return a;
}
Vec3 vec(const double v[3]) { return {v[0], v[1], v[2]}; }

}  // namespace

CameraAxes camera_axes(const SurfaceView& view) {
  const double az = view.azimuth_deg * std::numbers::pi / 180;
  const double el = view.elevation_deg * std::numbers::pi / 180;
  const Vec3 eye{std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el)};
  Vec3 right = normalized(cross(Vec3{-eye[0], -eye[1], -eye[2]}, Vec3{0, 0, 1}));
  if (dot(right, right) == 0) right = {0, 1, 0};  // looking straight up or down
  return {right, cross(right, Vec3{-eye[0], -eye[1], -eye[2]}), eye};
}

SurfaceRenderer::SurfaceRenderer(const LimitSurface& surface, const PatchGrid& grid) : grid_(grid) {
  const int n = grid.n(), patches = grid.patches();
  const std::size_t count = std::size_t(patches) * std::size_t(n + 1) * std::size_t(n + 1);
  vertices_.resize(count);
  corners_.resize(count);
  patch_rows_.resize(std::size_t(patches));
  field_ = grid.make_field();
  double lo[3], hi[3];
  for (int k = 0; k < 3; ++k)
    lo[k] = std::numeric_limits<double>::max(), hi[k] = -std::numeric_limits<double>::max();
  for (int p = 0; p < patches; ++p)
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) {
        Vertex& v = vertices_[(std::size_t(p) * (n + 1) + j) * (n + 1) + i];
        limit_vertex(surface, p, double(i) / n, double(j) / n, v.x, v.n);
        for (int k = 0; k < 3; ++k)
          lo[k] = std::min(lo[k], v.x[k]), hi[k] = std::max(hi[k], v.x[k]);
      }
  if (count == 0) return;
  for (int k = 0; k < 3; ++k) centre_[k] = 0.5 * (lo[k] + hi[k]);
  // The farthest vertex, not the box's corner: a flat shape (a torus seen from above) then fills
  // the view as it would with kOutline.
  double r2 = 0;
  for (const Vertex& v : vertices_)
    r2 = std::max(r2, (v.x[0] - centre_[0]) * (v.x[0] - centre_[0]) +
                          (v.x[1] - centre_[1]) * (v.x[1] - centre_[1]) +
                          (v.x[2] - centre_[2]) * (v.x[2] - centre_[2]));
  radius_ = std::sqrt(r2);
}

void SurfaceRenderer::render(const PatchField& field, const SurfaceColours& colours,
                             const SurfaceView& view, ImageRgb8& out) {
  // assign reuses field_'s storage: it was sized for the grid in the constructor.
  field_.assign(field.begin(), field.end());
  grid_.exchange(field_);
  const int n = grid_.n(), patches = grid_.patches();
  const auto [right, up, eye] = camera_axes(view);

  // Every cell corner of every patch, projected (screen units before the fit) and coloured.
  double lo_x = std::numeric_limits<double>::max(), hi_x = -lo_x, lo_y = lo_x, hi_y = -lo_x;
  for (int p = 0; p < patches; ++p)
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) {
        const std::size_t at = (std::size_t(p) * (n + 1) + j) * (n + 1) + i;
        const Vertex& v = vertices_[at];
        const Vec3 x = vec(v.x);
        const double value = grid_.corner_mean(field_, p, i, j);
        const Rgb8 c = colours.colour(value);
        const float shade = float(0.25 + 0.75 * std::abs(dot(vec(v.n), eye)));
        Corner& k = corners_[at];
        k = {dot(x, right), dot(x, up), dot(x, eye), c.r * shade, c.g * shade, c.b * shade};
        lo_x = std::min(lo_x, k.x), hi_x = std::max(hi_x, k.x);
        lo_y = std::min(lo_y, k.y), hi_y = std::max(hi_y, k.y);
      }
  // Fit, centred; screen y grows downwards. kOutline: the outline's box, exact for this view.
  // kSphere: the box of the bounding sphere's outline, a disc of its radius around its centre
  // from every direction, so turning the view keeps the scale (and the centre) fixed.
  if (view.fit == SurfaceFit::kSphere) {
    const Vec3 c = vec(centre_);
    lo_x = dot(c, right) - radius_, hi_x = dot(c, right) + radius_;
    lo_y = dot(c, up) - radius_, hi_y = dot(c, up) + radius_;
  }
  const int w = std::max(1, view.width), h = std::max(1, view.height);
  const double extent = std::max({hi_x - lo_x, hi_y - lo_y, 1e-30});
  const double scale = 0.9 * std::min(w, h) / extent;
  const double cx = 0.5 * (lo_x + hi_x), cy = 0.5 * (lo_y + hi_y);
  const std::size_t per_patch = std::size_t(n + 1) * std::size_t(n + 1);
  for (int p = 0; p < patches; ++p) {
    double top = std::numeric_limits<double>::max(), bottom = -top;
    for (std::size_t q = std::size_t(p) * per_patch; q < std::size_t(p + 1) * per_patch; ++q) {
      Corner& k = corners_[q];
      k.x = 0.5 * w + (k.x - cx) * scale;
      k.y = 0.5 * h - (k.y - cy) * scale;
      top = std::min(top, k.y), bottom = std::max(bottom, k.y);
    }
    patch_rows_[std::size_t(p)] = {top, bottom};
  }

  if (out.width != w || out.height != h) out.resize(w, h);
  const std::size_t pixels = std::size_t(w) * std::size_t(h);
  if (w != width_ || h != height_) {
    depth_.resize(pixels);
    pick_.resize(pixels);
    width_ = w, height_ = h;
  }
  // Fills the part of a triangle in rows [band0, band1): pixel centres inside it (edge
  // functions), nearer than what is there; the pixel's colour interpolates the corners' and its
  // pick records `cell`.
  const auto fill = [&](const Corner& a, const Corner& b, const Corner& c, long cell, int band0,
                        int band1) {
    const double area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    if (std::abs(area) < 1e-12) return;
    const int y0 = std::max(band0, int(std::floor(std::min({a.y, b.y, c.y}))));
    const int y1 = std::min(band1 - 1, int(std::ceil(std::max({a.y, b.y, c.y}))));
    if (y0 > y1) return;
    const int x0 = std::max(0, int(std::floor(std::min({a.x, b.x, c.x}))));
    const int x1 = std::min(w - 1, int(std::ceil(std::max({a.x, b.x, c.x}))));
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const double px = x + 0.5, py = y + 0.5;
        const double wa = ((b.x - px) * (c.y - py) - (b.y - py) * (c.x - px)) / area;
        const double wb = ((c.x - px) * (a.y - py) - (c.y - py) * (a.x - px)) / area;
        const double wc = 1 - wa - wb;
        if (wa < 0 || wb < 0 || wc < 0) continue;
        const double z = wa * a.depth + wb * b.depth + wc * c.depth;
        double& nearest = depth_[std::size_t(y) * w + x];
        if (z <= nearest) continue;
        nearest = z;
        pick_[std::size_t(y) * w + x] = cell;
        uint8_t* px_rgb = out.row(y) + 3 * x;
        const auto mix = [&](float fa, float fb, float fc) {
          return uint8_t(std::clamp(std::lround(wa * fa + wb * fb + wc * fc), 0L, 255L));
        };
        px_rgb[0] = mix(a.r, b.r, c.r);
        px_rgb[1] = mix(a.g, b.g, c.g);
        px_rgb[2] = mix(a.b, b.b, c.b);
      }
  };
  // Bands of image rows on the executor's workers: each clears its rows and draws every
  // triangle's part in them, the triangles in the same order as one band would, so a pixel's
  // depth test sees the same sequence and the image is the same for any number of bands.
  (executor_ ? *executor_ : RowExecutor::serial()).for_rows(h, w, [&](int band0, int band1) {
    for (int y = band0; y < band1; ++y) {
      uint8_t* row = out.row(y);
      for (int x = 0; x < w; ++x)
        row[3 * x] = view.background.r, row[3 * x + 1] = view.background.g,
                row[3 * x + 2] = view.background.b;
      std::fill_n(depth_.begin() + std::ptrdiff_t(y) * w, w, -std::numeric_limits<double>::max());
      std::fill_n(pick_.begin() + std::ptrdiff_t(y) * w, w, -1L);
    }
    for (int p = 0; p < patches; ++p) {
      // A patch whose rows miss the band has no triangle to draw in it (fill would clip each
      // to nothing): skipped whole, so a band's work follows its share of the image.
      const auto [top, bottom] = patch_rows_[std::size_t(p)];
      if (std::ceil(bottom) < band0 || std::floor(top) > band1 - 1) continue;
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          const auto at = [&](int di, int dj) -> const Corner& {
            return corners_[(std::size_t(p) * (n + 1) + j + dj) * (n + 1) + i + di];
          };
          const long cell = long(grid_.index(p, i, j));
          fill(at(0, 0), at(1, 0), at(1, 1), cell, band0, band1);
          fill(at(0, 0), at(1, 1), at(0, 1), cell, band0, band1);
        }
    }
  });
}

long SurfaceRenderer::cell_at(int x, int y) const {
  if (x < 0 || y < 0 || x >= width_ || y >= height_) return -1;
  return pick_[std::size_t(y) * width_ + x];
}

ImageRgb8 render_surface(const LimitSurface& surface, const PatchGrid& grid,
                         const PatchField& field, const SurfaceColours& colours,
                         const SurfaceView& view) {
  ImageRgb8 image;
  SurfaceRenderer(surface, grid).render(field, colours, view, image);
  return image;
}

}  // namespace ardcell
