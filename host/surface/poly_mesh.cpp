#include "host/surface/poly_mesh.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <numeric>
#include <unordered_map>

#include "host/io/user_file.h"

namespace ardcell {

void PolyMesh::add_face(std::initializer_list<int> vs) {
  face_vertices.insert(face_vertices.end(), vs.begin(), vs.end());
  face_offsets.push_back(int(face_vertices.size()));
}

bool PolyMesh::all_quads() const {
  for (int f = 0; f < face_count(); ++f)
    if (face_size(f) != 4) return false;
  return true;
}

namespace {

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

// Splits a line into whitespace-separated tokens (views into the line).
void tokenize(std::string_view line, std::vector<std::string_view>& tokens) {
  tokens.clear();
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && is_space(line[i])) ++i;
    std::size_t j = i;
    while (j < line.size() && !is_space(line[j])) ++j;
    if (j > i) tokens.push_back(line.substr(i, j - i));
    i = j;
  }
}

std::string at_line(std::size_t line, const std::string& what) {
  return "line " + std::to_string(line) + ": " + what;
}

bool parse_double(std::string_view s, double& out) {
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  const auto r = std::from_chars(s.data(), s.data() + s.size(), out);
  return r.ec == std::errc() && r.ptr == s.data() + s.size() && std::isfinite(out);
}

}  // namespace

Status parse_obj(std::string_view text, const ObjLimits& limits, PolyMesh& out) {
  out = PolyMesh{};
  if (text.size() > limits.max_bytes)
    return Status::error("mesh is larger than " + std::to_string(limits.max_bytes) + " bytes");
  std::vector<std::string_view> tokens;
  std::size_t line_no = 0, pos = 0;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line = text.substr(pos, end - pos);
    pos = end + 1;
    ++line_no;
    if (const auto hash = line.find('#'); hash != std::string_view::npos)
      line = line.substr(0, hash);
    tokenize(line, tokens);
    if (tokens.empty()) continue;
    const std::string_view key = tokens[0];
    if (key == "v") {
      if (tokens.size() != 4 && tokens.size() != 5)
        return Status::error(at_line(line_no, "a vertex needs x y z (and at most w)"));
      std::array<double, 3> p{};
      for (int k = 0; k < 3; ++k)
        if (!parse_double(tokens[1 + k], p[k]))
          return Status::error(at_line(line_no, "vertex coordinate '" +
                                                    escaped_prefix(tokens[1 + k], 32) +
                                                    "' is not a finite number"));
      if (int(out.points.size()) >= limits.max_points)
        return Status::error(
            at_line(line_no, "more than " + std::to_string(limits.max_points) + " vertices"));
      out.points.push_back(p);
    } else if (key == "f") {
      const int n = int(tokens.size()) - 1;
      if (n < 3) return Status::error(at_line(line_no, "a face needs at least 3 vertices"));
      if (n > limits.max_face_size)
        return Status::error(at_line(
            line_no, "a face of more than " + std::to_string(limits.max_face_size) + " vertices"));
      if (out.face_count() >= limits.max_faces)
        return Status::error(
            at_line(line_no, "more than " + std::to_string(limits.max_faces) + " faces"));
      for (int k = 1; k <= n; ++k) {
        // Only the vertex index (before the first '/') matters; vt and vn are not used.
        const std::string_view t = tokens[k];
        const std::string_view idx = t.substr(0, t.find('/'));
        long long v = 0;
        const auto r = std::from_chars(idx.data(), idx.data() + idx.size(), v);
        if (r.ec != std::errc() || r.ptr != idx.data() + idx.size() || v == 0)
          return Status::error(
              at_line(line_no, "face index '" + escaped_prefix(t, 32) +
                                   "' is not a vertex number (1-based or negative)"));
        const long long count = (long long)out.points.size();
        const long long zero_based = v > 0 ? v - 1 : count + v;
        if (zero_based < 0 || zero_based >= count)
          return Status::error(at_line(line_no, "face index " + std::to_string(v) +
                                                    " names no vertex (" + std::to_string(count) +
                                                    " so far)"));
        out.face_vertices.push_back(int(zero_based));
      }
      out.face_offsets.push_back(int(out.face_vertices.size()));
    } else if (key == "vt" || key == "vn" || key == "vp" || key == "o" || key == "g" ||
               key == "s" || key == "usemtl" || key == "mtllib" || key == "l") {
      continue;
    } else {
      return Status::error(at_line(line_no, "unknown OBJ keyword '" + escaped_prefix(key, 32) +
                                                "' (expected v, f, vt, vn, o, g, s)"));
    }
  }
  if (out.face_count() == 0) return Status::error("the mesh has no faces (f lines)");
  return Status::ok();
}

void drop_unused_points(PolyMesh& mesh) {
  std::vector<int> remap(mesh.points.size(), -1);
  for (int v : mesh.face_vertices) remap[v] = 0;
  int next = 0;
  for (std::size_t v = 0; v < remap.size(); ++v)
    if (remap[v] == 0) {
      remap[v] = next;
      mesh.points[next++] = mesh.points[v];
    }
  mesh.points.resize(next);
  for (int& v : mesh.face_vertices) v = remap[v];
}

Status read_obj(const std::filesystem::path& path, const ObjLimits& limits, PolyMesh& out) {
  UserFile file;
  if (Status s = file.open(path, limits.max_bytes, "a Wavefront OBJ mesh"); !s) return s;
  std::string text;
  if (Status s = file.read_rest(text); !s) return s;
  if (Status s = parse_obj(text, limits, out); !s)
    return Status::error(path.string() + ": " + s.message());
  return Status::ok();
}

namespace {

int find_root(std::vector<int>& parent, int a) {
  while (parent[a] != a) a = parent[a] = parent[parent[a]];
  return a;
}

}  // namespace

Status check_manifold(const PolyMesh& mesh) {
  const int faces = mesh.face_count();
  if (faces == 0) return Status::error("the mesh has no faces");
  for (int f = 0; f < faces; ++f) {
    const int n = mesh.face_size(f);
    if (n < 3) return Status::error("face " + std::to_string(f + 1) + " has fewer than 3 vertices");
    const int* fv = mesh.face(f);
    for (int a = 0; a < n; ++a)
      for (int b = a + 1; b < n; ++b)
        if (fv[a] == fv[b])
          return Status::error("non-manifold vertex " + std::to_string(fv[a] + 1) + ": face " +
                               std::to_string(f + 1) + " uses it twice");
  }
  // Directed edges: each undirected edge may appear once in each direction.
  struct EdgeUse {
    int faces = 0, forward = 0;
    int face_ids[3] = {-1, -1, -1};
  };
  std::unordered_map<std::uint64_t, EdgeUse> edges;
  edges.reserve(mesh.face_vertices.size());
  auto key = [](int a, int b) {
    return (std::uint64_t(std::uint32_t(std::min(a, b))) << 32) | std::uint32_t(std::max(a, b));
  };
  for (int f = 0; f < faces; ++f) {
    const int n = mesh.face_size(f);
    const int* fv = mesh.face(f);
    for (int k = 0; k < n; ++k) {
      const int a = fv[k], b = fv[(k + 1) % n];
      EdgeUse& e = edges[key(a, b)];
      if (e.faces < 3) e.face_ids[e.faces] = f;
      ++e.faces;
      if (a < b) ++e.forward;
      const std::string name =
          std::to_string(std::min(a, b) + 1) + "-" + std::to_string(std::max(a, b) + 1);
      if (e.faces == 3)
        return Status::error("non-manifold edge " + name + ": shared by 3 or more faces (" +
                             std::to_string(e.face_ids[0] + 1) + ", " +
                             std::to_string(e.face_ids[1] + 1) + ", " + std::to_string(f + 1) +
                             ")");
      if (e.faces == 2 && e.forward != 1)
        return Status::error("edge " + name + ": faces " + std::to_string(e.face_ids[0] + 1) +
                             " and " + std::to_string(f + 1) +
                             " traverse it in the same direction (inconsistent orientation)");
    }
  }
  // Vertex fans: the corners at a vertex joined through the edges they share must be one set.
  const int corners = int(mesh.face_vertices.size());
  std::vector<int> parent(corners);
  std::iota(parent.begin(), parent.end(), 0);
  // The corner of face f at vertex v, found through the directed edge (v -> next) it starts.
  std::unordered_map<std::uint64_t, int> corner_of_out_edge;
  corner_of_out_edge.reserve(corners);
  auto dkey = [](int a, int b) {
    return (std::uint64_t(std::uint32_t(a)) << 32) | std::uint32_t(b);
  };
  for (int f = 0; f < faces; ++f) {
    const int n = mesh.face_size(f), o = mesh.face_offsets[f];
    const int* fv = mesh.face(f);
    for (int k = 0; k < n; ++k) corner_of_out_edge[dkey(fv[k], fv[(k + 1) % n])] = o + k;
  }
  for (int f = 0; f < faces; ++f) {
    const int n = mesh.face_size(f), o = mesh.face_offsets[f];
    const int* fv = mesh.face(f);
    for (int k = 0; k < n; ++k) {
      // Corner k at vertex fv[k] has the incoming edge prev -> v; the face across it holds the
      // edge v -> prev, which starts that face's corner at v.
      const int v = fv[k], prev = fv[(k + n - 1) % n];
      const auto it = corner_of_out_edge.find(dkey(v, prev));
      if (it != corner_of_out_edge.end())
        parent[find_root(parent, o + k)] = find_root(parent, it->second);
    }
  }
  // An interior vertex (no boundary edge at it) needs at least 3 faces: with 2, those faces
  // share both of its edges and the limit surface is undefined there (OpenSubdiv's Bfr does not
  // guard against it).
  std::vector<int> corners_at(mesh.points.size(), 0);
  std::vector<char> on_boundary(mesh.points.size(), 0);
  for (int f = 0; f < faces; ++f) {
    const int n = mesh.face_size(f);
    const int* fv = mesh.face(f);
    for (int k = 0; k < n; ++k) {
      const int a = fv[k], b = fv[(k + 1) % n];
      ++corners_at[a];
      if (edges[key(a, b)].faces == 1) on_boundary[a] = on_boundary[b] = 1;
    }
  }
  for (std::size_t v = 0; v < corners_at.size(); ++v)
    if (corners_at[v] > 0 && corners_at[v] < 3 && !on_boundary[v])
      return Status::error("non-manifold vertex " + std::to_string(v + 1) +
                           ": an interior vertex of only " + std::to_string(corners_at[v]) +
                           " faces (expected 3 or more)");
  std::vector<int> fan_of_vertex(mesh.points.size(), -1);
  for (int c = 0; c < corners; ++c) {
    const int v = mesh.face_vertices[c], root = find_root(parent, c);
    if (fan_of_vertex[v] == -1)
      fan_of_vertex[v] = root;
    else if (fan_of_vertex[v] != root)
      return Status::error("non-manifold vertex " + std::to_string(v + 1) +
                           ": two fans of faces meet only there");
  }
  return Status::ok();
}

}  // namespace ardcell
