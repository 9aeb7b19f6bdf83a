// The texture atlas and UV-mapped OBJ of a field on a patched surface (host/io/surface_atlas.h):
// every cell's texel has the cell's colour and every ghost texel its neighbour's, the OBJ reads
// back with one vertex per cell corner on the limit surface and each quad's texture coordinates
// around its cell's texel, and a file that cannot be written leaves nothing behind.
#include "host/io/surface_atlas.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "host/surface/procedural_mesh.h"

namespace ardcell {
namespace {

namespace fs = std::filesystem;

LimitSurface cube_sphere() {
  LimitSurface s;
  EXPECT_TRUE(LimitSurface::build(cube_mesh(2), {}, s));
  return s;
}

TEST(SurfaceAtlas, LayoutIsNearlySquare) {
  const AtlasLayout a = atlas_layout(24, 16);
  EXPECT_EQ(a.columns, 5);
  EXPECT_EQ(a.rows, 5);
  EXPECT_EQ(a.width(), 90);
  EXPECT_EQ(a.tile_x(7), 2 * 18);
  EXPECT_EQ(a.tile_y(7), 18);
  EXPECT_EQ(atlas_layout(1, 4).width(), 6);
  EXPECT_EQ(atlas_layout(26, 4).rows, 5);  // 6 a row
}

TEST(SurfaceAtlas, TexelsAreTheCellsAndTheirGhosts) {
  const LimitSurface surface = cube_sphere();
  const int n = 4;
  const PatchGrid grid(surface.topology(), n, CornerGhosts::kDiagonalExtrapolate);
  // A field of distinct values in [0, 1], so every cell gets its own colour (gray: value * 255).
  PatchField field = grid.make_field();
  for (int p = 0; p < grid.patches(); ++p)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) field[grid.index(p, i, j)] = (p * n * n + j * n + i) / 400.0;
  const AtlasLayout layout = atlas_layout(grid.patches(), n);
  SurfaceColours colours;
  colours.colormap = Colormap::kGray;
  const ImageRgb8 image = surface_atlas_image(grid, field, layout, colours);
  ASSERT_EQ(image.width, layout.width());
  ASSERT_EQ(image.height, layout.height());
  PatchField exchanged = field;
  grid.exchange(exchanged);
  const auto& lut = colormap_lut(Colormap::kGray);
  for (int p = 0; p < grid.patches(); ++p)
    for (int j = -1; j <= n; ++j)
      for (int i = -1; i <= n; ++i) {
        const uint8_t* texel = image.row(layout.tile_y(p) + j + 1) + 3 * (layout.tile_x(p) + i + 1);
        const Rgb8 want = colormap_at(lut, float(exchanged[grid.index(p, i, j)]));
        ASSERT_EQ(texel[0], want.r) << p << " " << i << "," << j;
        ASSERT_EQ(texel[1], want.g);
        ASSERT_EQ(texel[2], want.b);
      }
  // A ghost texel shows a neighbour patch's cell: some ghost of patch 0 has another patch's value.
  bool neighbour_seen = false;
  for (int i = 0; i < n; ++i) {
    const double ghost = exchanged[grid.index(0, i, -1)];
    neighbour_seen = neighbour_seen || ghost >= n * n / 400.0;
  }
  EXPECT_TRUE(neighbour_seen);
}

struct ObjFile {
  std::vector<std::array<double, 3>> v, vn;
  std::vector<std::array<double, 2>> vt;
  std::vector<std::array<long long, 4>> f;  // 1-based, v = vt = vn index
  std::string mtllib;
};

ObjFile read_obj_back(const fs::path& path) {
  ObjFile obj;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream s(line);
    std::string tag;
    s >> tag;
    if (tag == "v" || tag == "vn") {
      std::array<double, 3> x{};
      s >> x[0] >> x[1] >> x[2];
      (tag == "v" ? obj.v : obj.vn).push_back(x);
    } else if (tag == "vt") {
      std::array<double, 2> t{};
      s >> t[0] >> t[1];
      obj.vt.push_back(t);
    } else if (tag == "f") {
      std::array<long long, 4> q{};
      for (long long& k : q) {
        std::string corner;
        s >> corner;
        long long a = 0, b = 0, c = 0;
        EXPECT_EQ(std::sscanf(corner.c_str(), "%lld/%lld/%lld", &a, &b, &c), 3) << line;
        EXPECT_TRUE(a == b && b == c) << line;
        k = a;
      }
      obj.f.push_back(q);
    } else if (tag == "mtllib") {
      s >> obj.mtllib;
    }
  }
  return obj;
}

TEST(SurfaceAtlas, ObjHasTheLimitSurfaceAndEachQuadMapsToItsCell) {
  const LimitSurface surface = cube_sphere();
  const int n = 4, patches = surface.patches();
  const AtlasLayout layout = atlas_layout(patches, n);
  const fs::path dir = fs::temp_directory_path() / ("ardcell_atlas_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  ASSERT_TRUE(write_surface_obj(dir / "s.obj", dir / "s.mtl", "s.png", surface, layout));
  const ObjFile obj = read_obj_back(dir / "s.obj");
  EXPECT_EQ(obj.mtllib, "s.mtl");
  std::ifstream mtl(dir / "s.mtl");
  const std::string material((std::istreambuf_iterator<char>(mtl)), {});
  EXPECT_NE(material.find("map_Kd s.png\n"), std::string::npos) << material;
  ASSERT_EQ(obj.v.size(), std::size_t(patches * (n + 1) * (n + 1)));
  ASSERT_EQ(obj.vt.size(), obj.v.size());
  ASSERT_EQ(obj.vn.size(), obj.v.size());
  ASSERT_EQ(obj.f.size(), std::size_t(patches * n * n));
  // Vertices on the limit surface (to the 7 digits written), unit normals.
  double position[3], normal[3];
  for (int p = 0; p < patches; ++p)
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) {
        const std::size_t k = std::size_t((p * (n + 1) + j) * (n + 1) + i);
        limit_vertex(surface, p, double(i) / n, double(j) / n, position, normal);
        for (int c = 0; c < 3; ++c) {
          ASSERT_NEAR(obj.v[k][std::size_t(c)], position[c], 1e-6) << p << " " << i << "," << j;
          ASSERT_NEAR(obj.vn[k][std::size_t(c)], normal[c], 1e-5);
        }
        for (double t : obj.vt[k]) {
          EXPECT_GE(t, 0.0);
          EXPECT_LE(t, 1.0);
        }
      }
  // Quad (p, i, j): the mean of its texture coordinates is the centre of cell (i, j)'s texel.
  for (int p = 0; p < patches; ++p)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const auto& q = obj.f[std::size_t((p * n + j) * n + i)];
        double u = 0, v = 0;
        for (long long k : q)
          u += obj.vt[std::size_t(k - 1)][0] / 4, v += obj.vt[std::size_t(k - 1)][1] / 4;
        EXPECT_NEAR(u * layout.width(), layout.tile_x(p) + 1 + i + 0.5, 1e-5);
        EXPECT_NEAR((1 - v) * layout.height(), layout.tile_y(p) + 1 + j + 0.5, 1e-5);
      }
  fs::remove_all(dir);
}

TEST(SurfaceAtlas, UnwritableFolderIsOneErrorAndNoFile) {
  const LimitSurface surface = cube_sphere();
  const fs::path dir = fs::temp_directory_path() / "ardcell_no_such_folder" / "deeper";
  const Status s =
      write_surface_obj(dir / "s.obj", dir / "s.mtl", "s.png", surface, atlas_layout(24, 2));
  EXPECT_FALSE(s);
  EXPECT_FALSE(s.message().empty());
  EXPECT_FALSE(fs::exists(dir / "s.obj"));
}

}  // namespace
}  // namespace ardcell
