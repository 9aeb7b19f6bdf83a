#pragma once
// A polygon control mesh read from a Wavefront OBJ or an OFF file, and the checks a
// Catmull-Clark surface needs of it before OpenSubdiv sees it: every face a simple polygon, every
// edge shared by at most two faces that traverse it in opposite directions, the faces around
// every vertex one fan.
//
// Vertices and faces are counted from 0 here; messages name them as the file does (OBJ from 1,
// OFF from 0: PolyMesh::first_number).
#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "host/config/status.h"

namespace ardcell {

struct PolyMesh {
  std::vector<std::array<double, 3>> points;
  std::vector<int> face_offsets{0};  // face f is face_vertices[face_offsets[f], face_offsets[f+1])
  std::vector<int> face_vertices;
  // The number the mesh's file gives its first vertex and face (OBJ 1, OFF 0), so that
  // check_manifold's messages name what the file's reader sees there.
  int first_number = 1;

  int face_count() const { return int(face_offsets.size()) - 1; }
  int face_size(int f) const { return face_offsets[f + 1] - face_offsets[f]; }
  const int* face(int f) const { return face_vertices.data() + face_offsets[f]; }
  void add_face(std::initializer_list<int> vs);
  bool all_quads() const;
};

// What a mesh file may hold; beyond it the reader stops with one line instead of allocating.
struct MeshLimits {
  std::uint64_t max_bytes = std::uint64_t(256) << 20;
  int max_points = 4 << 20;
  int max_faces = 4 << 20;
  int max_face_size = 64;
};

// Parses OBJ text: `v x y z [w]` and `f a b c ...` with 1-based or negative (relative)
// indices in the forms a, a/t, a//n, a/t/n; vt, vn, o, g, s, usemtl, mtllib, l and comments are
// skipped; any other keyword, a malformed number or an index out of range is one line naming
// the line number ("line 12: face index 9 names no vertex (8 so far)").
Status parse_obj(std::string_view text, const MeshLimits& limits, PolyMesh& out);

// Parses OFF text (Geomview's Object File Format, as CGAL and Princeton's shape benchmark write
// it): an optional `OFF` line, `vertices faces edges` (the edge count is not used), one
// `x y z` line a vertex, one `n i0 .. in-1` line a face with 0-based indices, anything after
// a face's indices (its colour) ignored; '#' starts a comment. The counts are held to `limits`
// before anything is allocated, and counts that do not match the lines after them (the file
// ends first, a vertex line where a face is expected, lines left over) are one line naming the
// line number ("line 320: face 0: '-0.14' is not a vertex count ..."). Headers with vertex
// colours, normals or texture coordinates (COFF, NOFF, STOFF, ...) and binary OFF are refused.
Status parse_off(std::string_view text, const MeshLimits& limits, PolyMesh& out);

enum class MeshFormat { kObj, kOff };
// OFF when the text's first token names an OFF header (OFF, or a variant parse_off refuses with
// one line) or the file name ends in .off (the header is optional); OBJ otherwise.
MeshFormat mesh_format(const std::filesystem::path& path, std::string_view text);

// Reads a mesh file (UserFile: a regular file no larger than limits.max_bytes) and parses it as
// mesh_format says; errors start with the path.
Status read_mesh(const std::filesystem::path& path, const MeshLimits& limits, PolyMesh& out);

// Empty faces, faces with fewer than 3 vertices or a repeated vertex, non-manifold edges
// (three or more faces), edges two faces traverse in the same direction (inconsistent
// orientation) and non-manifold vertices (two fans of faces meeting at one vertex): one line
// naming the first, e.g. "non-manifold edge 3-7: shared by 3 faces (2, 5, 9)".
Status check_manifold(const PolyMesh& mesh);

// Drops vertices no face uses (OpenSubdiv would take them for isolated points of the surface)
// and renumbers the faces; after check_manifold, whose messages use the file's numbers.
void drop_unused_points(PolyMesh& mesh);

}  // namespace ardcell
