#include "host/io/surface_atlas.h"

#include <cmath>
#include <cstdio>

#include "host/io/atomic_file.h"

namespace ardcell {

AtlasLayout atlas_layout(int patches, int n) {
  AtlasLayout layout;
  layout.n = n;
  layout.columns = std::max(1, int(std::ceil(std::sqrt(double(patches)))));
  layout.rows = (patches + layout.columns - 1) / layout.columns;
  return layout;
}

ImageRgb8 surface_atlas_image(const PatchGrid& grid, PatchField field, const AtlasLayout& layout,
                              const SurfaceColours& colours) {
  grid.exchange(field);
  ImageRgb8 image;
  image.resize(layout.width(), layout.height());
  const int n = grid.n();
  for (int p = 0; p < grid.patches(); ++p)
    for (int j = -1; j <= n; ++j) {
      uint8_t* row = image.row(layout.tile_y(p) + j + 1) + 3 * (layout.tile_x(p) + 1);
      for (int i = -1; i <= n; ++i) {
        const Rgb8 c = colours.colour(field[grid.index(p, i, j)]);
        uint8_t* texel = row + 3 * i;
        texel[0] = c.r, texel[1] = c.g, texel[2] = c.b;
      }
    }
  return image;
}

namespace {

// Writes printf-formatted text to an AtomicFile; false once a write failed.
template <class... Args>
bool put(AtomicFile& file, const char* format, Args... args) {
  char line[160];
  const int length = std::snprintf(line, sizeof line, format, args...);
  return length > 0 && file.write(line, std::size_t(length));
}

}  // namespace

Status write_surface_obj(const std::filesystem::path& obj_path,
                         const std::filesystem::path& mtl_path, const std::string& atlas_png,
                         const LimitSurface& surface, const AtlasLayout& layout) {
  {
    AtomicFile mtl;
    if (Status s = mtl.open(mtl_path); !s) return s;
    put(mtl, "# ardcell surface: the field's texture atlas\nnewmtl ardcell_field\n");
    put(mtl, "Ka 0 0 0\nKd 1 1 1\nKs 0 0 0\nillum 1\nmap_Kd %s\n", atlas_png.c_str());
    if (Status s = mtl.commit(); !s) return s;
  }
  AtomicFile obj;
  if (Status s = obj.open(obj_path); !s) return s;
  const int n = layout.n, patches = surface.patches();
  const double w = layout.width(), h = layout.height();
  put(obj, "# ardcell surface: Catmull-Clark limit surface, %d patches of %d x %d cells\n", patches,
      n, n);
  put(obj, "mtllib %s\nusemtl ardcell_field\n", mtl_path.filename().string().c_str());
  double position[3], normal[3];
  for (int p = 0; p < patches; ++p)
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) {
        limit_vertex(surface, p, double(i) / n, double(j) / n, position, normal);
        // Corner (i, j) of the cells is texel corner (i + 1, j + 1) of the tile; OBJ's v grows
        // upwards, the image's rows downwards.
        const double u = (layout.tile_x(p) + 1 + i) / w;
        const double v = 1.0 - (layout.tile_y(p) + 1 + j) / h;
        if (!put(obj, "v %.7g %.7g %.7g\nvn %.6f %.6f %.6f\nvt %.8f %.8f\n", position[0],
                 position[1], position[2], normal[0], normal[1], normal[2], u, v))
          return obj.commit();
      }
  const long long per_patch = (long long)(n + 1) * (n + 1);
  for (int p = 0; p < patches; ++p)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const long long base = per_patch * p + 1;  // OBJ counts from 1
        const long long a = base + (long long)j * (n + 1) + i, b = a + 1, c = b + n + 1,
                        d = a + n + 1;
        if (!put(obj, "f %lld/%lld/%lld %lld/%lld/%lld %lld/%lld/%lld %lld/%lld/%lld\n", a, a, a, b,
                 b, b, c, c, c, d, d, d))
          return obj.commit();
      }
  return obj.commit();
}

}  // namespace ardcell
