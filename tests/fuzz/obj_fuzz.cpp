// libFuzzer target for the mesh readers and the mesh checks (host/surface/poly_mesh.h): an input
// whose first token names an OFF header goes to the OFF reader (as read_mesh sends it), any other
// to the OBJ reader; either it parses or gives one line; what parses names only vertices it has;
// a mesh that passes check_manifold (and is small) builds a limit surface whose patch adjacency
// is symmetric. Seeds: tests/fuzz/corpus/obj_fuzz/ (a cube, a pyramid with every face index
// form, a pinched vertex; an OFF tetrahedron with face colours, an OFF pentagon and triangles).
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
  const Status s = mesh_format("fuzz", text) == MeshFormat::kOff ? parse_off(text, limits, mesh)
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
