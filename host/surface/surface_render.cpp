#include "host/surface/surface_render.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

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

// A projected corner: screen position (pixels), depth (larger is nearer), colour and shade.
struct Corner {
  double x, y, depth;
  float r, g, b;
};

}  // namespace

ImageRgb8 render_surface(const LimitSurface& surface, const PatchGrid& grid, PatchField field,
                         const SurfaceColours& colours, const SurfaceView& view) {
  grid.exchange(field);
  const int n = grid.n(), patches = grid.patches();
  const double az = view.azimuth_deg * std::numbers::pi / 180;
  const double el = view.elevation_deg * std::numbers::pi / 180;
  // Camera basis: `eye` from the surface towards the camera, `right` and `up` span the screen.
  const Vec3 eye{std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el)};
  Vec3 right = normalized(cross(Vec3{-eye[0], -eye[1], -eye[2]}, Vec3{0, 0, 1}));
  if (dot(right, right) == 0) right = {0, 1, 0};  // looking straight up or down
  const Vec3 up = cross(right, Vec3{-eye[0], -eye[1], -eye[2]});

  // Every cell corner of every patch, projected (screen units before the fit) and coloured.
  std::vector<Corner> corners(std::size_t(patches) * std::size_t(n + 1) * std::size_t(n + 1));
  double lo_x = std::numeric_limits<double>::max(), hi_x = -lo_x, lo_y = lo_x, hi_y = -lo_x;
  double position[3], normal[3];
  for (int p = 0; p < patches; ++p)
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) {
        limit_vertex(surface, p, double(i) / n, double(j) / n, position, normal);
        const Vec3 x{position[0], position[1], position[2]};
        const double value = grid.corner_mean(field, p, i, j);
        const Rgb8 c = colours.colour(value);
        const float shade =
            float(0.25 + 0.75 * std::abs(dot(Vec3{normal[0], normal[1], normal[2]}, eye)));
        Corner& k = corners[(std::size_t(p) * (n + 1) + j) * (n + 1) + i];
        k = {dot(x, right), dot(x, up), dot(x, eye), c.r * shade, c.g * shade, c.b * shade};
        lo_x = std::min(lo_x, k.x), hi_x = std::max(hi_x, k.x);
        lo_y = std::min(lo_y, k.y), hi_y = std::max(hi_y, k.y);
      }
  // Fit: the outline fills 90% of the smaller side, centred; screen y grows downwards.
  const int w = std::max(1, view.width), h = std::max(1, view.height);
  const double extent = std::max({hi_x - lo_x, hi_y - lo_y, 1e-30});
  const double scale = 0.9 * std::min(w, h) / extent;
  const double cx = 0.5 * (lo_x + hi_x), cy = 0.5 * (lo_y + hi_y);
  for (Corner& k : corners) {
    k.x = 0.5 * w + (k.x - cx) * scale;
    k.y = 0.5 * h - (k.y - cy) * scale;
  }

  ImageRgb8 image;
  image.resize(w, h);
  for (int y = 0; y < h; ++y) {
    uint8_t* row = image.row(y);
    for (int x = 0; x < w; ++x)
      row[3 * x] = view.background.r, row[3 * x + 1] = view.background.g,
              row[3 * x + 2] = view.background.b;
  }
  std::vector<double> depth(std::size_t(w) * std::size_t(h), -std::numeric_limits<double>::max());
  // Fills a triangle: pixel centres inside it (edge functions), nearer than what is there.
  const auto fill = [&](const Corner& a, const Corner& b, const Corner& c) {
    const double area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    if (std::abs(area) < 1e-12) return;
    const int x0 = std::max(0, int(std::floor(std::min({a.x, b.x, c.x}))));
    const int x1 = std::min(w - 1, int(std::ceil(std::max({a.x, b.x, c.x}))));
    const int y0 = std::max(0, int(std::floor(std::min({a.y, b.y, c.y}))));
    const int y1 = std::min(h - 1, int(std::ceil(std::max({a.y, b.y, c.y}))));
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const double px = x + 0.5, py = y + 0.5;
        const double wa = ((b.x - px) * (c.y - py) - (b.y - py) * (c.x - px)) / area;
        const double wb = ((c.x - px) * (a.y - py) - (c.y - py) * (a.x - px)) / area;
        const double wc = 1 - wa - wb;
        if (wa < 0 || wb < 0 || wc < 0) continue;
        const double z = wa * a.depth + wb * b.depth + wc * c.depth;
        double& nearest = depth[std::size_t(y) * w + x];
        if (z <= nearest) continue;
        nearest = z;
        uint8_t* px_rgb = image.row(y) + 3 * x;
        const auto mix = [&](float fa, float fb, float fc) {
          return uint8_t(std::clamp(std::lround(wa * fa + wb * fb + wc * fc), 0L, 255L));
        };
        px_rgb[0] = mix(a.r, b.r, c.r);
        px_rgb[1] = mix(a.g, b.g, c.g);
        px_rgb[2] = mix(a.b, b.b, c.b);
      }
  };
  for (int p = 0; p < patches; ++p)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const auto at = [&](int di, int dj) -> const Corner& {
          return corners[(std::size_t(p) * (n + 1) + j + dj) * (n + 1) + i + di];
        };
        fill(at(0, 0), at(1, 0), at(1, 1));
        fill(at(0, 0), at(1, 1), at(0, 1));
      }
  return image;
}

}  // namespace ardcell
