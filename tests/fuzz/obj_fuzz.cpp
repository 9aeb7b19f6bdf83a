// libFuzzer target for the mesh readers and the mesh checks (host/surface/poly_mesh.h): an input
// goes to the reader read_mesh would choose for it (an OFF header, or a name ending in .off: odd
// lengths are named so), the others to the OBJ reader; either it parses or gives one line; what
// parses names only vertices it has; a mesh that passes check_manifold (and is small) builds a
// limit surface whose patch adjacency is symmetric. Seeds: tests/fuzz/corpus/obj_fuzz/ (a cube, a
// pyramid with every face index form, a pinched vertex; an OFF tetrahedron with face colours, an
// OFF pentagon and triangles).
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>

#if ARDCELL_WITH_OPENSUBDIV
#include "host/surface/limit_surface.h"
#include "host/surface/poly_mesh.h"
#endif

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
#if ARDCELL_WITH_OPENSUBDIV
  using namespace ardcell;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  MeshLimits limits;
  limits.max_points = 4096;
  limits.max_faces = 4096;
  PolyMesh mesh;
  // The file name decides when the first token names no OFF header: half the inputs (by their
  // length's parity) are named .off, so the OFF reader also sees files without a header.
  const char* name = size % 2 ? "fuzz.off" : "fuzz.obj";
  const Status s = mesh_format(name, text) == MeshFormat::kOff ? parse_off(text, limits, mesh)
                                                               : parse_obj(text, limits, mesh);
  if (!s.is_ok()) {
    if (s.message().find('\n') != std::string::npos) std::abort();
    return 0;
  }
  for (int v : mesh.face_vertices)
    if (v < 0 || v >= int(mesh.points.size())) std::abort();
  const Status m = check_manifold(mesh);
  if (!m.is_ok()) {
    if (m.message().find('\n') != std::string::npos) std::abort();
    return 0;
  }
  if (mesh.face_count() > 64) return 0;
  for (const auto& p : mesh.points)
    for (double x : p)
      if (std::abs(x) > 1e6) return 0;  // keep OpenSubdiv's arithmetic finite
  LimitSurface surface;
  if (!LimitSurface::build(mesh, {}, surface).is_ok()) std::abort();
  const PatchTopology& topo = surface.topology();
  for (int p = 0; p < topo.patches; ++p)
    for (int e = 0; e < 4; ++e) {
      const EdgeTransition& tr = topo.transition(p, e);
      if (tr.patch < 0) continue;
      const EdgeTransition& back = topo.transition(tr.patch, tr.edge);
      if (back.patch != p || back.edge != e) std::abort();
    }
#else
  (void)data, (void)size;
#endif
  return 0;
}
