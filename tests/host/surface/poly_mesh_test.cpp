// OBJ and OFF reading, the manifold checks, the one Catmull-Clark refinement of non-quad meshes,
// and the figure eight of Debian's libcgal-demo (ARDCELL_MESH_DIR) as a closed genus-2 surface.
#include "host/surface/poly_mesh.h"

#include <unistd.h>

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

std::string error_of(std::string_view text, MeshLimits limits = {}) {
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
  MeshLimits small;
  small.max_points = 2;
  EXPECT_EQ(error_of("v 0 0 0\nv 0 0 0\nv 0 0 0\n", small), "line 3: more than 2 vertices");
  EXPECT_NE(error_of("v 0 0 \x01\n").find("\\x01"), std::string::npos);  // escaped, one line
}

// A fresh folder for the running test's files.
std::filesystem::path fresh_dir() {
  const ::testing::TestInfo* test = ::testing::UnitTest::GetInstance()->current_test_info();
  const auto dir = std::filesystem::temp_directory_path() /
                   ("ardcell_mesh_test_" + std::to_string(::getpid()) + "_" + test->name());
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

TEST(ObjReader, FileErrorsNameTheFile) {
  const auto dir = fresh_dir();
  const auto path = dir / "bad.obj";
  std::ofstream(path) << "v 0 0 0\nf 1 2 3\n";
  PolyMesh m;
  const Status s = read_mesh(path, {}, m);
  ASSERT_FALSE(s);
  EXPECT_EQ(s.message(), path.string() + ": line 2: face index 2 names no vertex (1 so far)");
  EXPECT_FALSE(read_mesh(dir / "missing.obj", {}, m));
  std::filesystem::remove_all(dir);
}

std::string off_error_of(std::string_view text, MeshLimits limits = {}) {
  PolyMesh m;
  const Status s = parse_off(text, limits, m);
  return s ? std::string() : s.message();
}

// A unit cube's six quads, 0-based, outward-facing: 8 vertices, 6 faces, 12 edges.
constexpr const char* kCubeOff =
    "OFF\n"
    "# a cube\n"
    "8 6 12\n"
    "0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
    "4 3 2 1 0\n4 4 5 6 7\n4 0 1 5 4\n4 1 2 6 5\n4 2 3 7 6\n4 3 0 4 7\n";

TEST(OffReader, CubeWithCommentsAndColours) {
  PolyMesh m;
  ASSERT_TRUE(parse_off(kCubeOff, {}, m)) << off_error_of(kCubeOff);
  EXPECT_EQ(m.points.size(), 8u);
  ASSERT_EQ(m.face_count(), 6);
  EXPECT_TRUE(m.all_quads());
  EXPECT_EQ(std::vector<int>(m.face(2), m.face(2) + 4), (std::vector<int>{0, 1, 5, 4}));
  EXPECT_EQ(m.first_number, 0);
  EXPECT_TRUE(check_manifold(m));

  // The counts on the header's line, blank lines, CRLF, a face's colour after its indices, a
  // triangle and a pentagon (mixed: refined once).
  const char* mixed =
      "OFF 6 2 0\r\n\n"
      "0 0 0\n1 0 0\n2 0 0\n2 1 0\n1 1 0\n0 1 0  # last vertex\n"
      "3 0 1 4 255 0 0\n"
      "5 1 2 3 4 0 0.5 0.5 0.5 1\n";
  ASSERT_TRUE(parse_off(mixed, {}, m)) << off_error_of(mixed);
  ASSERT_EQ(m.face_count(), 2);
  EXPECT_EQ(m.face_size(0), 3);
  EXPECT_EQ(m.face_size(1), 5);
  EXPECT_EQ(m.face(1)[4], 0);
  EXPECT_EQ(m.points[5], (std::array<double, 3>{0, 1, 0}));

  // The OFF keyword is optional.
  ASSERT_TRUE(parse_off("3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", {}, m));
  EXPECT_EQ(m.face_count(), 1);
}

TEST(OffReader, BadInputIsOneLineWithItsLineNumber) {
  // Truncated: in the vertices, in the faces, after the keyword.
  EXPECT_EQ(off_error_of("OFF\n4 1 0\n0 0 0\n1 0 0\n"),
            "the file ends after 2 of the header's 4 vertices");
  EXPECT_EQ(off_error_of("OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),
            "the file ends after 1 of the header's 2 faces");
  EXPECT_EQ(off_error_of("OFF\n"), "the file ends after OFF (expected the vertex and face counts)");
  EXPECT_EQ(off_error_of("# nothing\n"),
            "the file is empty (expected OFF, then the vertex and face counts)");
  EXPECT_EQ(off_error_of("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 3 0 1 2\n"), "");
  EXPECT_EQ(off_error_of("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1\n"),
            "line 6: face 0: expected 3 vertex indices, got 2");
  // Indices out of range, malformed.
  EXPECT_EQ(off_error_of("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n"),
            "line 6: face 0: index 3 names no vertex (3 in the file)");
  EXPECT_EQ(off_error_of("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n"),
            "line 6: face 0: index -1 names no vertex (3 in the file)");
  EXPECT_EQ(off_error_of("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1.5 2\n"),
            "line 6: face 0: index '1.5' is not a vertex number (0-based)");
  EXPECT_EQ(off_error_of("OFF\n3 1 0\n0 0 0\n1 0 nan\n0 1 0\n3 0 1 2\n"),
            "line 4: vertex coordinate 'nan' is not a finite number");
  EXPECT_EQ(off_error_of("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n"),
            "line 6: face 0: a face needs at least 3 vertices");
  // Counts that lie: more vertices than the lines hold (a face line read as a vertex), fewer
  // (a vertex line read as a face), fewer faces (lines left over).
  EXPECT_EQ(off_error_of("OFF\n4 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),
            "line 6: vertex 3: expected x y z, got 4 values (the header counts 4 vertices)");
  EXPECT_EQ(off_error_of("OFF\n2 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),
            "line 5: face 0: a face needs at least 3 vertices");
  EXPECT_EQ(off_error_of("OFF\n2 1 0\n0 0 0\n1 0 0\n0.5 1 0\n3 0 1 2\n"),
            "line 5: face 0: '0.5' is not a vertex count (expected n i0 .. in-1 after the "
            "header's 2 vertices)");
  EXPECT_EQ(off_error_of("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 2 1 0\n"),
            "line 7: more than the header's 1 faces");
  EXPECT_EQ(off_error_of("OFF\n3 1\n"),
            "line 2: expected the counts 'vertices faces edges', got 2 values");
  EXPECT_EQ(off_error_of("OFF\n3 -1 0\n"),
            "line 2: count '-1' is not a number of 0 or more (expected vertices faces edges)");
  EXPECT_EQ(off_error_of("OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0\n"),
            "the mesh has no faces (the header counts 0)");
  // Variants whose vertex lines hold more than x y z, and binary OFF, are refused.
  EXPECT_EQ(off_error_of("COFF\n3 1 0\n"),
            "line 1: header 'COFF': vertex colours, normals or texture coordinates are not read "
            "(expected OFF)");
  EXPECT_EQ(off_error_of("OFF BINARY\n"), "line 1: binary OFF is not read (expected text)");
  EXPECT_NE(off_error_of("OFF\n3 1 0\n0 0 \x01\n").find("\\x01"), std::string::npos);
  // The messages of check_manifold count from 0, as the file does.
  PolyMesh fin;
  ASSERT_TRUE(
      parse_off("OFF\n8 3 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n1 0 1\n0 0 1\n1 0 -1\n"
                "0 0 -1\n4 0 1 2 3\n4 1 0 5 4\n4 0 1 6 7\n",
                {}, fin));
  EXPECT_EQ(check_manifold(fin).message(),
            "non-manifold edge 0-1: shared by 3 or more faces (0, 1, 2)");
}

// Whatever the header claims, the reader allocates for what the text can hold and stops at the
// limits before allocating: a 20-byte file claiming 4 Mi vertices reserves a few, and 2^40
// vertices or faces are refused at the header.
TEST(OffReader, HugeCountsAreBounded) {
  const char* liar = "OFF\n4000000 4000000 0\n0 0 0\n";
  PolyMesh m;
  EXPECT_EQ(off_error_of(liar), "the file ends after 1 of the header's 4000000 vertices");
  EXPECT_FALSE(parse_off(liar, {}, m));
  EXPECT_LE(m.points.capacity() * sizeof(m.points[0]), 1024u);
  EXPECT_LE(m.face_offsets.capacity() * sizeof(int), 1024u);
  EXPECT_EQ(off_error_of("OFF\n1099511627776 1 0\n"),
            "line 2: 1099511627776 vertices (expected at most 4194304)");
  EXPECT_EQ(off_error_of("OFF\n3 1099511627776 0\n"),
            "line 2: 1099511627776 faces (expected at most 4194304)");
  EXPECT_EQ(off_error_of("OFF\n99999999999999999999999 1 0\n"),
            "line 2: count '99999999999999999999999' is not a number of 0 or more (expected "
            "vertices faces edges)");
  MeshLimits small;
  small.max_points = 2;
  small.max_face_size = 4;
  EXPECT_EQ(off_error_of("OFF\n3 1 0\n", small), "line 2: 3 vertices (expected at most 2)");
  small.max_points = 8;
  EXPECT_EQ(off_error_of("OFF\n5 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 2 0\n5 0 1 2 3 4\n", small),
            "line 8: face 0: a face of more than 4 vertices");
  small.max_bytes = 8;
  EXPECT_EQ(off_error_of(kCubeOff, small), "mesh is larger than 8 bytes");
}

TEST(MeshFiles, FormatByFirstTokenOrExtension) {
  EXPECT_EQ(mesh_format("a.obj", "OFF\n3 1 0\n"), MeshFormat::kOff);
  EXPECT_EQ(mesh_format("a", "# made by CGAL\n\nOFF 3 1 0\n"), MeshFormat::kOff);
  EXPECT_EQ(mesh_format("a", "COFF\n"), MeshFormat::kOff);  // refused by parse_off, by name
  EXPECT_EQ(mesh_format("a.OFF", "3 1 0\n"), MeshFormat::kOff);
  EXPECT_EQ(mesh_format("a.obj", "v 0 0 0\n"), MeshFormat::kObj);
  EXPECT_EQ(mesh_format("a", ""), MeshFormat::kObj);

  const auto dir = fresh_dir();
  std::ofstream(dir / "cube.off") << kCubeOff;
  std::ofstream(dir / "headless.off") << "3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n";
  PolyMesh m;
  ASSERT_TRUE(read_mesh(dir / "cube.off", {}, m));
  EXPECT_EQ(m.face_count(), 6);
  const Status s = read_mesh(dir / "headless.off", {}, m);
  EXPECT_EQ(s.message(), (dir / "headless.off").string() +
                             ": line 5: face 0: index 3 names no vertex (3 in the "
                             "file)");
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

// V - E + F, and whether every edge lies in exactly two faces (a closed surface).
struct EdgeCensus {
  long long vertices = 0, edges = 0, faces = 0;
  bool every_edge_in_two_faces = true;
  long long euler() const { return vertices - edges + faces; }
};

EdgeCensus edge_census(const PolyMesh& m) {
  std::map<std::pair<int, int>, int> faces_at_edge;
  for (int f = 0; f < m.face_count(); ++f)
    for (int k = 0, n = m.face_size(f); k < n; ++k) {
      const int a = m.face(f)[k], b = m.face(f)[(k + 1) % n];
      ++faces_at_edge[{std::min(a, b), std::max(a, b)}];
    }
  EdgeCensus census;
  census.vertices = (long long)m.points.size();
  census.edges = (long long)faces_at_edge.size();
  census.faces = m.face_count();
  for (const auto& [edge, faces] : faces_at_edge)
    census.every_edge_in_two_faces = census.every_edge_in_two_faces && faces == 2;
  return census;
}

// A mesh Debian's libcgal-demo ships, as CMake extracted it; skipped only without the package.
bool packaged_mesh(const char* file, std::filesystem::path& path) {
  path = std::filesystem::path(ARDCELL_MESH_DIR) / file;
  if (std::filesystem::exists(path)) return true;
  EXPECT_FALSE(std::filesystem::exists(ARDCELL_CGAL_DATA_ARCHIVE))
      << path << " is missing though libcgal-demo is installed: run cmake again";
  return false;
}

// CGAL's figure eight (`ardcell surface --shape eight`): 634 triangles, refined once into 1902
// quads that close up into a surface of genus 2, every patch edge shared with another patch.
TEST(PackagedMesh, EightIsAClosedGenus2Surface) {
  std::filesystem::path path;
  if (!packaged_mesh("eight.off", path))
    GTEST_SKIP() << "needs Debian's libcgal-demo (" ARDCELL_CGAL_DATA_ARCHIVE ")";
  PolyMesh m;
  const Status read = read_mesh(path, {}, m);
  ASSERT_TRUE(read) << read.message();
  EXPECT_EQ(m.points.size(), 315u);
  ASSERT_EQ(m.face_count(), 634);
  for (int f = 0; f < m.face_count(); ++f) ASSERT_EQ(m.face_size(f), 3) << f;
  EXPECT_EQ(edge_census(m).euler(), -2);

  LimitSurface s;
  const Status built = LimitSurface::build(m, {}, s);
  ASSERT_TRUE(built) << built.message();
  EXPECT_TRUE(s.refined());
  EXPECT_EQ(s.patches(), 1902);
  ASSERT_TRUE(s.quads().all_quads());
  const EdgeCensus census = edge_census(s.quads());
  EXPECT_TRUE(census.every_edge_in_two_faces);
  EXPECT_EQ(census.vertices, 315 + 951 + 634);  // old vertices, edge points, face points
  EXPECT_EQ(census.edges, 2 * 951 + 3 * 634);
  EXPECT_EQ(census.faces, 1902);
  EXPECT_EQ(census.euler(), -2);
  const PatchTopology& topology = s.topology();
  for (int p = 0; p < topology.patches; ++p)
    for (int e = 0; e < 4; ++e) {
      const EdgeTransition& across = topology.transition(p, e);
      ASSERT_GE(across.patch, 0) << "patch " << p << " edge " << e << " is a boundary";
      EXPECT_EQ(topology.transition(across.patch, across.edge).patch, p);
    }
}

// CGAL's elephant (2775 vertices, 5558 triangles): closed, genus 3, 16674 patches once refined.
TEST(PackagedMesh, ElephantIsAClosedGenus3Surface) {
  std::filesystem::path path;
  if (!packaged_mesh("elephant.off", path))
    GTEST_SKIP() << "needs Debian's libcgal-demo (" ARDCELL_CGAL_DATA_ARCHIVE ")";
  PolyMesh m;
  const Status read = read_mesh(path, {}, m);
  ASSERT_TRUE(read) << read.message();
  EXPECT_EQ(m.points.size(), 2775u);
  ASSERT_EQ(m.face_count(), 5558);
  EXPECT_TRUE(check_manifold(m)) << check_manifold(m).message();
  const EdgeCensus census = edge_census(m);
  EXPECT_TRUE(census.every_edge_in_two_faces);
  EXPECT_EQ(census.euler(), -4);
}

}  // namespace
}  // namespace ardcell
