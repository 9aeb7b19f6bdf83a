// OBJ reading, the manifold checks and the one Catmull-Clark refinement of non-quad meshes.
#include "host/surface/poly_mesh.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <utility>

#include "host/surface/limit_surface.h"
#include "host/surface/procedural_mesh.h"

namespace ardcell {
namespace {

std::string error_of(std::string_view text, ObjLimits limits = {}) {
  PolyMesh m;
  const Status s = parse_obj(text, limits, m);
  return s ? std::string() : s.message();
}

TEST(ObjReader, QuadsWithEveryIndexForm) {
  const char* text =
      "# a square pair\n"
      "o thing\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\n"
      "f 1/1/1 2/1/1 3//1 4\n"
      "v 2 0 0\nv 2 1 0\n"
      "f -4 -2 -1 -3   # relative: 3 5 6 4\n";
  PolyMesh m;
  ASSERT_TRUE(parse_obj(text, {}, m)) << error_of(text);
  ASSERT_EQ(m.face_count(), 2);
  EXPECT_EQ(m.points.size(), 6u);
  EXPECT_EQ(std::vector<int>(m.face(1), m.face(1) + 4), (std::vector<int>{2, 4, 5, 3}));
  EXPECT_TRUE(m.all_quads());
}

TEST(ObjReader, BadInputIsOneLineWithItsLineNumber) {
  EXPECT_EQ(error_of("v 0 0 0\nv 1 0 zero\n"),
            "line 2: vertex coordinate 'zero' is not a finite number");
  EXPECT_EQ(error_of("v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 4\n"),
            "line 4: face index 4 names no vertex (3 so far)");
  EXPECT_EQ(error_of("v 0 0 0\nf 1 1\n"), "line 2: a face needs at least 3 vertices");
  EXPECT_EQ(error_of("v 0 0 0\nv 0 0 inf\n"),
            "line 2: vertex coordinate 'inf' is not a finite number");
  EXPECT_EQ(error_of("v 0 0 0\nf 1 0 1\n"),
            "line 2: face index '0' is not a vertex number (1-based or negative)");
  EXPECT_EQ(error_of("v 0 0 0\ncurv 1 2\n"),
            "line 2: unknown OBJ keyword 'curv' (expected v, f, vt, vn, o, g, s)");
  EXPECT_EQ(error_of("v 0 0\n"), "line 1: a vertex needs x y z (and at most w)");
  EXPECT_EQ(error_of("# nothing\n"), "the mesh has no faces (f lines)");
  ObjLimits small;
  small.max_points = 2;
  EXPECT_EQ(error_of("v 0 0 0\nv 0 0 0\nv 0 0 0\n", small), "line 3: more than 2 vertices");
  EXPECT_NE(error_of("v 0 0 \x01\n").find("\\x01"), std::string::npos);  // escaped, one line
}

TEST(ObjReader, FileErrorsNameTheFile) {
  const auto dir = std::filesystem::temp_directory_path() / "ardcell_obj_test";
  std::filesystem::create_directories(dir);
  const auto path = dir / "bad.obj";
  std::ofstream(path) << "v 0 0 0\nf 1 2 3\n";
  PolyMesh m;
  const Status s = read_obj(path, {}, m);
  ASSERT_FALSE(s);
  EXPECT_EQ(s.message(), path.string() + ": line 2: face index 2 names no vertex (1 so far)");
  EXPECT_FALSE(read_obj(dir / "missing.obj", {}, m));
  std::filesystem::remove_all(dir);
}

TEST(Manifold, NamesTheFirstBadEdgeOrVertex) {
  PolyMesh fin;  // three quads on the edge 1-2
  fin.points.assign(8, {0, 0, 0});
  fin.add_face({0, 1, 2, 3});
  fin.add_face({1, 0, 4, 5});
  fin.add_face({0, 1, 6, 7});
  EXPECT_EQ(check_manifold(fin).message(),
            "non-manifold edge 1-2: shared by 3 or more faces (1, 2, 3)");

  PolyMesh flipped;  // two quads traversing 1-2 the same way
  flipped.points.assign(6, {0, 0, 0});
  flipped.add_face({0, 1, 2, 3});
  flipped.add_face({0, 1, 4, 5});
  EXPECT_EQ(check_manifold(flipped).message(),
            "edge 1-2: faces 1 and 2 traverse it in the same direction (inconsistent orientation)");

  PolyMesh bowtie;  // two quads meeting only at vertex 1
  bowtie.points.assign(7, {0, 0, 0});
  bowtie.add_face({0, 1, 2, 3});
  bowtie.add_face({0, 4, 5, 6});
  EXPECT_EQ(check_manifold(bowtie).message(),
            "non-manifold vertex 1: two fans of faces meet only there");

  PolyMesh repeated;
  repeated.points.assign(3, {0, 0, 0});
  repeated.add_face({0, 1, 1, 2});
  EXPECT_EQ(check_manifold(repeated).message(), "non-manifold vertex 2: face 1 uses it twice");

  // A quad and a triangle sharing both edges at vertex 4 (the obj fuzzer's input that crashed
  // OpenSubdiv's Bfr): an interior vertex of two faces.
  PolyMesh pinched;
  pinched.points.assign(5, {0, 0, 0});
  pinched.add_face({3, 2, 1, 0});
  pinched.add_face({0, 1, 4});
  pinched.add_face({2, 3, 0});
  EXPECT_EQ(check_manifold(pinched).message(),
            "non-manifold vertex 4: an interior vertex of only 2 faces (expected 3 or more)");

  EXPECT_TRUE(check_manifold(cube_mesh(2)));
  EXPECT_TRUE(check_manifold(torus_mesh(8, 4, 2, 0.5)));
}

TEST(LimitSurfaceBuild, MixedMeshIsRefinedOnceIntoQuads) {
  // A square pyramid: four triangles and one quad, 5 + 4*3 + ... faces after one refinement.
  PolyMesh pyramid;
  pyramid.points = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}, {0, 0, 1.5}};
  pyramid.add_face({3, 2, 1, 0});
  pyramid.add_face({0, 1, 4});
  pyramid.add_face({1, 2, 4});
  pyramid.add_face({2, 3, 4});
  pyramid.add_face({3, 0, 4});
  LimitSurface s;
  ASSERT_TRUE(LimitSurface::build(pyramid, {}, s));
  EXPECT_TRUE(s.refined());
  EXPECT_EQ(s.patches(), 4 + 4 * 3);
  EXPECT_TRUE(s.quads().all_quads());

  LimitSurface cube;
  ASSERT_TRUE(LimitSurface::build(cube_mesh(1), {}, cube));
  EXPECT_FALSE(cube.refined());
  EXPECT_EQ(cube.patches(), 6);

  PolyMesh fin;
  fin.points.assign(8, {0, 0, 0});
  fin.add_face({0, 1, 2, 3});
  fin.add_face({1, 0, 4, 5});
  fin.add_face({0, 1, 6, 7});
  LimitSurface bad;
  EXPECT_FALSE(LimitSurface::build(fin, {}, bad));
}

// The procedural double torus: a closed, outward-facing quad mesh of Euler characteristic -2
// (genus 2) enclosing the plate's 13 cubes, whose limit surface builds with a patch a quad.
TEST(ProceduralMesh, Genus2IsAClosedOutwardDoubleTorus) {
  const double size = 0.5;
  const PolyMesh m = genus2_mesh(size);
  ASSERT_TRUE(check_manifold(m));
  ASSERT_TRUE(m.all_quads());
  EXPECT_EQ(m.face_count(), 50);
  std::map<std::pair<int, int>, int> edges;  // undirected edge -> faces using it
  double volume = 0;
  for (int f = 0; f < m.face_count(); ++f) {
    const int* v = m.face(f);
    for (int k = 0; k < 4; ++k) {
      const int a = v[k], b = v[(k + 1) % 4];
      ++edges[{std::min(a, b), std::max(a, b)}];
    }
    // Divergence theorem over the quad's two triangles: (1/6) p0 . (p1 x p2).
    for (int t : {1, 2}) {
      const auto& p0 = m.points[std::size_t(v[0])];
      const auto& p1 = m.points[std::size_t(v[t])];
      const auto& p2 = m.points[std::size_t(v[t + 1])];
      volume += (p0[0] * (p1[1] * p2[2] - p1[2] * p2[1]) - p0[1] * (p1[0] * p2[2] - p1[2] * p2[0]) +
                 p0[2] * (p1[0] * p2[1] - p1[1] * p2[0])) /
                6;
    }
  }
  for (const auto& [edge, faces] : edges) EXPECT_EQ(faces, 2) << edge.first << "-" << edge.second;
  const long long euler =
      (long long)m.points.size() - (long long)edges.size() + (long long)m.face_count();
  EXPECT_EQ(euler, -2);
  EXPECT_NEAR(volume, 13 * size * size * size, 1e-12);
  LimitSurface s;
  ASSERT_TRUE(LimitSurface::build(m, {}, s));
  EXPECT_FALSE(s.refined());
  EXPECT_EQ(s.patches(), 50);
}

}  // namespace
}  // namespace ardcell
