#include "host/surface/surface_render.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <utility>

#include "runtime/check.h"

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
Vec3 minus(const double a[3], const double b[3]) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }

// Screen positions are fixed point, 1/256 pixel: integer edge functions are then exact (so
// stepping them pixel to pixel gives the same values in every band, and two triangles sharing
// an edge agree on which side each pixel centre lies), and 8 fraction bits keep the snap far
// below what a pixel shows. Coordinates are clamped to +-2^20 pixels, so an edge function, the
// difference of two products of differences (each under 2^58), stays under 2^59.
constexpr int kSubpixelBits = 8;
constexpr int32_t kHalfPixel = 1 << (kSubpixelBits - 1);
constexpr double kMaxPixels = double(1 << 20);

int32_t to_fixed(double pixels) {
  pixels = pixels > -kMaxPixels ? std::min(pixels, kMaxPixels) : -kMaxPixels;  // NaN too
  return int32_t(std::floor(pixels * (1 << kSubpixelBits) + 0.5));
}
// The first and last pixel whose centre lies in [lo, hi] (fixed point).
int first_pixel(int32_t lo) {
  return (lo - kHalfPixel + (1 << kSubpixelBits) - 1) >> kSubpixelBits;
}
int last_pixel(int32_t hi) { return (hi - kHalfPixel) >> kSubpixelBits; }

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
  // The pick buffer holds cell indices as int32.
  ARDCELL_CHECK(
      grid.patch_cells() * std::size_t(patches) <= std::size_t(std::numeric_limits<int32_t>::max()),
      "SurfaceRenderer: too many cells for the pick buffer");
  const std::size_t per_patch = std::size_t(n + 1) * std::size_t(n + 1);
  const std::size_t count = std::size_t(patches) * per_patch;
  vertices_.resize(count);
  corners_.resize(count);
  patch_rows_.resize(std::size_t(patches));
  cull_sign_.assign(std::size_t(patches), 0);
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

  // Which triangles may be skipped: on a closed piece (no boundary edge), the nearest surface
  // along a ray from the camera is where the ray enters the solid, through a triangle facing
  // the camera if the piece winds outwards, away from it if inwards; the others lie behind it.
  // The patches' parametrisations wind the same way across every shared edge (the transitions
  // are rotations), so the sign of the piece's signed volume tells which. A piece whose volume is
  // next to nothing beside its triangles' (a closed but flat piece) keeps all of them. This takes
  // no part of a piece to be folded inside out (its winding number of the opposite sign: there a
  // triangle facing away would be the nearest); a piece passing through itself or another one
  // without turning inside out is fine.
  const PatchTopology& topo = surface.topology();
  if (topo.patches != patches || topo.across.size() != 4 * std::size_t(patches)) return;
  const std::vector<int> piece = patch_pieces(topo);
  const int pieces = piece.empty() ? 0 : *std::max_element(piece.begin(), piece.end()) + 1;
  std::vector<bool> open(std::size_t(pieces), false);
  std::vector<std::array<double, 3>> mean(std::size_t(pieces), {0, 0, 0});
  std::vector<double> corners_in(std::size_t(pieces), 0), volume(std::size_t(pieces), 0),
      magnitude(std::size_t(pieces), 0);
  for (int p = 0; p < patches; ++p) {
    const std::size_t k = std::size_t(piece[std::size_t(p)]);
    for (int e = 0; e < 4; ++e) open[k] = open[k] || topo.transition(p, e).patch < 0;
    for (std::size_t q = std::size_t(p) * per_patch; q < std::size_t(p + 1) * per_patch; ++q)
      for (int c = 0; c < 3; ++c) mean[k][c] += vertices_[q].x[c];
    corners_in[k] += double(per_patch);
  }
  for (int k = 0; k < pieces; ++k)
    for (int c = 0; c < 3; ++c) mean[std::size_t(k)][c] /= corners_in[std::size_t(k)];
  for (int p = 0; p < patches; ++p) {
    const std::size_t k = std::size_t(piece[std::size_t(p)]);
    const auto at = [&](int i, int j) {
      return minus(vertices_[(std::size_t(p) * (n + 1) + j) * (n + 1) + i].x, mean[k].data());
    };
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        // The two triangles as render() draws them.
        const Vec3 a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
        const double t1 = dot(a, cross(b, c)), t2 = dot(a, cross(c, d));
        volume[k] += t1 + t2;
        magnitude[k] += std::abs(t1) + std::abs(t2);
      }
  }
  // A triangle whose winding normal faces the eye has a negative signed area on the screen
  // (right, up, eye is right-handed and rows grow downwards): on an outward piece (volume > 0)
  // the positive ones face away.
  for (int p = 0; p < patches; ++p) {
    const std::size_t k = std::size_t(piece[std::size_t(p)]);
    if (!open[k] && std::abs(volume[k]) > 1e-3 * magnitude[k])
      cull_sign_[std::size_t(p)] = volume[k] > 0 ? 1 : -1;
  }
}

void SurfaceRenderer::render(const PatchField& field, const SurfaceColours& colours,
                             const SurfaceView& view, ImageRgb8& out) {
  // assign reuses field_'s storage: it was sized for the grid in the constructor.
  field_.assign(field.begin(), field.end());
  const int n = grid_.n(), patches = grid_.patches();
  // Named, not a structured binding: the corner pass's lambda captures them (clang 14 cannot
  // capture a binding).
  const CameraAxes axes = camera_axes(view);
  const Vec3& right = axes.right;
  const Vec3& up = axes.up;
  const Vec3& eye = axes.eye;
  const std::size_t per_patch = std::size_t(n + 1) * std::size_t(n + 1);
  RowExecutor& executor = executor_ ? *executor_ : RowExecutor::serial();

  // Fit, centred; screen y grows downwards. kOutline: the outline's box, exact for this view.
  // kSphere: the box of the bounding sphere's outline, a disc of its radius around its centre
  // from every direction, so turning the view keeps the scale (and the centre) fixed.
  double lo_x = std::numeric_limits<double>::max(), hi_x = -lo_x, lo_y = lo_x, hi_y = -lo_x;
  if (view.fit == SurfaceFit::kSphere) {
    const Vec3 c = vec(centre_);
    lo_x = dot(c, right) - radius_, hi_x = dot(c, right) + radius_;
    lo_y = dot(c, up) - radius_, hi_y = dot(c, up) + radius_;
  } else {
    for (const Vertex& v : vertices_) {
      const Vec3 x = vec(v.x);
      const double sx = dot(x, right), sy = dot(x, up);
      lo_x = std::min(lo_x, sx), hi_x = std::max(hi_x, sx);
      lo_y = std::min(lo_y, sy), hi_y = std::max(hi_y, sy);
    }
  }
  const int w = std::max(1, view.width), h = std::max(1, view.height);
  const double extent = std::max({hi_x - lo_x, hi_y - lo_y, 1e-30});
  const double scale = 0.9 * std::min(w, h) / extent;
  const double cx = 0.5 * (lo_x + hi_x), cy = 0.5 * (lo_y + hi_y);

  // Every cell corner of every patch, projected and coloured once (colours.colour's arithmetic,
  // its table looked up once a frame), patch by patch on the workers: a patch's exchange reads
  // the others' interiors, which nothing writes here, and fills only its own ghosts, all that its
  // corners read.
  const auto& lut = colormap_lut(colours.colormap);
  const double span = colours.hi > colours.lo ? colours.hi - colours.lo : 1.0;
  executor.for_rows(patches, int(per_patch), [&](int p0, int p1) {
    for (int p = p0; p < p1; ++p) {
      grid_.exchange(field_, p);
      int32_t top = std::numeric_limits<int32_t>::max();
      int32_t bottom = std::numeric_limits<int32_t>::min();
      for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
          const std::size_t at = std::size_t(p) * per_patch + std::size_t(j) * (n + 1) + i;
          const Vertex& v = vertices_[at];
          const Vec3 x = vec(v.x);
          const double value = grid_.corner_mean(field_, p, i, j);
          const Rgb8 c = colormap_at(lut, float((value - colours.lo) / span));
          const float shade = float(0.25 + 0.75 * std::abs(dot(vec(v.n), eye)));
          Corner& k = corners_[at];
          k.x = to_fixed(0.5 * w + (dot(x, right) - cx) * scale);
          k.y = to_fixed(0.5 * h - (dot(x, up) - cy) * scale);
          // Depth from the centre, where float keeps the most of it.
          k.depth = float(dot(minus(v.x, centre_), eye));
          k.r = c.r * shade, k.g = c.g * shade, k.b = c.b * shade;
          top = std::min(top, k.y), bottom = std::max(bottom, k.y);
        }
      patch_rows_[std::size_t(p)] = {first_pixel(top), last_pixel(bottom)};
    }
  });

  if (out.width != w || out.height != h) out.resize(w, h);
  if (w != width_ || h != height_) {
    const std::size_t pixels = std::size_t(w) * std::size_t(h);
    depth_.assign(pixels, -std::numeric_limits<float>::max());
    pick_.assign(pixels, -1);
    drawn_.assign(std::size_t(h), {0, 0});
    background_row_.resize(3 * std::size_t(w));
    width_ = w, height_ = h;
  }
  for (int x = 0; x < w; ++x)
    background_row_[3 * x] = view.background.r, background_row_[3 * x + 1] = view.background.g,
                        background_row_[3 * x + 2] = view.background.b;

  // Fills the part of triangle (a, b, c) in rows [band0, band1): the pixel centres inside it
  // (its three edge functions >= 0) nearer than what is there; the pixel's colour interpolates
  // the corners' and its pick records `cell`. `cull`: the signed area's sign to skip, or 0.
  const auto fill = [&](const Corner& a, const Corner* b, const Corner* c, int32_t cell, int cull,
                        int band0, int band1) {
    const int y0 = std::max(band0, first_pixel(std::min({a.y, b->y, c->y})));
    const int y1 = std::min(band1 - 1, last_pixel(std::max({a.y, b->y, c->y})));
    if (y0 > y1) return;
    int64_t area = int64_t(b->x - a.x) * (c->y - a.y) - int64_t(b->y - a.y) * (c->x - a.x);
    if (area == 0 || (cull != 0 && (area > 0) == (cull > 0))) return;
    if (area < 0) std::swap(b, c), area = -area;  // a positive area from here
    const int x0 = std::max(0, first_pixel(std::min({a.x, b->x, c->x})));
    const int x1 = std::min(w - 1, last_pixel(std::max({a.x, b->x, c->x})));
    if (x0 > x1) return;
    // Edge function of the side opposite corner k, at point p: twice the area of the triangle
    // p and that side make, k's barycentric weight times `area`; it grows by (dx, dy) a pixel.
    constexpr int64_t kPixel = 1 << kSubpixelBits;
    const int64_t px = int64_t(x0) * kPixel + kHalfPixel, py = int64_t(y0) * kPixel + kHalfPixel;
    const auto edge = [&](const Corner& s, const Corner& t) {
      return std::array<int64_t, 3>{(s.x - px) * (t.y - py) - (s.y - py) * (t.x - px),
                                    kPixel * (s.y - t.y), kPixel * (t.x - s.x)};
    };
    const auto [ea0, dxa, dya] = edge(*b, *c);
    const auto [eb0, dxb, dyb] = edge(*c, a);
    const auto [ec0, dxc, dyc] = edge(a, *b);
    const float inv = 1.0f / float(area);
    int64_t ra = ea0, rb = eb0, rc = ec0;
    for (int y = y0; y <= y1; ++y, ra += dya, rb += dyb, rc += dyc) {
      int64_t ea = ra, eb = rb, ec = rc;
      float* depth = depth_.data() + std::size_t(y) * w;
      int32_t* pick = pick_.data() + std::size_t(y) * w;
      uint8_t* rgb = out.row(y);
      int x = x0;
      // The row's inside is one run (a triangle is convex): up to it, then through it.
      for (; x <= x1 && (ea | eb | ec) < 0; ++x) ea += dxa, eb += dxb, ec += dxc;
      std::array<int, 2>& drawn = drawn_[std::size_t(y)];
      drawn[0] = std::min(drawn[0], x);
      for (; x <= x1 && (ea | eb | ec) >= 0; ++x, ea += dxa, eb += dxb, ec += dxc) {
        const float wa = float(ea) * inv, wb = float(eb) * inv, wc = float(ec) * inv;
        const float z = wa * a.depth + wb * b->depth + wc * c->depth;
        if (z <= depth[x]) continue;
        depth[x] = z;
        pick[x] = cell;
        // The weights are >= 0 and sum to 1 up to rounding: only the top needs the clamp.
        const auto mix = [&](float fa, float fb, float fc) {
          return uint8_t(std::min(wa * fa + wb * fb + wc * fc + 0.5f, 255.0f));
        };
        rgb[3 * x] = mix(a.r, b->r, c->r);
        rgb[3 * x + 1] = mix(a.g, b->g, c->g);
        rgb[3 * x + 2] = mix(a.b, b->b, c->b);
      }
      drawn[1] = std::max(drawn[1], x);
    }
  };
  // Bands of image rows on the executor's workers: each clears its rows and draws every
  // triangle's part in them, the triangles in the same order as one band would, so a pixel's
  // depth test sees the same sequence and the image is the same for any number of bands. Depth
  // and pick are cleared only where the last frame drew (each row's span): the rest still holds
  // the clear values, and the surface covers a fraction of the image.
  executor.for_rows(h, w, [&](int band0, int band1) {
    for (int y = band0; y < band1; ++y) {
      std::memcpy(out.row(y), background_row_.data(), background_row_.size());
      auto& [x0, x1] = drawn_[std::size_t(y)];
      if (x0 < x1) {
        const std::ptrdiff_t row = std::ptrdiff_t(y) * w;
        std::fill(depth_.begin() + row + x0, depth_.begin() + row + x1,
                  -std::numeric_limits<float>::max());
        std::fill(pick_.begin() + row + x0, pick_.begin() + row + x1, int32_t(-1));
      }
      x0 = w, x1 = 0;
    }
    for (int p = 0; p < patches; ++p) {
      // A patch whose rows miss the band has no triangle to draw in it (fill would clip each
      // to nothing): skipped whole, so a band's work follows its share of the image.
      const auto [top, bottom] = patch_rows_[std::size_t(p)];
      if (bottom < band0 || top >= band1) continue;
      const int cull = cull_sign_[std::size_t(p)];
      const Corner* corners = corners_.data() + std::size_t(p) * per_patch;
      for (int j = 0; j < n; ++j) {
        const Corner* row0 = corners + std::size_t(j) * (n + 1);
        const Corner* row1 = row0 + (n + 1);
        const int32_t cells = int32_t(grid_.index(p, 0, j));  // cell (i, j) is cells + i
        for (int i = 0; i < n; ++i) {
          fill(row0[i], &row0[i + 1], &row1[i + 1], cells + i, cull, band0, band1);
          fill(row0[i], &row1[i + 1], &row1[i], cells + i, cull, band0, band1);
        }
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
