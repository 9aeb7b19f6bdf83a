#include "host/surface/poly_mesh.h"

#include <algorithm>
#include <cctype>
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

// Splits a line into whitespace-separated tokens (views into the line), at most max_tokens of
// them: no valid line of either format has that many, so the counts' checks reject a longer one,
// and a line of millions of values costs no memory.
void tokenize(std::string_view line, std::vector<std::string_view>& tokens,
              std::size_t max_tokens) {
  tokens.clear();
  std::size_t i = 0;
  while (i < line.size() && tokens.size() < max_tokens) {
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

// A whole token of decimal digits, optionally signed, that fits a long long.
bool parse_integer(std::string_view s, long long& out) {
  const auto r = std::from_chars(s.data(), s.data() + s.size(), out);
  return r.ec == std::errc() && r.ptr == s.data() + s.size();
}

// Walks text line by line, '#' comments dropped, handing out the lines that hold a token
// (tokenized) and the number of the last one handed out. Both formats read through it, so that
// their messages count lines alike.
class LineCursor {
 public:
  // Lines hold at most max_face_size + 16 tokens (a face's indices, its keyword or count, an
  // OFF face's colour; see tokenize).
  LineCursor(std::string_view text, const MeshLimits& limits)
      : text_(text), max_tokens_(std::size_t(std::max(limits.max_face_size, 0)) + 16) {}

  // The next line with a token into `tokens`; false at the end of the text.
  bool next(std::vector<std::string_view>& tokens) {
    while (pos_ < text_.size()) {
      std::size_t end = text_.find('\n', pos_);
      if (end == std::string_view::npos) end = text_.size();
      std::string_view line = text_.substr(pos_, end - pos_);
      pos_ = end + 1;
      ++line_;
      if (const auto hash = line.find('#'); hash != std::string_view::npos)
        line = line.substr(0, hash);
      tokenize(line, tokens, max_tokens_);
      if (!tokens.empty()) return true;
    }
    return false;
  }
  std::size_t line() const { return line_; }

 private:
  std::string_view text_;
  std::size_t max_tokens_;
  std::size_t pos_ = 0, line_ = 0;
};

Status too_large(std::string_view text, const MeshLimits& limits) {
  if (text.size() > limits.max_bytes)
    return Status::error("mesh is larger than " + std::to_string(limits.max_bytes) + " bytes");
  return Status::ok();
}

bool ends_with_off(std::string_view token) {
  return token.size() >= 3 && token.substr(token.size() - 3) == "OFF";
}

}  // namespace

Status parse_obj(std::string_view text, const MeshLimits& limits, PolyMesh& out) {
  out = PolyMesh{};
  if (Status s = too_large(text, limits); !s) return s;
  std::vector<std::string_view> tokens;
  LineCursor lines(text, limits);
  while (lines.next(tokens)) {
    const std::size_t line_no = lines.line();
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
        long long v = 0;
        if (!parse_integer(t.substr(0, t.find('/')), v) || v == 0)
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

Status parse_off(std::string_view text, const MeshLimits& limits, PolyMesh& out) {
  out = PolyMesh{};
  out.first_number = 0;
  if (Status s = too_large(text, limits); !s) return s;
  std::vector<std::string_view> tokens;
  LineCursor lines(text, limits);
  if (!lines.next(tokens))
    return Status::error("the file is empty (expected OFF, then the vertex and face counts)");
  // The header keyword is optional; the counts may follow it on the same line.
  std::size_t counts_at = 0;
  if (ends_with_off(tokens[0])) {
    if (tokens[0] != "OFF")
      return Status::error(
          at_line(lines.line(), "header '" + escaped_prefix(tokens[0], 32) +
                                    "': vertex colours, normals or texture coordinates are not "
                                    "read (expected OFF)"));
    if (tokens.size() > 1 && tokens[1] == "BINARY")
      return Status::error(at_line(lines.line(), "binary OFF is not read (expected text)"));
    counts_at = 1;
    if (tokens.size() == 1) {
      if (!lines.next(tokens))
        return Status::error("the file ends after OFF (expected the vertex and face counts)");
      counts_at = 0;
    }
  }
  long long counts[3] = {};
  if (tokens.size() - counts_at != 3)
    return Status::error(at_line(lines.line(), "expected the counts 'vertices faces edges', got " +
                                                   std::to_string(tokens.size() - counts_at) +
                                                   " values"));
  for (int k = 0; k < 3; ++k)
    if (!parse_integer(tokens[counts_at + k], counts[k]) || counts[k] < 0)
      return Status::error(at_line(lines.line(), "count '" +
                                                     escaped_prefix(tokens[counts_at + k], 32) +
                                                     "' is not a number of 0 or more (expected "
                                                     "vertices faces edges)"));
  const long long vertex_count = counts[0], face_count = counts[1];
  // Held to the limits before anything is allocated: a header may claim anything.
  if (vertex_count > limits.max_points)
    return Status::error(at_line(lines.line(), std::to_string(vertex_count) +
                                                   " vertices (expected at most " +
                                                   std::to_string(limits.max_points) + ")"));
  if (face_count > limits.max_faces)
    return Status::error(at_line(lines.line(), std::to_string(face_count) +
                                                   " faces (expected at most " +
                                                   std::to_string(limits.max_faces) + ")"));
  if (face_count == 0) return Status::error("the mesh has no faces (the header counts 0)");
  // No more than the text can hold either: a vertex line takes at least 6 bytes, a face 8.
  out.points.reserve(std::size_t(std::min<long long>(vertex_count, (long long)text.size() / 6)));
  out.face_offsets.reserve(
      std::size_t(std::min<long long>(face_count, (long long)text.size() / 8)) + 1);
  for (long long v = 0; v < vertex_count; ++v) {
    if (!lines.next(tokens))
      return Status::error("the file ends after " + std::to_string(v) + " of the header's " +
                           std::to_string(vertex_count) + " vertices");
    if (tokens.size() != 3)
      return Status::error(
          at_line(lines.line(), "vertex " + std::to_string(v) + ": expected x y z, got " +
                                    std::to_string(tokens.size()) + " values (the header counts " +
                                    std::to_string(vertex_count) + " vertices)"));
    std::array<double, 3> p{};
    for (int k = 0; k < 3; ++k)
      if (!parse_double(tokens[k], p[k]))
        return Status::error(at_line(
            lines.line(),
            "vertex coordinate '" + escaped_prefix(tokens[k], 32) + "' is not a finite number"));
    out.points.push_back(p);
  }
  for (long long f = 0; f < face_count; ++f) {
    if (!lines.next(tokens))
      return Status::error("the file ends after " + std::to_string(f) + " of the header's " +
                           std::to_string(face_count) + " faces");
    const std::size_t line_no = lines.line();
    const std::string face = "face " + std::to_string(f) + ": ";
    long long n = 0;
    if (!parse_integer(tokens[0], n))
      return Status::error(at_line(
          line_no, face + "'" + escaped_prefix(tokens[0], 32) +
                       "' is not a vertex count (expected n i0 .. in-1 after the header's " +
                       std::to_string(vertex_count) + " vertices)"));
    if (n < 3) return Status::error(at_line(line_no, face + "a face needs at least 3 vertices"));
    if (n > limits.max_face_size)
      return Status::error(at_line(
          line_no,
          face + "a face of more than " + std::to_string(limits.max_face_size) + " vertices"));
    if ((long long)tokens.size() - 1 < n)
      return Status::error(at_line(line_no, face + "expected " + std::to_string(n) +
                                                " vertex indices, got " +
                                                std::to_string(tokens.size() - 1)));
    // Values after the n indices (a colour) are not used.
    for (long long k = 1; k <= n; ++k) {
      long long v = 0;
      if (!parse_integer(tokens[k], v))
        return Status::error(at_line(line_no, face + "index '" + escaped_prefix(tokens[k], 32) +
                                                  "' is not a vertex number (0-based)"));
      if (v < 0 || v >= vertex_count)
        return Status::error(at_line(line_no, face + "index " + std::to_string(v) +
                                                  " names no vertex (" +
                                                  std::to_string(vertex_count) + " in the file)"));
      out.face_vertices.push_back(int(v));
    }
    out.face_offsets.push_back(int(out.face_vertices.size()));
  }
  if (lines.next(tokens))
    return Status::error(
        at_line(lines.line(), "more than the header's " + std::to_string(face_count) + " faces"));
  return Status::ok();
}

MeshFormat mesh_format(const std::filesystem::path& path, std::string_view text) {
  std::vector<std::string_view> tokens;
  LineCursor lines(text, MeshLimits{});
  if (lines.next(tokens) && ends_with_off(tokens[0])) return MeshFormat::kOff;
  std::string extension = path.extension().string();
  for (char& c : extension) c = char(std::tolower((unsigned char)c));
  return extension == ".off" ? MeshFormat::kOff : MeshFormat::kObj;
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

Status read_mesh(const std::filesystem::path& path, const MeshLimits& limits, PolyMesh& out) {
  UserFile file;
  if (Status s = file.open(path, limits.max_bytes, "a mesh (Wavefront OBJ or OFF)"); !s) return s;
  std::string text;
  if (Status s = file.read_rest(text); !s) return s;
  const Status parsed = mesh_format(path, text) == MeshFormat::kOff ? parse_off(text, limits, out)
                                                                    : parse_obj(text, limits, out);
  if (!parsed) return Status::error(path.string() + ": " + parsed.message());
  return Status::ok();
}

namespace {

int find_root(std::vector<int>& parent, int a) {
  while (parent[a] != a) a = parent[a] = parent[parent[a]];
  return a;
}

}  // namespace

Status check_manifold(const PolyMesh& mesh) {
  // Vertices and faces as the file numbers them.
  const auto number = [&](int index) { return std::to_string(index + mesh.first_number); };
  const int faces = mesh.face_count();
  if (faces == 0) return Status::error("the mesh has no faces");
  for (int f = 0; f < faces; ++f) {
    const int n = mesh.face_size(f);
    if (n < 3) return Status::error("face " + number(f) + " has fewer than 3 vertices");
    const int* fv = mesh.face(f);
    for (int a = 0; a < n; ++a)
      for (int b = a + 1; b < n; ++b)
        if (fv[a] == fv[b])
          return Status::error("non-manifold vertex " + number(fv[a]) + ": face " + number(f) +
                               " uses it twice");
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
      const std::string name = number(std::min(a, b)) + "-" + number(std::max(a, b));
      if (e.faces == 3)
        return Status::error("non-manifold edge " + name + ": shared by 3 or more faces (" +
                             number(e.face_ids[0]) + ", " + number(e.face_ids[1]) + ", " +
                             number(f) + ")");
      if (e.faces == 2 && e.forward != 1)
        return Status::error("edge " + name + ": faces " + number(e.face_ids[0]) + " and " +
                             number(f) +
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
      return Status::error("non-manifold vertex " + number(int(v)) +
                           ": an interior vertex of only " + std::to_string(corners_at[v]) +
                           " faces (expected 3 or more)");
  std::vector<int> fan_of_vertex(mesh.points.size(), -1);
  for (int c = 0; c < corners; ++c) {
    const int v = mesh.face_vertices[c], root = find_root(parent, c);
    if (fan_of_vertex[v] == -1)
      fan_of_vertex[v] = root;
    else if (fan_of_vertex[v] != root)
      return Status::error("non-manifold vertex " + number(int(v)) +
                           ": two fans of faces meet only there");
  }
  return Status::ok();
}

}  // namespace ardcell
