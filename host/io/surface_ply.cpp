#include "host/io/surface_ply.h"

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "host/io/atomic_file.h"
#include "host/io/surface_atlas.h"

namespace ardcell {
namespace {

// One PLY vertex: position, normal (float32 each) and colour, 27 bytes packed.
constexpr std::size_t kVertexBytes = 6 * sizeof(float) + 3;

void put_float(unsigned char*& at, double v) {
  const float f = float(v);
  std::memcpy(at, &f, sizeof f);  // x86 and ARM are little-endian, as the header says
  at += sizeof f;
}

}  // namespace

Status write_surface_ply(const std::filesystem::path& path, const LimitSurface& surface,
                         const PatchGrid& grid, PatchField field, const SurfaceColours& options) {
  const int n = grid.n(), patches = grid.patches();
  const long long per_patch = (long long)(n + 1) * (n + 1);
  const long long vertices = per_patch * patches, faces = (long long)n * n * patches;
  grid.exchange(field);
  const std::string header =
      "ply\nformat binary_little_endian 1.0\ncomment ardcell surface: limit surface, field as "
      "vertex colour\nelement vertex " +
      std::to_string(vertices) +
      "\nproperty float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float "
      "ny\nproperty float nz\nproperty uchar red\nproperty uchar green\nproperty uchar "
      "blue\nelement face " +
      std::to_string(faces) + "\nproperty list uchar int vertex_indices\nend_header\n";
  AtomicFile file;
  if (Status s = file.open(path); !s) return s;
  // A failed write is remembered by the file: commit() reports it and removes the temporary.
  auto failed = [&] { return file.commit(); };
  if (!file.write(header.data(), header.size())) return failed();
  std::vector<unsigned char> row(std::size_t(n + 1) * kVertexBytes);
  for (int p = 0; p < patches; ++p)
    for (int j = 0; j <= n; ++j) {
      unsigned char* at = row.data();
      for (int i = 0; i <= n; ++i) {
        double position[3], normal[3];
        limit_vertex(surface, p, double(i) / n, double(j) / n, position, normal);
        for (double v : position) put_float(at, v);
        for (double v : normal) put_float(at, v);
        const double value = grid.corner_mean(field, p, i, j);
        const Rgb8 c = options.colour(value);
        *at++ = c.r, *at++ = c.g, *at++ = c.b;
      }
      if (!file.write(row.data(), row.size())) return failed();
    }
  std::vector<unsigned char> quads(std::size_t(n) * (1 + 4 * sizeof(int)));
  for (int p = 0; p < patches; ++p)
    for (int j = 0; j < n; ++j) {
      unsigned char* at = quads.data();
      for (int i = 0; i < n; ++i) {
        const long long base = per_patch * p;
        const int v[4] = {int(base + (long long)j * (n + 1) + i),
                          int(base + (long long)j * (n + 1) + i + 1),
                          int(base + (long long)(j + 1) * (n + 1) + i + 1),
                          int(base + (long long)(j + 1) * (n + 1) + i)};
        *at++ = 4;
        std::memcpy(at, v, sizeof v);
        at += sizeof v;
      }
      if (!file.write(quads.data(), quads.size())) return failed();
    }
  return file.commit();
}

}  // namespace ardcell
